"""The one exit-status scheme (lumis_tools.exitcodes): 0 pass, 1 a check failed, 2 nothing could
be checked."""

from __future__ import annotations

import argparse
import sys

import pytest

from lumis_tools import exitcodes
from lumis_tools.geometry import LoadError
from lumis_tools.lumis import LumisError, StaleBinary


def status(main, **kw):
    return exitcodes.status(main, [], **kw)


def test_returned_statuses_pass_through():
    assert status(lambda argv: None) == 0  # a benchmark that ran to the end
    assert status(lambda argv: 0) == 0
    assert status(lambda argv: 1) == 1
    assert status(lambda argv: 2) == 2
    with pytest.raises(ValueError):  # idiff's 3 and 4 must be mapped, not leak out
        status(lambda argv: 4)


def raiser(exc):
    def main(argv):
        raise exc
    return main


def test_setup_problems_are_2_with_a_message(capsys):
    for exc in (exitcodes.SetupError("no model"), LoadError("bad.obj: line 3"),
                LumisError("lumis hits failed"), StaleBinary("older than src/main.rs")):
        assert status(raiser(exc), prog="tool") == 2
        assert capsys.readouterr().err == f"tool: error: {exc}\n"
    # A missing requirement: 2, naming the module.
    assert status(raiser(ModuleNotFoundError("no module", name="embreex"))) == 2
    assert "embreex is not installed" in capsys.readouterr().err
    # Errors a tool declares as setup problems, and only those.
    assert status(raiser(OSError("disk full")), setup_errors=(OSError,)) == 2
    with pytest.raises(KeyError):
        status(raiser(KeyError("bug")), setup_errors=(OSError,))


def test_usage_errors_are_2():
    def main(argv):
        p = argparse.ArgumentParser()
        p.add_argument("--n", type=int)
        p.parse_args(["--n", "many"])
    assert status(main) == 2
    assert status(raiser(SystemExit("usage: tool FILE"))) == 2  # sys.exit(message) is 1 alone
    assert status(raiser(SystemExit(0))) == 0  # --help


def test_run_exits_with_the_status(monkeypatch):
    with pytest.raises(SystemExit) as e:
        exitcodes.run(lambda argv: 1)
    assert e.value.code == 1
    monkeypatch.setattr(sys, "argv", ["tool"])
    with pytest.raises(SystemExit) as e:
        exitcodes.run(raiser(exitcodes.SetupError("x")))
    assert e.value.code == 2

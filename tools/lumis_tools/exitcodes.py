"""The exit status every tool uses (documented in tools/README.md):

    0  every check passed (a benchmark: it ran to the end)
    1  a check failed: the engines or the images disagree beyond a threshold (idiff-style
       warnings included: like idiff, a warning is not a pass)
    2  nothing could be checked: a usage error, a missing dependency, input file, or binary, a
       stale lumis binary, a file that could not be read or written, or a program (lumis,
       the original, Mitsuba) that failed to run

Kept free of numpy and the other requirements so that a missing one can be reported with
status 2 instead of an ImportError traceback."""

from __future__ import annotations

import sys

OK, FAILED, SETUP = 0, 1, 2


class SetupError(Exception):
    """The tool could not run its check (status 2); the message says why."""


def run(main, argv=None, *, setup_errors: tuple = (), prog: str | None = None):
    """Calls `main(argv)` and exits with its status: its return value (None is 0), or 2 after
    printing `error: ...` for a SetupError, a missing module, or one of `setup_errors`."""
    sys.exit(status(main, argv, setup_errors=setup_errors, prog=prog))


def status(main, argv=None, *, setup_errors: tuple = (), prog: str | None = None) -> int:
    """`run` without the exit, for callers (and tests) that want the number."""
    prefix = f"{prog}: " if prog else ""
    try:
        code = main(argv)
    except ModuleNotFoundError as e:
        print(f"{prefix}error: {e.name} is not installed (pip install -e tools/, or the "
              "requirements file the tool names)", file=sys.stderr)
        return SETUP
    except (SetupError, *setup_errors) as e:
        print(f"{prefix}error: {e}", file=sys.stderr)
        return SETUP
    except SystemExit as e:  # argparse's usage errors are 2 already; sys.exit(msg) would be 1
        if isinstance(e.code, str):
            print(e.code, file=sys.stderr)
            return SETUP
        return OK if e.code is None else int(e.code)
    if code is None:
        return OK
    if code not in (OK, FAILED, SETUP):
        raise ValueError(f"tool returned exit status {code!r}, not one of 0, 1, 2")
    return int(code)

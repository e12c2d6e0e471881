"""What machine a benchmark ran on, for printing beside its figures."""

from __future__ import annotations

import platform
import subprocess
from pathlib import Path

# The vector extensions that decide how fast either program's compiled code can be (neither
# build uses -march=native by default, but a reader comparing machines wants to know).
FLAGS_OF_INTEREST = ("sse4_2", "avx", "avx2", "fma", "avx512f")


def _lscpu() -> dict[str, str]:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return {}
    fields = {}
    for line in out.splitlines():
        key, sep, value = line.partition(":")
        if sep:
            fields[key.strip()] = value.strip()
    return fields


def _cpuinfo() -> dict[str, str]:
    """The first processor's entries of /proc/cpuinfo (where lscpu is missing)."""
    fields = {}
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if not line.strip():
                break
            key, sep, value = line.partition(":")
            if sep:
                fields[key.strip()] = value.strip()
    except OSError:
        pass
    return fields


def cpu_info() -> dict:
    """{"model": str, "flags": {flag: bool} for FLAGS_OF_INTEREST}, from lscpu, else
    /proc/cpuinfo."""
    lscpu = _lscpu()
    model, flags = lscpu.get("Model name"), lscpu.get("Flags")
    if model is None or flags is None:
        info = _cpuinfo()
        model = model or info.get("model name")
        flags = flags or info.get("flags", "")
    present = set(flags.split())
    return {
        "model": model or platform.processor() or "unknown",
        "flags": {f: f in present for f in FLAGS_OF_INTEREST},
    }


def cpu_summary() -> str:
    """One line: model name and which of the interesting flags the CPU has."""
    info = cpu_info()
    flags = ", ".join(f"{f} {'yes' if have else 'no'}" for f, have in info["flags"].items())
    return f"{info['model']} ({flags})"

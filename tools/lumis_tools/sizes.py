"""Image sizes on the tools' command lines (`--size 96x72`, `--camera 512x384`): one parser,
so every tool accepts and refuses the same forms."""

from __future__ import annotations

import argparse


def wxh(parser: argparse.ArgumentParser, flag: str, text: str, example: str) -> tuple[int, int]:
    """`text` as (width, height), both at least 1; otherwise `parser.error` naming `flag`
    and an `example` of the form (exits with argparse's usage error)."""
    try:
        w, h = (int(x) for x in text.lower().split("x"))
        if w < 1 or h < 1:
            raise ValueError
    except ValueError:
        parser.error(f"{flag}: expected WxH such as {example}, got {text!r}")
    return w, h

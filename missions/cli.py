"""The ``baobab`` command line (placeholder until the missions issue lands)."""

from __future__ import annotations

import sys


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``baobab`` console script."""
    del argv
    print("baobab: the mission launcher is not built yet", file=sys.stderr)
    return 2

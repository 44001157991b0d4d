"""``baobab schema [-o FILE]``: the JSON Schema of the mission format, for editor completion."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from baobab.missions.run.exit_codes import EXIT_OK


def configure_schema(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``baobab schema``."""
    parser.add_argument("-o", "--output", type=Path, help="write to this file instead of stdout")


def schema_command(args: argparse.Namespace) -> int:
    """Print (or write) the schema."""
    import json

    from baobab.missions.language.json_schema import mission_json_schema

    text = json.dumps(mission_json_schema(), indent=2) + "\n"
    if args.output is None:
        sys.stdout.write(text)
    else:
        args.output.write_text(text, encoding="utf-8")
    return EXIT_OK

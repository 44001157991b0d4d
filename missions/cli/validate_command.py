"""``baobab validate FILE... [--set KEY=VALUE]``: check mission files without running them.

Loading a mission checks everything a file can get wrong (node types, capabilities,
parameters, subtrees, poses); building the py_trees tree from a loaded mission cannot fail, so
validate does not build it (and does not import py_trees). Exit 0 when every file is valid,
2 otherwise, with one located message per invalid file.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from baobab.missions.cli.arguments import add_robot, add_set, overrides
from baobab.missions.cli.startup import loading_modules
from baobab.missions.run.exit_codes import EXIT_INVALID, EXIT_OK
from baobab.sim.errors import SourceError, one_line

if TYPE_CHECKING:
    from baobab.missions.language.loader import Mission


def configure_validate(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``baobab validate``."""
    parser.add_argument("files", nargs="+", metavar="FILE", help="mission files")
    add_set(parser)
    add_robot(parser, "each mission's robot (where the mission fits it)")


def validate_command(args: argparse.Namespace) -> int:
    """Load every file; one ``ok`` line or one located error each."""
    with loading_modules():
        from baobab.behaviours.builtin import default_registry
        from baobab.missions.language.loader import load_mission

        default_registry()
    values = overrides(args)
    failed = 0
    for file in args.files:
        try:
            mission = load_mission(file, values, robot=args.robot)
        except SourceError as exc:
            print(exc, file=sys.stderr)
            failed += 1
            continue
        nodes = len(mission.tree.walk())
        summary = f"{mission.name}: {mission.robot.name} in {_world(mission)}, {nodes} nodes"
        print(f"{one_line(file, None)}: ok ({summary})")
    return EXIT_INVALID if failed else EXIT_OK


def _world(mission: Mission) -> str:
    return Path(mission.world_name).name if "/" in mission.world_name else mission.world_name

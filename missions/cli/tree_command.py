"""``baobab tree MISSION [--format unicode|dot|btcpp]``: the compiled behaviour tree.

``unicode`` and ``dot`` draw the py_trees tree as compiled (offline: no robot, the clock at
0); ``btcpp`` is BehaviorTree.CPP v4 XML with a ``TreeNodesModel``, for Groot2.
"""

from __future__ import annotations

import argparse
import sys

from baobab.missions.cli.arguments import add_set, overrides
from baobab.missions.run.exit_codes import EXIT_OK


def configure_tree(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``baobab tree``."""
    parser.add_argument("mission", metavar="MISSION", help="a mission file")
    parser.add_argument(
        "--format",
        choices=("unicode", "dot", "btcpp"),
        default="unicode",
        help="unicode text, Graphviz dot, or BehaviorTree.CPP v4 XML for Groot2",
    )
    add_set(parser)


def tree_command(args: argparse.Namespace) -> int:
    """Print the tree in the asked format."""
    from baobab.behaviours.ports import Capabilities
    from baobab.missions.language.compiler import compile_mission
    from baobab.missions.language.loader import load_mission
    from baobab.missions.language.tree_export import to_btcpp, to_dot, to_unicode

    mission = load_mission(args.mission, overrides(args))
    if args.format == "btcpp":
        sys.stdout.write(to_btcpp(mission))
        return EXIT_OK
    offline = Capabilities(clock=lambda: 0.0)  # display only: nothing runs
    compiled = compile_mission(mission, offline, require_ports=False)
    text = to_dot(compiled) if args.format == "dot" else to_unicode(compiled)
    sys.stdout.write(text if text.endswith("\n") else text + "\n")
    return EXIT_OK

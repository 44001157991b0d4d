"""``baobab nav2-params PARAMS.yaml [--nav2-substitute] [--json]``: what a Nav2 file sets.

Prints, per node, every Nav2 parameter baobab's navigation stack has an equivalent for, with
the value it will run with, its unit and where the value came from (``file:LINE`` or
``default``: the robot's setting before the file), then the plugins that run as substitutes,
the parameters baobab does not use (by plugin), the ROS-only ones and the nodes it does not run.
A file baobab cannot use exits 2 with one located line (:mod:`baobab.nav.nav2_configuration`).
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from baobab.missions.run.exit_codes import EXIT_OK

if TYPE_CHECKING:
    from baobab.nav.nav2_configuration import Nav2Configuration

SUBSTITUTE_HELP = (
    "run a stated substitute for each Nav2 plugin baobab does not have (e.g. Regulated Pure"
    " Pursuit with MPPI's speed limits) instead of refusing the parameter file"
)


def add_nav2_params_options(parser: argparse.ArgumentParser) -> None:
    """``--nav2-params FILE`` and ``--nav2-substitute``, as run, nav2 and teleop take them."""
    parser.add_argument(
        "--nav2-params",
        metavar="PARAMS.yaml",
        help="a Nav2 parameter file (nav2_params.yaml) that configures the navigation stack",
    )
    parser.add_argument("--nav2-substitute", action="store_true", help=SUBSTITUTE_HELP)


def configure_nav2_params(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``baobab nav2-params``."""
    parser.add_argument("params", metavar="PARAMS.yaml", help="a Nav2 parameter file")
    parser.add_argument("--nav2-substitute", action="store_true", help=SUBSTITUTE_HELP)
    parser.add_argument("--json", action="store_true", help="one JSON object on stdout")


def nav2_params_command(args: argparse.Namespace) -> int:
    """Print what baobab will use of the file; a located error (exit 2) if it cannot."""
    import json

    from baobab.nav.nav2_configuration import load_nav2_params

    configuration = load_nav2_params(args.params, substitute=args.nav2_substitute)
    if args.json:
        print(json.dumps(as_json(configuration), indent=2))
    else:
        print("\n".join(report_lines(configuration)))
    return EXIT_OK


def as_json(configuration: Nav2Configuration) -> dict[str, Any]:
    """The ``--json`` object: ``file``, ``parameters`` (each with node, name, value, unit,
    origin, line, targets), ``substitutions``, ``unused`` (by plugin), ``ros_only``,
    ``ignored_nodes``."""
    return {
        "file": configuration.path,
        "parameters": [
            {
                "node": setting.node,
                "name": setting.name,
                "value": setting.value,
                "unit": setting.unit,
                "origin": setting.origin,
                "line": setting.line or None,
                "targets": list(setting.targets),
            }
            for setting in configuration.settings
        ],
        "substitutions": configuration.substitutions,
        "unused": configuration.unused,
        "ros_only": configuration.ros_only,
        "ignored_nodes": configuration.ignored_nodes,
    }


def report_lines(configuration: Nav2Configuration) -> list[str]:
    """The text report, one line per mapped parameter, grouped by node."""
    lines = [f"{configuration.path}: what baobab's navigation stack runs with"]
    node = None
    for setting in sorted(configuration.settings, key=lambda setting: setting.node):
        if setting.node != node:
            node = setting.node
            lines.append(f"{node}:")
        value = _shown(setting.value) + (f" {setting.unit}" if setting.unit else "")
        origin = f"file:{setting.line}" if setting.line else setting.origin
        lines.append(f"  {setting.name:<56} {value:<16} {origin}")
    if configuration.substitutions:
        lines.append("substituted plugins:")
        lines += [f"  {line}" for line in configuration.substitutions]
    if configuration.unused:
        lines.append("not used by baobab (warning):")
        for group, names in configuration.unused.items():
            lines.append(f"  {group}: {', '.join(names)}")
    if configuration.ros_only:
        lines.append(f"ROS-only, ignored: {', '.join(configuration.ros_only)}")
    if configuration.ignored_nodes:
        lines.append(
            f"nodes baobab does not run, ignored: {', '.join(configuration.ignored_nodes)}"
        )
    return lines


def _shown(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)

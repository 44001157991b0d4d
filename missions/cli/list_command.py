"""``baobab list [--json]``: the bundled missions, worlds, scenes, robots and behaviour types."""

from __future__ import annotations

import argparse
from typing import Any

from baobab.missions.run.exit_codes import EXIT_OK
from baobab.robots.catalog import RobotInfo


def configure_list(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``baobab list``."""
    parser.add_argument("--json", action="store_true", help="one JSON object on stdout")


def catalogue() -> dict[str, Any]:
    """Everything ``baobab list`` shows, as plain data (its ``--json`` object)."""
    from baobab.behaviours.builtin import default_registry
    from baobab.missions.language.bundled_missions import bundled_missions
    from baobab.robots.catalog import ROBOTS
    from baobab.sim.world import bundled_world_names

    registry = default_registry()
    return {
        "missions": bundled_missions(),
        "worlds": bundled_world_names(),
        "scenes": sorted({scene for robot in ROBOTS.values() for scene in robot.scenes}),
        "robots": {name: robot_entry(robot) for name, robot in ROBOTS.items()},
        "behaviours": {
            behaviour.name: {
                "kind": behaviour.kind.value,
                "capability": behaviour.capability,
                "description": behaviour.description,
                "parameters": list(behaviour.ports()),
            }
            for behaviour in registry
        },
    }


def robot_entry(robot: RobotInfo) -> dict[str, Any]:
    """What ``baobab list`` says of one robot: description, capabilities, aliases and, for a
    mobile robot, its footprint (m), speed limits (m/s, rad/s) and lidar."""
    entry: dict[str, Any] = {
        "description": robot.description,
        "capabilities": sorted(robot.capabilities),
        "aliases": list(robot.aliases),
    }
    facts = robot.facts
    if facts is not None:
        footprint = facts.footprint
        entry["footprint"] = (
            {"radius": footprint.radius}
            if footprint.radius is not None
            else {"polygon": [list(point) for point in footprint.polygon]}
        )
        entry["max_linear_speed"] = facts.max_linear_speed
        entry["max_angular_speed"] = facts.max_angular_speed
        lidar = facts.lidar
        entry["lidar"] = {
            "model": lidar.model,
            "range": [lidar.range_min, lidar.range_max],
            "rate": lidar.rate,
            "beams": lidar.beams,
        }
    return entry


def list_command(args: argparse.Namespace) -> int:
    """Print the catalogue as text, or as one JSON object."""
    import json

    from baobab.behaviours.registry import NodeKind

    listed = catalogue()
    if args.json:
        print(json.dumps(listed, indent=2))
        return EXIT_OK
    lines = ["missions:"]
    lines += [f"  {n:<24} {d}" for n, d in listed["missions"].items()] or ["  (none bundled)"]
    lines += ["worlds:"] + [f"  {name}" for name in listed["worlds"]]
    lines += [f"  {name} (scene)" for name in listed["scenes"]]
    lines.append("robots:")
    for name, robot in listed["robots"].items():
        lines.append(f"  {name:<24} {', '.join(robot['capabilities'])}: {robot['description']}")
        if robot["aliases"]:
            lines.append(f"  {'':<24} also: {', '.join(robot['aliases'])}")
    lines.append("behaviours:")
    for kind in NodeKind:
        for name, info in listed["behaviours"].items():
            if info["kind"] == kind.value:
                need = f"[{info['capability']}]" if info["capability"] else ""
                lines.append(f"  {name:<24} {kind.value:<10} {need:<19} {info['description']}")
    print("\n".join(lines))
    return EXIT_OK

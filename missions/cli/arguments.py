"""Argument types and options that several ``baobab`` subcommands share.

A type raises :class:`argparse.ArgumentTypeError`, which argparse turns into a one-line usage
error (exit 2).
"""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING

from baobab.sim.errors import BaobabError, clip

if TYPE_CHECKING:
    from baobab.robots.footprint import Footprint
    from baobab.sim.world import Pose2D, World


def add_set(parser: argparse.ArgumentParser) -> None:
    """``--set KEY=VALUE`` (repeatable): override a mission parameter."""
    parser.add_argument(
        "--set",
        dest="sets",
        action="append",
        default=[],
        type=_assignment,
        metavar="KEY=VALUE",
        help="override a mission parameter (repeatable)",
    )


def add_robot(parser: argparse.ArgumentParser, what: str) -> None:
    """``--robot NAME_OR_PATH``: a bundled robot or a robot file (``what`` it replaces)."""
    parser.add_argument(
        "--robot",
        metavar="NAME_OR_PATH",
        help=f"a bundled robot (see baobab list) or a robot YAML file, instead of {what}",
    )


def overrides(args: argparse.Namespace) -> dict[str, str]:
    """The ``--set`` values by key.

    Raises:
        BaobabError: a key given twice.
    """
    values: dict[str, str] = {}
    for key, value in args.sets:
        if key in values:
            raise BaobabError(f"--set {key} is given twice")
        values[key] = value
    return values


def _assignment(text: str) -> tuple[str, str]:
    from baobab.missions.language.params import parse_assignment

    try:
        return parse_assignment(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def positive_int(text: str) -> int:
    """A whole number above 0."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: '{text}'") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value}")
    return value


def port(text: str) -> int:
    """A TCP port, 0..65535 (0 picks a free one)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a port number: '{text}'") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"a port is 0..65535, got {value}")
    return value


def video_size(text: str) -> tuple[int, int]:
    """``WIDTHxHEIGHT`` in pixels, both positive and even (H.264 needs even sizes)."""
    width, _, height = text.lower().partition("x")
    if not (width.isdigit() and height.isdigit()):
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT in pixels, e.g. 640x480: '{text}'")
    size = int(width), int(height)
    if min(size) <= 0 or size[0] % 2 or size[1] % 2:
        raise argparse.ArgumentTypeError(f"width and height must be positive and even: '{text}'")
    return size


def add_start(parser: argparse.ArgumentParser) -> None:
    """``--start X,Y[,YAW]``: where the robot starts (needed on a map without a spawn)."""
    parser.add_argument(
        "--start",
        metavar="X,Y,YAW",
        help="start pose (m, m, rad; default: the world's spawn, on a map without one the "
        "origin); --start=-1,2,0 for negatives",
    )


def robot_footprint(robot: str | None) -> Footprint:
    """The footprint of the robot ``--robot`` names (the default mobile robot's without it).

    Raises:
        BaobabError: an unknown or fixed robot.
        RobotFileError: a robot file that cannot be used (located).
    """
    from baobab.nav.navigator_robot import NavigatorSetupError, navigator_robot

    try:
        return navigator_robot(robot).mobile_facts.footprint
    except NavigatorSetupError as exc:
        raise BaobabError(f"--robot: {exc}") from None


def start_pose(text: str | None, world: World, footprint: Footprint) -> Pose2D:
    """The pose of ``--start X,Y[,YAW]`` (m, m, rad), checked to be free for ``footprint`` in
    ``world``.

    Without ``--start`` (None): the world's default spawn, or on a map without one its origin
    (as ``BasicNavigator``), checked the same way.

    Raises:
        BaobabError: not two or three finite numbers, or a pose the robot cannot stand on.
    """
    from baobab.nav.navigator_robot import NavigatorSetupError, check_free, default_start
    from baobab.sim.world import Pose2D

    if text is None:
        what = "the default spawn" if "default" in world.spawns else "the map origin"
        try:
            pose = default_start(world, footprint)
        except NavigatorSetupError as exc:
            raise BaobabError(str(exc)) from None
    else:
        parts = text.split(",")
        try:
            values = [float(part) for part in parts]
        except ValueError:
            values = []
        if len(values) not in (2, 3) or not all(math.isfinite(value) for value in values):
            raise BaobabError(f"--start: expected X,Y,YAW (m, m, rad), got '{clip(text)}'")
        pose = Pose2D(x=values[0], y=values[1], yaw=values[2] if len(values) == 3 else 0.0)
        what = "--start"
    try:
        check_free(world, pose, footprint, what=what)
    except NavigatorSetupError as exc:
        raise BaobabError(str(exc)) from None
    return pose

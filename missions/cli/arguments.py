"""Argument types and options that several ``baobab`` subcommands share.

A type raises :class:`argparse.ArgumentTypeError`, which argparse turns into a one-line usage
error (exit 2).
"""

from __future__ import annotations

import argparse

from baobab.sim.errors import BaobabError


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

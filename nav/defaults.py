"""What a ``BasicNavigator()`` built without arguments runs in: world, start pose, seed, pacing.

Nav2 scripts construct ``BasicNavigator()`` with no arguments and find a running robot; in
baobab the navigator builds its own simulation, so something has to say which. That is this
context-local setting: ``baobab nav2 SCRIPT.py --world town`` (through ``run_nav2_script``)
wraps the script in :func:`use_navigator_defaults`, and the navigator reads
:func:`navigator_defaults` when its constructor is not told otherwise.

Example:
    >>> with use_navigator_defaults(world="farm", seed=7):
    ...     navigator_defaults().world
    'farm'
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path

from baobab.sim.world import Pose2D

DEFAULT_WORLD = "cafe"
"""The bundled world a navigator uses when nothing names one."""


@dataclass(frozen=True, kw_only=True)
class NavigatorDefaults:
    """The settings a ``BasicNavigator()`` without arguments uses.

    Attributes:
        world: a bundled world name (``"cafe"``) or a world YAML path.
        robot: a bundled mobile robot's name or a robot file's path; None: the registry's
            default mobile robot.
        start: the robot's start pose in the map frame; ``None`` is the world's default spawn.
        seed: seeds the run's one random generator (non-negative).
        realtime: pace the simulation to the wall clock (for watching); off, the simulation
            runs as fast as it computes.
    """

    world: str | Path = DEFAULT_WORLD
    robot: str | Path | None = None
    start: Pose2D | None = None
    seed: int = 0
    realtime: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.world, str | Path) or not str(self.world):
            raise TypeError(f"world must be a world name or path, not {self.world!r}")
        if self.robot is not None and (
            not isinstance(self.robot, str | Path) or not str(self.robot)
        ):
            raise TypeError(f"robot must be a robot name or path, not {self.robot!r}")
        if self.start is not None and not isinstance(self.start, Pose2D):
            raise TypeError(f"start must be a Pose2D or None, not {self.start!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise TypeError(f"seed must be a non-negative int, not {self.seed!r}")
        if not isinstance(self.realtime, bool):
            raise TypeError(f"realtime must be a bool, not {self.realtime!r}")


_STANDARD = NavigatorDefaults()
_current: ContextVar[NavigatorDefaults | None] = ContextVar("navigator_defaults", default=None)


def navigator_defaults() -> NavigatorDefaults:
    """The navigator defaults in force in the current context."""
    return _current.get() or _STANDARD


@contextmanager
def use_navigator_defaults(
    *,
    world: str | Path | None = None,
    robot: str | Path | None = None,
    start: Pose2D | None = None,
    seed: int | None = None,
    realtime: bool | None = None,
) -> Iterator[NavigatorDefaults]:
    """Override the navigator defaults inside a ``with`` block; ``None`` keeps a setting.

    Overrides apply on top of the defaults in force (blocks nest), and the previous defaults
    come back when the block ends, also on an exception.

    Raises:
        TypeError: a value of the wrong type (a programming error, not user input).
    """
    current = navigator_defaults()
    updated = NavigatorDefaults(
        world=current.world if world is None else world,
        robot=current.robot if robot is None else robot,
        start=current.start if start is None else start,
        seed=current.seed if seed is None else seed,
        realtime=current.realtime if realtime is None else realtime,
    )
    token = _current.set(updated)
    try:
        yield updated
    finally:
        _current.reset(token)

"""Scripted moving objects: the world file's ``moving_objects:`` and the paths they walk.

A moving object is an upright cylinder (a person by default: 0.2 m radius, 1.7 m tall) that
walks waypoints at a speed, pausing ``wait`` s where asked and looping if told, or drives a
velocity profile (constant-twist steps) from a start pose. It starts ``start_time`` s into the
run and stays where its script ends. It names the topic and the TF frame its pose is published
on (``/<name>/pose`` and ``<name>`` unless given); who publishes, and when, is the navigation
stack's business (a detector that sees it with the lidar). Plain math: checking a world costs no
numpy; :mod:`baobab.sim.moving_object_motion` moves the objects in a simulation.
"""

from __future__ import annotations

import bisect
import itertools
import math
import re
from dataclasses import dataclass
from typing import Annotated, Any

from pydantic import ConfigDict, Field, field_validator, model_validator

from baobab.sim.planar_shapes import circle_distance_at, rectangle_distance_at
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import FieldValueError

Finite = Annotated[float, Field(allow_inf_nan=False)]
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]

MAX_OBJECT_SPEED = 3.0
"""Fastest walk or drive of a moving object (m/s)."""
MAX_OBJECT_TURN_RATE = 3.0
"""Fastest turn of a moving object (rad/s)."""
MAX_SCRIPT_STEPS = 1_000
"""Most waypoints or velocity steps of one object."""
CHECK_SPACING = 0.05
"""Spacing (m) of the points a path is checked at against the obstacles."""
OBJECT_COLOUR = (0.20, 0.45, 0.80, 1.0)

_TOPIC = re.compile(r"/?[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*")
_FRAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


class _Strict(YamlModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Waypoint(_Strict):
    """A point to walk to (m), and how long to stand there (s)."""

    x: Finite
    y: Finite
    wait: NonNegative = 0.0


class VelocityStep(_Strict):
    """Drive ``linear`` (m/s) and turn ``angular`` (rad/s) for ``duration`` (s)."""

    duration: Positive
    linear: Annotated[float, Field(ge=-MAX_OBJECT_SPEED, le=MAX_OBJECT_SPEED)] = 0.0
    angular: Annotated[float, Field(ge=-MAX_OBJECT_TURN_RATE, le=MAX_OBJECT_TURN_RATE)] = 0.0


class StartPose(_Strict):
    """Where a velocity profile starts: metres and radians."""

    x: Finite
    y: Finite
    yaw: Finite = 0.0


@dataclass(frozen=True)
class Leg:
    """A stretch of constant twist: from ``t0`` (s) for ``duration`` (s), from the pose
    (``x``, ``y`` m, ``yaw`` rad), at ``linear`` (m/s) and ``angular`` (rad/s)."""

    t0: float
    duration: float
    x: float
    y: float
    yaw: float
    linear: float
    angular: float
    step: int = 0
    """The waypoint this leg walks to or waits at, or the velocity step it drives."""

    def pose(self, dt: float) -> tuple[float, float, float]:
        """The pose ``dt`` s into the leg (exact arcs)."""
        yaw = self.yaw + self.angular * dt
        if abs(self.angular) < 1e-12:
            distance = self.linear * dt
            return (
                self.x + distance * math.cos(self.yaw),
                self.y + distance * math.sin(self.yaw),
                yaw,
            )
        radius = self.linear / self.angular
        return (
            self.x + radius * (math.sin(yaw) - math.sin(self.yaw)),
            self.y - radius * (math.cos(yaw) - math.cos(self.yaw)),
            yaw,
        )


class MovingObject(_Strict):
    """One scripted object: its body, its script and its names (module docstring)."""

    name: str = Field(pattern=r"^[A-Za-z_][A-Za-z0-9_]*$")
    radius: Annotated[float, Field(gt=0, le=2.0, allow_inf_nan=False)] = 0.2
    height: Annotated[float, Field(gt=0, le=10.0, allow_inf_nan=False)] = 1.7
    colour: tuple[float, float, float, float] = OBJECT_COLOUR
    topic: str | None = None
    frame: str | None = None
    start_time: NonNegative = 0.0
    waypoints: list[Waypoint] = Field(default_factory=list, max_length=MAX_SCRIPT_STEPS)
    speed: Annotated[float, Field(gt=0, le=MAX_OBJECT_SPEED, allow_inf_nan=False)] = 0.3
    loop: bool = False
    start: StartPose | None = None
    velocity_profile: list[VelocityStep] = Field(default_factory=list, max_length=MAX_SCRIPT_STEPS)

    @field_validator("topic")
    @classmethod
    def _topic_name(cls, value: str | None) -> str | None:
        if value is not None and not _TOPIC.fullmatch(value):
            raise ValueError(
                f"topic '{value}' is not a ROS topic name (letters, digits, '_', parts "
                "separated by '/', e.g. /person/pose)"
            )
        return value

    @field_validator("frame")
    @classmethod
    def _frame_name(cls, value: str | None) -> str | None:
        if value is not None and not _FRAME.fullmatch(value):
            raise ValueError(f"frame '{value}' is not a TF frame name (letters, digits, '_')")
        return value

    @model_validator(mode="after")
    def _one_script(self) -> MovingObject:
        if self.velocity_profile:
            if self.waypoints:
                raise FieldValueError(
                    ("velocity_profile",), "give either waypoints or a velocity_profile, not both"
                )
            if self.start is None:
                raise FieldValueError(("start",), "a velocity_profile needs a start pose")
        elif len(self.waypoints) < 2:
            raise FieldValueError(
                ("waypoints",),
                "a moving object needs at least two waypoints (or a start and a velocity_profile)",
            )
        elif self.start is not None:
            raise FieldValueError(("start",), "waypoints start at the first one; drop 'start'")
        return self

    @property
    def pose_topic(self) -> str:
        """The absolute topic its pose is published on."""
        return absolute_topic(self.topic or f"{self.name}/pose")

    @property
    def tf_frame(self) -> str:
        """The TF frame its pose is published as."""
        return self.frame or self.name

    def legs(self) -> list[Leg]:
        """The script as legs from time 0 (s after ``start_time``); one loop of it if looping."""
        if self.velocity_profile:
            assert self.start is not None  # checked by the model
            return _profile_legs(self.start, self.velocity_profile)
        return _waypoint_legs(self.waypoints, self.speed, self.loop)


def _waypoint_legs(waypoints: list[Waypoint], speed: float, loop: bool) -> list[Leg]:
    numbered = list(enumerate(waypoints))
    if loop:
        numbered.append((0, waypoints[0]))
    legs: list[Leg] = []
    t = 0.0
    first, second = waypoints[0], waypoints[1]
    yaw = math.atan2(second.y - first.y, second.x - first.x)
    for (number, start), (next_number, end) in itertools.pairwise(numbered):
        if start.wait > 0:
            legs.append(Leg(t, start.wait, start.x, start.y, yaw, 0.0, 0.0, number))
            t += start.wait
        length = math.hypot(end.x - start.x, end.y - start.y)
        if length > 0:
            yaw = math.atan2(end.y - start.y, end.x - start.x)
            legs.append(Leg(t, length / speed, start.x, start.y, yaw, speed, 0.0, next_number))
            t += length / speed
    number, last = numbered[-1]
    if last.wait > 0 and not loop:
        legs.append(Leg(t, last.wait, last.x, last.y, yaw, 0.0, 0.0, number))
    if not legs:
        legs.append(Leg(0.0, 0.0, last.x, last.y, yaw, 0.0, 0.0, number))
    return legs


def _profile_legs(start: StartPose, steps: list[VelocityStep]) -> list[Leg]:
    legs: list[Leg] = []
    t, x, y, yaw = 0.0, start.x, start.y, start.yaw
    for step in steps:
        leg = Leg(t, step.duration, x, y, yaw, step.linear, step.angular, len(legs))
        legs.append(leg)
        x, y, yaw = leg.pose(step.duration)
        t += step.duration
    return legs


class Script:
    """Where an object is at any time: its legs, looped or held at the end."""

    def __init__(self, legs: list[Leg], start_time: float, loop: bool) -> None:
        self.legs = legs
        self.start_time = start_time
        self.loop = loop
        self._starts = [leg.t0 for leg in legs]
        last = legs[-1]
        self.length = last.t0 + last.duration
        """s of one pass through the legs."""

    @classmethod
    def of(cls, item: MovingObject, start_time: float | None = None) -> Script:
        """The script of ``item`` (starting at ``start_time`` s, its own by default)."""
        start = item.start_time if start_time is None else start_time
        return cls(item.legs(), start, item.loop)

    def pose(self, time: float) -> tuple[float, float, float]:
        """x, y (m) and yaw (rad) at sim time ``time`` (s)."""
        return self.state(time)[:3]

    def state(self, time: float) -> tuple[float, float, float, float, float]:
        """x, y (m), yaw (rad), and the speed (m/s) and turn rate (rad/s) at ``time`` (s)."""
        t = max(time - self.start_time, 0.0)
        if self.loop and self.length > 0:
            t = math.fmod(t, self.length)
        elif t >= self.length:
            last = self.legs[-1]
            return (*last.pose(last.duration), 0.0, 0.0)
        leg = self.legs[max(bisect.bisect_right(self._starts, t) - 1, 0)]
        moving = time >= self.start_time
        return (
            *leg.pose(t - leg.t0),
            leg.linear if moving else 0.0,
            leg.angular if moving else 0.0,
        )

    def sample_points(self) -> list[tuple[int, float, float]]:
        """(leg index, x, y) every :data:`CHECK_SPACING` m or less along one pass (m)."""
        samples: list[tuple[int, float, float]] = []
        for index, leg in enumerate(self.legs):
            travel = abs(leg.linear) * leg.duration + abs(leg.angular) * leg.duration * 0.1
            count = max(1, math.ceil(travel / CHECK_SPACING))
            for step in range(count + 1):
                x, y, _ = leg.pose(leg.duration * step / count)
                samples.append((index, x, y))
        return samples


RESERVED_FRAMES = ("map", "odom")
"""TF frames an object may not take: the simulation publishes them."""


def check_moving_objects(
    objects: list[MovingObject],
    obstacles: list[Any],
    bounds: tuple[float, float, float, float],
) -> None:
    """Refuse objects whose names, topics or frames repeat, or whose path leaves the floor or
    runs into an obstacle (boxes, cylinders and docks' parts: ``obstacles``, each with a name
    and either a size and yaw or a radius).

    Raises:
        FieldValueError: located at the object, or at the waypoint or step at fault.
    """
    used: dict[str, set[str]] = {"name": set(), "topic": set(), "frame": set(RESERVED_FRAMES)}
    for index, item in enumerate(objects):
        for key, value in (
            ("name", item.name),
            ("topic", item.pose_topic),
            ("frame", item.tf_frame),
        ):
            if value in used[key]:
                field = key if key == "name" or getattr(item, key) is not None else "name"
                raise FieldValueError(
                    ("moving_objects", index, field),
                    f"{key} '{value}' is taken (by another object, or by the simulation)",
                )
            used[key].add(value)
        _check_path(index, item, obstacles, bounds)


def _check_path(
    index: int, item: MovingObject, obstacles: list[Any], bounds: tuple[float, float, float, float]
) -> None:
    x_min, y_min, x_max, y_max = bounds
    script = Script.of(item)
    key = "velocity_profile" if item.velocity_profile else "waypoints"
    r = item.radius
    for leg_index, x, y in script.sample_points():
        where = ("moving_objects", index, key, script.legs[leg_index].step)
        if not (x_min + r <= x <= x_max - r and y_min + r <= y <= y_max - r):
            raise FieldValueError(
                where, f"'{item.name}' (radius {r:g} m) leaves the floor near ({x:.2f}, {y:.2f})"
            )
        for obstacle in obstacles:
            if _distance(x, y, obstacle) < r - 1e-9:
                raise FieldValueError(
                    where,
                    f"'{item.name}' (radius {r:g} m) walks into '{obstacle.name}' near "
                    f"({x:.2f}, {y:.2f}); its path must stay clear of the obstacles",
                )


def absolute_topic(topic: str) -> str:
    """``topic`` with its leading ``/``: how a moving object's pose topic is named and looked
    up."""
    return topic if topic.startswith("/") else f"/{topic}"


def _distance(x: float, y: float, obstacle: Any) -> float:
    if hasattr(obstacle, "radius"):
        return circle_distance_at(x, y, obstacle)
    return rectangle_distance_at(x, y, obstacle)

"""A user's own differential-drive robot, read from a YAML file of its facts.

The file gives what a bundled robot's facts module gives (:class:`DiffDriveFacts`), in SI
units, ``base_link`` on the floor under the middle of the wheel axle, x forward, y left::

    name: rover                      # optional: the file's name without .yaml
    description: a warehouse rover   # optional
    footprint: {radius: 0.2}         # or {polygon: [[x, y], ...]} around base_link
    body: {shape: box, length: 0.32, width: 0.26, height: 0.12, bottom: 0.02, center_x: -0.03}
    wheels: {radius: 0.04, separation: 0.28, width: 0.02, mass: 0.15}
    casters: [{x: -0.15, y: 0.0, radius: 0.012}]
    mass: 3.0                        # the whole robot, kg
    limits: {linear_speed: 0.4, angular_speed: 2.0, linear_accel: 1.0, angular_accel: 4.0}
    lidar: {x: -0.03, z: 0.2, range_min: 0.12, range_max: 8.0, rate: 10, beams: 360}

``body`` may be ``{shape: cylinder, radius, height, bottom}``. ``limits`` may add
``wheel_speed`` (rad/s, the motors' top speed) and ``wheel_torque`` (N m, default 1.4);
``lidar`` may add ``y`` and ``model``; ``encoder_ticks_per_rev`` defaults to 4096.

Every mistake is one located error (``file:line:col: what is wrong``, exit 2): missing or
unknown keys, non-physical values (zero or negative sizes, masses, speeds), a footprint that is
not a simple polygon holding ``base_link``, a body, wheel or caster outside the footprint, a
lidar mounted outside the body or below it, a centre of mass the wheels and casters cannot
carry, and limits that contradict each other (a speed the wheels cannot reach, an acceleration
the motors cannot give, a lidar whose nearest range is not below its farthest).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal

from pydantic import ConfigDict, Field, ValidationError, model_validator

from baobab.robots.catalog import (
    DIFF_DRIVE_KERNEL,
    MOBILE_CAPABILITIES,
    ROBOTS,
    RobotInfo,
    robot_named,
)
from baobab.robots.diff_drive.facts import Body, Caster, DiffDriveFacts, LidarFacts
from baobab.robots.footprint import Footprint
from baobab.sim.errors import BaobabError, SourceError, unknown_name
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import (
    FieldValueError,
    describe_validation_error,
    load_located_yaml,
    read_yaml_text,
)

MAX_SIZE = 10.0
"""Largest length (m) of any part of a robot: larger is no robot baobab simulates."""
MAX_MASS = 1000.0
"""kg."""
MAX_SPEED = 10.0
"""m/s; rad/s for turning."""
MAX_SCAN_RATE = 100.0
"""Hz: two physics steps per scan at the 5 ms step."""
MAX_BEAMS = 4000
"""Samples per lidar turn."""

Size = Annotated[float, Field(gt=0, le=MAX_SIZE, allow_inf_nan=False)]
Coordinate = Annotated[float, Field(ge=-MAX_SIZE, le=MAX_SIZE, allow_inf_nan=False)]
Mass = Annotated[float, Field(gt=0, le=MAX_MASS, allow_inf_nan=False)]
Acceleration = Annotated[float, Field(gt=0, le=MAX_SPEED * 100, allow_inf_nan=False)]
Name = Annotated[str, Field(pattern=r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$", max_length=100)]


class RobotFileError(SourceError):
    """A robot file that cannot be read or describes no robot baobab can build."""


class UnknownRobotError(BaobabError, ValueError):
    """A robot name that is neither a bundled robot's nor a robot file's path."""


class _Strict(YamlModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class FootprintSpec(_Strict):
    """``radius`` (m) or ``polygon`` (vertices ``[x, y]`` in order around the robot, m)."""

    radius: Size | None = None
    polygon: list[tuple[Coordinate, Coordinate]] | None = None

    def footprint(self) -> Footprint:
        """The footprint."""
        if self.radius is not None:
            return Footprint.circle(self.radius)
        return Footprint(polygon=tuple(self.polygon or ()))

    @model_validator(mode="after")
    def _check(self) -> FootprintSpec:
        if (self.radius is None) == (self.polygon is None):
            raise ValueError("give the footprint's radius or its polygon (one of the two)")
        problem = self.footprint().problem()
        if problem is not None:
            raise FieldValueError(("polygon",), problem)
        return self


class BodySpec(_Strict):
    """The chassis' collision envelope: a box (``length``, ``width``) or a cylinder
    (``radius``), ``height`` tall, its underside ``bottom`` above the floor (m)."""

    shape: Literal["box", "cylinder"]
    height: Size
    bottom: Size
    center_x: Coordinate = 0.0
    length: Size | None = None
    width: Size | None = None
    radius: Size | None = None

    @model_validator(mode="after")
    def _check(self) -> BodySpec:
        needed = ("length", "width") if self.shape == "box" else ("radius",)
        unused = ("radius",) if self.shape == "box" else ("length", "width")
        for key in needed:
            if getattr(self, key) is None:
                raise FieldValueError((), f"a {self.shape} body needs '{key}' (m)")
        for key in unused:
            if getattr(self, key) is not None:
                raise FieldValueError((key,), f"a {self.shape} body has no '{key}'")
        return self

    def body(self) -> Body:
        """The body."""
        return Body(
            shape=self.shape,
            height=self.height,
            bottom=self.bottom,
            center_x=self.center_x,
            length=self.length or 0.0,
            width=self.width or 0.0,
            radius=self.radius or 0.0,
        )


class WheelsSpec(_Strict):
    """The two driven wheels (m, kg): ``separation`` between their contact points."""

    radius: Size
    separation: Size
    width: Size
    mass: Mass


class CasterSpec(_Strict):
    """A frictionless ball caster touching the floor at ``(x, y)`` (m)."""

    x: Coordinate
    y: Coordinate = 0.0
    radius: Size = 0.01


class LimitsSpec(_Strict):
    """Speed and acceleration limits (m/s, rad/s, m/s^2, rad/s^2), and optionally the wheel
    motors' top speed (rad/s) and torque (N m)."""

    linear_speed: Annotated[float, Field(gt=0, le=MAX_SPEED, allow_inf_nan=False)]
    angular_speed: Annotated[float, Field(gt=0, le=10 * MAX_SPEED, allow_inf_nan=False)]
    linear_accel: Acceleration
    angular_accel: Acceleration
    wheel_speed: Acceleration | None = None
    wheel_torque: Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)] = 1.4


class LidarSpec(_Strict):
    """The planar lidar: its scan origin (m), ranges (m), scan rate (Hz) and beams a turn."""

    x: Coordinate
    z: Size
    range_min: Size
    range_max: Annotated[float, Field(gt=0, le=100.0, allow_inf_nan=False)]
    rate: Annotated[float, Field(gt=0, le=MAX_SCAN_RATE, allow_inf_nan=False)]
    beams: Annotated[int, Field(ge=3, le=MAX_BEAMS)]
    y: Coordinate = 0.0
    model: str = "lidar"

    @model_validator(mode="after")
    def _check(self) -> LidarSpec:
        if self.range_min >= self.range_max:
            raise FieldValueError(
                ("range_min",),
                f"range_min {self.range_min:g} m must be below range_max {self.range_max:g} m",
            )
        return self


class RobotFile(_Strict):
    """A user's differential-drive robot (see the module docstring)."""

    name: Name | None = None
    description: str = ""
    footprint: FootprintSpec
    body: BodySpec
    wheels: WheelsSpec
    casters: list[CasterSpec] = Field(min_length=1)
    mass: Mass
    limits: LimitsSpec
    lidar: LidarSpec
    encoder_ticks_per_rev: Annotated[float, Field(gt=0, le=1e6, allow_inf_nan=False)] = 4096

    @model_validator(mode="after")
    def _check(self) -> RobotFile:
        footprint = self.footprint.footprint()
        _check_body(self.body.body(), footprint)
        _check_wheels(self.wheels, footprint)
        for index, caster in enumerate(self.casters):
            if not _inside(footprint, (caster.x, caster.y)):
                raise FieldValueError(
                    ("casters", index),
                    f"caster at ({caster.x:g}, {caster.y:g}) is outside the footprint",
                )
        _check_support(self.body.body(), self.casters)
        _check_lidar(self.lidar, self.body.body())
        if self.mass <= 2 * self.wheels.mass:
            raise FieldValueError(
                ("mass",),
                f"mass {self.mass:g} kg is the whole robot: more than its two wheels "
                f"({2 * self.wheels.mass:g} kg)",
            )
        _check_limits(self)
        return self

    def facts(self, name: str) -> DiffDriveFacts:
        """The robot's facts, its MuJoCo model called ``name``."""
        wheels, limits, lidar = self.wheels, self.limits, self.lidar
        return DiffDriveFacts(
            model_name=name,
            footprint=self.footprint.footprint(),
            body=self.body.body(),
            wheel_radius=wheels.radius,
            wheel_separation=wheels.separation,
            wheel_width=wheels.width,
            wheel_mass=wheels.mass,
            chassis_mass=self.mass - 2 * wheels.mass,
            casters=tuple(Caster(x=c.x, y=c.y, radius=c.radius) for c in self.casters),
            max_linear_speed=limits.linear_speed,
            max_angular_speed=limits.angular_speed,
            max_linear_accel=limits.linear_accel,
            max_angular_accel=limits.angular_accel,
            encoder_ticks_per_rev=self.encoder_ticks_per_rev,
            wheel_max_torque=limits.wheel_torque,
            lidar=LidarFacts(
                model=lidar.model,
                x=lidar.x,
                y=lidar.y,
                z=lidar.z,
                range_min=lidar.range_min,
                range_max=lidar.range_max,
                rate=lidar.rate,
                beams=lidar.beams,
            ),
        )


def _inside(footprint: Footprint, point: tuple[float, float]) -> bool:
    """True when ``point`` (m, ``base_link``) lies in the footprint (on its edge counts)."""
    return footprint.contains(point, tolerance=1e-9)


def _body_outline(body: Body) -> list[tuple[float, float]]:
    if body.shape == "cylinder":
        return [
            (body.center_x + body.radius * math.cos(a), body.radius * math.sin(a))
            for a in (i * math.pi / 8 for i in range(16))
        ]
    half_x, half_y = body.half_extents
    return [(body.center_x + sx * half_x, sy * half_y) for sx in (-1, 1) for sy in (-1, 1)]


def _check_body(body: Body, footprint: Footprint) -> None:
    for x, y in _body_outline(body):
        if not _inside(footprint, (x, y)):
            raise FieldValueError(
                ("body",),
                f"the body reaches outside the footprint at ({x:.3f}, {y:.3f}); the footprint "
                "must hold the whole robot",
            )


def _check_wheels(wheels: WheelsSpec, footprint: Footprint) -> None:
    outer = wheels.separation / 2 + wheels.width / 2
    for x in (-wheels.radius, wheels.radius):
        for y in (-outer, outer):
            if not _inside(footprint, (x, y)):
                raise FieldValueError(
                    ("wheels",),
                    f"a wheel reaches outside the footprint at ({x:.3f}, {y:.3f})",
                )


def _check_support(body: Body, casters: list[CasterSpec]) -> None:
    """The chassis' centre of mass (the body's centre) must lie between the axle and the
    casters, or the robot tips over."""
    low = min(0.0, *(caster.x for caster in casters))
    high = max(0.0, *(caster.x for caster in casters))
    if not low < body.center_x < high:
        raise FieldValueError(
            ("casters",),
            f"the body's centre (x {body.center_x:g} m) is not between the wheel axle (x 0) and "
            "a caster: the robot would tip over; put a caster on that side",
        )


def _check_lidar(lidar: LidarSpec, body: Body) -> None:
    half_x, half_y = body.half_extents
    dx, dy = lidar.x - body.center_x, lidar.y
    if body.shape == "cylinder":
        outside = math.hypot(dx, dy) > body.radius + 1e-9
    else:
        outside = abs(dx) > half_x + 1e-9 or abs(dy) > half_y + 1e-9
    if outside:
        raise FieldValueError(
            ("lidar",),
            f"the lidar at ({lidar.x:g}, {lidar.y:g}) is mounted outside the body; it must "
            "stand on it",
        )
    if lidar.z <= body.bottom:
        raise FieldValueError(
            ("lidar", "z"),
            f"the lidar at z {lidar.z:g} m is below the body's underside ({body.bottom:g} m)",
        )


def _check_limits(robot: RobotFile) -> None:
    wheels, limits = robot.wheels, robot.limits
    if limits.wheel_speed is not None:
        rim = limits.wheel_speed * wheels.radius
        if limits.linear_speed > rim + 1e-9:
            raise FieldValueError(
                ("limits", "linear_speed"),
                f"linear_speed {limits.linear_speed:g} m/s contradicts wheel_speed "
                f"{limits.wheel_speed:g} rad/s: the wheels reach only {rim:.3g} m/s",
            )
        turn = 2 * rim / wheels.separation
        if limits.angular_speed > turn + 1e-9:
            raise FieldValueError(
                ("limits", "angular_speed"),
                f"angular_speed {limits.angular_speed:g} rad/s contradicts wheel_speed "
                f"{limits.wheel_speed:g} rad/s: the wheels turn the robot at most {turn:.3g} "
                "rad/s",
            )
    most = 2 * limits.wheel_torque / (robot.mass * wheels.radius)
    if limits.linear_accel > most:
        raise FieldValueError(
            ("limits", "linear_accel"),
            f"linear_accel {limits.linear_accel:g} m/s^2 contradicts wheel_torque "
            f"{limits.wheel_torque:g} N m: the motors give a {robot.mass:g} kg robot at most "
            f"{most:.3g} m/s^2",
        )


def load_robot_file(path: str | Path) -> RobotInfo:
    """Read a user's robot file into a registry entry of its own.

    Raises:
        RobotFileError: located ``file:line:col: message`` for any problem in the file.
    """
    path = Path(path)
    text = read_yaml_text(path, RobotFileError)
    document = load_located_yaml(path, RobotFileError, text=text)
    if not isinstance(document.data, dict):
        raise document.error((), "a robot file is a mapping of keys", RobotFileError)
    try:
        robot = RobotFile.model_validate(document.data)
    except ValidationError as exc:
        raise describe_validation_error(document, exc, (), RobotFileError) from None
    name = robot.name or path.stem
    return RobotInfo(
        name=name,
        description=robot.description or f"differential drive from {path.name}",
        capabilities=MOBILE_CAPABILITIES,
        facts=robot.facts(name),
        kernel=DIFF_DRIVE_KERNEL,
        path=str(path.resolve()),
    )


def is_robot_path(text: str) -> bool:
    """True when ``text`` names a robot file (a path or a ``.yaml`` name), not a bundled robot."""
    return "/" in text or "\\" in text or text.endswith((".yaml", ".yml"))


def load_robot(name_or_path: str | Path) -> RobotInfo:
    """A bundled robot by name (or alias), or a user's robot file by path.

    Raises:
        UnknownRobotError: an unknown name, listing the bundled ones.
        RobotFileError: a robot file that cannot be used (located).
    """
    text = str(name_or_path)
    if isinstance(name_or_path, Path) or is_robot_path(text):
        return load_robot_file(name_or_path)
    robot = robot_named(text)
    if robot is None:
        message = unknown_name("robot", text, ROBOTS)
        raise UnknownRobotError(f"{message} (or give a robot file's path)")
    return robot

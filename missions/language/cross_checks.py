"""Cross-checks of ``events`` and ``expect`` against the robot, the world and the locations.

The pydantic models check each value on its own; these checks need the whole mission: a
teleop event needs a robot with teleop, a wheel or lidar fault a mobile robot, a teleport a
free spot, an obstacle can only be moved after it was spawned, an expectation about a lifted
object needs an arm, a location must exist.
"""

from __future__ import annotations

from collections.abc import Sequence

from baobab.behaviours.ports import ARM, TELEOP
from baobab.behaviours.poses import MissionScope, Pose
from baobab.missions.language.error_codes import error_codes
from baobab.missions.language.errors import MissionError, located
from baobab.missions.language.metric_names import (
    FILTER_METRICS,
    metric_names,
    structured_metric_names,
)
from baobab.missions.language.models import (
    ARM_EXPECTATIONS,
    FILTER_EXPECTATIONS,
    LIDAR_FAULTS,
    MAX_EVENTS,
    MOBILE_EXPECTATIONS,
    NOISE_NEEDS_LIDAR,
    ROBOT_INDEPENDENT_FAULTS,
    Event,
    Expect,
    FaultEvent,
    MoveObstacleEvent,
    Noise,
    SpawnObstacleEvent,
    TeleopEvent,
)
from baobab.robots.catalog import RobotInfo
from baobab.sim.errors import unknown_name
from baobab.sim.world import MOVABLE_SLOT_COUNT
from baobab.sim.yaml_source import KeyPath, LocatedDocument


class MissionChecks:
    """Runs the cross-checks; every problem is a located :class:`MissionError`."""

    def __init__(
        self, document: LocatedDocument, scope: MissionScope, origins: dict[KeyPath, str]
    ) -> None:
        self.document = document
        self.scope = scope
        self.origins = origins

    def _error(self, path: KeyPath, message: str) -> MissionError:
        return located(self.document, path, message, self.origins)

    def events(self, events: Sequence[Event], timeout: float) -> None:
        """Check timing, capabilities, obstacle names and slots, and positions."""
        if len(events) > MAX_EVENTS:
            raise self._error(
                ("events", MAX_EVENTS),
                f"{len(events)} events; the limit is {MAX_EVENTS} (MAX_EVENTS)",
            )
        robot = self.scope.robot
        spawned: dict[str, int] = {}
        order = sorted(range(len(events)), key=lambda i: (events[i].at, i))
        for index in order:
            event = events[index]
            path: KeyPath = ("events", index)
            if event.at > timeout:
                raise self._error(
                    (*path, "at"),
                    f"event at {event.at:g} s comes after the mission timeout {timeout:g} s",
                )
            if isinstance(event, TeleopEvent):
                self._teleop(event, path)
            elif isinstance(event, FaultEvent):
                self._fault(event, path)
            elif isinstance(event, SpawnObstacleEvent | MoveObstacleEvent):
                key = "spawn_obstacle" if isinstance(event, SpawnObstacleEvent) else "move_obstacle"
                if not robot.mobile or self.scope.world is None:
                    raise self._error(
                        (*path, key), f"{key} needs a mobile robot in a 2D world, not {robot.name}"
                    )
                obstacle = (
                    event.spawn_obstacle
                    if isinstance(event, SpawnObstacleEvent)
                    else event.move_obstacle
                )
                if not self.scope.world.contains(obstacle.x, obstacle.y):
                    raise self._error(
                        (*path, key, "x"),
                        f"obstacle '{obstacle.name}' at ({obstacle.x:g}, {obstacle.y:g}) is "
                        f"outside the floor of world '{self.scope.world.name}'",
                    )
                if isinstance(event, SpawnObstacleEvent):
                    self._spawn(event, index, spawned)
                elif obstacle.name not in spawned:
                    message = unknown_name("obstacle", obstacle.name, spawned)
                    raise self._error(
                        (*path, key, "name"),
                        f"{message} (spawn it with an earlier spawn_obstacle event)",
                    )

    def _teleop(self, event: TeleopEvent, path: KeyPath) -> None:
        robot = self.scope.robot
        if TELEOP not in robot.capabilities:
            raise self._error(
                (*path, "teleop"),
                f"teleop needs capability 'teleop'; robot '{robot.name}' has: "
                f"{robot.describe_capabilities()}",
            )
        command = event.teleop
        for key, value, limit, unit in (
            ("linear", command.linear, robot.max_linear_speed, "m/s"),
            ("angular", command.angular, robot.max_angular_speed, "rad/s"),
        ):
            if abs(value) > limit:
                raise self._error(
                    (*path, "teleop", key),
                    f"teleop {key} {value:g} {unit} exceeds {robot.name}'s limit {limit:g} {unit}",
                )

    def _fault(self, event: FaultEvent, path: KeyPath) -> None:
        robot = self.scope.robot
        kind = event.fault.kind
        where: KeyPath = (*path, "fault", kind)
        if kind not in ROBOT_INDEPENDENT_FAULTS and not robot.mobile:
            raise self._error(where, f"a {kind} fault needs a mobile robot, not {robot.name}")
        if kind in LIDAR_FAULTS and not robot.has_lidar:
            raise self._error(where, f"a {kind} fault needs a robot with a lidar")
        target = event.fault.teleport
        if target is not None:
            problem = self.scope.free_space_problem(Pose.from_planar(target.x, target.y, 0.0))
            if problem is not None:
                raise self._error((*where, "x"), f"teleport target {problem}")

    def _spawn(self, event: SpawnObstacleEvent, index: int, spawned: dict[str, int]) -> None:
        path: KeyPath = ("events", index)
        name = event.spawn_obstacle.name
        if name in spawned:
            first = self.document.locate(("events", spawned[name]))[0]
            raise self._error(
                (*path, "spawn_obstacle", "name"),
                f"obstacle '{name}' is already spawned by the event at line {first}",
            )
        if len(spawned) == MOVABLE_SLOT_COUNT:
            raise self._error(
                (*path, "spawn_obstacle"),
                f"at most {MOVABLE_SLOT_COUNT} obstacles can be spawned in one run",
            )
        spawned[name] = index

    def noise(self, noise: Noise) -> None:
        """Check that the robot has the sensors whose noise is switched on."""
        robot = self.scope.robot
        for key in NOISE_NEEDS_LIDAR:
            if getattr(noise, key) > 0 and not robot.has_lidar:
                raise self._error(
                    ("noise", key), f"{key} needs a robot with a lidar; {robot.name} has none"
                )

    def expect(self, expect: Expect, timeout: float) -> None:
        """Check that each expectation fits the robot and names known locations."""
        robot = self.scope.robot
        given = {key for key in type(expect).model_fields if getattr(expect, key) is not None}
        for key in sorted(given):
            needs_mobile = key in MOBILE_EXPECTATIONS and not robot.mobile
            needs_arm = key in ARM_EXPECTATIONS and ARM not in robot.capabilities
            if needs_mobile or needs_arm:
                kind = "a mobile robot" if needs_mobile else "a robot with capability 'arm'"
                raise self._error(
                    ("expect", key), f"expectation '{key}' needs {kind}, not {robot.name}"
                )
        if expect.max_sim_time is not None and expect.max_sim_time > timeout:
            raise self._error(
                ("expect", "max_sim_time"),
                f"max_sim_time {expect.max_sim_time:g} s is longer than the mission timeout "
                f"{timeout:g} s",
            )
        self._error_code(expect.error_code)
        for name in expect.metrics or {}:
            problem = metric_name_problem(name, robot)
            if problem is not None:
                raise self._error(("expect", "metrics", name), problem)
        self._masks(expect)
        if expect.final_pose_near is not None and expect.final_pose_near.location is not None:
            self._location(
                expect.final_pose_near.location, ("expect", "final_pose_near", "location")
            )
        for index, name in enumerate(expect.visited_in_order or []):
            self._location(name, ("expect", "visited_in_order", index))
        placed = expect.object_placed
        if placed is not None and isinstance(placed.target, str):
            pose = self._location(placed.target, ("expect", "object_placed", "target"))
            if pose.planar:
                raise self._error(
                    ("expect", "object_placed", "target"),
                    f"location '{placed.target}' is planar; object_placed needs a spatial "
                    "location {position: [x, y, z]} or [x, y, z]",
                )

    def _masks(self, expect: Expect) -> None:
        """Refuse an expectation or a metric bound about a filter mask the world lacks."""
        world = self.scope.world
        wanted: list[tuple[KeyPath, str, str]] = [
            (("expect", key), f"expectation '{key}'", kind)
            for key, kind in FILTER_EXPECTATIONS.items()
            if getattr(expect, key) is not None
        ]
        wanted += [
            (("expect", "metrics", name), f"metric '{name}'", FILTER_METRICS[name])
            for name in expect.metrics or {}
            if name in FILTER_METRICS
        ]
        for path, what, kind in wanted:
            if world is None or getattr(world.masks, kind) is None:
                name = "a mobile robot's world" if world is None else f"world '{world.name}'"
                raise self._error(
                    path,
                    f"{what} needs a {kind} filter mask, and {name} has none (filters: "
                    f"{kind}: in the world file or the mission)",
                )

    def _error_code(self, code: int | str | None) -> None:
        """Refuse a code no run of this robot can end with (the expectation could never hold)."""
        if code is None:
            return
        robot = self.scope.robot
        known = error_codes(robot)
        if isinstance(code, str) and code not in known:
            message = unknown_name("error code", code, known, f"runs of {robot.name}")
            raise self._error(("expect", "error_code"), message)
        numbers = sorted({number for numbers in known.values() for number in numbers})
        if isinstance(code, int) and code not in numbers:
            message = unknown_name(
                "error code", str(code), map(str, numbers), f"runs of {robot.name}"
            )
            raise self._error(("expect", "error_code"), message)

    def _location(self, name: str, path: KeyPath) -> Pose:
        try:
            return self.scope.location(name)
        except ValueError as exc:
            raise self._error(path, str(exc)) from None


def metric_name_problem(name: str, robot: RobotInfo) -> str | None:
    """Why ``expect: metrics:`` cannot bound ``name`` in runs of ``robot``, or None."""
    numbers = metric_names(robot)
    if name in numbers:
        return None
    if name in structured_metric_names(robot):
        return f"metric '{name}' is not a number; bounds apply to: {', '.join(numbers)}"
    return unknown_name("metric", name, numbers, f"runs of {robot.name}")

"""Pydantic models of a mission file's top level, its timed events and its expectations.

The behaviour tree itself (``tree:`` and each subtree's ``tree:``) is validated node by node
by :mod:`baobab.missions.language.tree_parser` against the behaviour registry, so these models
keep it
as raw data and mark it with :data:`~baobab.behaviours.registry.NODE_SCHEMA_MARKER` for the JSON
Schema.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import (
    AfterValidator,
    ConfigDict,
    Discriminator,
    Field,
    PlainValidator,
    Tag,
    WithJsonSchema,
    model_validator,
)

from baobab.behaviours.poses import POSE_REF_SCHEMA, POSE_SCHEMA, PlanarPose, Pose, parse_pose
from baobab.behaviours.registry import NodeData
from baobab.missions.language.params import PARAM_NAME_PATTERN, ParamSpec
from baobab.robots.catalog import ROBOT_NAMES, ROBOTS, robot_named
from baobab.robots.robot_file import is_robot_path
from baobab.sim.errors import unknown_name
from baobab.sim.world_map import FilterSettings
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import FieldValueError, empty_list

Finite = Annotated[float, Field(allow_inf_nan=False)]
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Name = Annotated[str, Field(pattern=r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$", max_length=100)]
ParamName = Annotated[str, Field(pattern=PARAM_NAME_PATTERN, max_length=100)]


DEFAULT_TIMEOUT = 600.0
"""Mission timeout (s of sim time) when the file gives none."""


class _Strict(YamlModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


def _known_robot(name: str) -> str:
    robot = robot_named(name)
    if robot is None:
        raise ValueError(unknown_name("robot", name, ROBOTS))
    return robot.name


def _robot_or_file(name: str) -> str:
    return name if is_robot_path(name) else _known_robot(name)


RobotName = Annotated[
    str, AfterValidator(_known_robot), WithJsonSchema({"enum": list(ROBOT_NAMES)})
]
"""A bundled robot's name or alias (validated to its name)."""
RobotRef = Annotated[
    str,
    AfterValidator(_robot_or_file),
    WithJsonSchema(
        {
            "anyOf": [
                {"enum": list(ROBOT_NAMES)},
                {"type": "string", "pattern": r"\.ya?ml$", "description": "a robot file"},
            ]
        }
    ),
]
"""A bundled robot's name, or the path of a robot file inside the mission's folder."""
WrittenPose = Annotated[Pose, PlainValidator(parse_pose), POSE_SCHEMA]


class SubtreeSpec(_Strict):
    """A reusable, parameterised tree, used as ``subtree: {name: ..., args: {...}}``."""

    description: str = ""
    params: dict[ParamName, ParamSpec] = Field(default_factory=dict)
    tree: NodeData


# --- events ---------------------------------------------------------------------------------


class ObstacleSpawn(_Strict):
    """A box obstacle that appears at run time: centre (m), ``yaw`` (rad), full ``size`` (m)."""

    name: Name
    x: Finite
    y: Finite
    yaw: Finite = 0.0
    size: tuple[Positive, Positive, Positive] = (0.3, 0.3, 0.5)


class ObstacleMove(_Strict):
    """Move a spawned obstacle to (x, y) (m); ``yaw`` (rad) keeps the old heading if omitted."""

    name: Name
    x: Finite
    y: Finite
    yaw: Finite | None = None


class TeleopCommand(_Strict):
    """A velocity command held for the event's duration: m/s and rad/s."""

    linear: Finite = 0.0
    angular: Finite = 0.0


class CancelEvent(_Strict):
    """Cancel the mission at ``at`` s: the running goal is canceled, the result is CANCELED."""

    at: NonNegative
    cancel: Literal[True]


class SpawnObstacleEvent(_Strict):
    """Place an obstacle at ``at`` s."""

    at: NonNegative
    spawn_obstacle: ObstacleSpawn


class MoveObstacleEvent(_Strict):
    """Move an earlier spawned obstacle at ``at`` s."""

    at: NonNegative
    move_obstacle: ObstacleMove


class TeleopEvent(_Strict):
    """Send a teleop command from ``at`` s for ``duration`` s."""

    at: NonNegative
    duration: Positive
    teleop: TeleopCommand


class TeleportFault(_Strict):
    """The robot is picked up and put down at rest at (x, y) (m) heading ``yaw`` (rad)."""

    x: Finite
    y: Finite
    yaw: Finite = 0.0


class LidarDropoutFault(_Strict):
    """The lidar publishes no scan (its last scan grows old)."""


class LidarNoiseFault(_Strict):
    """Gaussian range noise of ``std`` (m) on every beam, drawn from the run's generator."""

    std: Positive = Field(description="standard deviation of each range reading, m")


class WheelFailureFault(_Strict):
    """One wheel's motor gives no torque: the wheel turns freely."""

    wheel: Literal["left", "right"]


class DivergeFault(_Strict):
    """A non-finite force on the robot's root joint: the physics diverges at the next step."""


FAULT_KINDS = ("teleport", "lidar_dropout", "lidar_noise", "wheel_failure", "diverge")
INSTANT_FAULTS = ("teleport", "diverge")
"""Faults that happen at once and take no ``duration``."""
LIDAR_FAULTS = ("lidar_dropout", "lidar_noise")
"""Faults that need a robot with a lidar."""
ROBOT_INDEPENDENT_FAULTS = ("diverge",)
"""Faults any robot can suffer; the others need a mobile robot."""


class FaultSpec(_Strict):
    """Exactly one fault kind, with its parameters (``{}`` or nothing when it has none)."""

    model_config = ConfigDict(
        extra="forbid", frozen=True, json_schema_extra={"minProperties": 1, "maxProperties": 1}
    )

    teleport: TeleportFault | None = None
    lidar_dropout: LidarDropoutFault | None = None
    lidar_noise: LidarNoiseFault | None = None
    wheel_failure: WheelFailureFault | None = None
    diverge: DivergeFault | None = None

    @model_validator(mode="before")
    @classmethod
    def _empty_means_defaults(cls, value: Any) -> Any:
        if isinstance(value, dict):
            return {
                key: {} if item is None and key in FAULT_KINDS else item
                for key, item in value.items()
            }
        return value

    @model_validator(mode="after")
    def _exactly_one(self) -> FaultSpec:
        if len(self.kinds()) != 1:
            raise ValueError(f"give exactly one fault kind: {', '.join(FAULT_KINDS)}")
        return self

    def kinds(self) -> list[str]:
        """The fault kinds given (one once validated)."""
        return [kind for kind in FAULT_KINDS if getattr(self, kind) is not None]

    @property
    def kind(self) -> str:
        """The fault kind, e.g. ``lidar_dropout``."""
        return self.kinds()[0]


class FaultEvent(_Strict):
    """Inject a fault at ``at`` s; a lasting fault ends after ``duration`` s (else never)."""

    at: NonNegative
    duration: Positive | None = Field(
        default=None, description="s; omitted: the fault lasts to the end of the run"
    )
    fault: FaultSpec

    @model_validator(mode="after")
    def _instant_faults_take_no_duration(self) -> FaultEvent:
        if self.duration is not None and self.fault.kind in INSTANT_FAULTS:
            raise FieldValueError(
                ("duration",), f"a {self.fault.kind} fault happens at once; it takes no duration"
            )
        return self


ROS_TOPIC = r"^/?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$"
ROS_MESSAGE_TYPE = r"^[A-Za-z_][A-Za-z0-9_]*/(msg/)?[A-Za-z_][A-Za-z0-9_]*$"


class PublishMessage(_Strict):
    """One message: its topic, its type (``pkg/msg/Type``) and its fields, as YAML (as
    ``ros2 topic pub`` takes them; a field not given keeps its ROS default)."""

    topic: str = Field(pattern=ROS_TOPIC, description="e.g. /goal")
    type: str = Field(pattern=ROS_MESSAGE_TYPE, description="e.g. geometry_msgs/msg/PoseStamped")
    message: dict[str, Any] = Field(default_factory=dict, description="the fields")


class PublishEvent(_Strict):
    """Publish a message on a ROS topic at ``at`` s, for the nodes the tree runs."""

    at: NonNegative
    publish: PublishMessage


EVENT_KINDS = ("cancel", "spawn_obstacle", "move_obstacle", "teleop", "fault", "publish")
MAX_EVENTS = 1_000
"""Most timed events in one mission."""


def _event_kind(value: Any) -> str | None:
    if isinstance(value, dict):
        present = [kind for kind in EVENT_KINDS if kind in value]
        return f"<{present[0]}>" if len(present) == 1 else None
    return None


Event = Annotated[
    Annotated[CancelEvent, Tag("<cancel>")]
    | Annotated[SpawnObstacleEvent, Tag("<spawn_obstacle>")]
    | Annotated[MoveObstacleEvent, Tag("<move_obstacle>")]
    | Annotated[TeleopEvent, Tag("<teleop>")]
    | Annotated[FaultEvent, Tag("<fault>")]
    | Annotated[PublishEvent, Tag("<publish>")],
    Discriminator(
        _event_kind,
        custom_error_type="event_kind",
        custom_error_message=f"an event has 'at' and exactly one of: {', '.join(EVENT_KINDS)}",
    ),
]


# --- expectations ---------------------------------------------------------------------------

ErrorName = Annotated[str, Field(pattern=r"^[A-Z][A-Z0-9_]*$")]


class Bounds(_Strict):
    """An allowed range; give ``min``, ``max`` or both."""

    min: Finite | None = None
    max: Finite | None = None

    @model_validator(mode="after")
    def _some_bound(self) -> Bounds:
        if self.min is None and self.max is None:
            raise ValueError("give min, max or both")
        if self.min is not None and self.max is not None and self.min > self.max:
            raise FieldValueError(("max",), f"max {self.max:g} is below min {self.min:g}")
        return self


class FinalPoseNear(_Strict):
    """The robot ends within ``xy_tolerance`` m (and ``yaw_tolerance`` rad, if given) of a pose."""

    location: Name | None = None
    pose: PlanarPose | None = None
    xy_tolerance: Positive = 0.25
    yaw_tolerance: Positive | None = None

    @model_validator(mode="after")
    def _one_target(self) -> FinalPoseNear:
        if (self.location is None) == (self.pose is None):
            raise ValueError("give exactly one of location or pose")
        return self


class ObjectPlaced(_Strict):
    """The object ends within ``tolerance`` m of ``target`` (a location or [x, y, z] in m)."""

    target: Name | tuple[Finite, Finite, Finite]
    tolerance: Positive = 0.02


SPEED_LIMIT_TOLERANCE = 0.01
"""How much faster than a speed limit (m/s) ``within_speed_limits`` lets the robot go: the
base's velocity tracking (bound ``metrics: speed_limit_excess`` for another figure)."""


class Expect(_Strict):
    """What a run must show to count as intended. Every key is optional."""

    result: Literal["SUCCEEDED", "FAILED", "CANCELED"] | None = None
    error_code: Annotated[int, Field(ge=0)] | ErrorName | None = Field(
        default=None, description="Nav2 error code, number or name; with result FAILED"
    )
    max_sim_time: Positive | None = Field(default=None, description="s")
    final_pose_near: FinalPoseNear | None = None
    visited_in_order: list[Name] | None = Field(default=None, min_length=1)
    min_clearance: NonNegative | None = Field(default=None, description="m, to any obstacle")
    no_contact: bool | None = None
    no_keepout_entry: bool | None = Field(
        default=None,
        description="the footprint never reaches into a keepout zone of the keepout mask",
    )
    within_speed_limits: bool | None = Field(
        default=None,
        description="the speed stays within the speed mask's limits (at most "
        f"{SPEED_LIMIT_TOLERANCE:g} m/s over) wherever the whole footprint is under one",
    )
    max_path_length_ratio: Annotated[float, Field(ge=1, allow_inf_nan=False)] | None = Field(
        default=None, description="driven path length / straight-line distance"
    )
    max_recoveries: Annotated[int, Field(ge=0)] | None = None
    object_lifted: Positive | None = Field(default=None, description="m above its start")
    object_placed: ObjectPlaced | None = None
    metrics: dict[Name, Bounds] | None = None

    @model_validator(mode="after")
    def _code_needs_failure(self) -> Expect:
        if self.error_code is not None and self.result != "FAILED":
            raise FieldValueError(
                ("error_code",), "error_code is only meaningful with result: FAILED"
            )
        return self


MOBILE_EXPECTATIONS = (
    "final_pose_near",
    "visited_in_order",
    "min_clearance",
    "max_path_length_ratio",
    "max_recoveries",
    "no_keepout_entry",
    "within_speed_limits",
)
FILTER_EXPECTATIONS = {"no_keepout_entry": "keepout", "within_speed_limits": "speed"}
"""Expectations about a costmap filter mask, by the mask they need."""
ARM_EXPECTATIONS = ("object_lifted", "object_placed")


# --- sensor noise ---------------------------------------------------------------------------


class Noise(_Strict):
    """Sensor noise of the run, drawn from the run's seeded generator (off by default).

    With noise on, a different seed gives a different run; the same seed, the same run.
    """

    lidar_std: NonNegative = Field(
        default=0.0, description="standard deviation of each lidar range reading, m"
    )


NOISE_NEEDS_LIDAR = ("lidar_std",)
"""Noise keys that need a robot with a lidar."""


# --- the whole file -------------------------------------------------------------------------


class MissionFile(_Strict):
    """A baobab mission: one robot, one world, a behaviour tree, timed events, expectations."""

    mission: Name = Field(description="the mission's name")
    description: str = ""
    world: str | None = Field(
        default=None,
        description="a bundled world name, or a world file or a map_server map YAML inside "
        "the mission's folder",
    )
    filters: FilterSettings | None = Field(
        default=None,
        description="Nav2 costmap filter masks (map_server YAML files inside the mission's "
        "folder), replacing the world's of the same kind",
    )
    robot: RobotRef = Field(
        description="a bundled robot's name, or a robot file path inside the mission's folder"
    )
    robots: list[RobotName] | None = Field(
        default=None,
        min_length=1,
        description="the bundled robots this mission fits; robot: and --robot must be one",
    )
    start: Annotated[Any, POSE_REF_SCHEMA] = Field(
        default=None,
        description="start pose or location; default: the world's spawn (a map has none)",
    )
    seed: Annotated[int, Field(ge=0)] = 0
    params: dict[ParamName, ParamSpec] = Field(default_factory=dict)
    locations: dict[Name, WrittenPose] = Field(default_factory=dict)
    tree: NodeData
    subtrees: dict[ParamName, SubtreeSpec] = Field(default_factory=dict)
    events: list[Event] = Field(default_factory=empty_list)
    noise: Noise = Field(default_factory=Noise, description="sensor noise, off by default")
    timeout: Positive = Field(default=DEFAULT_TIMEOUT, description="s of sim time")
    expect: Expect | None = None


TOP_LEVEL_KEYS = tuple(MissionFile.model_fields)
SUBSTITUTED_SECTIONS = ("start", "tree", "events", "noise", "timeout", "expect")
"""Top-level sections where ``${param}`` is replaced (subtrees use their own parameters)."""

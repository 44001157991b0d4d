"""The robots a mission may name, with the facts validation needs before any physics.

Figures are DESIGN §5 (TurtleBot3 Burger) and the bundled Panda scene
(``sim/worlds/panda_table.xml``: a table and a 5 cm cube named ``cube``).
"""

from __future__ import annotations

from dataclasses import dataclass

from baobab.behaviours.ports import ARM, BASE_CONTROLLERS, NAVIGATION, ROS_NODES, TELEOP


@dataclass(frozen=True)
class RobotInfo:
    """What a mission can ask of one robot.

    Attributes:
        name: the ``robot:`` value.
        description: one line for ``baobab list``.
        capabilities: capability names, e.g. ``navigation``.
        mobile: True for a base that drives on a 2D world's floor (needs ``world``/``start``).
        footprint_radius: radius of the base's footprint (m); goals closer than this to an
            obstacle are refused. 0 for fixed robots.
        max_linear_speed: forward speed limit (m/s); 0 for fixed robots.
        max_angular_speed: turn rate limit (rad/s); 0 for fixed robots.
        scenes: for fixed robots, the scene names ``world:`` may give (first = default).
        scene_objects: free objects of those scenes, by name (``relative_to:`` targets).
        has_lidar: True when the robot carries a 2D lidar (``noise: lidar_std`` applies).
    """

    name: str
    description: str
    capabilities: frozenset[str]
    mobile: bool
    footprint_radius: float = 0.0
    max_linear_speed: float = 0.0
    max_angular_speed: float = 0.0
    scenes: tuple[str, ...] = ()
    scene_objects: tuple[str, ...] = ()
    has_lidar: bool = False

    @property
    def metrics(self) -> tuple[str, ...]:
        """The numeric metrics of this robot's runs (what ``expect: metrics:`` may bound)."""
        if self.mobile:
            return MOBILE_METRICS
        objects = self.scene_objects
        per_object = tuple(f"{name}_max_lift" for name in objects)
        placement = ("placement_error",) if objects else ()
        return ARM_METRICS + per_object + placement + ("max_tracking_error",)

    @property
    def structured_metrics(self) -> tuple[str, ...]:
        """The metrics of this robot's runs whose values are not numbers (poses, names)."""
        if self.mobile:
            return MOBILE_STRUCTURED_METRICS
        return ("contact_objects", *(f"{name}_final_position" for name in self.scene_objects))

    def describe_capabilities(self) -> str:
        """``arm`` or ``base_controllers, navigation, teleop``."""
        return ", ".join(sorted(self.capabilities))


MOBILE_METRICS = (
    "sim_time",
    "path_length",
    "straight_line_distance",
    "min_clearance",
    "contacts",
    "number_of_recoveries",
    "planned_path_length",
    "costmap_clears",
    "replans",
    "teleop_min_scaling",
    "teleop_slowed_cycles",
    "teleop_max_speed",
    "teleop_costmap_clears",
)
"""The numeric metrics of a mobile robot's run (``baobab.missions.robots_wiring.MobileRig``)."""
MOBILE_STRUCTURED_METRICS = ("contact_objects", "start_pose", "final_pose", "visited")
ARM_METRICS = ("sim_time", "tcp_path_length", "object_max_lift", "contacts")
"""The numeric metrics of every arm run; each scene object adds ``<object>_max_lift``, and
``placement_error`` and ``max_tracking_error`` follow (``ArmRig``)."""

ROBOTS: dict[str, RobotInfo] = {
    "turtlebot3": RobotInfo(
        name="turtlebot3",
        description="TurtleBot3 Burger: differential drive with a 360-beam 2D lidar",
        capabilities=frozenset({NAVIGATION, BASE_CONTROLLERS, TELEOP, ROS_NODES}),
        mobile=True,
        footprint_radius=0.105,
        max_linear_speed=0.22,
        max_angular_speed=2.84,
        has_lidar=True,
    ),
    "panda": RobotInfo(
        name="panda",
        description="Franka Panda arm with a parallel gripper, Cartesian impedance control",
        capabilities=frozenset({ARM, ROS_NODES}),
        mobile=False,
        scenes=("panda_table",),
        scene_objects=("cube",),
    ),
}

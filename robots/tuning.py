"""The settings a mobile robot's facts decide: navigation, teleop and fault-monitor defaults.

Nav2's defaults are for no robot in particular; a robot's configuration scales the few that
depend on it. :func:`tune` does the same from a robot's facts, with these rules (Nav2's
defaults where a rule keeps them):

- costmaps: the footprint as Nav2 uses it (a radius as given, a polygon padded by Nav2's
  ``footprint_padding`` 0.01 m); ``inflation_radius`` Nav2's 0.55 m, or the circumscribed
  radius plus two 0.05 m cells when that is larger (Nav2 warns when it is smaller);
  ``cost_scaling_factor`` 3.0;
- Regulated Pure Pursuit: ``desired_linear_vel`` and ``max_angular_vel`` the robot's limits;
  ``regulated_linear_scaling_min_speed`` Nav2's 0.25 m/s of 0.5 m/s scaled like the top speed;
  ``rotate_to_heading_angular_vel`` Nav2's 1.8 rad/s, or the yaw-rate limit if lower;
  ``max_angular_accel`` the robot's;
- behaviours: Spin's 1.0 and 0.4 rad/s within the yaw-rate limit, its 3.2 rad/s^2 and the
  drives' 2.5 m/s^2 the robot's accelerations; BackUp's 0.10 m/s floor within the top speed;
- controller server: goal 0.25 m / 0.25 rad; progress 0.5 m in 10 s, or a quarter of what the
  robot drives in 10 s when that is less;
- keyboard teleop: the seed's 0.25 m/s and 1.2 rad/s, within the limits;
- fault monitors: a pose may not move faster than 3 times the limits (at least 2 m/s and
  10 rad/s, for contact jitter), and a lidar that misses 5 scan periods has timed out.

Plain numbers, no navigation import: ``baobab.nav`` turns them into its parameter records.
"""

from __future__ import annotations

from dataclasses import dataclass

from baobab.robots.diff_drive.facts import DiffDriveFacts
from baobab.robots.footprint import NAV2_FOOTPRINT_PADDING, Footprint

NAV2_INFLATION_RADIUS = 0.55
"""m."""
INFLATION_MARGIN = 0.10
"""m beyond the circumscribed radius that the inflation reaches at least (two 0.05 m cells)."""
NAV2_ROTATE_TO_HEADING_SPEED = 1.8
"""rad/s."""
NAV2_MIN_SPEED_SHARE = 0.25 / 0.5
"""``regulated_linear_scaling_min_speed`` over ``desired_linear_vel`` in Nav2's defaults."""
NAV2_SPIN_SPEEDS = (0.4, 1.0)
"""Spin's ``min_rotational_vel`` and ``max_rotational_vel`` (rad/s)."""
NAV2_BACKUP_MIN_SPEED = 0.10
"""The drives' ``minimum_speed`` (m/s)."""
NAV2_PROGRESS = (0.5, 10.0)
"""``required_movement_radius`` (m) and ``movement_time_allowance`` (s)."""
SEED_TELEOP_SPEEDS = (0.25, 1.2)
"""The keyboard teleop's m/s and rad/s (seed §5)."""
PLAUSIBLE_FACTOR = 3.0
"""How many times its limits a robot may seem to move between two fault checks."""
MIN_PLAUSIBLE = (2.0, 10.0)
"""m/s and rad/s below which no jump counts as a displacement."""
SCAN_PERIODS_TO_TIMEOUT = 5
"""Lidar periods without a scan before SENSOR_TIMEOUT."""


@dataclass(frozen=True)
class RobotTuning:
    """A mobile robot's navigation, teleop and fault-monitor settings (SI units).

    Attributes:
        footprint: the costmaps' footprint (a polygon already padded).
        inflation_radius: m.
        cost_scaling_factor: 1/m.
        max_linear_speed: the controller's top speed (m/s).
        max_angular_speed: the controller's yaw-rate limit (rad/s).
        min_regulated_speed: the slowest the controller's regulation goes (m/s).
        rotate_to_heading_speed: rad/s.
        max_angular_accel: rad/s^2.
        max_linear_accel: m/s^2.
        spin_speeds: Spin's slowest and fastest turn (rad/s).
        backup_min_speed: m/s.
        goal_tolerances: m and rad.
        progress: the progress checker's radius (m) and time (s).
        teleop_speeds: m/s and rad/s.
        plausible_speeds: m/s and rad/s beyond which a pose jump is a displacement.
        scan_timeout: s.
    """

    footprint: Footprint
    inflation_radius: float
    cost_scaling_factor: float
    max_linear_speed: float
    max_angular_speed: float
    min_regulated_speed: float
    rotate_to_heading_speed: float
    max_angular_accel: float
    max_linear_accel: float
    spin_speeds: tuple[float, float]
    backup_min_speed: float
    goal_tolerances: tuple[float, float]
    progress: tuple[float, float]
    teleop_speeds: tuple[float, float]
    plausible_speeds: tuple[float, float]
    scan_timeout: float


def tune(facts: DiffDriveFacts) -> RobotTuning:
    """The settings ``facts`` decide (the rules are in the module docstring)."""
    footprint = facts.footprint.padded(NAV2_FOOTPRINT_PADDING)
    v_max, w_max = facts.max_linear_speed, facts.max_angular_speed
    radius, allowance = NAV2_PROGRESS
    return RobotTuning(
        footprint=footprint,
        inflation_radius=max(
            NAV2_INFLATION_RADIUS, footprint.circumscribed_radius + INFLATION_MARGIN
        ),
        cost_scaling_factor=3.0,
        max_linear_speed=v_max,
        max_angular_speed=w_max,
        min_regulated_speed=v_max * NAV2_MIN_SPEED_SHARE,
        rotate_to_heading_speed=min(NAV2_ROTATE_TO_HEADING_SPEED, w_max),
        max_angular_accel=facts.max_angular_accel,
        max_linear_accel=facts.max_linear_accel,
        spin_speeds=(min(NAV2_SPIN_SPEEDS[0], w_max), min(NAV2_SPIN_SPEEDS[1], w_max)),
        backup_min_speed=min(NAV2_BACKUP_MIN_SPEED, v_max),
        goal_tolerances=(0.25, 0.25),
        progress=(min(radius, 0.25 * v_max * allowance), allowance),
        teleop_speeds=(min(SEED_TELEOP_SPEEDS[0], v_max), min(SEED_TELEOP_SPEEDS[1], w_max)),
        plausible_speeds=(
            max(MIN_PLAUSIBLE[0], PLAUSIBLE_FACTOR * v_max),
            max(MIN_PLAUSIBLE[1], PLAUSIBLE_FACTOR * w_max),
        ),
        scan_timeout=SCAN_PERIODS_TO_TIMEOUT / facts.lidar.rate,
    )

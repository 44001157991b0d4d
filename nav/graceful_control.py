"""Nav2's graceful control law: the smooth pose-following law of the docking and following
servers (``nav2_graceful_controller::SmoothControlLaw``).

The law steers a unicycle onto a target pose along a smooth spiral (Park and Kuipers, "A smooth
control law for graceful motion of differential wheeled mobile robots in 2D environments",
ICRA 2011). The target is seen in egocentric polar coordinates: ``r`` its distance, ``phi`` its
heading and ``delta`` the robot's, both against the line of sight. The path curvature is

    kappa = -1/r * (k_delta * (delta - atan(-k_phi * phi))
                    + (1 + k_phi / (1 + (k_phi * phi)^2)) * sin(delta))

and the forward speed ``v_max / (1 + beta * |kappa|^lambda)``, capped by ``v_max * r /
slowdown_radius`` near the target and held within [``v_min``, ``v_max``]; the turn rate
``kappa * v`` is bounded by ``w_max``, the speed then scaled down to keep the curvature.
Backwards, the line of sight turns by pi and the curvature and speed change sign.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baobab.sim.world import Pose2D


@dataclass(frozen=True)
class GracefulParams:
    """The law's gains and limits, Nav2's defaults (``controller.*`` of the docking server)."""

    k_phi: float = 3.0
    """Gain of the target heading error (-)."""
    k_delta: float = 2.0
    """Gain of the robot heading error (-)."""
    beta: float = 0.4
    """How much curvature slows the robot (-)."""
    lambda_: float = 2.0
    """How sharply it does (-): Nav2's ``lambda``."""
    v_linear_min: float = 0.1
    """Slowest forward speed (m/s) away from the target."""
    v_linear_max: float = 0.25
    """Fastest forward speed (m/s)."""
    v_angular_max: float = 0.75
    """Fastest turn (rad/s)."""
    v_angular_min: float = 0.15
    """Slowest turn (rad/s) when rotating in place towards a heading."""
    slowdown_radius: float = 0.25
    """Distance to the target (m) within which the speed falls towards zero."""


def polar_coordinates(
    target: Pose2D, current: Pose2D, backward: bool = False
) -> tuple[float, float, float]:
    """``(r, phi, delta)`` of ``target`` seen from ``current``: metres, radians, radians."""
    dx, dy = target.x - current.x, target.y - current.y
    line_of_sight = math.atan2(-dy, dx) + (math.pi if backward else 0.0)
    return (
        math.hypot(dx, dy),
        math.remainder(target.yaw + line_of_sight, math.tau),
        math.remainder(current.yaw + line_of_sight, math.tau),
    )


def curvature(params: GracefulParams, r: float, phi: float, delta: float) -> float:
    """The law's path curvature (1/m) for the polar coordinates of the target."""
    if r < 1e-9:
        return 0.0
    proportional = params.k_delta * (delta - math.atan(-params.k_phi * phi))
    feedback = (1.0 + params.k_phi / (1.0 + (params.k_phi * phi) ** 2)) * math.sin(delta)
    return -1.0 / r * (proportional + feedback)


def velocity(
    params: GracefulParams, target: Pose2D, current: Pose2D, backward: bool = False
) -> tuple[float, float]:
    """The command towards ``target`` from ``current``: speed (m/s), turn rate (rad/s)."""
    r, phi, delta = polar_coordinates(target, current, backward)
    kappa = curvature(params, r, phi, delta)
    if backward:
        kappa = -kappa
    speed = params.v_linear_max / (1.0 + params.beta * abs(kappa) ** params.lambda_)
    speed = min(params.v_linear_max * r / params.slowdown_radius, speed)
    speed = min(max(speed, params.v_linear_min), params.v_linear_max)
    if backward:
        speed = -speed
    turn = kappa * speed
    bounded = min(max(turn, -params.v_angular_max), params.v_angular_max)
    if kappa != 0.0:
        speed = bounded / kappa
    return speed, bounded


def rotate_towards(params: GracefulParams, angle: float) -> float:
    """Turn rate (rad/s) that rotates in place by ``angle`` (rad): ``angle * w_max``, at least
    ``v_angular_min`` and at most ``v_angular_max`` (the docking controller's
    ``rotateToTarget``)."""
    if angle == 0.0:
        return 0.0
    rate = min(max(abs(angle) * params.v_angular_max, params.v_angular_min), params.v_angular_max)
    return math.copysign(rate, angle)


def projected_poses(
    params: GracefulParams,
    target: Pose2D,
    start: Pose2D,
    *,
    backward: bool = False,
    horizon: float = 5.0,
    dt: float = 0.1,
) -> np.ndarray:
    """Where the law drives from ``start`` in ``dt`` steps (Euler, as Nav2's
    ``calculateNextPose``), until within 1 cm of ``target`` or ``horizon`` s: ``(K, 3)`` rows
    of x, y (m) and yaw (rad), ``start`` excluded."""
    rows: list[tuple[float, float, float]] = []
    pose = start
    for _ in range(math.ceil(horizon / dt)):
        speed, turn = velocity(params, target, pose, backward)
        yaw = pose.yaw + turn * dt
        pose = Pose2D(
            x=pose.x + speed * dt * math.cos(pose.yaw),
            y=pose.y + speed * dt * math.sin(pose.yaw),
            yaw=yaw,
        )
        rows.append((pose.x, pose.y, pose.yaw))
        if math.hypot(target.x - pose.x, target.y - pose.y) <= 1e-2:
            break
    return np.array(rows, dtype=float).reshape(-1, 3)

"""Bring a robot up for node code: its simulation, on its topics, in a runtime.

What a robot's Gazebo launch or an arm's bringup launch do for a course's nodes:
:func:`bring_up` builds the world with the robot (any mobile robot of the registry or a robot
file, or an arm in its own scene), starts its controllers, puts it on ROS topics
(:mod:`~baobab.nav.ros.sim_topics`) and returns the runtime to run nodes in.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from baobab.nav.navigator_robot import (
    ARM_MODELS,
    ROBOT_MODELS,
    NavigatorSetupError,
    SimulatedArm,
    SimulatedRobot,
    build_simulated_arm,
    build_simulated_robot,
    navigator_robot,
)
from baobab.nav.ros.runtime import RosRuntime
from baobab.nav.ros.sim_topics import ArmTopics, MobileRobotTopics
from baobab.robots.catalog import ROBOTS
from baobab.robots.robot_file import is_robot_path
from baobab.sim.world import Pose2D, World, load_world


@dataclass
class Bringup:
    """A robot on its topics: the runtime to run node code in, and the robot itself."""

    runtime: RosRuntime
    mobile: SimulatedRobot | None = None
    arm: SimulatedArm | None = None


def bring_up(
    robot: str,
    world: str | Path | World | None = None,
    *,
    seed: int = 0,
    start: Pose2D | None = None,
) -> Bringup:
    """``robot`` in ``world`` (a bundled name, a world file, a loaded world; an arm has its
    own scene), seeded with ``seed``, on its ROS topics.

    Raises:
        NavigatorSetupError: an unknown robot, a world an arm cannot use, a blocked start.
        WorldError: the world cannot be loaded.
    """
    if robot in ARM_MODELS:
        scene = ROBOTS[robot].scenes[0]
        if world not in (None, scene):
            raise NavigatorSetupError(
                f"the {robot} runs in its own scene '{scene}', not in world {world!r}"
            )
        arm = build_simulated_arm(robot, seed)
        runtime = RosRuntime(arm.sim)
        ArmTopics(runtime, arm)
        return Bringup(runtime, arm=arm)
    if robot not in ROBOT_MODELS and not is_robot_path(robot):
        known = ", ".join((*ROBOT_MODELS, *ARM_MODELS))
        raise NavigatorSetupError(
            f"unknown robot {robot!r}; the ROS runtime runs one of: {known}, or a robot file"
        )
    loaded = world if isinstance(world, World) else load_world(world or "walls")
    info = navigator_robot(robot)
    mobile = build_simulated_robot(info, loaded, start or loaded.spawn, seed)
    runtime = RosRuntime(mobile.sim)
    MobileRobotTopics(runtime, mobile)
    return Bringup(runtime, mobile=mobile)

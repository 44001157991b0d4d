"""Fault injection: what the mission's ``fault`` events do to the robot and its simulation.

Each fault acts through the robot's public API or named MuJoCo access, never raw indices:

- ``teleport``: :meth:`DiffDriveBase.teleport` puts the robot down at rest elsewhere (a
  kidnapped robot); odometry restarts there, as a wheel-odometry stack would not notice.
- ``lidar_dropout``: the scanner is silenced (:attr:`Lidar.silenced`), no scan arrives.
- ``lidar_noise``: the scanner's range noise is raised to ``std`` (m); the noise is drawn
  from the run's seeded generator, so the same seed gives the same burst.
- ``wheel_failure``: the wheel's velocity actuator loses its gain and bias (``gainprm``,
  ``biasprm`` of ``model.actuator(name)``): the motor gives no torque, the wheel turns freely.
- ``diverge``: a NaN generalised force on the robot's root joint
  (``data.joint(name).qfrc_applied``). The next physics step finds the accelerations
  non-finite, as a real blow-up would; the state the controllers read at that step is still
  finite, so only the physics check reports it.

A lasting fault (dropout, noise, wheel) ends after its event's ``duration``. Faults may
overlap: the lidar stays silent and a wheel dead while any of their faults lasts, and
overlapping noise adds up as independent noise does (standard deviations in quadrature, on
top of the mission's own ``noise: lidar_std``).
"""

from __future__ import annotations

import math
from collections import Counter
from typing import Any

import numpy as np

from baobab.missions.language.models import FaultEvent
from baobab.missions.run.rig import ArmRig, MobileRig, Rig
from baobab.robots.diff_drive.robot import MobileRobot
from baobab.sim.errors import BaobabError
from baobab.sim.simulation import Simulation
from baobab.sim.world import Pose2D


class FaultError(BaobabError):
    """A fault cannot be injected into this robot (e.g. a wheel fault into an arm)."""


class FaultInjector:
    """Injects and ends the faults of a run.

    Args:
        sim: the run's simulation.
        diverge_joint: the joint whose generalised force a ``diverge`` fault makes NaN
            (the robot's root joint).
        robot: the mobile robot, for the teleport, lidar and wheel faults; None for an arm.
    """

    def __init__(
        self, sim: Simulation, diverge_joint: str, robot: MobileRobot | None = None
    ) -> None:
        self.sim = sim
        self.robot = robot
        self.diverge_joint = diverge_joint
        self._base_noise = 0.0 if robot is None else robot.lidar.noise_std
        self._noise_bursts: list[float] = []
        self._dropouts = 0
        self._dead_wheels: Counter[str] = Counter()
        self._healthy: dict[str, tuple[np.ndarray, np.ndarray]] = {}

    def start(self, event: FaultEvent) -> dict[str, Any]:
        """Inject ``event``'s fault now; returns the trace fields describing it.

        Raises:
            FaultError: the robot has nothing this fault can act on.
        """
        spec = event.fault
        if spec.diverge is not None:
            self.sim.data.joint(self.diverge_joint).qfrc_applied[0] = math.nan
            return {"joint": self.diverge_joint}
        robot = self._mobile(spec.kind)
        if spec.teleport is not None:
            target = Pose2D(x=spec.teleport.x, y=spec.teleport.y, yaw=spec.teleport.yaw)
            robot.base.teleport(target)
            return {"x": target.x, "y": target.y, "yaw": target.yaw}
        if spec.lidar_dropout is not None:
            self._dropouts += 1
            robot.lidar.silenced = True
            return {}
        if spec.lidar_noise is not None:
            self._noise_bursts.append(spec.lidar_noise.std)
            robot.lidar.noise_std = math.hypot(self._base_noise, *self._noise_bursts)
            return {"std": spec.lidar_noise.std, "lidar_std": robot.lidar.noise_std}
        if spec.wheel_failure is not None:
            name = self._wheel_actuator(robot, spec.wheel_failure.wheel)
            actuator = self.sim.model.actuator(name)
            if not self._dead_wheels[name]:
                self._healthy[name] = (actuator.gainprm.copy(), actuator.biasprm.copy())
                actuator.gainprm[:] = 0.0
                actuator.biasprm[:] = 0.0
            self._dead_wheels[name] += 1
            return {"actuator": name}
        raise FaultError(f"unknown fault '{spec.kind}'")  # pragma: no cover - schema has no more

    def end(self, event: FaultEvent) -> None:
        """End ``event``'s lasting fault: restore what :meth:`start` changed."""
        spec = event.fault
        robot = self._mobile(spec.kind)
        if spec.lidar_dropout is not None:
            self._dropouts -= 1
            robot.lidar.silenced = self._dropouts > 0
        elif spec.lidar_noise is not None:
            self._noise_bursts.remove(spec.lidar_noise.std)
            robot.lidar.noise_std = math.hypot(self._base_noise, *self._noise_bursts)
        elif spec.wheel_failure is not None:
            name = self._wheel_actuator(robot, spec.wheel_failure.wheel)
            self._dead_wheels[name] -= 1
            if not self._dead_wheels[name]:
                gain, bias = self._healthy.pop(name)
                actuator = self.sim.model.actuator(name)
                actuator.gainprm[:] = gain
                actuator.biasprm[:] = bias

    def _mobile(self, kind: str) -> MobileRobot:
        if self.robot is None:
            raise FaultError(f"a {kind} fault needs a mobile robot")
        return self.robot

    @staticmethod
    def _wheel_actuator(robot: MobileRobot, wheel: str) -> str:
        left, right = robot.names.wheel_actuators
        return left if wheel == "left" else right


def fault_injector(rig: Rig) -> FaultInjector:
    """The injector for ``rig``'s robot: a mobile robot takes every fault, an arm ``diverge``
    (on the joint its runtime names)."""
    if isinstance(rig, MobileRig):
        robot = rig.robot
        return FaultInjector(rig.sim, robot.names.root_joint, robot)
    if not isinstance(rig, ArmRig):  # pragma: no cover - every rig is one of the two
        raise FaultError(f"no faults for {type(rig).__name__}")
    return FaultInjector(rig.sim, rig.runtime.ROOT_JOINT)

"""What a recording of a run holds: the sim callbacks that log a robot's topics.

Every callback only reads the simulation, so a recorded run is the same run (same trace
digest) as an unrecorded one. Rates (sim time), following the topics Nav2 and the Cartesian
impedance controllers of ROS arms publish:

- a mobile robot: ``/tf`` (map -> odom -> base_link), ``/robot_pose`` and the followed-path trail
  at 20 Hz, each new navigation plan on ``/plan`` (looked at 20 Hz), every scan on ``/scan``
  (the lidar's rate), the robot's geoms and its footprint (the outline the navigation stack
  checks, in ``base_link``) on ``/robot/scene`` at 5 Hz, and at 1 Hz the global
  costmap, ``/followed_path`` and the world scene (obstacles, spawned obstacles, named
  locations; republished so that a live client that joins late sees it). On a map: ``/map``
  and the filter masks (``/keepout_filter_mask``, ``/speed_filter_mask``) as Grids of their
  occupancy values (int8, -1 unknown) at the start and every :data:`MAP_PERIOD`, latched;
  each new speed limit on ``/speed_limit`` (looked at 20 Hz).
- an arm: the three ``/cartesian_impedance/*`` poses (TCP, set-point, filtered reference, in
  the arm's base frame) and ``/joint_states`` at 100 Hz, the scene (arm, table, objects) at
  20 Hz, and the transform world -> base frame on ``/tf_static`` at 1 Hz: latched for live
  viewers that join late, and never more than a second away for a viewer that opens the file
  anywhere.

``/tf`` is what a perfectly localised Nav2 robot publishes: odom -> base_link is the wheel
odometry, drift included, and map -> odom corrects it (ground truth composed with the inverse
of the odometry), so base_link lands on the ground-truth pose where the robot model and the
scan are drawn.

The topic names are :mod:`baobab.missions.run.recording_topics`'. This module imports foxglove
(through :mod:`baobab.sim.recording`): it is imported only when a run records.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from baobab.missions.run.recording_topics import SPEED_LIMIT_SCHEMA, Topics
from baobab.missions.run.rig import ArmRig, MobileRig
from baobab.sim.lidar import LaserScan
from baobab.sim.recording import Recorder, Trail, Transform
from baobab.sim.scene_primitives import Entity, GeomScene, Outline, location_entities
from baobab.sim.simulation import PeriodicHandle
from baobab.sim.world import Pose2D

MOBILE_FAST_PERIOD = 0.05
"""/tf, /robot_pose, trail and new plans (s): 20 Hz."""
ROBOT_SCENE_PERIOD = 0.2
"""/robot/scene (s): 5 Hz."""
SLOW_PERIOD = 1.0
"""Costmap, followed path, world scene, the arm's base transform (s): 1 Hz."""
MAP_PERIOD = 10.0
"""The map and the filter masks (s): they do not change, and a big map is megabytes."""
ARM_STATE_PERIOD = 0.01
"""Impedance poses and joint states (s): 100 Hz."""
ARM_SCENE_PERIOD = 0.05
"""The arm's scene (s): 20 Hz."""
FOOTPRINT_HEIGHT = 0.005
"""m above the floor the footprint's outline is drawn at."""
FOOTPRINT_COLOUR = (0.95, 0.55, 0.10, 1.0)
WORLD_SCENE_GROUPS = (1, 2)
"""Static and movable obstacles."""
ROBOT_SCENE_GROUPS = (3,)


class Streams:
    """Sim callbacks feeding a recorder; :meth:`close` stops them."""

    def __init__(self) -> None:
        self._handles: list[PeriodicHandle] = []

    def close(self) -> None:
        """Stop logging (idempotent)."""
        for handle in self._handles:
            handle.cancel()
        self._handles.clear()


class MobileStreams(Streams):
    """Logs a mobile robot's run (see the module docstring).

    Args:
        recorder: where the messages go.
        rig: the mobile rig (robot, world, locations, navigation server if any).
    """

    def __init__(self, recorder: Recorder, rig: MobileRig) -> None:
        super().__init__()
        self.recorder = recorder
        self.rig = rig
        self.base = rig.robot.base
        self.trail = Trail()
        self._plan: object = None
        model = rig.sim.model
        self._world_scene = GeomScene(model, groups=WORLD_SCENE_GROUPS)
        self._robot_scene = GeomScene(model, groups=ROBOT_SCENE_GROUPS)
        self._locations = {name: rig.mission.locations[name].pose2d() for name in rig.locations}
        footprint = rig.info.tuning.footprint  # Nav2's published_footprint: padded
        outline = tuple((x, y, FOOTPRINT_HEIGHT) for x, y in footprint.outline)
        self._footprint = Entity(
            "footprint", "base_link", outlines=(Outline(outline, FOOTPRINT_COLOUR),)
        )
        sim = rig.sim
        self._speed_limit: object = None
        self._handles = [
            sim.every(MOBILE_FAST_PERIOD, self._fast, name="record pose"),
            sim.every(ROBOT_SCENE_PERIOD, self._robot, name="record robot scene"),
            sim.every(SLOW_PERIOD, self._slow, name="record map"),
        ]
        masks = rig.world.masks
        self._grids = [
            (topic, grid)
            for topic, grid in (
                (Topics.MAP, masks.grid),
                (Topics.KEEPOUT_MASK, masks.keepout),
                (Topics.SPEED_MASK, masks.speed),
            )
            if grid is not None
        ]
        if self._grids:
            self._handles.append(sim.every(MAP_PERIOD, self._maps, name="record map files"))
        rig.robot.lidar.subscribe(self._scan)

    def close(self) -> None:
        """Stop logging (idempotent)."""
        super().close()
        self.rig.robot.lidar.unsubscribe(self._scan)

    def _scan(self, scan: LaserScan) -> None:
        self.recorder.log_scan(Topics.SCAN, scan, z=self.rig.robot.facts.lidar.z)

    def _fast(self, t: float) -> None:
        base, recorder = self.base, self.recorder
        pose, odometry = base.pose(), base.odometry.pose
        recorder.log_transforms(
            Topics.TF,
            t,
            [
                Transform.planar("map", "odom", map_to_odom(pose, odometry)),
                Transform.planar("odom", "base_link", odometry),
            ],
        )
        recorder.log_planar_pose(Topics.ROBOT_POSE, t, pose)
        self.trail.add(pose)
        navigation = self.rig.navigation
        path = None if navigation is None else navigation.current_path
        if path is not self._plan:
            self._plan = path
            poses = np.empty((0, 3)) if path is None else path.poses
            recorder.log_path(Topics.PLAN, t, poses)
        self._log_speed_limit(t)

    def _maps(self, t: float) -> None:
        for topic, grid in self._grids:
            self.recorder.log_grid(
                topic,
                t,
                grid.data,
                resolution=grid.resolution,
                origin=grid.origin,
                field="occupancy",
                latched=True,
            )

    def _log_speed_limit(self, t: float) -> None:
        navigation = self.rig.navigation
        speed_filter = None if navigation is None else navigation.speed_filter
        limit = None if speed_filter is None else speed_filter.current
        if limit is None or limit is self._speed_limit:
            return
        self._speed_limit = limit
        payload = {"percentage": limit.percentage, "speed_limit": limit.speed_limit}
        self.recorder.log_json(Topics.SPEED_LIMIT, t, payload, schema=SPEED_LIMIT_SCHEMA)

    def _robot(self, t: float) -> None:
        data = self.rig.sim.data
        entities = [*self._robot_scene.entities(data), self._footprint]
        self.recorder.log_scene(Topics.ROBOT_SCENE, t, entities)

    def _slow(self, t: float) -> None:
        recorder = self.recorder
        navigation = self.rig.navigation
        if navigation is not None:
            costmap = navigation.global_costmap()
            recorder.log_grid(
                Topics.GLOBAL_COSTMAP,
                t,
                costmap.data,
                resolution=costmap.resolution,
                origin=costmap.origin,
            )
        recorder.log_path(Topics.FOLLOWED_PATH, t, self.trail.poses)
        entities = self._world_scene.entities(self.rig.sim.data)
        entities += location_entities(self._locations)
        recorder.log_scene(Topics.WORLD_SCENE, t, entities, replace_all=True)


class ArmStreams(Streams):
    """Logs an arm's run (see the module docstring).

    Args:
        recorder: where the messages go.
        rig: the arm rig (sim, arm server and the runtime that names its frames and joints).
    """

    def __init__(self, recorder: Recorder, rig: ArmRig) -> None:
        super().__init__()
        self.recorder = recorder
        self.server = rig.server
        sim = rig.sim
        self._data = sim.data
        self.base_frame = rig.runtime.BASE_FRAME
        self.joint_names = list(rig.runtime.JOINT_NAMES)
        self._joints = [sim.data.joint(name) for name in self.joint_names]
        self._scene = GeomScene(sim.model, frame_id="world")
        self._base = Transform(
            "world",
            self.base_frame,
            _triple(self.server.base_position),
            _quad(self.server.base_rotation.as_quat()),
        )
        self._handles = [
            sim.every(ARM_STATE_PERIOD, self._state, name="record arm state"),
            sim.every(ARM_SCENE_PERIOD, self._scene_update, name="record arm scene"),
            sim.every(SLOW_PERIOD, self._base_transform, name="record tf_static"),
        ]

    def _base_transform(self, t: float) -> None:
        self.recorder.log_static_transforms(Topics.TF_STATIC, t, [self._base])

    def _state(self, t: float) -> None:
        recorder, controller, frame = self.recorder, self.server.controller, self.base_frame
        position, rotation = controller.tcp
        recorder.log_pose(
            Topics.CURRENT_POSE,
            t,
            position,
            Rotation.from_matrix(rotation).as_quat(),
            frame_id=frame,
        )
        recorder.log_pose(Topics.DESIRED_POSE, t, *controller.target, frame_id=frame)
        recorder.log_pose(Topics.FILT_REF_POSE, t, *controller.reference, frame_id=frame)
        recorder.log_joint_states(
            Topics.JOINT_STATES,
            t,
            self.joint_names,
            [float(joint.qpos[0]) for joint in self._joints],
            [float(joint.qvel[0]) for joint in self._joints],
        )

    def _scene_update(self, t: float) -> None:
        self.recorder.log_scene(Topics.ARM_SCENE, t, self._scene.entities(self._data))


def map_to_odom(truth: Pose2D, odometry: Pose2D) -> Pose2D:
    """Where the odom frame lies in the map frame when ``odometry`` (odom frame) is at ``truth``.

    The transform a perfect localisation publishes: ``truth`` composed with the inverse of
    ``odometry`` (m, rad).
    """
    yaw = math.remainder(truth.yaw - odometry.yaw, math.tau)
    cos, sin = math.cos(yaw), math.sin(yaw)
    return Pose2D(
        x=truth.x - (cos * odometry.x - sin * odometry.y),
        y=truth.y - (sin * odometry.x + cos * odometry.y),
        yaw=yaw,
    )


def _triple(values: np.ndarray) -> tuple[float, float, float]:
    return (float(values[0]), float(values[1]), float(values[2]))


def _quad(values: np.ndarray) -> tuple[float, float, float, float]:
    return (float(values[0]), float(values[1]), float(values[2]), float(values[3]))

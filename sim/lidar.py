"""2D lidar: the LaserScan message shape and a ray-cast planar scanner (LDS-01 by default).

The scanner casts its beams from a site with the compiled caster of
:mod:`baobab.sim.lidar_kernel`, which returns ``mujoco.mj_multiRay``'s ranges bit for bit
(a 360-beam scan costs a few tens of microseconds); a noisy scanner, or one that sees mesh,
height-field or sdf geoms, calls ``mj_multiRay`` itself. Geoms of the robot carrying it (geom
group ``ROBOT_GROUP``) are invisible to it; the floor is not hit by horizontal beams.

Range conventions (as the LDS-01 driver reports them): a beam that hits nothing, hits beyond
``range_max``, or hits closer than ``range_min`` reads ``inf``. The LDS-01 cannot measure below
its minimum range and its driver reports those returns as no return; reporting them as
``inf`` (not as ``range_min``) keeps a consumer from mistaking a blind spot for an obstacle at
12 cm, and lets ``numpy.isfinite`` select the valid returns.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import mujoco
import numpy as np

from baobab.sim.builder import ROBOT_GROUP
from baobab.sim.lidar_kernel import FAN, Fan, fan_directions, ranges_from_hits, scan_fan
from baobab.sim.mujoco_native import geom_arrays
from baobab.sim.records import record
from baobab.sim.simulation import PeriodicHandle, Simulation
from baobab.sim.world import Pose2D

SCAN = np.dtype(
    [
        ("x", np.float64),  # the sensor's map-frame pose when the scan was taken (m)
        ("y", np.float64),  # m
        ("yaw", np.float64),  # rad
        ("angle_min", np.float64),  # rad, sensor frame
        ("angle_increment", np.float64),  # rad
        ("range_min", np.float64),  # m
        ("range_max", np.float64),  # m
    ]
)
"""A :class:`LaserScan`'s figures as compiled kernels read them (:meth:`LaserScan.pack`); the
ranges travel beside it as their own array."""


@dataclass(frozen=True)
class LaserScan:
    """One planar scan, shaped like ``sensor_msgs/LaserScan``.

    Beam ``i`` points at ``angle_min + i * angle_increment`` (rad, counter-clockwise, 0 ahead)
    in the sensor frame. ``ranges`` (m) holds ``inf`` where nothing was hit within
    ``range_max``. ``sensor_pose`` is the sensor's planar pose in the map frame when the scan
    was taken (the sim localises perfectly), and ``stamp`` is the sim time (s).
    """

    stamp: float
    frame_id: str
    angle_min: float
    angle_max: float
    angle_increment: float
    range_min: float
    range_max: float
    ranges: np.ndarray
    sensor_pose: Pose2D

    @property
    def angles(self) -> np.ndarray:
        """Beam angles (rad) in the sensor frame."""
        return self.angle_min + self.angle_increment * np.arange(len(self.ranges))

    def pack(self) -> np.ndarray:
        """The scan's figures and sensor pose as a :data:`SCAN` record; read only (made once:
        both costmaps mark the same scan)."""
        return self._record

    @cached_property
    def _record(self) -> np.ndarray:
        pose = self.sensor_pose
        return record(SCAN, self, x=pose.x, y=pose.y, yaw=pose.yaw)


ScanSubscriber = Callable[[LaserScan], None]
"""Called with every new scan, in subscription order."""


class Lidar:
    """A planar scanning lidar on a site of the model, running as a periodic sim callback.

    Beams lie in the site's x-y plane and follow the site's full 3D orientation, so a robot
    that pitches sees the floor or over a wall as a real scanner would. The first scan is taken
    at once (at the current sim time); later ones every ``1 / rate`` seconds.

    Args:
        sim: the simulation; the scanner registers itself with :meth:`Simulation.every`.
        site: name of the site at the scan origin (x forward, z up).
        rate: scans per second (Hz); ``1 / rate`` must be a multiple of the physics step.
        beams: number of beams over the full turn ``[0, 2 pi)``.
        range_min: nearer returns read ``inf`` (m).
        range_max: farther returns read ``inf`` (m).
        noise_std: standard deviation of Gaussian range noise (m), drawn from ``sim.rng``.
        frame_id: the frame name written into each scan.
        exclude_group: geom group the beams pass through (the robot's own geoms).

    Raises:
        ValueError: for a non-positive beam count, rate or range, a negative noise, or a
            site the model does not have.
    """

    def __init__(
        self,
        sim: Simulation,
        site: str,
        *,
        rate: float = 5.0,
        beams: int = 360,
        range_min: float = 0.12,
        range_max: float = 3.5,
        noise_std: float = 0.0,
        frame_id: str = "base_scan",
        exclude_group: int = ROBOT_GROUP,
    ) -> None:
        if beams <= 0 or rate <= 0 or not 0 <= range_min < range_max or noise_std < 0:
            raise ValueError(
                f"lidar needs beams > 0, rate > 0, 0 <= range_min < range_max and "
                f"noise_std >= 0; got beams={beams}, rate={rate}, range_min={range_min}, "
                f"range_max={range_max}, noise_std={noise_std}"
            )
        if mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_SITE, site) < 0:
            raise ValueError(f"no site named '{site}' in the model")
        self._sim = sim
        self._site = sim.data.site(site)
        # Views made once: reading a MuJoCo array attribute builds a new view each time.
        self._site_xpos, self._site_xmat = self._site.xpos, self._site.xmat
        self._geom = geom_arrays(sim.model, sim.data)  # valid while sim lives
        self.site_name = site
        self.frame_id = frame_id
        self.beams = beams
        self.range_min = range_min
        self.range_max = range_max
        self.noise_std = noise_std
        self.angle_min = 0.0
        self.angle_increment = 2 * math.pi / beams
        self.angle_max = self.angle_min + (beams - 1) * self.angle_increment
        angles = (self.angle_min + self.angle_increment * np.arange(beams)).tolist()
        # The C library's cos and sin, as compiled code calls them (numpy has its own).
        local = [(math.cos(angle), math.sin(angle), 0.0) for angle in angles]
        geomgroup = np.ones(mujoco.mjNGROUP, dtype=np.uint8)
        geomgroup[exclude_group] = 0
        self._fan = Fan(
            local=np.array(local),
            geomgroup=geomgroup,
            origin=np.empty(3),
            directions=np.empty((beams, 3)),
            best=np.empty(beams),
        )
        self._settings = self.pack()
        self._geom_ids = np.empty(beams, dtype=np.int32)
        self._no_ranges = np.empty(0)
        self._subscribers: list[ScanSubscriber] = []
        self.latest: LaserScan | None = None
        """The most recent scan, or None before the first."""
        self.silenced = False
        """While True (a dropout fault) no scan is taken or published; ``latest`` grows old."""
        self.handle: PeriodicHandle = sim.every(1.0 / rate, self._on_tick, name=f"lidar {site}")

    def pack(self) -> np.ndarray:
        """The beam layout and range limits as the caster's :data:`~.lidar_kernel.FAN` record."""
        return record(FAN, self)

    def subscribe(self, subscriber: ScanSubscriber) -> None:
        """Call ``subscriber(scan)`` with every scan from now on."""
        self._subscribers.append(subscriber)

    def unsubscribe(self, subscriber: ScanSubscriber) -> None:
        """Stop calling ``subscriber`` (no-op if it was not subscribed)."""
        if subscriber in self._subscribers:
            self._subscribers.remove(subscriber)

    def scan(self) -> LaserScan:
        """Cast the beams from the site's current pose and return the scan (no callbacks)."""
        ranges, fan = self._no_ranges, self._fan
        if self.noise_std == 0:
            ranges = scan_fan(self._site_xpos, self._site_xmat, fan, self._settings, self._geom)
        if ranges.shape[0] == 0:  # noisy, or a geom type the compiled caster does not take
            np.copyto(fan.origin, self._site_xpos)
            fan_directions(self._site_xmat, fan.local, fan.directions)
            noise = self._no_ranges
            if self.noise_std > 0:
                noise = self._sim.rng.normal(0.0, self.noise_std, self.beams)
            self._multi_ray()
            ranges = ranges_from_hits(fan.best, noise, self.range_min, self.range_max)
        rotation = self._site_xmat
        return LaserScan(
            stamp=self._sim.time,
            frame_id=self.frame_id,
            angle_min=self.angle_min,
            angle_max=self.angle_max,
            angle_increment=self.angle_increment,
            range_min=self.range_min,
            range_max=self.range_max,
            ranges=ranges,
            sensor_pose=Pose2D(
                x=float(fan.origin[0]),
                y=float(fan.origin[1]),
                yaw=math.atan2(rotation[3], rotation[0]),
            ),
        )

    def _multi_ray(self) -> None:
        """Fill the fan's hit distances with ``mj_multiRay`` (-1 where a beam hits nothing)."""
        fan = self._fan
        mujoco.mj_multiRay(
            self._sim.model,
            self._sim.data,
            fan.origin,
            fan.directions.reshape(-1),
            fan.geomgroup,
            1,
            -1,
            self._geom_ids,
            fan.best,
            None,
            self.beams,
            self.range_max,
        )
        fan.best[self._geom_ids < 0] = -1.0

    def _on_tick(self, _time: float) -> None:
        if self.silenced:
            return
        scan = self.scan()
        self.latest = scan
        for subscriber in list(self._subscribers):
            subscriber(scan)

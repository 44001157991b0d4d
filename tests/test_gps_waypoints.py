"""GPS waypoints (issue 26): the local tangent plane against published reference points, the
datum in world files (located errors), the follow_gps_waypoints leaf's checks, and
FollowGPSWaypoints driving the robot to geographic waypoints in the lanes test world.

Reference points: IOGP Geomatics Guidance Note 7-2 (EPSG coordinate conversions), the worked
examples of method 9602 (geographic to geocentric) and method 9837 (geographic to
topocentric), both on WGS 84: the point 53 deg 48' 33.820" N, 2 deg 07' 46.380" E, 73.0 m is
at X 3771793.968, Y 140253.342, Z 5124304.349 m, and, seen from the topocentric origin
55 N, 5 E, 200 m, at U (east) -189013.869, V (north) -128642.040, W (up) -4220.171 m.
"""

from __future__ import annotations

import math
from pathlib import Path

import pymap3d
import pytest

from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.nav import BasicNavigator, TaskResult
from baobab.nav.errors import FollowGPSWaypointsError
from baobab.nav.gps_waypoints import GpsWaypointFollower
from baobab.nav.msgs import Quaternion
from baobab.nav.ros.geographic_msgs.msg import GeoPoint, GeoPose
from baobab.sim.datum import Datum
from baobab.sim.errors import WorldError
from baobab.sim.geodesy import GeodesyError, GeoWaypoint, MapDatum, geodetic_to_enu
from baobab.sim.world import load_world

WORLDS = Path(__file__).parent / "missions" / "worlds"
LANES = WORLDS / "lanes.yaml"

POINT = (53 + 48 / 60 + 33.820 / 3600, 2 + 7 / 60 + 46.380 / 3600, 73.0)
"""IOGP GN 7-2's example point (deg, deg, m)."""
GEOCENTRIC = (3771793.968, 140253.342, 5124304.349)
TOPOCENTRIC_ORIGIN = (55.0, 5.0, 200.0)
TOPOCENTRIC = (-189013.869, -128642.040, -4220.171)
MILLIMETRE = 0.001
METRES_PER_DEGREE = 111_000.0
"""Roughly, along a meridian: how a latitude error reads in metres."""


def test_the_conversions_meet_the_published_reference_points_to_the_millimetre() -> None:
    ecef = pymap3d.geodetic2ecef(*POINT)  # the library, on the published geocentric example
    assert all(abs(a - b) < MILLIMETRE for a, b in zip(ecef, GEOCENTRIC, strict=True)), ecef
    enu = geodetic_to_enu(*POINT, TOPOCENTRIC_ORIGIN)
    assert all(abs(a - b) < MILLIMETRE for a, b in zip(enu, TOPOCENTRIC, strict=True)), enu
    # The map frame at a datum with heading 0 is east, north: x = U, y = V.
    plane = MapDatum(Datum(latitude=55.0, longitude=5.0, altitude=200.0))
    x, y = plane.to_map(*POINT)
    assert abs(x - TOPOCENTRIC[0]) < MILLIMETRE and abs(y - TOPOCENTRIC[1]) < MILLIMETRE
    # And back: the published topocentric point is the published geographic one.
    back = pymap3d.enu2geodetic(*TOPOCENTRIC, *TOPOCENTRIC_ORIGIN)
    assert abs(back[0] - POINT[0]) * METRES_PER_DEGREE < MILLIMETRE
    assert abs(back[1] - POINT[1]) * METRES_PER_DEGREE * math.cos(math.radians(POINT[0])) < (
        MILLIMETRE
    )
    assert abs(back[2] - POINT[2]) < MILLIMETRE
    latitude, longitude, altitude = plane.to_geodetic(x, y)
    assert plane.to_map(latitude, longitude, altitude) == pytest.approx((x, y), abs=MILLIMETRE)


def test_the_datum_heading_turns_the_map_frame() -> None:
    """Heading pi/2: the map's x axis points north, its y axis west."""
    plane = MapDatum(Datum(latitude=52.0, longitude=4.0, heading=math.pi / 2))
    north = pymap3d.enu2geodetic(0.0, 100.0, 0.0, 52.0, 4.0, 0.0)
    x, y = plane.to_map(float(north[0]), float(north[1]))
    assert abs(x - 100.0) < MILLIMETRE and abs(y) < MILLIMETRE
    east = pymap3d.enu2geodetic(100.0, 0.0, 0.0, 52.0, 4.0, 0.0)
    x, y = plane.to_map(float(east[0]), float(east[1]))
    assert abs(x) < MILLIMETRE and abs(y + 100.0) < MILLIMETRE
    back = plane.to_geodetic(3.0, -4.0)
    assert plane.to_map(back[0], back[1], back[2]) == pytest.approx((3.0, -4.0), abs=1e-6)
    with pytest.raises(GeodesyError, match=r"latitude 91.0 is outside -90\.\.90"):
        plane.to_map(91.0, 4.0)
    with pytest.raises(GeodesyError, match="longitude nan"):
        plane.to_map(52.0, math.nan)


@pytest.mark.parametrize(
    ("datum", "message"),
    [
        ("{latitude: 95.0, longitude: 4.0}", "latitude"),
        ("{latitude: 52.0, longitude: -181}", "longitude"),
        ("{latitude: 52.0, longitude: 4.0, heading_deg: 400}", "heading_deg 400: expected"),
        ("{latitude: 52.0, longitude: 4.0, heading: 1, heading_deg: 5}", "either heading"),
        ("{latitude: 52.0, longitude: 4.0, altitude: 30000}", "altitude"),
        ("{latitude: 52.0}", "longitude"),
    ],
)
def test_a_datum_out_of_range_is_a_located_error(tmp_path: Path, datum: str, message: str) -> None:
    text = LANES.read_text()
    start = text.index("datum: ")
    line = text[:start].count("\n") + 1
    text = text[:start] + "datum: " + datum + text[text.index("\n", start) :]
    (tmp_path / "lanes.geojson").write_text((WORLDS / "lanes.geojson").read_text())
    path = tmp_path / "lanes.yaml"
    path.write_text(text)
    with pytest.raises(WorldError) as caught:
        load_world(path)
    assert str(caught.value).startswith(f"{path}:{line}:"), str(caught.value)
    assert message in str(caught.value)


def geo_pose(latitude: float, longitude: float, altitude: float = math.nan) -> GeoPose:
    return GeoPose(position=GeoPoint(latitude=latitude, longitude=longitude, altitude=altitude))


def test_waypoints_that_cannot_be_converted_are_skipped_or_stop_the_goal() -> None:
    world = load_world(LANES)
    assert world.datum is not None
    plane = MapDatum(world.datum)
    good = plane.to_geodetic(1.0, 2.0)
    poses = [geo_pose(good[0], good[1]), geo_pose(95.0, 4.0), geo_pose(good[0], good[1])]
    poses[2].orientation = Quaternion(x=0.0, y=0.0, z=0.0, w=0.0)
    follower = GpsWaypointFollower.__new__(GpsWaypointFollower)
    follower.map, follower.stop_on_failure = plane, False
    converted, failed = follower.to_map([*poses, GeoWaypoint(good[0], good[1], 0.5)])
    assert failed == [1, 2]
    assert [(round(p.x, 6), round(p.y, 6), p.yaw) for p in converted] == [
        (1.0, 2.0, 0.0),
        (1.0, 2.0, 0.5),
    ]
    follower.stop_on_failure = True
    assert follower.to_map(poses) == ([], [1])


def test_follow_gps_waypoints_drives_to_each_geographic_waypoint(lanes: BasicNavigator) -> None:
    world = lanes.world
    assert world.datum is not None
    plane = MapDatum(world.datum)
    targets = [(-1.5, 1.6, 0.0), (1.0, 1.6, 0.0)]
    poses = []
    for x, y, yaw in targets:
        latitude, longitude, _ = plane.to_geodetic(x, y)
        pose = geo_pose(latitude, longitude)
        pose.orientation = Quaternion(z=math.sin(yaw / 2), w=math.cos(yaw / 2))
        poses.append(pose)
    assert lanes.followGpsWaypoints(poses)
    reached = []
    sim = lanes.server.sim
    end = sim.time + 90.0
    while not lanes.isTaskComplete():
        assert sim.time < end, "still following"
        feedback = lanes.getFeedback()
        if feedback is not None and (not reached or reached[-1] != feedback.current_waypoint):
            reached.append(feedback.current_waypoint)
    assert lanes.getResult() is TaskResult.SUCCEEDED, lanes.getTaskError()
    assert reached == [0, 1]
    pose = lanes.robot_pose()
    assert math.hypot(pose.x - 1.0, pose.y - 1.6) < 0.3
    # No waypoints: Nav2's NO_WAYPOINTS_GIVEN.
    lanes.followGpsWaypoints([])
    while not lanes.isTaskComplete():
        pass
    assert lanes.getResult() is TaskResult.FAILED
    assert lanes.getTaskError()[0] == FollowGPSWaypointsError.NO_WAYPOINTS_GIVEN


def mission_with(tmp_path: Path, world: str, waypoints: str) -> Path:
    for name in ("lanes.yaml", "lanes.geojson"):
        (tmp_path / name).write_text((WORLDS / name).read_text())
    path = tmp_path / "gps.yaml"
    path.write_text(
        f"mission: gps\nworld: {world}\nrobot: turtlebot3\n"
        f"tree:\n  follow_gps_waypoints:\n{waypoints}"
    )
    return path


def test_the_leaf_refuses_waypoints_off_the_floor_or_in_obstacles_and_worlds_without_datum(
    tmp_path: Path,
) -> None:
    world = load_world(LANES)
    assert world.datum is not None
    plane = MapDatum(world.datum)
    free = plane.to_geodetic(-1.5, 1.6)
    island = plane.to_geodetic(0.0, 0.0)
    away = plane.to_geodetic(30.0, 0.0)
    lines = "".join(
        f"    - {{latitude: {lat:.10f}, longitude: {lon:.10f}}}\n"
        for lat, lon, _ in (free, island, away)
    )
    load_mission(mission_with(tmp_path, "lanes.yaml", lines.split("\n")[0] + "\n"))
    with pytest.raises(MissionError) as caught:
        load_mission(mission_with(tmp_path, "lanes.yaml", lines))
    assert ":7:7: follow_gps_waypoints.waypoints.1: GPS waypoint" in str(caught.value)
    assert "lands at map (0.00, 0.00): (0.00, 0.00) is inside obstacle 'island'" in str(
        caught.value
    )
    with pytest.raises(MissionError, match=r"gps.yaml:5:\d+: .*world 'walls' has no datum"):
        load_mission(mission_with(tmp_path, "walls", lines))

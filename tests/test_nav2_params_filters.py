"""Costmap filters from a Nav2 parameter file: keepout and speed masks found through Nav2's
filter -> costmap_filter_info_server -> filter mask server links, laid on the world."""

from __future__ import annotations

import shutil
import textwrap
from pathlib import Path

import pytest

from baobab.missions.language.loader import load_mission
from baobab.nav import BasicNavigator
from baobab.nav.nav2_configuration import load_nav2_params
from baobab.nav.nav2_params_file import Nav2ParamsError
from baobab.sim.world import Pose2D

OFFICE = Path(__file__).parents[1] / "missions" / "office"

FILTERS = """\
global_costmap:
  global_costmap:
    ros__parameters:
      track_unknown_space: true
      plugins: [static_layer, obstacle_layer, inflation_layer]
      filters: [keepout_filter, speed_filter]
      keepout_filter:
        plugin: nav2_costmap_2d::KeepoutFilter
        enabled: true
        filter_info_topic: keepout_costmap_filter_info
        override_lethal_cost: true
        lethal_override_cost: 150
      speed_filter:
        plugin: nav2_costmap_2d::SpeedFilter
        enabled: true
        filter_info_topic: speed_costmap_filter_info
        speed_limit_topic: speed_limit
keepout_filter_mask_server:
  ros__parameters:
    topic_name: keepout_filter_mask
    yaml_filename: {keepout}
keepout_costmap_filter_info_server:
  ros__parameters:
    type: 0
    filter_info_topic: keepout_costmap_filter_info
    mask_topic: keepout_filter_mask
    base: 0.0
    multiplier: 1.0
speed_filter_mask_server:
  ros__parameters:
    topic_name: speed_filter_mask
    yaml_filename: speed.yaml
speed_costmap_filter_info_server:
  ros__parameters:
    type: 1
    filter_info_topic: speed_costmap_filter_info
    mask_topic: speed_filter_mask
    base: 100.0
    multiplier: -0.5
"""


def _folder(tmp_path: Path, keepout: str = "keepout.yaml") -> Path:
    for name in ("keepout.yaml", "keepout.pgm", "speed.yaml", "speed.pgm"):
        shutil.copy(OFFICE / name, tmp_path / name)
    path = tmp_path / "nav2_params.yaml"
    path.write_text(FILTERS.replace("{keepout}", keepout))
    return path


def test_the_files_masks_reach_the_costmaps_and_the_controller(tmp_path: Path) -> None:
    params = _folder(tmp_path)
    configuration = load_nav2_params(params)
    assert configuration.masks is not None
    assert configuration.params.keepout.lethal_override_cost == 150
    assert configuration.params.global_costmap.static.track_unknown_space is True
    assert configuration.ignored_nodes == []  # the filter servers were read
    assert configuration.unused == {}
    start = Pose2D(x=1.6, y=3.2, yaw=0.0)
    bare = BasicNavigator(world=OFFICE / "office.yaml", start=start)
    try:
        assert bare.server.global_layers.keepout is None and bare.server.speed_filter is None
    finally:
        bare.destroy_node()
    nav = BasicNavigator(world=OFFICE / "office.yaml", start=start, params_file=params)
    try:
        server = nav.server
        assert server.global_layers.keepout is not None
        assert server.params.keepout.lethal_override_cost == 150
        speed = server.speed_filter
        assert speed is not None and (speed.base, speed.multiplier) == (100.0, -0.5)
        assert server.global_layers.params.static.track_unknown_space is True
    finally:
        nav.destroy_node()


def test_a_mission_takes_the_files_masks(tmp_path: Path) -> None:
    params = _folder(tmp_path)
    mission_path = tmp_path / "mission.yaml"
    shutil.copy(OFFICE / "office.yaml", tmp_path / "office.yaml")
    shutil.copy(OFFICE / "office.pgm", tmp_path / "office.pgm")
    mission_path.write_text(
        "mission: m\nworld: ./office.yaml\nrobot: turtlebot3\nstart: {x: 1.6, y: 3.2}\n"
        "tree:\n  navigate_to_pose: {x: 2.45, y: 8.0}\n"
    )
    assert load_mission(mission_path).world.filters is None  # type: ignore[union-attr]
    mission = load_mission(mission_path, nav2_params=params)
    assert mission.world is not None and mission.world.filters is not None
    assert mission.world.filters.speed is not None
    assert mission.world.filters.speed.multiplier == -0.5


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            ("yaml_filename: {keepout}", "yaml_filename: absent.yaml"),
            "mask file 'absent.yaml' does not exist",
        ),
        (
            ("yaml_filename: {keepout}", "yaml_filename: /etc/hosts"),
            "must be inside the parameter file's folder",
        ),
        (
            ("    type: 0\n", "    type: 1\n"),
            "type 1 does not fit its filter: a keepout filter's type is 0",
        ),
        (
            ("mask_topic: keepout_filter_mask", "mask_topic: elsewhere"),
            "no filter mask server (map_server) publishes 'elsewhere'",
        ),
        (
            (
                "filter_info_topic: keepout_costmap_filter_info\n        override",
                "filter_info_topic: nowhere\n        override",
            ),
            "no costmap_filter_info_server publishes 'nowhere'",
        ),
    ],
)
def test_broken_filter_links_are_located_errors(
    tmp_path: Path, change: tuple[str, str], message: str
) -> None:
    path = _folder(tmp_path)
    text = FILTERS.replace(*change).replace("{keepout}", "keepout.yaml")
    path.write_text(textwrap.dedent(text))
    with pytest.raises(Nav2ParamsError) as caught:
        load_nav2_params(path)
    assert message in str(caught.value)
    assert str(caught.value).startswith(f"{path}:")

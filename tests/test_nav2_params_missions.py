"""A mission's ``nav2_params:`` (and ``baobab run --nav2-params``) configure its navigation."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.run.rig import MobileRig, build_rig
from baobab.nav.nav2_params_file import Nav2ParamsError
from baobab.sim.errors import BaobabError

PARAMS = Path(__file__).parent / "nav2_params"

MISSION = """\
mission: short_drive
world: walls
robot: turtlebot3
{extra}
tree:
  follow_waypoints:
    waypoints: [{{x: 0.5, y: 0.5}}]
timeout: 60
expect:
  result: SUCCEEDED
"""


def _mission(folder: Path, extra: str = "") -> Path:
    path = folder / "mission.yaml"
    path.write_text(MISSION.format(extra=extra))
    return path


def test_the_mission_key_configures_the_navigation_stack(tmp_path: Path) -> None:
    shutil.copy(PARAMS / "bringup_rpp.yaml", tmp_path / "nav2_params.yaml")
    mission = load_mission(_mission(tmp_path, "nav2_params: ./nav2_params.yaml"))
    assert mission.nav2_params is not None
    assert mission.nav2_warning is not None and "FollowPath.allow_reversing" in mission.nav2_warning
    rig = build_rig(mission, seed=0)
    assert isinstance(rig, MobileRig) and rig.navigation is not None
    server = rig.navigation
    assert server.params.waypoint_stop_on_failure is False
    assert server.follower.controller.params.max_robot_pose_search_dist == 10.0
    assert server.local_layers.params.use_static_layer is False


def test_without_a_file_the_stack_keeps_its_defaults(tmp_path: Path) -> None:
    mission = load_mission(_mission(tmp_path))
    assert mission.nav2_params is None and mission.nav2_warning is None
    rig = build_rig(mission, seed=0)
    assert isinstance(rig, MobileRig) and rig.navigation is not None
    assert rig.navigation.params.waypoint_stop_on_failure is True


@pytest.mark.parametrize(
    ("written", "message"),
    [
        ("../nav2_params.yaml", "nav2_params file '../nav2_params.yaml' is outside the mission's"),
        ("./absent.yaml", "no nav2_params file './absent.yaml' in the mission's folder"),
    ],
)
def test_the_file_must_be_inside_the_missions_folder(
    tmp_path: Path, written: str, message: str
) -> None:
    folder = tmp_path / "mission"
    folder.mkdir()
    (tmp_path / "nav2_params.yaml").write_text("amcl:\n  ros__parameters: {}\n")
    with pytest.raises(MissionError) as caught:
        load_mission(_mission(folder, f"nav2_params: {written}"))
    assert str(caught.value).startswith(f"{folder / 'mission.yaml'}:4:")
    assert message in str(caught.value)


def test_a_mistake_inside_the_file_is_located_there(tmp_path: Path) -> None:
    params = tmp_path / "nav2_params.yaml"
    params.write_text("controller_server:\n  ros__parameters:\n    controller_frequency: fast\n")
    with pytest.raises(Nav2ParamsError) as caught:
        load_mission(_mission(tmp_path, "nav2_params: nav2_params.yaml"))
    assert str(caught.value).startswith(f"{params}:3:5: controller_frequency (Hz) must be a number")


def test_a_robot_without_navigation_refuses_the_file(tmp_path: Path) -> None:
    (tmp_path / "p.yaml").write_text("amcl:\n  ros__parameters: {}\n")
    path = tmp_path / "arm.yaml"
    path.write_text(
        "mission: arm\nrobot: panda\nnav2_params: p.yaml\ntree:\n  gripper: {command: open}\n"
    )
    with pytest.raises(MissionError, match="robot 'panda' has no navigation stack"):
        load_mission(path)
    with pytest.raises(BaobabError, match="--nav2-params: robot 'panda'"):
        load_mission(path.with_name("arm.yaml"), nav2_params=tmp_path / "p.yaml")


def test_run_takes_nav2_params_and_warns_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mission = _mission(tmp_path)
    code = main(
        [
            "run",
            str(mission),
            "--nav2-params",
            str(PARAMS / "every_mapped.yaml"),
            "--out",
            str(tmp_path / "run"),
            "--json",
        ]
    )
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert json.loads(captured.out)["result"] == "SUCCEEDED"
    assert "baobab does not use" not in captured.err  # every parameter is mapped
    code = main(
        [
            "run",
            str(mission),
            "--nav2-params",
            str(PARAMS / "bringup_rpp.yaml"),
            "--json",
            "--out",
            str(tmp_path / "run2"),
        ]
    )
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert captured.err.count("parameter(s) baobab does not use") == 1

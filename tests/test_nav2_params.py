"""Reading Nav2 parameter files: the mapping, unsupported plugins, unused parameters, errors."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from baobab.missions.cli.command_line import main
from baobab.nav.nav2_configuration import DEFAULT, FILE, Nav2Configuration, load_nav2_params
from baobab.nav.nav2_params_file import Nav2ParamsError
from baobab.nav.navigation_params import NavigationParams

PARAMS = Path(__file__).parent / "nav2_params"
BRINGUP = PARAMS / "bringup_rpp.yaml"


def _load(tmp_path: Path, text: str, *, substitute: bool = False) -> Nav2Configuration:
    path = tmp_path / "nav2_params.yaml"
    path.write_text(textwrap.dedent(text))
    return load_nav2_params(path, substitute=substitute)


def _error(tmp_path: Path, text: str) -> str:
    with pytest.raises(Nav2ParamsError) as caught:
        _load(tmp_path, text)
    return str(caught.value)


def test_nav2_bringup_layout_maps_and_reports_what_it_does_not_use() -> None:
    configuration = load_nav2_params(BRINGUP)
    params = configuration.params
    assert params.controller.rpp.desired_linear_vel == 0.22
    assert params.controller.rpp.max_robot_pose_search_dist == 10.0
    assert params.controller.rpp.use_cost_regulated_linear_velocity_scaling is False
    assert params.local_costmap_size == (3.0, 3.0)
    assert params.local_costmap.use_static_layer is False  # [voxel_layer, inflation_layer]
    assert params.global_costmap.use_static_layer is True
    assert params.waypoint_stop_on_failure is False
    assert params.waypoint_pause == pytest.approx(0.2)
    assert configuration.value("controller_server", "FollowPath.desired_linear_vel") == 0.22
    origins = {(s.node, s.name): s.origin for s in configuration.settings}
    assert origins[("controller_server", "FollowPath.desired_linear_vel")] == FILE
    assert origins[("controller_server", "FollowPath.max_angular_vel")] == DEFAULT
    rpp = "controller_server/FollowPath (nav2_regulated_pure_pursuit_controller::"
    group = next(name for name in configuration.unused if name.startswith(rpp))
    assert "FollowPath.allow_reversing" in configuration.unused[group]
    assert "controller_server: use_sim_time" in configuration.ros_only
    assert configuration.ignored_nodes == ["amcl", "map_server"]
    warning = configuration.warning()
    assert warning is not None and warning.count("FollowPath.allow_reversing") == 1
    assert "\n" not in warning


def test_a_file_that_sets_nothing_baobab_maps_changes_nothing(tmp_path: Path) -> None:
    text = """\
    amcl:
      ros__parameters:
        use_sim_time: true
    controller_server:
      ros__parameters:
        use_sim_time: true
    """
    configuration = _load(tmp_path, text)
    assert configuration.params == NavigationParams()
    assert configuration.warning() is None


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        (
            """\
            controller_server:
              ros__parameters:
                FollowPath:
                  desired_linear_vel: fast
            """,
            ":4:7:",
            "FollowPath.desired_linear_vel (m/s) must be a number, got 'fast'",
        ),
        (
            """\
            controller_server:
              ros__parameters:
                controller_frequency: -20.0
            """,
            ":3:5:",
            "controller_frequency (Hz) must be positive, got -20.0",
        ),
        (
            """\
            local_costmap:
              local_costmap:
                ros__parameters:
                  update_frequency: 0
            """,
            ":4:7:",
            "update_frequency (Hz) must be positive",
        ),
        (
            """\
            global_costmap:
              global_costmap:
                ros__parameters:
                  plugins: [inflation_layer]
                  inflation_layer:
                    plugin: nav2_costmap_2d::InflationLayer
                    inflation_radius: true
            """,
            ":7:9:",
            "inflation_layer.inflation_radius (m) must be a number, got true",
        ),
        (
            """\
            waypoint_follower:
              ros__parameters:
                stop_on_failure: "yes"
            """,
            ":3:5:",
            "stop_on_failure (end FollowWaypoints at the first missed waypoint) must be true or",
        ),
        (
            """\
            controler_server:
              ros__parameters:
                controller_frequency: 20.0
            """,
            ":1:1:",
            "unknown Nav2 node 'controler_server'; did you mean 'controller_server'?",
        ),
        (
            """\
            controller_server:
              controller_frequency: 20.0
            """,
            ":1:1:",
            "node 'controller_server' needs 'ros__parameters:' above its parameters",
        ),
        (
            """\
            controller_server:
              ros__parameters:
                controller_plugins: 3
            """,
            ":3:5:",
            "controller_plugins must be a list of plugin names, got 3",
        ),
        (
            """\
            controller_server:
              ros__parameters:
                controller_plugins: [Fast]
            """,
            ":3:5:",
            "controller 'Fast' has no 'Fast.plugin' (its class)",
        ),
        (
            """\
            robot1:
              controller_server:
                ros__parameters:
                  controller_frequency: 20.0
            /robot1/controller_server:
              ros__parameters:
                controller_frequency: 10.0
            """,
            ":7:5:",
            "parameter 'controller_frequency' of 'controller_server' set twice (first at line 4)",
        ),
        (
            """\
            local_costmap:
              local_costmap:
                ros__parameters:
                  footprint: "[[0.2, 0.1], [0.2, -0.1]]"
            """,
            ":4:7:",
            "footprint is not a usable polygon: a footprint polygon needs at least 3 vertices",
        ),
        (
            """\
            local_costmap:
              local_costmap:
                ros__parameters:
                  footprint: "[[0.2, 0.1], [-0.2, -0.1], [0.2, -0.1], [-0.2, 0.1]]"
            """,
            ":4:7:",
            "footprint is not a usable polygon:",
        ),
        (
            """\
            global_costmap:
              global_costmap:
                ros__parameters:
                  footprint: "[[0.2, 0.1], [0.2, -0.1], [-0.2"
            """,
            ":4:7:",
            "footprint must be a polygon such as",
        ),
        (
            """\
            global_costmap:
              global_costmap:
                ros__parameters:
                  robot_radius: -0.2
            """,
            ":4:7:",
            "robot_radius (m) must be a positive number, got -0.2",
        ),
    ],
)
def test_bad_input_is_a_located_error(tmp_path: Path, text: str, where: str, message: str) -> None:
    error = _error(tmp_path, text)
    assert f"nav2_params.yaml{where}" in error
    assert message in error


MPPI = """\
controller_server:
  ros__parameters:
    controller_plugins: ["FollowPath"]
    FollowPath:
      plugin: "nav2_mppi_controller::MPPIController"
      vx_max: 0.15
      wz_max: 1.2
      batch_size: 2000
"""


def test_an_unsupported_controller_is_refused_with_its_substitute(tmp_path: Path) -> None:
    error = _error(tmp_path, MPPI)
    assert ":5:7: controller plugin 'nav2_mppi_controller::MPPIController' (FollowPath)" in error
    assert (
        "baobab has: nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController"
        in error
    )
    assert "--nav2-substitute runs Regulated Pure Pursuit with its vx_max and wz_max" in error


def test_the_substitute_takes_the_unsupported_controllers_speed_limits(tmp_path: Path) -> None:
    configuration = _load(tmp_path, MPPI, substitute=True)
    rpp = configuration.params.controller.rpp
    assert (rpp.desired_linear_vel, rpp.max_angular_vel) == (0.15, 1.2)
    assert configuration.substitutions == [
        "controller_server/FollowPath: nav2_mppi_controller::MPPIController -> Regulated Pure"
        " Pursuit with its vx_max and wz_max"
    ]
    assert list(configuration.unused.values()) == [["FollowPath.batch_size"]]


@pytest.mark.parametrize(
    ("node", "list_name", "plugin", "named"),
    [
        ("planner_server", "planner_plugins", "nav2_smac_planner/SmacPlannerHybrid", "planner"),
        ("planner_server", "planner_plugins", "nav2_smac_planner::SmacPlannerLattice", "planner"),
        (
            "planner_server",
            "planner_plugins",
            "nav2_theta_star_planner::ThetaStarPlanner",
            "planner",
        ),
        ("controller_server", "controller_plugins", "dwb_core::DWBLocalPlanner", "controller"),
        ("controller_server", "controller_plugins", "my_robot::MyController", "controller"),
        ("smoother_server", "smoother_plugins", "nav2_smoother::SavitzkyGolaySmoother", "smoother"),
    ],
)
def test_every_unsupported_plugin_is_named(
    tmp_path: Path, node: str, list_name: str, plugin: str, named: str
) -> None:
    text = f"""\
    {node}:
      ros__parameters:
        {list_name}: [main]
        main:
          plugin: "{plugin}"
    """
    error = _error(tmp_path, text)
    assert f":5:7: {named} plugin '{plugin.replace('/', '::')}' (main) is not in baobab" in error
    assert "--nav2-substitute" in error
    substituted = _load(tmp_path, text, substitute=True)
    assert substituted.substitutions[0].startswith(f"{node}/main: ")


def test_substituted_planner_takes_tolerance_and_allow_unknown(tmp_path: Path) -> None:
    text = """\
    planner_server:
      ros__parameters:
        planner_plugins: [GridBased]
        GridBased:
          plugin: nav2_smac_planner::SmacPlannerHybrid
          tolerance: 0.4
          allow_unknown: false
          motion_model_for_search: DUBIN
    """
    planner = _load(tmp_path, text, substitute=True).params.planner
    assert (planner.tolerance, planner.allow_unknown) == (0.4, False)


def test_inflation_before_a_layer_it_would_inflate(tmp_path: Path) -> None:
    text = """\
    global_costmap:
      global_costmap:
        ros__parameters:
          plugins: [static_layer, inflation_layer, obstacle_layer]
    """
    assert "'obstacle_layer' comes after 'inflation_layer'" in _error(tmp_path, text)
    assert _load(tmp_path, text, substitute=True).substitutions == [
        "global_costmap/plugins: layers run as static, obstacle, inflation"
    ]


def test_layers_left_out_or_disabled(tmp_path: Path) -> None:
    text = """\
    local_costmap:
      local_costmap:
        ros__parameters:
          plugins: [obstacle_layer, inflation_layer]
          obstacle_layer:
            plugin: nav2_costmap_2d/ObstacleLayer
            enabled: false
    global_costmap:
      global_costmap:
        ros__parameters:
          plugins: [static_layer, obstacle_layer]
    """
    params = _load(tmp_path, text).params
    assert (params.local_costmap.use_static_layer, params.local_costmap.use_obstacle_layer) == (
        False,
        False,
    )
    assert params.global_costmap.use_obstacle_layer is True
    assert params.global_costmap.inflation_radius == 0.0  # no inflation layer


def test_humble_names_and_the_old_speed_name(tmp_path: Path) -> None:
    text = """\
    controller_server:
      ros__parameters:
        progress_checker_plugin: "progress_checker"
        goal_checker_plugins: ["general_goal_checker"]
        progress_checker:
          plugin: "nav2_controller::SimpleProgressChecker"
          movement_time_allowance: 20.0
        general_goal_checker:
          plugin: "nav2_controller::SimpleGoalChecker"
          xy_goal_tolerance: 0.1
        FollowPath:
          max_linear_vel: 0.12
    """
    controller = _load(tmp_path, text).params.controller
    assert controller.movement_time_allowance == 20.0
    assert controller.xy_goal_tolerance == 0.1
    assert controller.rpp.desired_linear_vel == 0.12


def test_nav2_params_command_prints_values_and_origins(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["nav2-params", str(BRINGUP)]) == 0
    out = capsys.readouterr().out
    assert "FollowPath.desired_linear_vel" in out
    line = next(line for line in out.splitlines() if "FollowPath.desired_linear_vel" in line)
    assert line.split()[1:] == ["0.22", "m/s", "file:44"]
    line = next(line for line in out.splitlines() if "FollowPath.max_angular_vel" in line)
    assert line.split()[1:] == ["2.84", "rad/s", "default"]
    assert "not used by baobab (warning):" in out
    assert "nodes baobab does not run, ignored: amcl, map_server" in out


def test_nav2_params_command_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["nav2-params", str(BRINGUP), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    first = next(p for p in data["parameters"] if p["name"] == "FollowPath.desired_linear_vel")
    assert first == {
        "node": "controller_server",
        "name": "FollowPath.desired_linear_vel",
        "value": 0.22,
        "unit": "m/s",
        "origin": "file",
        "line": 44,
        "targets": ["controller.rpp.desired_linear_vel"],
    }
    assert data["ignored_nodes"] == ["amcl", "map_server"]


def test_nav2_params_command_refuses_a_bad_file_on_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "p.yaml"
    path.write_text(MPPI)
    assert main(["nav2-params", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.count("\n") == 1 and captured.err.startswith(f"{path}:5:7: controller")
    assert main(["nav2-params", str(path), "--nav2-substitute"]) == 0


SCRIPT = """\
from nav2_simple_commander.robot_navigator import BasicNavigator

navigator = BasicNavigator()
print("speed", navigator.server.follower.controller.params.desired_linear_vel)
navigator.destroy_node()
"""


def test_nav2_command_configures_the_scripts_navigator(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = tmp_path / "speed.py"
    script.write_text(SCRIPT)
    code = main(["nav2", str(script), "--world", "walls", "--nav2-params", str(BRINGUP)])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "speed 0.22" in captured.out
    assert captured.err.count("parameter(s) baobab does not use") == 1
    mppi = tmp_path / "mppi.yaml"
    mppi.write_text(MPPI)
    options = ["--world", "walls", "--nav2-params", str(mppi)]
    assert main(["nav2", str(script), *options]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.startswith(f"{mppi}:5:7: controller plugin")
    assert main(["nav2", str(script), *options, "--nav2-substitute"]) == 0
    assert "speed 0.15" in capsys.readouterr().out


def test_teleop_refuses_a_bad_parameter_file_before_it_needs_a_terminal(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("controller_server:\n  ros__parameters:\n    controller_frequency: -1\n")
    assert main(["teleop", "--world", "cafe", "--nav2-params", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:3:5: controller_frequency (Hz) must be positive")


def test_a_footprint_polygon_wins_over_the_radius_and_is_padded(tmp_path: Path) -> None:
    text = """\
    local_costmap:
      local_costmap:
        ros__parameters:
          robot_radius: 0.3
          footprint: [[0.2, 0.1], [0.2, -0.1], [-0.2, -0.1], [-0.2, 0.1]]
          footprint_padding: 0.05
    global_costmap:
      global_costmap:
        ros__parameters:
          footprint_padding: 0.05
    """
    configuration = _load(tmp_path, text)
    local = configuration.params.local_costmap.footprint
    expected = ((0.25, 0.15), (0.25, -0.15), (-0.25, -0.15), (-0.25, 0.15))
    assert np.allclose(local.polygon, expected)
    assert (
        configuration.params.global_costmap.footprint == NavigationParams().global_costmap.footprint
    )
    assert configuration.unused == {"global_costmap": ["footprint_padding"]}


def test_a_disabled_waypoint_task_pauses_nowhere(tmp_path: Path) -> None:
    text = """\
    waypoint_follower:
      ros__parameters:
        waypoint_task_executor_plugin: wait_at_waypoint
        wait_at_waypoint:
          plugin: nav2_waypoint_follower::WaitAtWaypoint
          enabled: false
          waypoint_pause_duration: 900
    """
    configuration = _load(tmp_path, text)
    assert configuration.params.waypoint_pause == 0.0
    assert configuration.unused == {
        "waypoint_follower/wait_at_waypoint (nav2_waypoint_follower::WaitAtWaypoint)": [
            "wait_at_waypoint.waypoint_pause_duration"
        ]
    }

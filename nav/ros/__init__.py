"""Stand-ins for the ROS 2 Python modules rclpy nodes and Nav2 Simple Commander scripts import,
and the runtime that runs such nodes on simulation time (:mod:`.runtime`).

Each subpackage mirrors one ROS package: ``baobab.nav.ros.rclpy.duration`` is what a script
gets for ``rclpy.duration``, ``baobab.nav.ros.geometry_msgs.msg`` for ``geometry_msgs.msg``,
``baobab.nav.ros.robot_navigator`` for the old top-level ``robot_navigator``. They are plain
baobab modules; :func:`ros_shims` makes them importable under their ROS names for the length
of a ``with`` block, so an unmodified script runs against baobab's navigator.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from types import ModuleType

from baobab.nav.errors import UnsupportedRosFeatureError as UnsupportedRosFeatureError

ROS_MODULES: tuple[str, ...] = (
    "rclpy",
    "rclpy.callback_groups",
    "rclpy.clock",
    "rclpy.context",
    "rclpy.duration",
    "rclpy.exceptions",
    "rclpy.executors",
    "rclpy.logging",
    "rclpy.node",
    "rclpy.parameter",
    "rclpy.publisher",
    "rclpy.qos",
    "rclpy.subscription",
    "rclpy.task",
    "rclpy.time",
    "rclpy.timer",
    "rclpy.utilities",
    "action_msgs",
    "action_msgs.msg",
    "builtin_interfaces",
    "builtin_interfaces.msg",
    "std_msgs",
    "std_msgs.msg",
    "geometry_msgs",
    "geometry_msgs.msg",
    "nav_msgs",
    "nav_msgs.msg",
    "sensor_msgs",
    "sensor_msgs.msg",
    "tf2_msgs",
    "tf2_msgs.msg",
    "rosgraph_msgs",
    "rosgraph_msgs.msg",
    "rcl_interfaces",
    "rcl_interfaces.msg",
    "tf2_ros",
    "tf2_ros.buffer",
    "tf2_ros.transform_listener",
    "tf2_ros.transform_broadcaster",
    "tf2_ros.static_transform_broadcaster",
    "nav2_msgs",
    "nav2_msgs.msg",
    "nav2_msgs.action",
    "geographic_msgs",
    "geographic_msgs.msg",
    "unique_identifier_msgs",
    "unique_identifier_msgs.msg",
    "nav2_simple_commander",
    "nav2_simple_commander.costmap_2d",
    "nav2_simple_commander.footprint_collision_checker",
    "nav2_simple_commander.line_iterator",
    "nav2_simple_commander.occupancy_grid",
    "nav2_simple_commander.robot_navigator",
    "nav2_simple_commander.utils",
    "robot_navigator",
    "pynput",
    "pynput.keyboard",
    "launch",
    "launch.actions",
    "launch.substitutions",
    "launch.launch_description_sources",
    "launch_ros",
    "launch_ros.actions",
    "launch_ros.parameter_descriptions",
    "ament_index_python",
    "ament_index_python.packages",
)
"""The ROS module names the shims provide; ``name`` is served by ``baobab.nav.ros.<name>``."""

RUNTIME_MODULES: tuple[str, ...] = (
    "actors",
    "arguments",
    "bringup",
    "graph",
    "launch_files",
    "mission_nodes",
    "node_files",
    "qos",
    "runtime",
    "script_files",
    "sim_topics",
    "tf_tree",
    "waiting",
)
"""baobab's own modules here, which run the ROS modules (not served under a ROS name)."""

_ROS_PACKAGES = frozenset(name.partition(".")[0] for name in ROS_MODULES)


def load_message_types() -> None:
    """Import every message module, so :func:`baobab.nav.rosmsg.message_class` knows them all."""
    for name in ROS_MODULES:
        if name.endswith(".msg"):
            importlib.import_module(f"{__name__}.{name}")


def _owned_by_ros_packages(module_name: str) -> bool:
    return module_name.partition(".")[0] in _ROS_PACKAGES


@contextmanager
def ros_shims() -> Iterator[None]:
    """Serve :data:`ROS_MODULES` from baobab inside the block, with a fresh rclpy context.

    Modules already loaded under those package names (a real ROS installation, say) are
    hidden during the block and put back afterwards; anything loaded under them during the
    block is dropped, so nothing leaks from one run into the next. ``sys.modules`` is
    process-wide: do not run two blocks in parallel threads.
    """
    from baobab.nav.ros.rclpy.context import fresh_default_context

    shims: dict[str, ModuleType] = {
        name: importlib.import_module(f"{__name__}.{name}") for name in ROS_MODULES
    }
    hidden = {name: mod for name, mod in sys.modules.items() if _owned_by_ros_packages(name)}
    for name in hidden:
        del sys.modules[name]
    sys.modules.update(shims)
    try:
        with fresh_default_context():
            yield
    finally:
        for name in [name for name in sys.modules if _owned_by_ros_packages(name)]:
            del sys.modules[name]
        sys.modules.update(hidden)

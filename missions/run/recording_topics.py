"""The topics a run's recording uses, and the JSON schemas of its own messages.

Names follow Nav2 and ROS where a topic exists there (``/tf``, ``/scan``, ``/plan``,
``/global_costmap/costmap``, ``/joint_states``, the ROS Cartesian impedance controllers'
``/cartesian_impedance/*``); the rest are baobab's (the tree's status, task feedback, scenes).
:class:`~baobab.sim.recording.Recorder` logs on whatever topic it is given.
"""

from __future__ import annotations

from baobab.sim.recording import JsonSchema


class Topics:
    """The topic names baobab records under (Nav2 / ROS conventions where they exist)."""

    TF = "/tf"
    TF_STATIC = "/tf_static"
    """Transforms that never change (ROS's latched ``/tf_static``)."""
    SCAN = "/scan"
    ROBOT_POSE = "/robot_pose"
    PLAN = "/plan"
    FOLLOWED_PATH = "/followed_path"
    GLOBAL_COSTMAP = "/global_costmap/costmap"
    MAP = "/map"
    """The map_server map a world stands on (occupancy values, -1 unknown)."""
    KEEPOUT_MASK = "/keepout_filter_mask"
    SPEED_MASK = "/speed_filter_mask"
    """Nav2's costmap filter masks, as nav2_bringup's filter mask servers name them."""
    SPEED_LIMIT = "/speed_limit"
    """Each new limit the speed filter gives the controller (``nav2_msgs/SpeedLimit``)."""
    WORLD_SCENE = "/world/scene"
    """Static obstacles, movable obstacles and named locations."""
    ROBOT_SCENE = "/robot/scene"
    TREE_STATUS = "/behavior_tree/status"
    TASK_FEEDBACK = "/task/feedback"
    JOINT_STATES = "/joint_states"
    CURRENT_POSE = "/cartesian_impedance/current_pose"
    DESIRED_POSE = "/cartesian_impedance/desired_pose"
    FILT_REF_POSE = "/cartesian_impedance/filt_ref_pose"
    ARM_SCENE = "/scene"
    """An arm's scene: arm, table and objects."""


TREE_STATUS_SCHEMA = JsonSchema(
    "baobab.BehaviourTreeStatus",
    {
        "type": "object",
        "properties": {
            "tick": {"type": "integer"},
            "root_status": {"type": "string"},
            "nodes": {
                "type": "array",
                "items": {
                    "type": "object",
                    "properties": {
                        "path": {"type": "string"},
                        "name": {"type": "string"},
                        "type": {"type": "string"},
                        "status": {"enum": ["INVALID", "RUNNING", "SUCCESS", "FAILURE"]},
                    },
                },
            },
        },
    },
)
"""Suggested payload: ``{"tick": n, "root_status": "RUNNING", "nodes": [{"path", "name",
"type", "status"}, ...]}`` with nodes in depth-first order."""

SPEED_LIMIT_SCHEMA = JsonSchema(
    "nav2_msgs.SpeedLimit",
    {
        "type": "object",
        "properties": {
            "percentage": {"type": "boolean"},
            "speed_limit": {"type": "number"},
        },
    },
)
"""``{"percentage": true, "speed_limit": 50.0}``: percent of the top speed, or m/s; 0 means
no limit."""

TASK_FEEDBACK_SCHEMA = JsonSchema(
    "baobab.TaskFeedback",
    {"type": "object", "properties": {"task": {"type": "string"}}},
)
"""Suggested payload: ``{"task": "NavigateToPose", ...}`` plus Nav2's feedback field names."""

"""The dock_robot, undock_robot and follow_object leaves: located errors, and trees that run."""

from __future__ import annotations

from pathlib import Path

import pytest

from baobab.missions.language.loader import load_mission
from baobab.sim.errors import BaobabError

HEAD = "mission: m\nworld: lobby\nrobot: turtlebot3\ntree:\n"


@pytest.mark.parametrize(
    ("tree", "where", "fragment"),
    [
        ("  dock_robot: garage\n", "5:3", "unknown dock 'garage'; did you mean 'charger'?"),
        (
            "  dock_robot: {dock_id: charger, dock_pose: {x: 1, y: 1}}\n",
            "5:16",
            "give either dock_id or dock_pose",
        ),
        (
            "  follow_object: {topic: /ghost/pose}\n",
            "5:19",
            "unknown moving object topic '/ghost/pose'",
        ),
        ("  follow_object: {frame: ghost}\n", "5:19", "unknown moving object frame 'ghost'"),
        ("  follow_object: {max_duration: 5}\n", "5:3", "give either topic or frame"),
        (
            "  follow_object: {frame: visitor, max_duration: -1}\n",
            "5:35",
            "greater than or equal to 0",
        ),
    ],
    ids=[
        "unknown-dock",
        "dock-id-and-pose",
        "unknown-topic",
        "unknown-frame",
        "no-source",
        "negative-duration",
    ],
)
def test_bad_leaves_are_located_errors(
    tmp_path: Path, tree: str, where: str, fragment: str
) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(HEAD + tree)
    with pytest.raises(BaobabError) as caught:
        load_mission(path)
    message = str(caught.value)
    assert message.startswith(f"{path}:{where}: "), message
    assert fragment in message and "\n" not in message

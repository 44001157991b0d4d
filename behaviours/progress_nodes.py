"""The forward-progress rule as a decorator around navigation nodes: ``clear_costmaps_when_stuck``.

::

    clear_costmaps_when_stuck:
      period: 0.5                      # s of sim time between clearings, at least
      child: {navigate_to_pose: table_3}

clears all costmaps every 0.5 s while the robot does not move forward and the navigation
runs (see :mod:`baobab.behaviours.progress`). ``clear_costmaps_when_stuck: {navigate_to_pose:
table_3}`` is the short form with the rule's defaults (0.5 s, all costmaps).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Literal

from pydantic import Field

from baobab.behaviours.ports import NAVIGATION
from baobab.behaviours.progress_rule import DEFAULT_MIN_SPEED, DEFAULT_PERIOD
from baobab.behaviours.registry import (
    BehaviourType,
    BuildRequest,
    NodeData,
    NodeKind,
    NodeParams,
)

if TYPE_CHECKING:  # imported by the factory, when a tree is built (validation needs none)
    import py_trees


class ClearCostmapsWhenStuckParams(NodeParams):
    """While the child runs, clear costmaps every ``period`` s without forward progress."""

    period: float = Field(
        default=DEFAULT_PERIOD, gt=0, allow_inf_nan=False, description="s of sim time"
    )
    which: Literal["local", "global", "all"] = Field(default="all", description="costmaps")
    min_speed: float = Field(
        default=DEFAULT_MIN_SPEED,
        ge=0,
        allow_inf_nan=False,
        description="forward speed (m/s) above which the robot makes progress",
    )
    child: Annotated[NodeData, Field(description="the decorated node")]

    def summary(self) -> str:
        """``all every 0.5 s``."""
        return f"{self.which} every {self.period:g} s"


def _clear_costmaps_when_stuck(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.progress import ClearCostmapsWhenStuck

    params = request.params_as(ClearCostmapsWhenStuckParams)
    caps = request.capabilities
    return ClearCostmapsWhenStuck(
        request.name,
        request.child,
        clear=lambda: caps.navigation_port().clear_costmaps(params.which),
        robot_pose=lambda: caps.navigation_port().robot_pose(),
        clock=caps.clock,
        period=params.period,
        min_speed=params.min_speed,
    )


NODE_TYPES = (
    BehaviourType(
        "clear_costmaps_when_stuck",
        NodeKind.DECORATOR,
        ClearCostmapsWhenStuckParams,
        "while the child runs, clear costmaps every period s without forward progress",
        _clear_costmaps_when_stuck,
        capability=NAVIGATION,
        shorthand="child",
    ),
)
"""The progress-rule node types."""

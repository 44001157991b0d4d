"""Nav2's AssistedTeleop behaviour: teleop commands through a collision projection.

The behaviour runs like the others of :mod:`baobab.nav.behaviors` (10 Hz cycles of sim time,
``time_allowance`` 0 = no limit) and reads the teleop twist and the preempt flag from
:class:`~baobab.nav.behaviors.TeleopInput`; its run totals go to
:class:`~baobab.nav.behaviors.AssistedTeleopStats`.
"""

from __future__ import annotations

import math

import numpy as np

from baobab.nav.behaviors import Behavior, BehaviorContext
from baobab.nav.errors import AssistedTeleopError
from baobab.nav.footprint import lethal_distances, outline_lethal_distances, project_motion
from baobab.sim.tasks import TaskOutcome

CLEARANCE_TOLERANCE = 1e-6
"""m: a projected pose at the same distance from obstacles as the robot is not nearer."""


class AssistedTeleop(Behavior):
    """Pass the teleop command through a collision projection until preempted or timed out.

    Nav2's AssistedTeleop (reference/nav2.md §5.4), every cycle (10 Hz):

    - feedback ``current_teleop_duration`` (s since the start) and ``scaling``, the factor
      applied to the teleop twist this cycle;
    - ``time_allowance`` passed (0: no limit): FAILED, TIMEOUT, robot stopped;
    - :attr:`TeleopInput.preempt_requested`: SUCCEEDED, robot stopped;
    - else the teleop twist is integrated ahead from the robot's pose in
      ``simulation_time_step`` (0.1 s) steps up to ``projection_time`` (1.0 s), checking the
      footprint on the local costmap at each step. A collision at the first step sends zero;
      at time ``t`` the twist is scaled by ``t / projection_time``; none sends it unchanged.

    The footprint is the local costmap's inscribed radius (a circle) or its polygon, kept
    ``teleop_footprint_padding`` away from lethal cells, checked exactly against them
    (:func:`~baobab.nav.footprint.lethal_distances`,
    :func:`~baobab.nav.footprint.outline_lethal_distances`; Nav2 checks the footprint outline
    for lethal cost), so the robot stops with at least the padding between its footprint and
    the obstacle. One addition to Nav2: a robot already
    nearer than that to a lethal cell (an obstacle that appeared, a lidar hit marking the cell
    in front of a wall) is not frozen; a pose collides only if it comes nearer still, so the
    robot can turn in place and back away. The motion is integrated as exact arcs (Nav2 takes Euler
    steps; the two agree for straight lines and turns in place). While it runs it clears all
    costmaps every ``1 / teleop_costmap_clear_frequency`` s (2 Hz, as the Nav2 Simple Commander
    tutorial's assisted teleop node), counting from its start. A cancel (the server's) stops the
    robot: CANCELED.
    """

    label = "AssistedTeleop"
    codes = AssistedTeleopError

    def __init__(self, context: BehaviorContext, time_allowance: float = 0.0) -> None:
        super().__init__(context, time_allowance)
        self._next_clear = math.inf

    def start(self, now: float) -> TaskOutcome | None:
        """Forget a stale preempt request; schedule the first costmap clearing."""
        self.context.teleop.preempt_requested = False
        frequency = self.params.teleop_costmap_clear_frequency
        self._next_clear = now + 1.0 / frequency if frequency > 0 else math.inf
        self.feedback["current_teleop_duration"] = 0.0
        self.feedback["scaling"] = 1.0
        return None

    def tick(self, now: float) -> TaskOutcome | None:
        """Report the teleop duration first, as Nav2 does, then run the cycle."""
        if self._started:
            self.feedback["current_teleop_duration"] = now - self._start_time
        return super().tick(now)

    def cycle(self, now: float) -> TaskOutcome | None:
        """Scale the latest teleop command by the time to collision and send it."""
        teleop, stats = self.context.teleop, self.context.teleop_stats
        if teleop.preempt_requested:
            teleop.preempt_requested = False
            return self._succeed()
        linear, angular = teleop.linear, teleop.angular
        scaling = self.scaling(linear, angular)
        self.feedback["scaling"] = scaling
        if linear != 0.0 or angular != 0.0:
            stats.record(scaling, abs(linear * scaling))
        self.base.command(linear * scaling, angular * scaling)
        self._clear_costmaps(now)
        return None

    def scaling(self, linear: float, angular: float) -> float:
        """The factor for the twist (m/s, rad/s) from the robot's pose now: 0, t/T or 1."""
        p = self.params
        pose = self.base.pose()
        poses = project_motion(pose, linear, angular, p.projection_time, p.simulation_time_step)
        if len(poses) == 0:
            return 1.0
        costmap = self.context.local_costmap()
        if costmap.has_polygon:
            reach = p.teleop_footprint_padding
            now = np.array([[pose.x, pose.y, pose.yaw]])
            current = outline_lethal_distances(costmap, costmap.outline, now, reach)[0]
            ahead = outline_lethal_distances(costmap, costmap.outline, poses, reach)
            return self._factor(ahead, reach, current)
        radius = costmap.inscribed_radius + p.teleop_footprint_padding
        current = lethal_distances(costmap, np.array([pose.x]), np.array([pose.y]), radius)[0]
        ahead = lethal_distances(costmap, poses[:, 0], poses[:, 1], radius)
        return self._factor(ahead, radius, current)

    def _factor(self, ahead: np.ndarray, radius: float, current: float) -> float:
        """0, t/T or 1 from the projected poses' distances (m) to lethal cells: a pose hits
        when it is nearer than ``radius`` and nearer than the robot is now (``current``)."""
        p = self.params
        # A robot already nearer than the padded footprint (a new obstacle, a lidar mark a cell
        # in front of a wall) may turn and back away, but not come nearer still.
        hits = ahead < min(radius, current) - CLEARANCE_TOLERANCE
        if not hits.any():
            return 1.0
        first = int(np.argmax(hits))
        if first == 0:
            return 0.0
        return (first + 1) * p.simulation_time_step / p.projection_time

    def _clear_costmaps(self, now: float) -> None:
        clear = self.context.clear_costmaps
        if clear is None or now < self._next_clear - 1e-9:
            return
        clear("all")
        self.context.teleop_stats.costmap_clears += 1
        period = 1.0 / self.params.teleop_costmap_clear_frequency
        while self._next_clear <= now + 1e-9:
            self._next_clear += period

"""Nav2's docking server: the ``dock_robot`` and ``undock_robot`` actions of one robot.

The server runs its goals in the navigation server's task slot, so a docking goal replaces or
is replaced by any other navigation goal and a cancel stops the base at once; its tasks tick
at the navigation controller rate (20 Hz; Nav2's docking loop runs at 50 Hz). Goals come from
a mission leaf (:meth:`DockingServer.dock_robot`, :meth:`DockingServer.undock_robot`) or as
Nav2's action messages from ``BasicNavigator`` (:meth:`DockingServer.action_servers`); the
handle's feedback holds Nav2's Feedback and Result messages. The phases, codes, retries and
timeouts are :mod:`baobab.nav.docking_tasks`'s.
"""

from __future__ import annotations

from typing import Any, Protocol

from baobab.nav.costmap import Costmap2D
from baobab.nav.docking import Charger, DockingParams, LatestScan, pose_of
from baobab.nav.docking_tasks import DockingContext, DockTarget, DockTask, UndockTask, failed_target
from baobab.nav.errors import DockRobotError, GoalRejectedError
from baobab.nav.interfaces import ActionServer, MobileBase, ScanSource, ServerTask
from baobab.nav.navigator_messages import goal_pose
from baobab.nav.task_slot import TaskSlot
from baobab.sim.docks import DOCK_TYPES, Dock, load_dock_database
from baobab.sim.errors import BaobabError
from baobab.sim.tasks import TaskHandle
from baobab.sim.world import Pose2D

DOCK_ACTION = "dock_robot"
UNDOCK_ACTION = "undock_robot"
RELOAD_DATABASE = "docking_server/reload_database"
"""The service that replaces the dock database: ``filepath`` -> ``success``."""


class _Rates(Protocol):
    @property
    def controller_frequency(self) -> float: ...


class _Params(Protocol):
    @property
    def controller(self) -> _Rates: ...


class DockingHost(Protocol):
    """What the docking server uses of the navigation server."""

    base: MobileBase
    tasks: TaskSlot

    @property
    def params(self) -> _Params:
        """Its settings: the controller rate is the docking tasks' tick rate."""
        ...

    def local_costmap(self) -> Costmap2D:
        """The local costmap, up to date."""
        ...

    def navigate_task(self, goals: list[Pose2D], *, through_poses: bool) -> ServerTask:
        """A NavigateToPose task towards ``goals[0]``."""
        ...


class DockingServer:
    """Docking for one robot (module docstring).

    Args:
        host: the navigation server: its base, task slot, local costmap, controller rate and
            NavigateToPose tasks (to the staging pose).
        lidar: the scans the dock is detected in (None: no dock is ever detected).
        world_docks: the docks that stand in the world (the chargers).
        params: settings; Nav2's defaults when None.
        database: the dock database; the world's docks when None.
    """

    def __init__(
        self,
        host: DockingHost,
        lidar: ScanSource | None,
        world_docks: dict[str, Dock],
        params: DockingParams | None = None,
        *,
        database: dict[str, Dock] | None = None,
    ) -> None:
        self.params = params or DockingParams()
        self.database = dict(world_docks if database is None else database)
        self.charger = Charger(host.base, world_docks)
        self._scans = LatestScan()
        self._lidar = lidar
        if lidar is not None:
            lidar.subscribe(self._scans)
        self.context = DockingContext(
            host.base,
            self.charger,
            self._scans,
            lambda goal: host.navigate_task([goal], through_poses=False),
            host.local_costmap,
            self.params,
            period=1.0 / host.params.controller.controller_frequency,
        )
        self._tasks = host.tasks

    def is_charging(self) -> bool:
        """True while the robot charges at a dock."""
        return self.charger.is_charging()

    def dock_robot(
        self,
        dock_id: str = "",
        dock_pose: Pose2D | None = None,
        dock_type: str = "",
        *,
        navigate_to_staging_pose: bool = True,
        max_staging_time: float = 1000.0,
    ) -> TaskHandle:
        """Dock at the database's dock ``dock_id``, or at ``dock_pose`` (map frame, m and
        rad) of ``dock_type`` when no id is given."""
        target = self._target(
            dock_id, dock_pose, dock_type, navigate_to_staging_pose, max_staging_time
        )
        return self._tasks.submit(DOCK_ACTION, lambda: DockTask(self.context, target), None)

    def undock_robot(self, dock_type: str = "", max_undocking_time: float = 30.0) -> TaskHandle:
        """Back out of the dock the robot is docked at, to its staging pose."""
        return self._tasks.submit(
            UNDOCK_ACTION,
            lambda: UndockTask(self.context, dock_type, max_undocking_time),
            None,
        )

    def reload_database(self, filepath: str) -> bool:
        """Replace the dock database with a Nav2 dock database file (Nav2's
        ``docking_server/reload_database`` service); False, database kept, if it is invalid."""
        try:
            self.database = load_dock_database(filepath)
        except BaobabError:
            return False
        return True

    def action_servers(self) -> dict[str, ActionServer]:
        """The ``dock_robot`` and ``undock_robot`` action servers, by action name."""
        return {DOCK_ACTION: _DockAction(self), UNDOCK_ACTION: _UndockAction(self)}

    def close(self) -> None:
        """Stop receiving scans."""
        if self._lidar is not None:
            self._lidar.unsubscribe(self._scans)

    def _target(
        self,
        dock_id: str,
        dock_pose: Pose2D | None,
        dock_type: str,
        navigate: bool,
        max_staging_time: float,
    ) -> Any:
        if dock_id or dock_pose is None:
            dock = self.database.get(dock_id)
            if dock is None:
                known = ", ".join(sorted(self.database)) or "none"
                return failed_target(
                    DockRobotError.DOCK_NOT_IN_DB,
                    f"dock '{dock_id}' is not in the dock database (docks: {known})",
                )
            return DockTarget(pose_of(dock), dock.type, navigate, max_staging_time)
        if dock_type == "" and len(DOCK_TYPES) == 1:
            dock_type = DOCK_TYPES[0]
        if dock_type not in DOCK_TYPES:
            return failed_target(
                DockRobotError.DOCK_NOT_VALID,
                f"dock type '{dock_type}' has no plugin (types: {', '.join(DOCK_TYPES)})",
            )
        return DockTarget(dock_pose, dock_type, navigate, max_staging_time)


class _DockAction:
    """``dock_robot``: Nav2's DockRobot goal messages."""

    def __init__(self, server: DockingServer) -> None:
        self._server = server

    def send_goal(self, goal: Any) -> TaskHandle:
        pose = None
        if not goal.use_dock_id:
            try:
                pose = goal_pose(goal.dock_pose, "dock pose")
            except GoalRejectedError as exc:
                raise GoalRejectedError(str(exc), DockRobotError.UNKNOWN) from None
        return self._server.dock_robot(
            goal.dock_id if goal.use_dock_id else "",
            pose,
            goal.dock_type,
            navigate_to_staging_pose=goal.navigate_to_staging_pose,
            max_staging_time=goal.max_staging_time,
        )


class _UndockAction:
    """``undock_robot``: Nav2's UndockRobot goal messages."""

    def __init__(self, server: DockingServer) -> None:
        self._server = server

    def send_goal(self, goal: Any) -> TaskHandle:
        return self._server.undock_robot(goal.dock_type, goal.max_undocking_time)


__all__ = ["DOCK_ACTION", "RELOAD_DATABASE", "UNDOCK_ACTION", "DockingServer"]

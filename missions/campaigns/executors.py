"""Where campaign runs execute: a local process pool, or a Dask cluster (``--scheduler``).

Both are :mod:`concurrent.futures` executors running :func:`execute_run`, and both return the
same rows: a run depends only on its :class:`~baobab.missions.campaigns.spec.RunTask`.

- :class:`LocalExecutor`: a ``ProcessPoolExecutor`` whose processes each run one task and exit
  (``max_tasks_per_child=1``; py_trees' blackboard and MuJoCo's state are per process). New
  processes fork from a forkserver that has already imported the simulation stack, so a fresh
  process costs milliseconds, not the seconds of importing MuJoCo and py_trees (``spawn``
  where there is no forkserver). Workers ignore SIGINT (the parent decides what a Ctrl-C
  stops; :meth:`LocalExecutor.abort` ends their runs at the next tick) and write to stderr
  only, so that ``--json`` output stays alone on stdout.
- :class:`DaskExecutor`: ``distributed.Client(address).get_executor()``. Dask workers are
  long-lived processes; the tree compiler clears the blackboard for every run, and a lock
  keeps a worker process to one run at a time even when it has several threads (give
  workers ``--nthreads 1`` and start more of them). Every worker needs baobab installed;
  the mission's text travels with each task, a world *file* must exist at the same path.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from multiprocessing.synchronize import Event
from typing import Any, Protocol

from baobab.behaviours.ports import NAVIGATION
from baobab.missions.campaigns.spec import RunTask
from baobab.missions.campaigns.variant import load_run_mission, variant_of
from baobab.missions.campaigns.vary import CampaignError
from baobab.missions.language.loader import Mission
from baobab.missions.run.rig import uses_capability
from baobab.missions.run.runner import RunRecord, run_mission
from baobab.missions.run.trace import jsonable
from baobab.sim.errors import SourceError

DASK_CONNECT_TIMEOUT = 10.0
"""How long to try reaching a Dask scheduler (s, wall clock)."""
DASK_MISSING = (
    '--scheduler needs dask.distributed, which is not installed: pip install "baobab[campaign]"'
)
INVALID = "INVALID"
"""The result of a run whose values do not make a valid mission (it exits 2 on replay)."""
ERROR = "ERROR"
"""The result of a run that raised instead of ending (e.g. SimulationError: the physics
diverged), or whose worker died; ``error_name`` is the exception's class."""


@dataclass(frozen=True)
class RunOutcome:
    """What a worker sends back.

    Attributes:
        row: the run's row (every column but ``replay`` and ``finished_at``).
        variant_text: the run's mission variant, if it has one (written for replay).
        interrupted: the run was stopped by an abort; its row is not a result.
    """

    row: dict[str, Any]
    variant_text: str | None
    interrupted: bool = False


_stop: Event | None = None
_one_run_at_a_time = threading.Lock()


def execute_run(task: RunTask) -> RunOutcome:
    """Load and run ``task``'s mission, and describe how it went as a row."""
    with _one_run_at_a_time:
        started = time.perf_counter()
        variant: str | None = None
        try:
            variant = variant_of(task)
            mission = load_run_mission(task, variant)
            record = run_mission(
                mission, seed=task.seed, interrupted=None if _stop is None else _stop.is_set
            )
        except SourceError as exc:  # the run's values make an invalid mission or world
            row = failed_row(task, INVALID, "INVALID_MISSION", str(exc))
        except Exception as exc:  # a run must not take the campaign down with it
            row = failed_row(task, ERROR, type(exc).__name__, str(exc))
        else:
            row = record_row(task, record)
            row["wall_time"] = round(time.perf_counter() - started, 3)
            return RunOutcome(row, variant, record.outcome.interrupted)
        row["wall_time"] = round(time.perf_counter() - started, 3)
        return RunOutcome(row, variant)


def _task_columns(task: RunTask) -> dict[str, Any]:
    return {
        "run": task.index,
        "cell": task.cell,
        "repeat": task.repeat,
        "seed": task.seed,
        "params": jsonable(task.values, None),
        "overrides": dict(task.overrides),
    }


def record_row(task: RunTask, record: RunRecord) -> dict[str, Any]:
    """The row of a run that ran."""
    result = record.result_object()
    metrics = result["metrics"]
    expectations = result["expectations"]
    passed = sum(1 for e in expectations if e["passed"])
    path_length = metrics.get("path_length", metrics.get("tcp_path_length"))
    return {
        **_task_columns(task),
        "result": result["result"],
        "error_code": result["error_code"],
        "error_name": result["error_name"],
        "error_msg": result["error_msg"],
        "intended": result["intended"],
        "exit_code": result["exit_code"],
        "sim_time": result["sim_time"],
        "path_length": path_length if isinstance(path_length, int | float) else None,
        "metrics": metrics,
        "expectations_passed": passed,
        "expectations_failed": len(expectations) - passed,
        "expectations": expectations,
        "trace_digest": result["trace_digest"],
    }


def failed_row(task: RunTask, result: str, name: str, message: str) -> dict[str, Any]:
    """The row of a run that could not run: ``INVALID`` input or an ``ERROR``."""
    return {
        **_task_columns(task),
        "result": result,
        "error_code": None,
        "error_name": name,
        "error_msg": message,
        "intended": False,
        "exit_code": 2 if result == INVALID else None,
        "sim_time": None,
        "path_length": None,
        "metrics": {},
        "expectations_passed": 0,
        "expectations_failed": 0,
        "expectations": [],
        "trace_digest": None,
    }


class CampaignExecutor(Protocol):
    """Runs tasks somewhere; the campaign loop keeps at most :meth:`slots` in flight."""

    description: str

    def slots(self) -> int:
        """How many runs can go at once."""
        ...

    def submit(self, task: RunTask) -> Future[RunOutcome]:
        """Start ``task``."""
        ...

    def abort(self) -> None:
        """Stop the runs in flight now (their outcomes are dropped)."""
        ...

    def close(self) -> None:
        """Release the workers."""
        ...


def _init_local_worker(stop: Event) -> None:
    """In each worker: leave SIGINT to the parent, keep stdout for the parent's ``--json``."""
    global _stop
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    sys.stdout.flush()
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
    _stop = stop


def preload_modules(mission: Mission) -> list[str]:
    """The modules a run of ``mission`` imports, for the forkserver to import once (and numba's
    compiler with the control dispatcher, :mod:`.worker_preload`)."""
    modules = [__name__, "baobab.missions.campaigns.worker_preload"]
    robot = mission.robot
    if robot.mobile:
        modules.append("baobab.robots.diff_drive.robot")
        if robot.body:
            modules.append(robot.body.partition(":")[0])
        if uses_capability(mission, NAVIGATION):
            modules.append("baobab.nav.server")
    else:
        modules.append(robot.runtime)
    return modules


def _process_context(preload: Sequence[str]) -> multiprocessing.context.BaseContext:
    if "forkserver" in multiprocessing.get_all_start_methods():
        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload(list(preload))
        return context
    return multiprocessing.get_context("spawn")


class LocalExecutor:
    """``workers`` local processes, one fresh process per run.

    Args:
        workers: how many runs go at once (>= 1).
        preload: modules the forkserver imports before forking workers (see
            :func:`preload_modules`; only the first pool of a process sets them).
    """

    def __init__(self, workers: int, preload: Sequence[str] = (__name__,)) -> None:
        if workers < 1:
            raise CampaignError(f"--workers must be >= 1, got {workers}")
        self._context = _process_context(preload)
        self.workers = workers
        self.description = f"{workers} local worker{'s' if workers > 1 else ''}"
        self._stop = self._context.Event()
        self._pool = self._new_pool()

    def _new_pool(self) -> ProcessPoolExecutor:
        return ProcessPoolExecutor(
            self.workers,
            mp_context=self._context,
            max_tasks_per_child=1,
            initializer=_init_local_worker,
            initargs=(self._stop,),
        )

    def slots(self) -> int:
        """The number of worker processes."""
        return self.workers

    def submit(self, task: RunTask) -> Future[RunOutcome]:
        """Run ``task`` in a fresh process (in a new pool if a dying worker broke this one)."""
        try:
            return self._pool.submit(execute_run, task)
        except BrokenProcessPool:
            self._pool.shutdown(wait=False, cancel_futures=True)
            self._pool = self._new_pool()
            return self._pool.submit(execute_run, task)

    def abort(self) -> None:
        """Tell the running runs to stop at their next tick."""
        self._stop.set()

    def close(self) -> None:
        """Wait for the processes to exit."""
        self._pool.shutdown(wait=True, cancel_futures=True)


class DaskExecutor:
    """The workers of a ``dask.distributed`` cluster.

    Args:
        address: the scheduler, e.g. ``tcp://127.0.0.1:8786``.

    Raises:
        CampaignError: dask.distributed is not installed, or the scheduler cannot be reached.
    """

    def __init__(self, address: str) -> None:
        try:
            from distributed import Client
        except ImportError:
            raise CampaignError(DASK_MISSING) from None
        try:
            self._client = Client(address, timeout=DASK_CONNECT_TIMEOUT, set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            detail = " ".join(str(exc).split()) or type(exc).__name__
            raise CampaignError(f"--scheduler {address}: cannot reach it: {detail}") from None
        self.description = f"Dask cluster at {address}"
        self._executor = self._client.get_executor(pure=False)
        self._futures: set[Future[RunOutcome]] = set()

    def slots(self) -> int:
        """The cluster's worker threads now (at least 1: tasks wait for workers to join)."""
        return max(1, sum(self._client.nthreads().values()))

    def submit(self, task: RunTask) -> Future[RunOutcome]:
        """Send ``task`` to the cluster."""
        future: Future[RunOutcome] = self._executor.submit(execute_run, task)
        self._futures.add(future)
        future.add_done_callback(self._futures.discard)
        return future

    def abort(self) -> None:
        """Cancel every task in flight (a worker drops a canceled task's result)."""
        for future in list(self._futures):
            future.cancel()

    def close(self) -> None:
        """Disconnect (the cluster keeps running)."""
        self._executor.shutdown(wait=False)
        self._client.close()

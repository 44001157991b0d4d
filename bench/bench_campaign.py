"""Campaign throughput: runs per minute with 1 and 2 local workers (and, asked, on Dask).

Run: ``python bench/bench_campaign.py [--mission walls_go_to_goal] [--runs 8] [--dask]``.

Each configuration runs the same seeded campaign (``start.x`` and ``start.y`` offsets drawn
from uniform(-0.05, 0.05)) through the real executors into a temporary folder; the clock
runs from the first dispatch to the last row written. A one-run campaign first starts the
forkserver (it imports MuJoCo and py_trees once; that start-up is reported on its own), so
both local figures pay only what every campaign pays per run: a fork, the mission load, the
run. The 1-minute load average before and after is printed, since other work on the machine
takes cores from the workers. ``--dask`` also times a LocalCluster of 2 single-threaded
worker processes (started and warmed up before the clock).
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path
from typing import Any

from baobab.missions.campaigns.dispatch import replay_target, results_path, run_campaign
from baobab.missions.campaigns.executors import (
    CampaignExecutor,
    DaskExecutor,
    LocalExecutor,
    preload_modules,
)
from baobab.missions.campaigns.results import ResultsTable, read_rows
from baobab.missions.campaigns.spec import CampaignSpec, build_spec
from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.loader import load_mission

VARY = ["start.x=uniform(-0.05,0.05)", "start.y=uniform(-0.05,0.05)"]


def _spec(mission_name: str, runs: int) -> CampaignSpec:
    path = resolve_mission(mission_name)
    text = path.read_text(encoding="utf-8")
    mission = load_mission(path, {}, text=text)
    return build_spec(mission, path, text, {}, VARY, [], runs, 0)


def _timed(spec: CampaignSpec, executor: CampaignExecutor, folder: Path) -> dict[str, Any]:
    folder.mkdir(parents=True)
    table = ResultsTable(results_path(folder))
    started = time.perf_counter()
    try:
        run_campaign(spec, executor, table, replay_target(spec, "bench", folder))
    finally:
        elapsed = time.perf_counter() - started
        table.close()
    rows = read_rows(results_path(folder))
    run_times = [row["wall_time"] for row in rows]
    return {
        "runs": len(rows),
        "seconds": round(elapsed, 2),
        "runs_per_minute": round(60 * len(rows) / elapsed, 1),
        "mean_run_seconds": round(sum(run_times) / len(run_times), 3),
        "intended": sum(row["intended"] for row in rows),
        "digests": [row["trace_digest"] for row in rows],
    }


def bench_campaign(mission: str, runs: int, dask: bool) -> dict[str, Any]:
    """Measure the figures above; returns a dict."""
    spec = _spec(mission, runs)
    figures: dict[str, Any] = {"mission": mission, "runs": runs, "cores": os.cpu_count()}
    figures["load_average_before"] = round(os.getloadavg()[0], 2)
    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)
        started = time.perf_counter()
        warm_up = LocalExecutor(1, preload_modules(spec.mission))
        try:
            _timed(_spec(mission, 1), warm_up, root / "warm-up")
        finally:
            warm_up.close()
        figures["forkserver_start_and_first_run_seconds"] = round(time.perf_counter() - started, 2)
        for workers in (1, 2):
            executor = LocalExecutor(workers, preload_modules(spec.mission))
            try:
                figures[f"local_{workers}"] = _timed(spec, executor, root / f"local-{workers}")
            finally:
                executor.close()
        if dask:
            figures["dask_2"] = _bench_dask(spec, root)
    figures["load_average_after"] = round(os.getloadavg()[0], 2)
    one, two = figures["local_1"], figures["local_2"]
    figures["speedup_2_workers"] = round(two["runs_per_minute"] / one["runs_per_minute"], 2)
    figures["same_digests"] = all(
        figures[key]["digests"] == one["digests"] for key in ("local_2", "dask_2") if key in figures
    )
    for key in ("local_1", "local_2", "dask_2"):
        if key in figures:
            del figures[key]["digests"]
    return figures


def _bench_dask(spec: CampaignSpec, root: Path) -> dict[str, Any]:
    from distributed import LocalCluster

    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=":0"
    ) as cluster:
        executor = DaskExecutor(cluster.scheduler_address)
        try:
            _timed(_spec(spec.mission_path.as_posix(), 2), executor, root / "dask-warm-up")
            return _timed(spec, executor, root / "dask-2")
        finally:
            executor.close()


def main() -> None:
    """Command-line entry: print the figures as JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mission", default="walls_go_to_goal", help="bundled name or file")
    parser.add_argument("--runs", type=int, default=8, help="runs per configuration")
    parser.add_argument("--dask", action="store_true", help="also time a 2-worker LocalCluster")
    args = parser.parse_args()
    print(json.dumps(bench_campaign(args.mission, args.runs, args.dask), indent=2))


if __name__ == "__main__":
    main()

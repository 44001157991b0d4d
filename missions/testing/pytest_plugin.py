"""pytest plugin: every mission file with an ``expect:`` block is a scenario test.

Installed with baobab (entry point ``pytest11``), so ``pytest missions/`` just works::

    pytest missions/                        # one test item per mission, named after it
    pytest missions/ -n 2 --junitxml=r.xml  # pytest-xdist and JUnit reports work as usual
    pytest missions/ --baobab-seed 7        # run every mission with seed 7
    pytest missions/ --baobab-update-baseline   # (re)write missions/<stem>.baseline.json
    pytest missions/ --baobab-plots all     # draw every run's plot.png (default: failed ones)

Which files: ``*.yaml``/``*.yml`` files with a top-level ``mission:`` key and a top-level
``expect:`` key, found by a cheap text scan (world files, schemas and other YAML are never
parsed). Like any pytest file plugin it collects wherever pytest looks; a folder of mission
fixtures opts out with ``collect_ignore_glob = ["*.yaml"]`` in its ``conftest.py``, a whole
project with ``baobab_missions = false`` in its pytest configuration.

Each item loads its mission at collection (a malformed one becomes an item that errors at
setup with the located ``path:line:col: message``, and the other items still run), runs it
in-process with :func:`~baobab.missions.run.runner.run_mission`, compares the baseline beside the
mission when there is one, and writes its run folder under pytest's temporary directory (or
``--baobab-runs DIR``). A run folder holds ``plot.png`` only when the scenario failed (drawing
it costs more than a short scenario's simulation), unless ``--baobab-plots all`` asks for
every one (``none``: for no one). A failure prints the table of expectations, measured against
expected, the run folder's path and the command that replays the run. Each scenario's loop time
is kept in pytest's cache (``baobab/loop_seconds/<file>/<name>``); under pytest-xdist the workers
collect the scenarios longest first by it, or by their timeouts where it is not known yet
(:func:`expected_seconds`, :func:`longest_first`), so the longest ones do not start last and
leave one worker running alone at the end. In a JUnit report
(:mod:`~baobab.missions.testing.pytest_junit`) each mission is a testcase named by its folder
and name,
with its result, sim time, trace digest, seed, baseline and run folder in its system-out.
"""

from __future__ import annotations

import argparse
import os
import re
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from baobab.missions.testing.pytest_junit import (
    FACTS_SECTION,
    MISSION_LABEL,
    format_facts,
    register,
)

if TYPE_CHECKING:
    from baobab.missions.language.loader import Mission

INI_COLLECT = "baobab_missions"
DURATION_KEY = "baobab/loop_seconds/"
"""pytest cache key prefix of a scenario's last loop time (wall s), by its node id."""
PLOTS_CHOICES = ("failed", "all", "none")
SUFFIXES = (".yaml", ".yml")
_MISSION_KEY = re.compile(rb"^mission[ \t]*:", re.MULTILINE)
_EXPECT_KEY = re.compile(rb"^expect[ \t]*:", re.MULTILINE)
_MISSION_NAME = re.compile(rb"^mission[ \t]*:[ \t]*[\"']?([A-Za-z0-9_][A-Za-z0-9_.-]*)", re.M)
_SCAN_BYTES = 2_000_001
"""Read at most this much of a file to decide (one more than the loader's size limit)."""


def _seed(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {value}")
    return value


def pytest_addoption(parser: pytest.Parser) -> None:
    """The ``--baobab-*`` options and the ``baobab_missions`` ini setting."""
    group = parser.getgroup("baobab", "baobab mission scenarios")
    group.addoption(
        "--baobab-seed",
        type=_seed,
        default=None,
        metavar="N",
        help="run every mission with seed N instead of its own",
    )
    group.addoption(
        "--baobab-update-baseline",
        action="store_true",
        default=False,
        help="write or refresh <mission>.baseline.json beside each mission that turned out "
        "as intended, instead of comparing with it",
    )
    group.addoption(
        "--baobab-runs",
        type=Path,
        default=None,
        metavar="DIR",
        help="write the run folders under DIR (default: pytest's temporary directory)",
    )
    group.addoption(
        "--baobab-plots",
        choices=PLOTS_CHOICES,
        default="failed",
        help="which run folders get a plot.png: failed (default), all or none",
    )
    parser.addini(
        INI_COLLECT,
        type="bool",
        default=True,
        help="collect mission files with an expect: block as tests (default true)",
    )


@pytest.hookimpl(trylast=True)  # after pytest's junitxml plugin made its report writer
def pytest_configure(config: pytest.Config) -> None:
    """Name mission testcases and record their facts in a JUnit report, if one is written."""
    register(config)


def is_scenario_file(path: Path) -> bool:
    """True for a YAML file with top-level ``mission:`` and ``expect:`` keys (text scan)."""
    if path.suffix not in SUFFIXES:
        return False
    try:
        with path.open("rb") as stream:
            head = stream.read(_SCAN_BYTES)
    except OSError:
        return False
    return bool(_MISSION_KEY.search(head)) and bool(_EXPECT_KEY.search(head))


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> pytest.Collector | None:
    """A :class:`MissionYamlFile` for each scenario file, when collection is on."""
    if not parent.config.getini(INI_COLLECT) or not is_scenario_file(file_path):
        return None
    collector: MissionYamlFile = MissionYamlFile.from_parent(parent, path=file_path)
    return collector


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """In a pytest-xdist worker, order the scenarios longest first: by their last loop time,
    or, the first time (or without pytest's cache), by their timeout (:func:`expected_seconds`)."""
    if not hasattr(config, "workerinput"):
        return
    cache = getattr(config, "cache", None)
    durations = {
        item.nodeid: expected_seconds(item, cache)
        for item in items
        if isinstance(item, MissionItem)
    }
    items[:] = longest_first(items, durations)


NOMINAL_SPEED = 150.0
"""Sim seconds per wall second a scenario is taken to run at before its first loop time is
known: only the order of scenarios depends on it."""


def expected_seconds(item: MissionItem, cache: Any) -> float:
    """How long ``item``'s loop is expected to take (wall s): its last one, else its timeout
    (sim s) at :data:`NOMINAL_SPEED` (a mission's timeout grows with its length)."""
    last = None if cache is None else cache.get(duration_key(item.nodeid), None)
    return float(last) if last is not None else item.mission.timeout / NOMINAL_SPEED


def duration_key(nodeid: str) -> str:
    """The cache key of a scenario's loop time (a file name: no ``:``)."""
    return DURATION_KEY + nodeid.replace("::", "/")


def longest_first(items: list[pytest.Item], durations: dict[str, float]) -> list[pytest.Item]:
    """``items`` with those named in ``durations`` (node id: seconds) moved to their places,
    longest first; the others keep their places."""
    places = [index for index, item in enumerate(items) if item.nodeid in durations]
    ordered = list(items)
    by_length = sorted(places, key=lambda index: -durations[items[index].nodeid])
    for place, index in zip(places, by_length, strict=True):
        ordered[place] = items[index]
    return ordered


class MissionYamlFile(pytest.File):
    """A mission file: one :class:`MissionItem`, or one :class:`InvalidMissionItem`."""

    def collect(self) -> Iterator[pytest.Item]:
        """Load and validate the mission (located errors become an erroring item)."""
        from baobab.missions.language.loader import load_mission
        from baobab.sim.errors import BaobabError

        try:
            mission = load_mission(self.path)
        except BaobabError as exc:
            yield InvalidMissionItem.from_parent(
                self, name=self._written_name(), message=_relative_message(exc, self.config)
            )
            return
        yield MissionItem.from_parent(self, name=mission.name, mission=mission)

    def _written_name(self) -> str:
        """The ``mission:`` name as written, else the file's stem (for a broken file)."""
        try:
            match = _MISSION_NAME.search(self.path.read_bytes()[:_SCAN_BYTES])
        except OSError:
            match = None
        return match.group(1).decode("ascii") if match else self.path.stem


class MissionItem(pytest.Item):
    """Runs one mission and passes when it turned out as intended."""

    def __init__(self, *, mission: Mission, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.mission = mission
        self.run_folder: Path | None = None

    def runtest(self) -> None:
        """Run, judge, compare or write the baseline, write the run folder."""
        from baobab.missions.testing.scenario import ScenarioFailedError, run_scenario

        config = self.config
        self.run_folder = self._new_run_folder()
        scenario = run_scenario(
            self.mission,
            seed=config.getoption("baobab_seed"),
            update_baseline=config.getoption("baobab_update_baseline"),
            folder=self.run_folder,
            plots=config.getoption("baobab_plots"),
        )
        record = scenario.record
        cache = getattr(config, "cache", None)
        if cache is not None:  # the next session's order (pytest_collection_modifyitems)
            cache.set(duration_key(self.nodeid), round(record.wall_time, 3))
        error = f" {record.outcome.error_name} ({record.outcome.error_code})"
        facts = {
            "result": record.outcome.result + (error if record.outcome.error_code else ""),
            "sim_time": f"{record.outcome.sim_time:.3f}",
            "trace_digest": record.trace_digest,
            "seed": str(record.seed),
            "baseline": scenario.baseline_status,
            "run_folder": str(scenario.folder),
        }
        self.add_report_section("call", FACTS_SECTION, format_facts(facts))
        if not scenario.intended:
            raise ScenarioFailedError(scenario)

    def _new_run_folder(self) -> Path:
        from baobab.missions.run.run_folder import default_run_folder

        root: Path | None = self.config.getoption("baobab_runs")
        if root is not None:
            return default_run_folder(self.mission.name, root=root)
        factory = getattr(self.config, "_tmp_path_factory", None)  # pytest's tmp_path root
        if isinstance(factory, pytest.TempPathFactory):
            return factory.mktemp(self.mission.name, numbered=True)
        return Path(tempfile.mkdtemp(prefix=f"{self.mission.name}-"))

    def repr_failure(
        self,
        excinfo: pytest.ExceptionInfo[BaseException],
        style: Any = None,
    ) -> str | Any:
        """The scenario report, or a located one-line message for a mission problem."""
        from baobab.missions.testing.scenario import ScenarioFailedError
        from baobab.sim.errors import BaobabError

        error = excinfo.value
        if isinstance(error, ScenarioFailedError):
            return str(error)
        if isinstance(error, BaobabError):
            where = f"\nrun folder: {self.run_folder}" if self.run_folder else ""
            return _relative_message(error, self.config) + where
        return super().repr_failure(excinfo, style=style)

    def reportinfo(self) -> tuple[Path, int, str]:
        """The mission file, the ``mission:`` line (0-based) and a label."""
        line, _column = self.mission.document.locate(("mission",))
        return self.path, line - 1, f"{MISSION_LABEL}{self.mission.name}"


class InvalidMissionItem(pytest.Item):
    """Stands for a mission file that does not load: errors at setup with the located message."""

    def __init__(self, *, message: str, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.message = message

    def setup(self) -> None:
        """Report the mission's problem as an error of this item."""
        pytest.fail(self.message, pytrace=False)

    def runtest(self) -> None:
        """Never reached: :meth:`setup` fails."""

    def reportinfo(self) -> tuple[Path, int, str]:
        """The mission file and a label."""
        return self.path, 0, f"invalid {MISSION_LABEL}{self.name}"


def _relative_message(error: BaseException, config: pytest.Config) -> str:
    """A located error with its path relative to where pytest was started, when inside it."""
    from baobab.sim.errors import SourceError

    if not isinstance(error, SourceError):
        return str(error)
    path = Path(error.path)
    start = config.invocation_params.dir
    if path.is_absolute() and path.is_relative_to(start):
        path = path.relative_to(start)
    return f"{os.fspath(path)}:{error.line}:{error.column}: {error.message}"

"""The pytest plugin: mission files with an ``expect:`` block are scenario tests.

Each test builds a folder of missions in pytester's temporary directory (copies of the quick
bundled walls missions, and variants of them) and runs pytest over it: in this process, or in
a subprocess for pytest-xdist.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from importlib import resources
from pathlib import Path
from types import SimpleNamespace
from typing import Any

# matplotlib, numpy's extension modules and baobab.missions.testing.scenario are imported before any
# inline pytest run: pytester drops the modules an inline run imports when it ends, numpy's
# extension modules cannot be loaded twice in one process (a later test in this worker that
# imports numpy.fft would fail), and importing matplotlib again for every plot would be slow.
import matplotlib.backends.backend_agg
import matplotlib.collections
import matplotlib.figure
import matplotlib.patches
import matplotlib.patheffects  # noqa: F401
import numpy.fft
import numpy.linalg
import numpy.random  # noqa: F401
import pytest
import xmlschema

import baobab.missions.testing.scenario  # noqa: F401
from baobab.missions.testing.pytest_plugin import (
    MissionItem,
    duration_key,
    is_scenario_file,
    longest_first,
    pytest_collection_modifyitems,
)

pytest_plugins = ["pytester"]

BUNDLED = Path(str(resources.files("baobab.missions")))
REPO = Path(__file__).resolve().parents[1]
JUNIT_XSD = Path(__file__).parent / "junit" / "junit-10.xsd"
JUNIT_SCHEMA = xmlschema.XMLSchema(str(JUNIT_XSD))
"""pytest's xunit2 schema (its source is named in the file)."""
BROKEN = """\
# yaml-language-server: $schema=mission.schema.json
mission: broken
world: walls
robot: turtlebot3
tree:
  wait: {duratoin: 3}
expect:
  result: SUCCEEDED
"""


QUIET = ("-p", "no:hypothesispytest", "-p", "no:cacheprovider")
"""Plugins the inner runs do without (hypothesis alone costs a second per run)."""


def _run(pytester: pytest.Pytester, *args: str) -> pytest.RunResult:
    """pytest in this process, without xdist or hypothesis."""
    return pytester.runpytest(*QUIET, "-p", "no:xdist", *args)


def _copy(pytester: pytest.Pytester, *names: str) -> None:
    for name in ("mission.schema.json", *(f"{n}.yaml" for n in names)):
        (pytester.path / name).write_text((BUNDLED / name).read_text())


def _variant(pytester: pytest.Pytester, source: str, name: str, old: str, new: str) -> Path:
    text = (BUNDLED / f"{source}.yaml").read_text()
    assert old in text
    text = text.replace(f"mission: {source}", f"mission: {name}").replace(old, new)
    path = pytester.path / f"{name}.yaml"
    path.write_text(text)
    return path


def _impossible(pytester: pytest.Pytester) -> Path:
    return _variant(pytester, "walls_go_to_goal", "too_fast", "max_sim_time: 60", "max_sim_time: 5")


def test_two_quick_missions_pass_and_other_yaml_is_left_alone(pytester: pytest.Pytester) -> None:
    _copy(pytester, "walls_go_to_goal", "walls_bug2")
    _variant(pytester, "walls_go_to_goal", "no_expect", "expect:", "unchecked:")
    pytester.makefile(".yaml", world="name: room\nfloor: {size: [2, 2]}\n")
    pytester.makefile(".yml", notes="mission: a word in a note\n")
    result = _run(pytester, "-v")
    result.assert_outcomes(passed=2)
    result.stdout.fnmatch_lines(
        [
            "*walls_bug2.yaml::walls_bug2 PASSED*",
            "*walls_go_to_goal.yaml::walls_go_to_goal PASSED*",
        ]
    )
    basetemp = pytester.path.parent / "basetemp"  # where pytester points inline runs
    folders = [path for path in basetemp.glob("walls_*") if not path.is_symlink()]
    assert sorted(path.name for path in folders) == ["walls_bug20", "walls_go_to_goal0"]
    results = [json.loads((path / "result.json").read_text()) for path in folders]
    assert {result["result"] for result in results} == {"SUCCEEDED"}
    # A passing scenario's folder has no plot.png unless asked (--baobab-plots all).
    assert [path for path in folders if (path / "plot.png").exists()] == []


def test_an_impossible_expectation_fails_with_the_table_and_the_run_folder(
    pytester: pytest.Pytester,
) -> None:
    _copy(pytester)
    _impossible(pytester)
    runs = pytester.path / "runs"
    result = _run(pytester, "--baobab-runs", str(runs))
    result.assert_outcomes(failed=1)
    text = result.stdout.str()
    assert "mission 'too_fast' (too_fast.yaml, seed 2) did not turn out as intended" in text
    assert re.search(r"expectation\s+expected\s+measured\s+held\s+detail", text)
    assert re.search(r"max_sim_time\s+5\s+14\.7\s+NO\s+14\.7 s of sim time, at most 5 s", text)
    assert re.search(r"final_pose_near\s+.*\s+yes\s+", text)
    (folder,) = runs.iterdir()
    assert f"run folder: {folder}" in text
    assert "replay: baobab run too_fast.yaml --seed 2" in text
    assert json.loads((folder / "result.json").read_text())["intended"] is False
    assert (folder / "plot.png").read_bytes()[:4] == b"\x89PNG"  # a failure is drawn


@pytest.mark.parametrize(("plots", "drawn"), [("all", True), ("none", False)])
def test_the_plots_option_says_which_run_folders_get_a_plot(
    pytester: pytest.Pytester, plots: str, drawn: bool
) -> None:
    _copy(pytester, "walls_go_to_goal")
    runs = pytester.path / "runs"
    _run(pytester, "--baobab-runs", str(runs), "--baobab-plots", plots).assert_outcomes(passed=1)
    (folder,) = runs.iterdir()
    assert (folder / "plot.png").exists() is drawn
    assert (folder / "result.json").is_file() and (folder / "trace.jsonl").is_file()


def test_a_malformed_mission_is_a_located_error_and_the_others_still_run(
    pytester: pytest.Pytester,
) -> None:
    _copy(pytester, "walls_go_to_goal")
    (pytester.path / "broken.yaml").write_text(BROKEN)
    (pytester.path / "unparsable.yaml").write_text("mission: [oops\nexpect: {}\n")
    result = _run(pytester)
    result.assert_outcomes(passed=1, errors=2)
    text = result.stdout.str()
    assert (
        "broken.yaml:6:10: unknown parameter 'duratoin' in wait; did you mean 'duration'?" in text
    )
    assert re.search(r"unparsable\.yaml:\d+:\d+: ", text)
    assert "Traceback" not in text and "INTERNALERROR" not in text


def _valid_junit(report: Path) -> dict[str, ET.Element]:
    """The testcases by name of a JUnit file that pytest's xunit2 schema accepts."""
    JUNIT_SCHEMA.validate(str(report))  # raises, naming the offending element
    if shutil.which("xmllint"):  # the tool strict CI setups use, where it is installed
        checked = subprocess.run(
            ["xmllint", "--noout", "--schema", str(JUNIT_XSD), str(report)],
            capture_output=True,
            text=True,
            check=False,
        )
        assert checked.returncode == 0, checked.stderr
    return {case.get("name") or "": case for case in ET.parse(report).getroot().iter("testcase")}


def _facts(case: ET.Element) -> dict[str, str]:
    (out,) = case.findall("system-out")
    return dict(line.split(": ", 1) for line in (out.text or "").splitlines())


def test_junitxml_is_valid_xunit2_names_each_item_and_records_its_run(
    pytester: pytest.Pytester,
) -> None:
    _copy(pytester, "walls_go_to_goal")
    _impossible(pytester)
    (pytester.path / "broken.yaml").write_text(BROKEN)
    (pytester.path / "missions").mkdir()
    for name in ("walls_go_to_goal.yaml", "too_fast.yaml", "broken.yaml"):
        (pytester.path / name).rename(pytester.path / "missions" / name)
    report = pytester.path / "report.xml"
    result = _run(pytester, f"--junitxml={report}", "--baobab-seed", "7")
    result.assert_outcomes(passed=1, failed=1, errors=1)
    cases = _valid_junit(report)
    assert set(cases) == {"walls_go_to_goal", "too_fast", "broken"}
    assert {case.get("classname") for case in cases.values()} == {"missions"}
    assert cases["too_fast"].find("failure") is not None
    assert cases["broken"].find("error") is not None
    facts = _facts(cases["walls_go_to_goal"])
    assert list(facts) == ["result", "sim_time", "trace_digest", "seed", "baseline", "run_folder"]
    assert (facts["result"], facts["seed"], facts["baseline"]) == ("SUCCEEDED", "7", "none")
    assert float(facts["sim_time"]) > 5.0
    assert re.fullmatch(r"[0-9a-f]{64}", facts["trace_digest"])
    assert (Path(facts["run_folder"]) / "trace.jsonl").is_file()
    assert _facts(cases["too_fast"])["result"] == "SUCCEEDED"  # as intended it was not: too slow


def test_the_seed_option_is_checked(pytester: pytest.Pytester) -> None:
    result = _run(pytester, "--baobab-seed", "-3")
    assert result.ret == pytest.ExitCode.USAGE_ERROR
    result.stderr.fnmatch_lines(["*--baobab-seed: must be >= 0, got -3*"])


def test_missions_run_under_xdist(pytester: pytest.Pytester) -> None:
    _copy(pytester, "walls_go_to_goal")
    _impossible(pytester)
    report = pytester.path / "report.xml"
    result = pytester.runpytest_subprocess(*QUIET, "-n", "2", f"--junitxml={report}")
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(["*2 workers*", "*max_sim_time*NO*", "*run folder: *"])
    cases = _valid_junit(report)  # the facts came from the workers
    assert {name: _facts(case)["seed"] for name, case in cases.items()} == {
        "walls_go_to_goal": "2",
        "too_fast": "2",
    }
    assert {case.get("classname") for case in cases.values()} == {pytester.path.name}


def test_baselines_are_written_then_guard_against_regressions(pytester: pytest.Pytester) -> None:
    _copy(pytester, "walls_go_to_goal")
    _impossible(pytester)
    written = _run(pytester, "--baobab-update-baseline")
    written.assert_outcomes(passed=1, failed=1)
    baseline = pytester.path / "walls_go_to_goal.baseline.json"
    data = json.loads(baseline.read_text())
    assert data["mission"] == "walls_go_to_goal" and data["metrics"]["sim_time"] == 14.7
    assert not (pytester.path / "too_fast.baseline.json").exists()  # a failed run is no reference
    assert "not written: the run did not turn out as intended" in written.stdout.str()

    (pytester.path / "too_fast.yaml").unlink()
    _run(pytester).assert_outcomes(passed=1)  # compared, and within tolerance

    data["metrics"]["sim_time"] = 10.0  # as if the mission used to finish in 10 s
    baseline.write_text(json.dumps(data))
    regressed = _run(pytester)
    regressed.assert_outcomes(failed=1)
    text = regressed.stdout.str()
    assert re.search(r"baseline\.sim_time\s+.*\s+14\.7\s+NO\s+14\.7 vs baseline 10", text)
    assert "baseline: compared with walls_go_to_goal.baseline.json" in text


def test_collection_can_be_switched_off_for_a_project(pytester: pytest.Pytester) -> None:
    _copy(pytester, "walls_go_to_goal")
    pytester.makeini("[pytest]\nbaobab_missions = false\n")
    _run(pytester).assert_outcomes()


def test_the_projects_own_yaml_is_not_collected_but_missions_are(
    pytester: pytest.Pytester,
) -> None:
    fixtures = _run(
        pytester,
        "--collect-only",
        "-q",
        str(REPO / "tests" / "missions"),
        str(REPO / "sim" / "worlds"),
    )
    assert fixtures.ret == pytest.ExitCode.NO_TESTS_COLLECTED
    bundled = _run(pytester, "--collect-only", "-q", str(REPO / "missions"))
    names = {line.split("::")[-1] for line in bundled.outlines if ".yaml::" in line}
    assert names == {path.stem for path in BUNDLED.glob("*.yaml")}


def test_the_cheap_check_wants_top_level_mission_and_expect_keys(tmp_path: Path) -> None:
    cases = {
        "both.yaml": "mission: a\nexpect:\n  result: SUCCEEDED\n",
        "nested.yaml": "mission: a\ntree:\n  expect: 1\n",
        "quoted.yml": "mission : a\nexpect : {}\n",
        "world.yaml": "name: cafe\nexpect: 1\n",
        "both.txt": "mission: a\nexpect: {}\n",
    }
    for name, text in cases.items():
        (tmp_path / name).write_text(text)
    found = {name for name in cases if is_scenario_file(tmp_path / name)}
    assert found == {"both.yaml", "quoted.yml"}


def test_each_scenario_keeps_its_loop_time_in_pytests_cache(pytester: pytest.Pytester) -> None:
    _copy(pytester, "walls_go_to_goal")
    pytester.runpytest("-p", "no:hypothesispytest", "-p", "no:xdist").assert_outcomes(passed=1)
    key = duration_key("walls_go_to_goal.yaml::walls_go_to_goal")
    seconds = json.loads((pytester.path / ".pytest_cache" / "v" / key).read_text())
    assert isinstance(seconds, float) and seconds > 0


def _item(nodeid: str) -> Any:
    return SimpleNamespace(nodeid=nodeid)


def test_scenarios_are_ordered_longest_first_and_other_tests_keep_their_places() -> None:
    items = [_item(name) for name in ("a", "test_x", "b", "c", "d")]
    durations = {"a": 0.2, "b": 5.0, "c": 3.0, "d": 1.0}
    ordered = longest_first(items, durations)
    assert [item.nodeid for item in ordered] == ["b", "test_x", "c", "d", "a"]


class _Scenario(MissionItem):
    nodeid = ""  # type: ignore[assignment]  (a plain attribute here)


def _scenario(nodeid: str, timeout: float) -> MissionItem:
    """A scenario item with only its node id and its mission's timeout (s)."""
    item = _Scenario.__new__(_Scenario)
    item.nodeid = nodeid
    item.mission = SimpleNamespace(timeout=timeout)  # type: ignore[assignment]
    return item


def test_only_pytest_xdist_workers_reorder_the_scenarios(tmp_path: Path) -> None:
    class Cache:
        def get(self, key: str, default: Any) -> Any:
            return {duration_key("m.yaml::slow"): 9.0}.get(key, default)

    fast, slow = _scenario("m.yaml::fast", 1500.0), _scenario("m.yaml::slow", 60.0)
    items: list[pytest.Item] = [slow, fast]
    pytest_collection_modifyitems(SimpleNamespace(cache=Cache()), items)  # type: ignore[arg-type]
    assert items == [slow, fast]  # a single process: the files' order
    worker = SimpleNamespace(cache=Cache(), workerinput={"workerid": "gw0"})
    pytest_collection_modifyitems(worker, items)  # type: ignore[arg-type]
    assert items == [fast, slow]  # fast, not measured yet: 1500 s timeout at 150x is 10 s > 9 s
    fast_seconds = {duration_key("m.yaml::fast"): 0.5, duration_key("m.yaml::slow"): 9.0}
    worker.cache.get = lambda key, default: fast_seconds.get(key, default)  # type: ignore[method-assign]
    pytest_collection_modifyitems(worker, items)  # type: ignore[arg-type]
    assert items == [slow, fast]


def test_without_pytests_cache_the_timeouts_order_the_first_session() -> None:
    short, long = _scenario("m.yaml::short", 90.0), _scenario("m.yaml::long", 1800.0)
    items: list[pytest.Item] = [short, long]
    worker = SimpleNamespace(cache=None, workerinput={"workerid": "gw0"})  # -p no:cacheprovider
    pytest_collection_modifyitems(worker, items)  # type: ignore[arg-type]
    assert items == [long, short]

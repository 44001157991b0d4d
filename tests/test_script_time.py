"""Time in Nav2 scripts under ``baobab nav2``: a script's waits are sim time.

``time.sleep``, ``Clock.sleep_for`` / ``sleep_until``, ``Rate.sleep`` and
``rclpy.spin_once(timeout_sec=...)`` advance the navigator's simulation; ``time.time`` and
``time.monotonic`` read sim time (offset from the script's start) while a navigator exists;
other threads keep the wall clock; ``--realtime`` keeps the wall clock's readings and paces.
Each script prints what it measured; the tests compare with exact sim times.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from baobab.nav import BasicNavigator
from baobab.nav.ros import UnsupportedRosFeatureError
from baobab.nav.rostime import Clock, ClockType, Duration, Time
from baobab.nav.script_runner import run_nav2_script

PRELUDE = """\
import threading
import time

import rclpy
from nav2_simple_commander.robot_navigator import BasicNavigator
from rclpy.duration import Duration

rclpy.init()
navigator = BasicNavigator()
clock = navigator.get_clock()


def sim():
    return clock.now().nanoseconds / 1e9

"""


def run(
    tmp_path: Path, body: str, capsys: pytest.CaptureFixture[str], **defaults: object
) -> list[str]:
    script = tmp_path / "timing.py"
    script.write_text(PRELUDE + body, encoding="utf-8")
    status = run_nav2_script(script, navigator_defaults={"world": "walls", **defaults})
    captured = capsys.readouterr()
    assert status == 0, captured.err
    return captured.out.split()


def test_the_clock_wait_loop_ends_after_two_seconds_of_sim_time(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = """\
start = clock.now()
polls = 0
while clock.now() - start < Duration(seconds=2):
    time.sleep(0.1)
    polls += 1
print(sim(), polls)
"""
    assert run(tmp_path, body, capsys) == ["2.0", "20"]


def test_time_sleep_advances_sim_time_and_time_reads_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = """\
wall, steady, before = time.time(), time.monotonic(), sim()
time.sleep(0.37)
time.sleep(0)
print(round(sim() - before, 6), round(time.time() - wall, 6), round(time.monotonic() - steady, 6))
ns = time.monotonic_ns()
time.sleep(1.5)
print(time.monotonic_ns() - ns, round(abs(time.time_ns() / 1e9 - time.time()), 3))
try:
    time.sleep(-1)
except ValueError as exc:
    print("refused")
"""
    assert run(tmp_path, body, capsys) == ["0.37", "0.37", "0.37", "1500000000", "0.0", "refused"]


def test_clock_sleeps_rates_and_spin_once_advance_sim_time(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = """\
from rclpy.time import Time

clock.sleep_for(Duration(seconds=1.25))
print(sim())
clock.sleep_until(clock.now() + Duration(seconds=0.75))
print(sim())
clock.sleep_until(Time(seconds=1.0, clock_type=clock.clock_type))  # in the past: at once
print(sim())
node = rclpy.create_node("ticker")
ticks = []
node.create_timer(0.5, lambda: ticks.append(sim()))
rclpy.spin_once(node, timeout_sec=0.2)  # nothing due: the whole timeout passes
print(round(sim(), 3))
rclpy.spin_once(node, timeout_sec=5.0)  # returns with the timer's callback
print(ticks)
node.create_rate(4).sleep()
print(sim())
"""
    assert run(tmp_path, body, capsys) == ["1.25", "2.0", "2.0", "2.2", "[2.5]", "2.75"]


def test_spin_runs_node_timers_on_sim_time(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = """\
node = rclpy.create_node("counter")
ticks = []


def tick():
    ticks.append(sim())
    if len(ticks) == 3:
        rclpy.shutdown()


node.create_timer(1.0, tick)
rclpy.spin(node)
print(ticks)
"""
    assert run(tmp_path, body, capsys) == ["[1.0,", "2.0,", "3.0]"]


def test_other_threads_and_time_before_a_navigator_keep_the_wall_clock(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = tmp_path / "threads.py"
    script.write_text(
        """\
import threading
import time
from datetime import datetime

before = time.monotonic()
time.sleep(0.01)  # no navigator yet: a real sleep
import rclpy
from nav2_simple_commander.robot_navigator import BasicNavigator

rclpy.init()
navigator = BasicNavigator()
sim = lambda: navigator.get_clock().now().nanoseconds / 1e9
after_start = time.monotonic()
seen = {}


def worker():
    seen["offset"] = time.time() - datetime.now().timestamp()
    time.sleep(0.01)  # another thread: a real sleep
    seen["sim"] = sim()


thread = threading.Thread(target=worker)
thread.start()
thread.join()
script_before, wall_before = time.time(), datetime.now().timestamp()
time.sleep(30.0)
script_after, wall_after = time.time(), datetime.now().timestamp()
print(after_start >= before, abs(seen["offset"]) < 1.0, seen["sim"])
# time.time() moved by the 30 s of sim time; datetime by the wall time the sleep took (less)
print(round(script_after - script_before, 6) == 30.0 and wall_after - wall_before < 30.0)
navigator.destroy_node()
later = time.monotonic()
time.sleep(0.01)
print(time.monotonic() >= later)
""",
        encoding="utf-8",
    )
    assert run_nav2_script(script, navigator_defaults={"world": "walls"}) == 0
    assert capsys.readouterr().out.split() == ["True", "True", "0.0", "True", "True"]


def test_realtime_keeps_the_wall_clocks_readings_and_sleeps_advance_paced(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = """\
from datetime import datetime

start = clock.now()
while clock.now() - start < Duration(seconds=0.3):
    time.sleep(0.1)
print(sim(), abs(time.time() - datetime.now().timestamp()) < 0.5)
"""
    assert run(tmp_path, body, capsys, realtime=True) == ["0.3", "True"]


def test_clock_sleeps_outside_a_script_use_the_navigator_or_refuse() -> None:
    clock = Clock(clock_type=ClockType.ROS_TIME)
    with pytest.raises(UnsupportedRosFeatureError, match=r"sleep_until\(\).*BasicNavigator"):
        clock.sleep_for(Duration(seconds=1.0))
    with pytest.raises(TypeError):
        clock.sleep_until(5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="clock type"):
        clock.sleep_until(Time(seconds=1, clock_type=ClockType.SYSTEM_TIME))
    navigator = BasicNavigator(world="walls")
    try:
        own = navigator.get_clock()
        assert own.sleep_for(Duration(seconds=0.5)) is True
        assert own.now().nanoseconds == 500_000_000
        assert clock.now().nanoseconds == 500_000_000  # every clock reads the same sim time
    finally:
        navigator.destroy_node()
    with pytest.raises(UnsupportedRosFeatureError):
        clock.sleep_for(Duration(seconds=1.0))  # the navigator is gone: nothing can wait

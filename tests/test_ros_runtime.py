"""The ROS runtime without physics: timers, rates, sleeps, topics, QoS, executors, threads,
run endings and failures, on a virtual clock (baobab.nav.ros.runtime, actors, graph)."""

from __future__ import annotations

from pathlib import Path

import pytest
from ros_harness import run_node_files, write_nodes

from baobab.nav.ros.runtime import RosRuntime

TIMES = """\
import time
import rclpy
from rclpy.node import Node

def main():
    rclpy.init()
    node = Node('clocked')
    now = lambda: node.get_clock().now().nanoseconds
    seen = []
    node.create_timer(0.3, lambda: seen.append(('timer', now())))
    time.sleep(0.1)
    node.create_timer(0.25, lambda: seen.append(('late timer', now())))
    rate = node.create_rate(4.0)
    for _ in range(3):
        rate.sleep()
        seen.append(('rate', now()))
    end = now() + 600_000_000
    while now() < end:
        rclpy.spin_once(node, timeout_sec=1.0)
    print(sorted(seen, key=lambda item: item[1]))
"""


def test_timers_rates_and_sleeps_fire_at_the_sim_times_ros_schedules(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = write_nodes(tmp_path, {"times.py": TIMES})
    end = run_node_files(RosRuntime(), paths, 5.0)
    assert end.failures == [] and end.sim_time == pytest.approx(1.5)
    ms = 1_000_000
    assert eval(capsys.readouterr().out) == [
        ("rate", 350 * ms),  # the rate was made at 0.1 s: ticks at 0.35, 0.6, 0.85
        ("rate", 600 * ms),
        ("rate", 850 * ms),
        # Nothing spun the timers while the code slept in rate.sleep(): at 0.85 s both are
        # overdue and run once, and rcl moves each past the periods it missed. The 0.25 s
        # timer (due 0.35) lands exactly on 0.85 again, so rcl finds it ready at once.
        ("timer", 850 * ms),
        ("late timer", 850 * ms),
        ("late timer", 850 * ms),
        ("timer", 900 * ms),
        ("late timer", 1100 * ms),
        ("timer", 1200 * ms),
        ("late timer", 1350 * ms),
        ("timer", 1500 * ms),  # the wait that began at 1.35 s ends with this call
    ]


BURST = """\
import rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy, DurabilityPolicy
from std_msgs.msg import Int32

def main():
    rclpy.init()
    talker, listener = Node('talker'), Node('listener')
    heard = {'depth2': [], 'keep_all': [], 'reliable_from_best_effort': [], 'latched': []}
    for key, qos in (('depth2', 2), ('keep_all', QoSProfile(history=2))):
        listener.create_subscription(Int32, 'numbers', lambda m, key=key: heard[key].append(m.data), qos)
    best_effort = talker.create_publisher(Int32, 'noisy', QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT))
    listener.create_subscription(Int32, 'noisy', lambda m: heard['reliable_from_best_effort'].append(m.data), 10)
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    talker.create_publisher(Int32, 'config', latched).publish(Int32(data=7))
    publisher = talker.create_publisher(Int32, 'numbers', 10)
    for number in range(5):
        publisher.publish(Int32(data=number))
    best_effort.publish(Int32(data=1))
    listener.create_subscription(Int32, 'config', lambda m: heard['latched'].append(m.data), latched)
    executor = rclpy.executors.MultiThreadedExecutor()
    executor.add_node(listener)
    executor.spin_once(timeout_sec=0.5)
    first = dict((key, list(value)) for key, value in heard.items())
    for _ in range(10):
        executor.spin_once(timeout_sec=0.0)
    print(first)
    print(heard)
"""


def test_queues_keep_their_qos_depth_and_qos_rules_decide_who_hears_what(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = write_nodes(tmp_path, {"burst.py": BURST})
    assert run_node_files(RosRuntime(), paths, 1.0).failures == []
    out, err = capsys.readouterr()
    first, final = (eval(line) for line in out.splitlines())
    assert first == {"depth2": [3], "keep_all": [], "reliable_from_best_effort": [], "latched": []}
    assert final == {
        "depth2": [3, 4],
        "keep_all": [0, 1, 2, 3, 4],
        "reliable_from_best_effort": [],
        "latched": [7],
    }
    assert (
        "[WARN] [0.000000000] [listener]: New publisher discovered on topic '/noisy', offering "
        "incompatible QoS. No messages will be received from it. Last incompatible policy: "
        "RELIABILITY"
    ) in err


SPIN_THREAD = """\
import threading
import rclpy
from rclpy.node import Node
from std_msgs.msg import String

def main():
    rclpy.init()
    node = Node('threaded')
    heard = []
    node.create_subscription(String, 'echo', lambda m: heard.append((m.data, node.get_clock().now().nanoseconds)), 10)
    publisher = node.create_publisher(String, 'echo', 10)
    spinner = threading.Thread(target=rclpy.spin, args=(node,), daemon=True)
    spinner.start()
    rate = node.create_rate(10)
    for index in range(3):
        publisher.publish(String(data=str(index)))
        rate.sleep()
    print(heard, rclpy.ok())
    rclpy.shutdown()
    spinner.join()
    print('joined at', node.get_clock().now().nanoseconds)
"""


def test_a_spin_thread_started_by_node_code_runs_beside_a_rate_loop(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = write_nodes(tmp_path, {"threaded.py": SPIN_THREAD})
    end = run_node_files(RosRuntime(), paths, 2.0)
    assert end.failures == [] and end.sim_time == pytest.approx(0.3)
    assert capsys.readouterr().out.splitlines() == [
        "[('0', 0), ('1', 100000000), ('2', 200000000)] True",
        "joined at 300000000",
    ]


ENDING = """\
import rclpy
from rclpy.node import Node

def main():
    rclpy.init()
    node = Node('ending')
    node.create_timer(0.5, lambda: None)
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        print('interrupted at', node.get_clock().now().nanoseconds)
        rclpy.spin_once(node, timeout_sec=1.0)
        print('never printed')
    finally:
        print('cleaned up')
"""

FAILING = """\
import rclpy
from rclpy.node import Node

class Faulty(Node):
    def __init__(self):
        super().__init__('faulty')
        self.create_timer(0.2, self.tick)
        self.ticks = 0

    def tick(self):
        self.ticks += 1
        if self.ticks == 3:
            raise ZeroDivisionError('the third tick fails')

def main():
    rclpy.init()
    rclpy.spin(Faulty())
"""


def test_the_end_of_a_run_interrupts_spinning_code_as_ctrl_c_does(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = write_nodes(tmp_path, {"ending.py": ENDING})
    end = run_node_files(RosRuntime(), paths, 1.2)
    assert end.failures == [] and end.sim_time == pytest.approx(1.2)
    assert capsys.readouterr().out.splitlines() == ["interrupted at 1200000000", "cleaned up"]


def test_an_exception_in_a_callback_stops_the_run_and_names_the_node(tmp_path: Path) -> None:
    from baobab.nav.ros.node_files import failure_report

    paths = write_nodes(tmp_path, {"ok.py": ENDING, "faulty.py": FAILING})
    runtime = RosRuntime()
    end = run_node_files(runtime, paths, 10.0)
    assert end.sim_time == pytest.approx(0.6)
    [failure] = end.failures
    assert failure.actor.origin == str(paths[1]) and isinstance(failure.error, ZeroDivisionError)
    report = failure_report(failure.actor.origin, ["faulty"], failure.error)
    assert report.startswith("Traceback (most recent call last):\n")
    assert f'File "{paths[1]}", line 13, in tick' in report
    assert report.endswith(
        f"{paths[1]}: node code failed ('faulty'): ZeroDivisionError: the third tick fails"
    )


def test_the_same_node_files_give_the_same_trace_digest(tmp_path: Path) -> None:
    paths = write_nodes(tmp_path, {"burst.py": BURST, "threaded.py": SPIN_THREAD})
    digests = set()
    for _ in range(2):
        runtime = RosRuntime()
        run_node_files(runtime, paths, 1.0)
        digests.add(runtime.trace_digest)
    assert len(digests) == 1 and runtime.scheduler.actors[1].error is None
    changed = RosRuntime()
    run_node_files(changed, paths[:1], 1.0)
    assert changed.trace_digest not in digests


FUTURES = """\
import rclpy
from rclpy.node import Node
from rclpy.task import Future

def main():
    rclpy.init()
    node = Node('waiter')
    now = lambda: node.get_clock().now().nanoseconds
    done = Future()
    node.create_timer(0.4, lambda: done.done() or done.set_result(now()))
    rclpy.spin_until_future_complete(node, done, timeout_sec=0.1)
    print('timed out', done.done(), now())
    rclpy.spin_until_future_complete(node, done)
    print('done', done.result(), now())
    executor = rclpy.executors.SingleThreadedExecutor()
    executor.add_node(node)
    task = executor.create_task(lambda: 6 * 7)
    executor.spin_until_future_complete(task, timeout_sec=1.0)
    print('task', task.result(), now())
"""


def test_spin_until_future_complete_waits_on_sim_time_with_a_timeout(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = write_nodes(tmp_path, {"futures.py": FUTURES})
    assert run_node_files(RosRuntime(), paths, 2.0).failures == []
    assert capsys.readouterr().out.splitlines() == [
        "timed out False 100000000",
        "done 400000000 400000000",
        "task 42 400000000",
    ]

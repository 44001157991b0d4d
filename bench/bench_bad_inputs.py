"""Benchmark: how long the real `baobab` command takes to refuse each bad input.

Usage: ``python bench/bench_bad_inputs.py [--commands validate run] [--only-huge]``

Every case of the bad-input corpus (tests/bad_inputs/, the same table as
tests/test_bad_inputs.py) plus huge documents made here (a 50 MB file, 50,500, 200,500 and
~700,000 values, values under the limit that fail validation, deep nesting, alias fan-out,
a syntax error or a control character at the end of a 2 MB file, a duplicate key or a tab
after 48 KB), special files (/dev/zero, /dev/urandom, a FIFO with and without a writer, a
socket) and inputs over the size limits (a 10 km world, 1001 obstacles, 1001 events, a
1.5 MB location name) goes through the installed console script as a fresh process, as a
user would run it: ``baobab validate FILE`` and ``baobab run FILE --out DIR``. So do whole
command lines that must be refused (issue 19): a special or deeply nested ``--baseline``,
special ``baobab nav2`` scripts and worlds, a blocked default spawn, campaign grids over the
run limit, argparse usage errors, a folder as ``--record``, unusable ``--live`` addresses,
arguments that are not UTF-8. Each must exit 2 with one line on stderr and no traceback, in
under a second (issues 12 and 19). Prints the slowest cases (wall time, and the process's CPU
time, which other processes on the machine do not inflate) and writes bench_bad_inputs.json.

The processes use a private bytecode cache (PYTHONPYCACHEPREFIX), as an installed baobab has
compiled modules; the first, warming run of each command (and of each whole command line) is
not timed.
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
BODY = "mission: m\nworld: walls\nrobot: turtlebot3\ntree: {wait: 1}\n"
TARGET_S = 1.0
HANG_GUARD_S = 60.0
"""A refusal still running after this long is stopped and counted as not refused."""


@dataclass
class Timing:
    """One bad input through one command."""

    case: str
    command: str
    seconds: float
    cpu_seconds: float
    exit_code: int
    one_line: bool

    @property
    def ok(self) -> bool:
        """Refused as the corpus requires: exit 2, one stderr line, under a second."""
        return self.exit_code == 2 and self.one_line and self.seconds < TARGET_S


def huge_inputs(folder: Path) -> dict[str, tuple[Path, tuple[str, ...]]]:
    """Inputs too big to commit: name -> (file, extra arguments)."""
    made: dict[str, str | bytes] = {
        "values 50,500": HEADER + BODY + "description: [" + "0, " * 50_500 + "0]\n",
        "values 200,500": HEADER + BODY + "description: [" + "0, " * 200_500 + "0]\n",
        "values in 1.9 MB": HEADER + BODY + "description: [" + "0, " * 630_000 + "0]\n",
        "values 19,000 under the limit": HEADER + BODY + "description: [" + "0, " * 19_000 + "0]\n",
        "nested lists 18,000 under the limit": HEADER
        + BODY
        + "description: ["
        + "[0], " * 9_000
        + "0]\n",
        "block list 19,000 under the limit": HEADER + BODY + "description:\n" + "- 0\n" * 19_000,
        "alias fan-out 60 x 1,000": HEADER
        + BODY
        + "a: &a ["
        + "0, " * 999
        + "0]\nb: ["
        + "*a, " * 59
        + "*a]\n",
        "flow nesting 10,000": HEADER + BODY + "description: " + "[" * 10_000 + "]" * 10_000,
        "block nesting 2,000": HEADER
        + BODY
        + "description:\n"
        + "".join("  " * i + "-\n" for i in range(1, 2_000)),
        "syntax error after 1.9 MB": HEADER + BODY + "description: [" + "0, " * 630_000 + "0\n",
        "duplicate key after 48 KB": HEADER
        + BODY
        + "description: ["
        + "0, " * 16_000
        + "0]\nmission: n\n",
        "tab after 48 KB": HEADER + BODY + "description: [" + "0, " * 16_000 + "0]\n\tx: 1\n",
        "control character after 1.9 MB": HEADER
        + BODY
        + "description: ["
        + "0, " * 630_000
        + "0]\n\x07\n",
    }
    cases: dict[str, tuple[Path, tuple[str, ...]]] = {}
    for index, (name, content) in enumerate(made.items()):
        path = folder / f"huge_{index}.yaml"
        if isinstance(content, str):
            path.write_text(content, encoding="utf-8")
        else:
            path.write_bytes(content)
        cases[name] = (path, ())
    fifty = folder / "fifty_mb.yaml"
    with fifty.open("wb") as stream:
        stream.write((HEADER + "mission: m\n").encode())
        stream.truncate(50 * 1024 * 1024)
    cases["50 MB file"] = (fifty, ())
    return cases


def limit_inputs(folder: Path) -> dict[str, tuple[Path, tuple[str, ...]]]:
    """Files over the size limits, or that a run would refuse: name -> (file, extra arguments)."""
    body = "mission: m\nrobot: turtlebot3\ntree: {wait: 1}\n"
    world = "name: w\nfloor: {size: [%s]}\nspawns:\n  default: {x: 0, y: 0}\n"
    boxes = "".join(
        f"  - {{name: b{i}, center: [{-1.9 + 0.01 * (i % 300):.2f}, {1 + 0.003 * (i // 300)}], "
        "size: [0.005, 0.002]}\n"
        for i in range(1001)
    )
    files = {
        "world_10km.yaml": world % "10000, 10000",
        "world_boxes.yaml": (world % "4, 4") + "boxes:\n" + boxes,
        "world_blocked.yaml": (world % "4, 4")
        + "cylinders:\n  - {name: pillar, center: [0, 0], radius: 0.5}\n",
    }
    for name, text in files.items():
        (folder / name).write_text(text)
    made = {
        "world 10 km across": HEADER + body + "world: world_10km.yaml\n",
        "world of 1001 obstacles": HEADER + body + "world: world_boxes.yaml\n",
        "default spawn in a pillar": HEADER + body + "world: world_blocked.yaml\n",
        "1001 events": HEADER
        + body
        + "world: walls\ntimeout: 2000\nevents:\n"
        + "".join(f"  - {{at: {i}, cancel: true}}\n" for i in range(1001)),
        "location name of 1.5 MB": HEADER
        + BODY.replace("{wait: 1}", "{navigate_to_pose: " + "a" * 1_500_000 + "}"),
    }
    cases: dict[str, tuple[Path, tuple[str, ...]]] = {}
    for index, (name, text) in enumerate(made.items()):
        path = folder / f"limit_{index}.yaml"
        path.write_text(text)
        cases[name] = (path, ())
    return cases


@contextmanager
def special_inputs(folder: Path) -> Iterator[dict[str, tuple[Path, tuple[str, ...]]]]:
    """Devices, FIFOs and a socket as mission files (kept open while the bench runs)."""
    fifo, held, socket_path = folder / "fifo.yaml", folder / "held.yaml", folder / "socket.yaml"
    os.mkfifo(fifo)
    os.mkfifo(held)
    writer = os.open(held, os.O_RDWR | os.O_NONBLOCK)
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(str(socket_path))
    server.listen()
    try:
        yield {
            "/dev/zero": (Path("/dev/zero"), ()),
            "/dev/urandom": (Path("/dev/urandom"), ()),
            "FIFO": (fifo, ()),
            "FIFO held open by a writer": (held, ()),
            "socket": (socket_path, ()),
        }
    finally:
        server.close()
        os.close(writer)


def command_inputs(folder: Path, taken_port: int) -> dict[str, list[str]]:
    """Whole command lines that must be refused: name -> arguments after ``baobab``."""
    mission = folder / "valid.yaml"
    mission.write_text(HEADER + BODY)
    deep = folder / "deep.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)
    script = folder / "script.py"
    script.write_text("print('ran')\n")
    (folder / "record_folder").mkdir()
    newline = folder / "bad\nname.yaml"
    newline.write_text(HEADER + BODY.replace("wait: 1", "wait: -1"))
    undecodable = b"\xff".decode("utf-8", "surrogateescape")
    run = ["run", str(mission), "--out", "{out}"]
    campaign = ["campaign", "walls_go_to_goal", "--out", "{out}"]
    return {
        "--baseline /dev/zero": [*run, "--baseline", "/dev/zero"],
        "--baseline FIFO": [*run, "--baseline", str(folder / "fifo.yaml")],
        "--baseline nested 100,000 deep": [*run, "--baseline", str(deep)],
        "nav2 script /dev/zero": ["nav2", "/dev/zero", "--world", "walls"],
        "nav2 script FIFO": ["nav2", str(folder / "fifo.yaml"), "--world", "walls"],
        "nav2 --world /dev/urandom": ["nav2", str(script), "--world", "/dev/urandom"],
        "nav2 --world 10 km across": [
            "nav2",
            str(script),
            "--world",
            str(folder / "world_10km.yaml"),
        ],
        "nav2 default spawn in a pillar": [
            "nav2",
            str(script),
            "--world",
            str(folder / "world_blocked.yaml"),
        ],
        "campaign grid of 10^8 points": [*campaign, "--vary", "start.x=grid(0,1,100000000)"],
        "campaign of 10^6 runs": [*campaign, "--runs", "1000000"],
        "campaign mission FIFO": ["campaign", str(folder / "fifo.yaml"), "--runs", "2"],
        "usage: no MISSION": ["run"],
        "usage: bad --port": ["run", str(mission), "--port", "70000"],
        "usage: unknown command": ["frobnicate"],
        "--record a folder": [*run, "--record", str(folder / "record_folder")],
        "--live unknown host": [*run, "--live", "--host", "no-such-host.invalid"],
        "--live port taken": [*run, "--live", "--port", str(taken_port)],
        "--set not UTF-8": [*run, "--set", f"x={undecodable}"],
        "mission path with a line break": ["validate", str(newline)],
    }


def corpus_inputs() -> dict[str, tuple[Path, tuple[str, ...]]]:
    """The committed corpus, with the ``--set`` cases, from the test module's tables."""
    sys.path.insert(0, str(REPO / "tests"))
    import test_bad_inputs as corpus  # the tests folder is not a package

    return {
        case.name: (case.given, tuple(arg for value in case.sets for arg in ("--set", value)))
        for case in corpus.ALL_CASES
    }


def time_case(
    name: str, path: Path, extra: tuple[str, ...], command: str, out: Path, env: dict[str, str]
) -> Timing:
    """Run one command on one input in a fresh process."""
    args = [command, str(path), *extra]
    if command == "run":
        args += ["--out", str(out)]
    return time_command(name, command, args, env)


def time_command(name: str, command: str, args: list[str], env: dict[str, str]) -> Timing:
    """Run ``baobab ARGS`` in a fresh process (stopped after :data:`HANG_GUARD_S`)."""
    baobab = str(Path(sys.executable).with_name("baobab"))
    before = os.times()
    began = time.perf_counter()
    try:
        done = subprocess.run(
            [baobab, *args], capture_output=True, env=env, timeout=HANG_GUARD_S, check=False
        )
        code, stderr = done.returncode, done.stderr.decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        code, stderr = -1, "(hung)"
    seconds = time.perf_counter() - began
    after = os.times()
    cpu = (after.children_user - before.children_user) + (
        after.children_system - before.children_system
    )
    lines = stderr.splitlines()
    one_line = len(lines) == 1 and "Traceback" not in stderr
    return Timing(name, command, seconds, cpu, code, one_line)


def bench_bad_inputs(commands: tuple[str, ...], only_huge: bool) -> list[Timing]:
    """Time every case through every command."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    timings: list[Timing] = []
    with tempfile.TemporaryDirectory() as scratch, socket.socket() as listener:
        folder = Path(scratch)
        listener.bind(("127.0.0.1", 0))
        listener.listen()
        env["PYTHONPYCACHEPREFIX"] = str(folder / "pycache")
        with special_inputs(folder) as special:
            cases = huge_inputs(folder)
            cases.update(special)
            cases.update(limit_inputs(folder))
            if not only_huge:
                cases.update(corpus_inputs())
            first = next(iter(cases.values()))
            for command in commands:
                time_case("warm-up", *first, command, folder / "warm", env)
            lines = command_inputs(folder, listener.getsockname()[1])
            for warming in (True, False):  # each command's modules compiled once, untimed
                for index, (name, args) in enumerate(lines.items()):
                    out = str(folder / f"command_{index}")
                    filled = [out if arg == "{out}" else arg for arg in args]
                    timing = time_command(name, args[0], filled, env)
                    if not warming:
                        timings.append(timing)
            for index, (name, (path, extra)) in enumerate(cases.items()):
                for command in commands:
                    out = folder / f"run_{index}_{command}"
                    timings.append(time_case(name, path, extra, command, out, env))
    return timings


def main() -> None:
    """Measure, print the slowest cases, write bench_bad_inputs.json."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--commands", nargs="+", default=["validate", "run"])
    parser.add_argument("--only-huge", action="store_true", help="skip the committed corpus")
    parser.add_argument("--output", default="bench_bad_inputs.json")
    args = parser.parse_args()
    timings = bench_bad_inputs(tuple(args.commands), args.only_huge)
    timings.sort(key=lambda timing: -timing.seconds)
    width = max(len(timing.case) for timing in timings)
    print(f"{len(timings)} refusals; the slowest:")
    for timing in timings[:15]:
        flag = "" if timing.ok else "   <-- NOT OK"
        print(
            f"  {timing.case:<{width}}  {timing.command:<8} {timing.seconds:6.3f} s"
            f" ({timing.cpu_seconds:5.2f} s CPU)"
            f"  exit {timing.exit_code}{'' if timing.one_line else ' (not one line)'}{flag}"
        )
    bad = [timing for timing in timings if not timing.ok]
    max_cpu = max(timing.cpu_seconds for timing in timings)
    print(
        f"max {timings[0].seconds:.3f} s ({max_cpu:.2f} s CPU); {len(bad)} not refused as required"
    )
    report = {
        "max_seconds": timings[0].seconds,
        "max_cpu_seconds": max_cpu,
        "not_ok": len(bad),
        "timings": [{**asdict(timing), "ok": timing.ok} for timing in timings],
    }
    Path(args.output).write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()

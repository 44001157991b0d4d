"""Benchmark: how long the real `baobab` command takes to refuse each bad input.

Usage: ``python bench/bench_bad_inputs.py [--commands validate run] [--only-huge]``

Every case of the bad-input corpus (tests/bad_inputs/, the same table as
tests/test_bad_inputs.py) plus huge documents made here (a 50 MB file, 50,500, 200,500 and
~700,000 values, values under the limit that fail validation, deep nesting, alias fan-out,
a syntax error or a control character at the end of a 2 MB file, a duplicate key or a tab
after 48 KB) goes through the installed
console script as a fresh process, as a user would run it: ``baobab validate FILE`` and
``baobab run FILE --out DIR``. Each must exit 2 with one line on stderr and no traceback, in
under a second (issue 12). Prints the slowest cases (wall time, and the process's CPU time,
which other processes on the machine do not inflate) and writes bench_bad_inputs.json.

The processes use a private bytecode cache (PYTHONPYCACHEPREFIX), as an installed baobab has
compiled modules; the first, warming run is not timed.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
BODY = "mission: m\nworld: walls\nrobot: turtlebot3\ntree: {wait: 1}\n"
TARGET_S = 1.0


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
    baobab = str(Path(sys.executable).with_name("baobab"))
    args = [baobab, command, str(path), *extra]
    if command == "run":
        args += ["--out", str(out)]
    before = os.times()
    began = time.perf_counter()
    done = subprocess.run(args, capture_output=True, text=True, env=env, check=False)
    seconds = time.perf_counter() - began
    after = os.times()
    cpu = (after.children_user - before.children_user) + (
        after.children_system - before.children_system
    )
    lines = done.stderr.splitlines()
    one_line = len(lines) == 1 and "Traceback" not in done.stderr
    return Timing(name, command, seconds, cpu, done.returncode, one_line)


def bench_bad_inputs(commands: tuple[str, ...], only_huge: bool) -> list[Timing]:
    """Time every case through every command."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    timings: list[Timing] = []
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        env["PYTHONPYCACHEPREFIX"] = str(folder / "pycache")
        cases = huge_inputs(folder)
        if not only_huge:
            cases.update(corpus_inputs())
        first = next(iter(cases.values()))
        time_case("warm-up", *first, "validate", folder / "warm", env)
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

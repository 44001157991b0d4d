"""Benchmark: how long ``baobab run`` takes to refuse an output it could not write.

Usage: ``python bench/bench_output_refusals.py`` (as root, for the tmpfs mounts)

Each case runs the installed console script as a fresh process on a valid mission
(``wait: 1`` in the walls world), with an output that cannot be written: ``--out`` on a
read-only or full file system (real tmpfs mounts), a file, a folder that another run holds,
``--record`` to a folder or a device, ``--baseline`` to be made on a read-only file system,
``--live`` on a port in use. Each must exit 2 with one line on stderr, before any physics, in
under a second (issue 19); the CPU time is printed too, which other processes on a busy
machine do not inflate. It also measures how soon after ``exec`` the process handles
SIGINT, SIGTERM and SIGHUP itself (from then on a signal never prints a traceback): the
median over 20 starts of ``baobab list``, read from ``/proc/PID/status``.
"""

from __future__ import annotations

import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BAOBAB = str(Path(sys.executable).with_name("baobab"))
MISSION = (
    "# yaml-language-server: $schema=mission.schema.json\n"
    "mission: pause\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: {seconds}\n"
)
TARGET_S = 1.0


def mount(where: Path, size_kib: int, *, read_only: bool = False) -> None:
    """A tmpfs of ``size_kib`` KiB at ``where``, read-only if asked."""
    where.mkdir()
    options = f"size={size_kib}k"
    subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(where)], check=True)
    if read_only:
        subprocess.run(["mount", "-o", "remount,ro", str(where)], check=True)


def refuse(name: str, arguments: list[str], mission: Path) -> bool:
    """Time one refusal; print it; True when it met the contract."""
    before = os.times()
    began = time.perf_counter()
    done = subprocess.run([BAOBAB, "run", str(mission), *arguments], capture_output=True, text=True)
    seconds = time.perf_counter() - began
    after = os.times()
    cpu = sum(after[i] - before[i] for i in (2, 3))  # children's user and system time
    ok = (
        done.returncode == 2
        and done.stdout == ""
        and done.stderr.count("\n") == 1
        and seconds < TARGET_S
    )
    verdict = "" if ok else "  <-- NOT OK"
    print(f"  {name:<40} {seconds:6.3f} s ({cpu:5.2f} s CPU)  exit {done.returncode}{verdict}")
    return ok


def handler_delay_ms(starts: int = 20) -> float:
    """Median ms from spawning ``baobab list`` until it handles SIGHUP itself."""
    delays = []
    for _ in range(starts):
        began = time.perf_counter()
        process = subprocess.Popen([BAOBAB, "list"], stdout=subprocess.DEVNULL)
        while True:
            try:
                status = Path(f"/proc/{process.pid}/status").read_text()
            except OSError:
                break
            caught = next(line for line in status.splitlines() if line.startswith("SigCgt:"))
            if int(caught.split()[1], 16) & (1 << (signal.SIGHUP - 1)):
                delays.append((time.perf_counter() - began) * 1000)
                break
        process.wait()
    return statistics.median(delays)


def main() -> None:
    """Run every case, print the timings and the start-up figure."""
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        mission = folder / "pause.yaml"
        mission.write_text(MISSION.format(seconds=1))
        long = folder / "long.yaml"
        long.write_text(MISSION.format(seconds=600))
        mount(folder / "ro", 4096, read_only=True)
        mount(folder / "full", 64)
        (folder / "full" / "filler").write_bytes(b"\0" * 60 * 1024)
        (folder / "a_file").write_text("x")
        (folder / "a_folder.mcap").mkdir()
        held = folder / "held"
        holder = subprocess.Popen(
            [BAOBAB, "run", str(long), "--realtime", "--out", str(held)],
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )
        assert holder.stdout is not None
        while not holder.stdout.readline().startswith("t="):
            pass  # its first tick: the folder is claimed, and its start-up no longer competes
        try:
            with socket.socket() as taken:
                taken.bind(("127.0.0.1", 0))
                taken.listen()
                port = str(taken.getsockname()[1])
                out = ["--out", str(folder / "run")]
                cases = {
                    "--out on a read-only file system": ["--out", str(folder / "ro" / "run")],
                    "--out on a full file system": ["--out", str(folder / "full" / "run")],
                    "--out is a file": ["--out", str(folder / "a_file")],
                    "--out held by another run": ["--out", str(held)],
                    "--record to a folder": [*out, "--record", str(folder / "a_folder.mcap")],
                    "--record to a device": [*out, "--record", os.devnull],
                    "--baseline on a read-only file system": [
                        *out,
                        "--baseline",
                        str(folder / "ro" / "b.json"),
                    ],
                    "--live on a port in use": [*out, "--live", "--port", port],
                }
                print(f"{len(cases)} refusals by `baobab run`:")
                results = [refuse(name, arguments, mission) for name, arguments in cases.items()]
        finally:
            holder.send_signal(signal.SIGINT)
            holder.wait()
            for name in ("ro", "full"):
                subprocess.run(["umount", "-l", str(folder / name)], check=False)
        print(f"{results.count(False)} not refused as required")
    print(f"signals handled by baobab {handler_delay_ms():.0f} ms after exec (median of 20)")


if __name__ == "__main__":
    main()

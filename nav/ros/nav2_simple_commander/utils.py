"""``nav2_simple_commander.utils``: quaternions from Euler angles, and finding or killing processes.

``euler_to_quaternion(roll, pitch, yaw)`` is the rotation ``Rz(yaw) Ry(pitch) Rx(roll)`` (rad),
as ``tf2`` builds it from RPY. The process helpers are Nav2's, for scripts that stop a
simulator they started: they match the start of each process's command line.
"""

from __future__ import annotations

import os
import signal
import subprocess

from scipy.spatial.transform import Rotation

from baobab.nav.msgs import Quaternion

__all__ = ["euler_to_quaternion", "find_os_processes", "kill_os_processes", "kill_process"]


def euler_to_quaternion(roll: float = 0.0, pitch: float = 0.0, yaw: float = 0.0) -> Quaternion:
    """The quaternion of roll, pitch and yaw (rad) applied about fixed x, y and z in turn."""
    x, y, z, w = Rotation.from_euler("xyz", [roll, pitch, yaw]).as_quat()
    return Quaternion(x=float(x), y=float(y), z=float(z), w=float(w))


def find_os_processes(name: str) -> list[tuple[str, str]]:
    """``(pid, command line)`` of every process whose command line starts with ``name``."""
    listing = subprocess.run(
        ["ps", "-ww", "-eo", "pid=,args="], capture_output=True, text=True, check=True
    ).stdout
    found = []
    for line in listing.splitlines():
        pid, _, command = line.strip().partition(" ")
        command = command.strip()
        if command.startswith(name):
            found.append((pid, command))
    return found


def kill_process(pid: int | str) -> None:
    """Send SIGKILL to ``pid`` and print whether it worked (Nav2's lines)."""
    try:
        os.kill(int(pid), signal.SIGKILL)
        print(f"Successfully killed process with PID: {pid}")
    except (OSError, ValueError) as exc:
        print(f"Failed to kill process with PID: {pid}. Error: {exc}")


def kill_os_processes(name: str) -> None:
    """Kill every process whose command line starts with ``name``."""
    processes = find_os_processes(name)
    if not processes:
        print(f"No processes found starting with {name}")
    for pid, _ in processes:
        kill_process(pid)

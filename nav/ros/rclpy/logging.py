"""``rclpy.logging``: named loggers that write ROS 2 console lines to standard error.

A line reads ``[INFO] [12.300000000] [basic_navigator]: message``, stamped with simulation
time, as ``rcutils`` prints it (ROS 2 sends every severity to standard error by default).
"""

from __future__ import annotations

import sys
from enum import IntEnum
from typing import Any

from baobab.nav.rostime import S_TO_NS, sim_time_ns


class LoggingSeverity(IntEnum):
    """rcutils severities; a logger prints messages at or above its level."""

    UNSET = 0
    DEBUG = 10
    INFO = 20
    WARN = 30
    ERROR = 40
    FATAL = 50


class RcutilsLogger:
    """A named logger (``node.get_logger()``), printing at INFO and above by default."""

    def __init__(self, name: str = "") -> None:
        self.name = name
        self._level = LoggingSeverity.INFO
        self._call_sites: dict[tuple[str, int], list[int]] = {}

    def get_child(self, name: str) -> RcutilsLogger:
        """The logger ``<this name>.<name>``, starting at this logger's level."""
        child = RcutilsLogger(f"{self.name}.{name}" if self.name else name)
        child._level = self._level
        return child

    def set_level(self, level: LoggingSeverity | int) -> None:
        """Print messages at ``level`` and above."""
        self._level = LoggingSeverity(level)

    def get_effective_level(self) -> LoggingSeverity:
        """The level this logger prints at and above."""
        return self._level

    def is_enabled_for(self, severity: LoggingSeverity | int) -> bool:
        """True when a message of ``severity`` would be printed."""
        return severity >= self._level

    def log(
        self,
        message: object,
        severity: LoggingSeverity | int,
        *,
        throttle_duration_sec: float | None = None,
        throttle_time_source_type: object = None,
        once: bool = False,
        skip_first: bool = False,
        name: str | None = None,
    ) -> bool:
        """Print ``message`` at ``severity``; True when it was printed.

        ``once`` prints only the first call from this line of code, ``skip_first`` all but
        the first, ``throttle_duration_sec`` at most once per that many seconds of sim time.
        """
        if not self.is_enabled_for(severity):
            return False
        now = sim_time_ns()
        if once or skip_first or throttle_duration_sec:
            frame = sys._getframe(2)
            site = self._call_sites.setdefault((frame.f_code.co_filename, frame.f_lineno), [])
            calls = len(site)
            if (once and calls) or (skip_first and not calls):
                site.append(now)
                return False
            if throttle_duration_sec and site and now - site[-1] < throttle_duration_sec * S_TO_NS:
                return False
            site.append(now)
        seconds, nanoseconds = divmod(now, S_TO_NS)
        label = LoggingSeverity(severity).name
        shown = self.name if name is None else name
        print(f"[{label}] [{seconds}.{nanoseconds:09d}] [{shown}]: {message}", file=sys.stderr)
        return True

    def debug(self, message: object, **kwargs: Any) -> bool:
        """Log at DEBUG."""
        return self.log(message, LoggingSeverity.DEBUG, **kwargs)

    def info(self, message: object, **kwargs: Any) -> bool:
        """Log at INFO."""
        return self.log(message, LoggingSeverity.INFO, **kwargs)

    def warning(self, message: object, **kwargs: Any) -> bool:
        """Log at WARN."""
        return self.log(message, LoggingSeverity.WARN, **kwargs)

    def warn(self, message: object, **kwargs: Any) -> bool:
        """Log at WARN (rclpy's older spelling)."""
        return self.log(message, LoggingSeverity.WARN, **kwargs)

    def error(self, message: object, **kwargs: Any) -> bool:
        """Log at ERROR."""
        return self.log(message, LoggingSeverity.ERROR, **kwargs)

    def fatal(self, message: object, **kwargs: Any) -> bool:
        """Log at FATAL."""
        return self.log(message, LoggingSeverity.FATAL, **kwargs)


def get_logger(name: str) -> RcutilsLogger:
    """A logger called ``name``."""
    return RcutilsLogger(name)

"""``nav2_simple_commander.line_iterator``: the points of a segment, one step at a time.

:class:`LineIterator` starts at ``(x0, y0)`` and each :meth:`~LineIterator.advance` moves
``step_size`` along x (along y for a vertical segment), the other coordinate following the
line, until the end point has been produced; then :meth:`~LineIterator.isValid` turns False.
Coordinates are rounded to 5 decimals, the last step is clamped to the end point, as in Nav2.
"""

from __future__ import annotations

import math
from numbers import Real

__all__ = ["LineIterator"]


def _number(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a number (int or float)")
    return value  # type: ignore[return-value]


class LineIterator:
    """Iterate over the points of the segment from ``(x0, y0)`` to ``(x1, y1)``.

    Args:
        x0: abscissa of the first point.
        y0: ordinate of the first point.
        x1: abscissa of the last point.
        y1: ordinate of the last point.
        step_size: the increment along the stepping axis (units of the coordinates).

    Raises:
        TypeError: a coordinate or ``step_size`` is not a number.
        ValueError: ``step_size`` is not positive, or the segment has zero length.
    """

    def __init__(self, x0: float, y0: float, x1: float, y1: float, step_size: float = 1.0) -> None:
        for name, value in (("x0", x0), ("y0", y0), ("x1", x1), ("y1", y1)):
            _number(name, value)
        _number("step_size", step_size)
        if step_size <= 0:
            raise ValueError("step_size must be a positive number")
        if x0 == x1 and y0 == y1:
            raise ValueError("Line has zero length (All 4 points have same coordinates)")
        self.x0_, self.y0_, self.x1_, self.y1_ = x0, y0, x1, y1
        self.x_, self.y_ = x0, y0
        self.step_size_ = step_size
        self.valid_ = True
        if x0 != x1:
            self.m_ = (y1 - y0) / (x1 - x0)
            self.b_ = y1 - self.m_ * x1

    def isValid(self) -> bool:
        """True while the current point is on the segment (False once past its end)."""
        return self.valid_

    def advance(self) -> None:
        """Move to the next point; past the end point the iterator becomes invalid."""
        x0, x1, y0, y1 = self.x0_, self.x1_, self.y0_, self.y1_
        if x0 != x1:
            forward = x1 > x0
            if (self.x_ < x1) if forward else (self.x_ > x1):
                step = self.step_size_ if forward else -self.step_size_
                self.x_ = round(self.clamp(self.x_ + step, min(x0, x1), max(x0, x1)), 5)
                self.y_ = round(self.m_ * self.x_ + self.b_, 5)
            else:
                self.valid_ = False
            return
        upward = y1 > y0
        if (self.y_ < y1) if upward else (self.y_ > y1):
            step = self.step_size_ if upward else -self.step_size_
            self.y_ = round(self.clamp(self.y_ + step, min(y0, y1), max(y0, y1)), 5)
        else:
            self.valid_ = False

    def getX(self) -> float:
        """Abscissa of the current point."""
        return self.x_

    def getY(self) -> float:
        """Ordinate of the current point."""
        return self.y_

    def getX0(self) -> float:
        """Abscissa of the first point."""
        return self.x0_

    def getY0(self) -> float:
        """Ordinate of the first point."""
        return self.y0_

    def getX1(self) -> float:
        """Abscissa of the last point."""
        return self.x1_

    def getY1(self) -> float:
        """Ordinate of the last point."""
        return self.y1_

    def get_line_length(self) -> float:
        """Length of the segment (Nav2 returns it as a complex number with no imaginary part;
        here it is a float, which compares equal)."""
        return math.hypot(self.x1_ - self.x0_, self.y1_ - self.y0_)

    def clamp(self, n: float, min_n: float, max_n: float) -> float:
        """``n`` limited to ``[min_n, max_n]``."""
        return min(max(n, min_n), max_n)

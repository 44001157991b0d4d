"""Compiled A* over an 8-connected cost grid (numba).

The search is exact: with the octile heuristic scaled by the cheapest cell weight it is
admissible and consistent, so the path it returns is optimal for the cost function

    cost(step a -> b) = length(a, b) * weight[cost_of(b)]    (length 1 or sqrt(2) cells)

where ``weight`` is a 256-entry table over Nav2 cost values; a weight of 0 blocks the cell. A
diagonal step needs both cells beside it open, so a path never squeezes between two blocked
corners. Every closed cell holds its optimal cost to reach, so one exhausted search answers
"which reachable cell is nearest to a blocked goal" exactly.

Compiled because pure Python A* on a 100k-cell map takes hundreds of milliseconds and this
kernel a few. The search's arrays travel in one :class:`SearchSpace` record
(:mod:`baobab.sim.records`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numba
import numpy as np

FOUND = 0
"""The goal cell was reached."""
EXHAUSTED = 1
"""Every cell reachable from the start was closed without reaching the goal."""
BUDGET_SPENT = 2
"""The expansion budget ran out first."""

# The eight neighbours as (row, column) offsets.
_D_ROW = np.array([-1, -1, -1, 0, 0, 1, 1, 1], dtype=np.int64)
_D_COL = np.array([-1, 0, 1, -1, 1, -1, 0, 1], dtype=np.int64)
# Step lengths in integer units: 577 / 408 = 1.4142157 approximates sqrt(2) to 1.5e-6, and
# integer costs make equal-cost ties exact, so ties can be broken towards the goal.
_CARDINAL = np.int64(408)
_DIAGONAL = np.int64(577)
CARDINAL_STEP = int(_CARDINAL)
"""A cardinal step's length in the search's integer cost units (a diagonal step is 577)."""
_UNREACHED = np.int64(1) << 62
# Cell states during a search (a cell nobody marked in this search is new).
_OPEN, _CLOSED = 1, 2


@numba.njit(cache=True, nogil=True, inline="always")
def _before(f_a: int, h_a: int, f_b: int, h_b: int) -> bool:  # pragma: no cover - compiled
    """Heap order: lower f first; on equal f, lower h (deeper along the way to the goal)."""
    return f_a < f_b or (f_a == f_b and h_a < h_b)


class Heap(NamedTuple):
    """The open list: a binary heap of cells, one slot per cell of the grid."""

    f: np.ndarray
    """Priority of each slot: cost so far plus the heuristic (``int64``)."""
    h: np.ndarray
    """The heuristic alone, to break ties (``int64``)."""
    cell: np.ndarray
    """The flat cell index ``row * width + col`` in each slot (``int64``)."""
    where: np.ndarray
    """Per cell: its slot while it is open (``int64``)."""


class SearchSpace(NamedTuple):
    """Everything a search keeps per cell (``int64``, one entry per cell)."""

    g: np.ndarray
    """Cost from the start."""
    parent: np.ndarray
    """The cell it was reached from; -1 for the start."""
    mark: np.ndarray
    """``4 * generation + state`` of the search that last touched it."""
    heap: Heap
    """The open list."""


@numba.njit(cache=True, nogil=True, inline="always")
def _sift_up(heap: Heap, i: int) -> None:  # pragma: no cover - compiled
    f, h, v = heap.f[i], heap.h[i], heap.cell[i]
    while i > 0:
        up = (i - 1) >> 1
        if not _before(f, h, heap.f[up], heap.h[up]):
            break
        heap.f[i], heap.h[i], heap.cell[i] = heap.f[up], heap.h[up], heap.cell[up]
        heap.where[heap.cell[i]] = i
        i = up
    heap.f[i], heap.h[i], heap.cell[i] = f, h, v
    heap.where[v] = i


@numba.njit(cache=True, nogil=True, inline="always")
def _sift_down(heap: Heap, i: int, size: int) -> None:  # pragma: no cover - compiled
    f, h, v = heap.f[i], heap.h[i], heap.cell[i]
    while True:
        child = 2 * i + 1
        if child >= size:
            break
        right = child + 1
        if right < size and _before(heap.f[right], heap.h[right], heap.f[child], heap.h[child]):
            child = right
        if not _before(heap.f[child], heap.h[child], f, h):
            break
        heap.f[i], heap.h[i], heap.cell[i] = heap.f[child], heap.h[child], heap.cell[child]
        heap.where[heap.cell[i]] = i
        i = child
    heap.f[i], heap.h[i], heap.cell[i] = f, h, v
    heap.where[v] = i


@numba.njit(cache=True, nogil=True)
def _astar(
    grid: np.ndarray,
    weight: np.ndarray,
    start: int,
    goal: int,
    max_expansions: int,
    generation: int,
    space: SearchSpace,
) -> tuple[int, int]:  # pragma: no cover - compiled
    """A* from flat cell ``start`` to ``goal``; returns the status and the cells expanded."""
    g, parent, mark, heap = space.g, space.parent, space.mark, space.heap
    height, width = grid.shape
    flat = grid.ravel()
    # A cell is new unless this search marked it: mark = 4 * generation + state. Nothing is
    # reset between searches, so a search costs what it explores, not the size of the map.
    opened = 4 * generation + _OPEN
    closed = 4 * generation + _CLOSED
    min_weight = _UNREACHED
    for c in range(256):
        if 0 < weight[c] < min_weight:
            min_weight = weight[c]
    h_card = _CARDINAL * min_weight
    h_extra = (_DIAGONAL - 2 * _CARDINAL) * min_weight
    goal_row, goal_col = goal // width, goal % width
    heap.f[0], heap.h[0], heap.cell[0] = 0, 0, start
    heap.where[start] = 0
    mark[start] = opened
    g[start] = 0
    parent[start] = -1
    size = 1
    expansions = 0
    while size > 0:
        current = heap.cell[0]
        size -= 1
        if size > 0:
            heap.f[0], heap.h[0], heap.cell[0] = heap.f[size], heap.h[size], heap.cell[size]
            _sift_down(heap, 0, size)
        mark[current] = closed
        if current == goal:
            return FOUND, expansions
        expansions += 1
        if expansions > max_expansions:
            return BUDGET_SPENT, expansions
        row, col = current // width, current % width
        g_current = g[current]
        for k in range(8):
            dr, dc = _D_ROW[k], _D_COL[k]
            r, c = row + dr, col + dc
            if r < 0 or r >= height or c < 0 or c >= width:
                continue
            neighbour = r * width + c
            w = weight[flat[neighbour]]
            seen = mark[neighbour]
            if w <= 0 or seen == closed:
                continue
            step = _CARDINAL
            if dr != 0 and dc != 0:
                if weight[flat[row * width + c]] <= 0 or weight[flat[r * width + col]] <= 0:
                    continue
                step = _DIAGONAL
            candidate = g_current + step * w
            if seen == opened and candidate >= g[neighbour]:
                continue
            g[neighbour] = candidate
            parent[neighbour] = current
            dy, dx = abs(r - goal_row), abs(c - goal_col)
            h = h_card * (dx + dy) + h_extra * min(dx, dy)
            if seen == opened:
                i = heap.where[neighbour]
                heap.f[i] = candidate + h
            else:
                mark[neighbour] = opened
                i = size
                size += 1
                heap.f[i], heap.h[i], heap.cell[i] = candidate + h, h, neighbour
            _sift_up(heap, i)
    return EXHAUSTED, expansions


@numba.njit(cache=True, nogil=True)
def _trace(parent: np.ndarray, end: int) -> np.ndarray:  # pragma: no cover - compiled
    length = 1
    cell = end
    while parent[cell] >= 0:
        cell = parent[cell]
        length += 1
    cells = np.empty(length, np.int64)
    cell = end
    for i in range(length - 1, -1, -1):
        cells[i] = cell
        cell = parent[cell]
    return cells


@dataclass(frozen=True)
class SearchResult:
    """The outcome of one :meth:`GridSearch.search`.

    Attributes:
        status: :data:`FOUND`, :data:`EXHAUSTED` or :data:`BUDGET_SPENT`.
        expansions: cells expanded.
    """

    status: int
    expansions: int


class GridSearch:
    """Reusable A* workspace for grids of one shape.

    After :meth:`search`, :meth:`reached` tells which cells were closed (their cost is optimal)
    and :meth:`path_to` walks the parents back to the start.
    """

    def __init__(self) -> None:
        self._shape: tuple[int, int] = (0, 0)
        self._generation = 0
        self._allocate(0)

    def _allocate(self, n: int) -> None:
        self._generation = 0
        self._space = SearchSpace(
            g=np.empty(n, dtype=np.int64),
            parent=np.empty(n, dtype=np.int64),
            mark=np.zeros(n, dtype=np.int64),
            heap=Heap(
                f=np.empty(n, dtype=np.int64),
                h=np.empty(n, dtype=np.int64),
                cell=np.empty(n, dtype=np.int64),
                where=np.empty(n, dtype=np.int64),
            ),
        )

    def search(
        self,
        grid: np.ndarray,
        weight: np.ndarray,
        start: tuple[int, int],
        goal: tuple[int, int],
        max_expansions: int,
    ) -> SearchResult:
        """Run A* on ``grid`` (``uint8`` costs, ``[row, col]``) from ``start`` to ``goal``.

        Args:
            grid: cost values, ``uint8`` array indexed ``[row, col]``.
            weight: 256 integer step weights by cost value (0 = blocked); a step costs
                408 (cardinal) or 577 (diagonal) times the weight of the cell it enters.
            start: ``(row, col)`` of the start cell.
            goal: ``(row, col)`` of the goal cell.
            max_expansions: budget of expanded cells.
        """
        grid = np.ascontiguousarray(grid, dtype=np.uint8)
        if grid.shape != self._shape:
            self._shape = (int(grid.shape[0]), int(grid.shape[1]))
            self._allocate(grid.size)
        width = grid.shape[1]
        self._generation += 1
        status, expansions = _astar(
            grid,
            np.ascontiguousarray(weight, dtype=np.int64),
            start[0] * width + start[1],
            goal[0] * width + goal[1],
            max_expansions,
            self._generation,
            self._space,
        )
        return SearchResult(int(status), int(expansions))

    def reached(self) -> np.ndarray:
        """Closed cells of the last search, as a ``bool`` grid."""
        return (self._space.mark == 4 * self._generation + _CLOSED).reshape(self._shape)

    def cost_to(self, cell: tuple[int, int]) -> int:
        """Cost from the start to a ``(row, col)`` cell; optimal once the cell is closed."""
        index = cell[0] * self._shape[1] + cell[1]
        if self._space.mark[index] < 4 * self._generation:
            return int(_UNREACHED)
        return int(self._space.g[index])

    def path_to(self, cell: tuple[int, int]) -> np.ndarray:
        """``(N, 2)`` array of ``(row, col)`` from the start to a reached ``cell``."""
        width = self._shape[1]
        flat = _trace(self._space.parent, cell[0] * width + cell[1])
        return np.stack([flat // width, flat % width], axis=1)

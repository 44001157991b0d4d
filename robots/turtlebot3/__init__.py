"""The TurtleBot3: the Burger (its own MuJoCo body) and the Waffle (the generic one).

- :mod:`.facts`: :data:`BURGER` and :data:`WAFFLE`, every figure with its source.
- :mod:`.model`: the Burger's body as an MjSpec (:func:`turtlebot3_spec`,
  :func:`attach_turtlebot3`).
- :mod:`.burger`: :func:`build_turtlebot3_sim` (world + Burger + running base and lidar).

Their registry entries are :mod:`baobab.robots.catalog`'s; everything that drives them is the
differential-drive code of :mod:`baobab.robots.diff_drive`. The public names load on first use
(PEP 562), so importing the facts does not load MuJoCo.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from baobab.sim.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from baobab.robots.turtlebot3.burger import build_turtlebot3_sim, start_turtlebot3
    from baobab.robots.turtlebot3.facts import BURGER, WAFFLE
    from baobab.robots.turtlebot3.model import DEFAULT_PREFIX, attach_turtlebot3, turtlebot3_spec

_EXPORTS = {
    "BURGER": "baobab.robots.turtlebot3.facts",
    "DEFAULT_PREFIX": "baobab.robots.turtlebot3.model",
    "WAFFLE": "baobab.robots.turtlebot3.facts",
    "attach_turtlebot3": "baobab.robots.turtlebot3.model",
    "build_turtlebot3_sim": "baobab.robots.turtlebot3.burger",
    "start_turtlebot3": "baobab.robots.turtlebot3.burger",
    "turtlebot3_spec": "baobab.robots.turtlebot3.model",
}
"""Public name -> the module defining it."""

__all__ = [
    "BURGER",
    "DEFAULT_PREFIX",
    "WAFFLE",
    "attach_turtlebot3",
    "build_turtlebot3_sim",
    "start_turtlebot3",
    "turtlebot3_spec",
]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)

"""World descriptions, the MuJoCo model built from them, and the simulation clock.

The public names below load on first use (PEP 562), so importing a light module such as
``baobab.sim.errors`` does not pull in MuJoCo, pydantic and the world loader.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from baobab.sim.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from baobab.sim.errors import BaobabError, SimulationError, SourceError, WorldError
    from baobab.sim.simulation import PeriodicHandle, Simulation
    from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World, load_world

_EXPORTS = {
    "BaobabError": "baobab.sim.errors",
    "Box": "baobab.sim.world",
    "Cylinder": "baobab.sim.world",
    "Floor": "baobab.sim.world",
    "PeriodicHandle": "baobab.sim.simulation",
    "Pose2D": "baobab.sim.world",
    "Simulation": "baobab.sim.simulation",
    "SimulationError": "baobab.sim.errors",
    "SourceError": "baobab.sim.errors",
    "World": "baobab.sim.world",
    "WorldError": "baobab.sim.errors",
    "load_world": "baobab.sim.world",
}

__all__ = [
    "BaobabError",
    "Box",
    "Cylinder",
    "Floor",
    "PeriodicHandle",
    "Pose2D",
    "Simulation",
    "SimulationError",
    "SourceError",
    "World",
    "WorldError",
    "load_world",
]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)

"""World descriptions, the MuJoCo model built from them, and the simulation clock."""

from baobab.sim.errors import BaobabError, SimulationError, SourceError, WorldError
from baobab.sim.simulation import PeriodicHandle, Simulation
from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World, load_world

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

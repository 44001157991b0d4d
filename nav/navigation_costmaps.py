"""The two costmaps of a navigation server: the global one over the whole world and the rolling
local one around the robot, each with its static layer and the world's keepout filter."""

from __future__ import annotations

from baobab.nav.costmap_filters import KeepoutParams, keepout_filter
from baobab.nav.layered_costmap import CostmapParams, LayeredCostmap
from baobab.nav.layers import StaticLayer
from baobab.sim.world import Pose2D, World


def navigation_costmaps(
    world: World,
    robot_pose: Pose2D,
    global_params: CostmapParams,
    local_params: CostmapParams,
    local_size: tuple[float, float],
    keepout: KeepoutParams,
) -> tuple[LayeredCostmap, LayeredCostmap]:
    """The global costmap and the local one of ``local_size`` (m) centred on ``robot_pose``.

    The two share one static layer when their resolutions and static-layer settings agree
    (the world is rasterised once), and then one keepout filter when their inflations agree
    too (the mask is sampled and inflated once; a filter holds no state of its costmap).
    """
    static = StaticLayer(world, global_params.resolution, params=global_params.static)
    local_static = (
        static
        if local_params.resolution == global_params.resolution
        and local_params.static == global_params.static
        else StaticLayer(world, local_params.resolution, params=local_params.static)
    )
    global_keepout = keepout_filter(world, static, global_params.inflation, keepout)
    local_keepout = (
        global_keepout
        if local_static is static and local_params.inflation == global_params.inflation
        else keepout_filter(world, local_static, local_params.inflation, keepout)
    )
    global_layers = LayeredCostmap.global_costmap(world, global_params, static, global_keepout)
    local_layers = LayeredCostmap.local_costmap(
        world, robot_pose, local_params, local_size, local_static, local_keepout
    )
    return global_layers, local_layers

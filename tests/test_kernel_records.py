"""Compiled kernels take a few named records, each built by a ``pack()`` beside its dataclass."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import math
import pkgutil

import numpy as np
import pytest
from numba.core.registry import CPUDispatcher

from baobab.nav.costmap import GRID, Costmap2D
from baobab.nav.layers import ObstacleParams
from baobab.nav.pure_pursuit import RegulatedPurePursuitParams
from baobab.nav.raytrace_kernels import OBSTACLE_RANGES
from baobab.nav.rpp_kernel import RPP_SETTINGS
from baobab.nav.smoother import SMOOTHER, SimpleSmoother
from baobab.sim.records import record

MAX_PARAMETERS = 8

PACKAGES = ("baobab.nav", "baobab.robots", "baobab.sim")
"""Where the compiled kernels live."""


def _compiled_kernels() -> list[tuple[str, CPUDispatcher]]:
    found: dict[str, CPUDispatcher] = {}
    for package in PACKAGES:
        module = importlib.import_module(package)
        for info in pkgutil.walk_packages(module.__path__, f"{package}."):
            if info.name.endswith("viewer"):  # mujoco.viewer needs a display
                continue
            for name, value in vars(importlib.import_module(info.name)).items():
                if isinstance(value, CPUDispatcher) and value.__module__ == info.name:
                    found[f"{info.name}.{name}"] = value
    return sorted(found.items())


def test_no_compiled_kernel_takes_more_than_eight_parameters() -> None:
    kernels = _compiled_kernels()
    assert len(kernels) > 40  # the walk found them: nav, the lidar, the bases, the arm
    counts = {name: len(inspect.signature(kernel.py_func).parameters) for name, kernel in kernels}
    assert {name: n for name, n in counts.items() if n > MAX_PARAMETERS} == {}


@pytest.mark.parametrize(
    ("params", "dtype", "special"),
    [
        (RegulatedPurePursuitParams(), RPP_SETTINGS, {"max_robot_pose_search_dist"}),
        (SimpleSmoother(), SMOOTHER, set()),
        (ObstacleParams(), OBSTACLE_RANGES, set()),
    ],
    ids=["pure_pursuit", "smoother", "obstacle_layer"],
)
def test_a_settings_record_mirrors_its_dataclass_field_by_field(
    params: object, dtype: np.dtype, special: set[str]
) -> None:
    fields = {field.name for field in dataclasses.fields(params)}  # type: ignore[arg-type]
    assert set(dtype.names or ()) <= fields
    packed = params.pack()[0]  # type: ignore[attr-defined]
    for name in set(dtype.names or ()) - special:
        assert packed[name] == getattr(params, name), name


def test_pure_pursuit_packs_no_search_distance_as_the_half_extent() -> None:
    assert math.isnan(RegulatedPurePursuitParams().pack()[0]["max_robot_pose_search_dist"])
    packed = RegulatedPurePursuitParams(max_robot_pose_search_dist=0.7).pack()
    assert packed[0]["max_robot_pose_search_dist"] == 0.7


def test_a_costmap_packs_its_geometry() -> None:
    grid = Costmap2D(4, 3, 0.05, (1.5, -2.0), inscribed_radius=0.1).pack()
    assert grid.dtype == GRID and grid.shape == (1,)
    assert grid[0].tolist() == (1.5, -2.0, 0.05, 0.1)


def test_a_record_takes_every_field_by_name() -> None:
    with pytest.raises(TypeError, match="'origin_z'"):
        record(GRID, origin_x=0.0, origin_y=0.0, origin_z=1.0, resolution=1.0)
    with pytest.raises(AttributeError, match="inscribed_radius"):
        record(GRID, object(), origin_x=0.0, origin_y=0.0, resolution=1.0)

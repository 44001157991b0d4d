"""Suite-wide settings: hypothesis draws the same examples on every run (no flaky CI); no run
server. Shared fixtures: ``lanes``."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import pytest
from hypothesis import settings

if TYPE_CHECKING:
    from baobab.nav import BasicNavigator

# `baobab run` processes the tests start run on their own, as before the run server; its own
# tests (test_run_server.py) start servers of their own.
os.environ.setdefault("BAOBAB_RUN_SERVER", "0")

settings.register_profile("baobab", derandomize=True, deadline=None, print_blob=True)
settings.load_profile("baobab")


@pytest.fixture(scope="module")
def lanes() -> Iterator[BasicNavigator]:
    """A navigator on the lanes world (tests/missions/worlds/lanes.yaml, seed 0), one per test
    module."""
    from baobab.nav import BasicNavigator
    from baobab.sim.world import load_world

    navigator = BasicNavigator(
        world=load_world(Path(__file__).parent / "missions" / "worlds" / "lanes.yaml"), seed=0
    )
    yield navigator
    navigator.destroy_node()

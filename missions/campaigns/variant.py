"""One campaign run's mission: the file with the run's ``--set`` values and variations.

Parameters go through :func:`~baobab.missions.language.loader.load_mission`'s overrides, as
``baobab run --set`` gives them. A start offset, noise or an event value changes the mission
data itself: the run's *variant* is the file's data with those values written in (the start
as the resolved pose plus the offset), dumped back to YAML under an editor comment that names
:data:`REPLAY_SCHEMA` beside it, and loaded like any mission file. The variant's text is what
the run loaded, so writing it to a file replays the run exactly
(``baobab run VARIANT.yaml --seed S --set ...``).
"""

from __future__ import annotations

import copy
import itertools
import math
from pathlib import Path
from typing import Any

import yaml

from baobab.missions.campaigns.spec import RunTask
from baobab.missions.language.loader import SCHEMA_HEADER, Mission, load_mission
from baobab.sim.errors import SourceError
from baobab.sim.yaml_source import KeyPath

REPLAY_SCHEMA = "mission.schema.json"
"""The schema a variant's editor comment names, in the variant's folder: a copy of the shipped
``baobab/missions/mission.schema.json`` (the output of ``baobab schema``)."""


class _PlainDumper(yaml.SafeDumper):
    """Writes repeated objects in full: the mission loader refuses most aliases."""

    def ignore_aliases(self, data: Any) -> bool:
        return True


def variant_of(task: RunTask) -> str | None:
    """The text of ``task``'s mission variant, or None when ``--set`` values are all it changes.

    Raises:
        MissionError: the mission with the run's ``--set`` values is not valid.
        WorldError: the world file cannot be read.
    """
    if not task.has_variant:
        return None
    mission = load_mission(Path(task.mission_path), task.overrides, text=task.mission_text)
    return variant_text(mission, task)


def load_run_mission(task: RunTask, variant: str | None) -> Mission:
    """The mission ``task`` runs: its variant if it has one, else the file with ``--set``.

    Raises:
        MissionError: the run's values do not make a valid mission; an error in the variant
            names it by ``task.variant_label`` (the line and column are the variant's).
        WorldError: the world file cannot be read.
    """
    path = Path(task.mission_path)
    if variant is None:
        return load_mission(path, task.overrides, text=task.mission_text)
    try:
        return load_mission(path, task.overrides, text=variant)
    except SourceError as exc:
        if exc.path != str(path):
            raise
        raise type(exc)(task.variant_label, exc.line, exc.column, exc.message) from None


def variant_text(mission: Mission, task: RunTask) -> str:
    """The mission file's text with the run's start offset and data changes written in."""
    data = copy.deepcopy(mission.document.data)
    if task.start_offset is not None and mission.start is not None:
        dx, dy, dyaw = task.start_offset
        start = mission.start
        data["start"] = {
            "x": start.x + dx,
            "y": start.y + dy,
            "yaw": math.remainder(start.yaw + dyaw, math.tau),
        }
    for key_path, value in task.data_changes:
        _write(data, key_path, value)
    header = f"{SCHEMA_HEADER}{REPLAY_SCHEMA}"
    varied = ", ".join(f"{key}={value}" for key, value in task.values.items())
    body = yaml.dump(data, Dumper=_PlainDumper, sort_keys=False, allow_unicode=True, width=100)
    return (
        f"{header}\n# Campaign run {task.index} of {Path(task.mission_path).name}: {varied}\n{body}"
    )


def _write(data: dict[str, Any], key_path: KeyPath, value: float | str) -> None:
    """Set ``data[k0][k1]...`` to ``value``, making mappings on the way (e.g. ``noise``).

    Integer keys index lists (``events``); the campaign checked they exist.
    """
    node: Any = data
    for key, next_key in itertools.pairwise(key_path):
        child = node[int(key)] if isinstance(node, list) else node.get(key)
        wanted = list if isinstance(next_key, int) else dict
        if not isinstance(child, wanted):
            child = wanted()
            node[key] = child
        node = child
    node[key_path[-1]] = value

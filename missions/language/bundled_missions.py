"""The missions that ship with baobab (``missions/*.yaml``), and MISSION as a path or a name.

Commands that take a MISSION (``run``, ``campaign``) accept a file path or the name of a
bundled mission; ``baobab list`` lists them with their descriptions.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from baobab.sim.errors import BaobabError, SourceError
from baobab.sim.yaml_source import load_located_yaml


class MissionNotFoundError(BaobabError):
    """MISSION is neither a file nor a bundled mission."""


def bundled_mission_path(name: str) -> Path | None:
    """The file of bundled mission ``name`` (``missions/<name>.yaml``), or None."""
    entry = resources.files("baobab.missions") / f"{name}.yaml"
    return Path(str(entry)) if entry.is_file() else None


def resolve_mission(text: str) -> Path:
    """MISSION as a file path, or as the name of a bundled mission.

    Raises:
        MissionNotFoundError: when it is neither.
    """
    path = Path(text)
    looks_like_a_path = "/" in text or "\\" in text or text.endswith((".yaml", ".yml"))
    if path.is_file() or looks_like_a_path:
        return path  # a missing file or a folder: the loader reports it as path:1:1
    bundled = bundled_mission_path(text)
    if bundled is not None:
        return bundled
    folder = resources.files("baobab.missions")
    names = sorted(
        e.name.removesuffix(".yaml") for e in folder.iterdir() if e.name.endswith(".yaml")
    )
    raise MissionNotFoundError(
        f"no mission file '{text}' and no bundled mission of that name "
        f"(bundled: {', '.join(names) or 'none'})"
    )


def bundled_missions() -> dict[str, str]:
    """Bundled mission files (``missions/*.yaml``): name -> description."""
    folder = resources.files("baobab.missions")
    missions: dict[str, str] = {}
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if not entry.name.endswith(".yaml"):
            continue
        try:
            data = load_located_yaml(Path(str(entry))).data
            description = str(data.get("description", "")) if isinstance(data, dict) else ""
        except SourceError as exc:
            description = f"(unreadable: {exc.message})"
        missions[entry.name.removesuffix(".yaml")] = " ".join(description.split())
    return missions

"""Run every bundled mission and write its ``trace_digest`` to ``tests/golden_digests.json``.

    python -m tests.update_golden            # from the repository root
    python -m tests.update_golden cafe_delivery farm_rows   # only these missions

The file pins what every bundled mission does, bit for bit: ``tests/test_determinism.py``
compares each mission's digest with it. When a change moves a digest on purpose (new
numerics, a new trace record), run this, review the file's diff like code and say in the
commit why the digests moved.
"""

from __future__ import annotations

import json
import sys
from importlib import resources
from pathlib import Path

GOLDEN = Path(__file__).with_name("golden_digests.json")
"""``{mission name: trace_digest}`` of every bundled mission, with its defaults and seed."""


def bundled_missions() -> list[Path]:
    """The bundled mission files, by name."""
    return sorted(Path(str(resources.files("baobab.missions"))).glob("*.yaml"))


def read_golden() -> dict[str, str]:
    """The pinned digests (empty before the first update)."""
    if not GOLDEN.exists():
        return {}
    digests: dict[str, str] = json.loads(GOLDEN.read_text(encoding="utf-8"))
    return digests


def main(names: list[str]) -> int:
    """Update the digests of the missions ``names`` (all when empty); return the exit code."""
    from baobab.missions.language.loader import load_mission
    from baobab.missions.run.runner import run_mission

    missions = {path.stem: path for path in bundled_missions()}
    unknown = sorted(set(names) - set(missions))
    if unknown:
        print(f"no bundled mission {unknown[0]!r}; bundled: {', '.join(missions)}")
        return 2
    digests = {name: digest for name, digest in read_golden().items() if name in missions}
    for name in names or list(missions):
        digest = run_mission(load_mission(missions[name])).trace_digest
        moved = "" if digests.get(name) == digest else "  (moved)"
        print(f"{name:28s} {digest}{moved}")
        digests[name] = digest
    GOLDEN.write_text(json.dumps(dict(sorted(digests.items())), indent=2) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

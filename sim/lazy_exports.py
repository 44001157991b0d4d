"""Package attributes that import their module on first use (PEP 562).

A package ``__init__`` lists ``{public name: module}`` and binds the two hooks::

    __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)

so ``import baobab.sim`` stays cheap and ``from baobab.sim import Simulation`` still works.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Iterable, Mapping
from typing import Any


def lazy_exports(
    package: str, exports: Mapping[str, str], public: Iterable[str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of a package whose names load lazily.

    Args:
        package: the package's ``__name__``.
        exports: public name -> module that defines it.
        public: every public name (``__all__`` plus any extras).
    """
    names = sorted(set(public) | set(exports))

    def __getattr__(name: str) -> Any:  # noqa: N807 — the PEP 562 hook's name
        module = exports.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:  # noqa: N807
        return names

    return __getattr__, __dir__

"""Start-up of the ``baobab`` process: what it arranges before its modules load.

``baobab validate`` of every bundled mission must finish well within half a second (the
start-up figure of ``bench/run.py``); importing pydantic and building the mission models is
most of that. Two costs of that start-up are not work the command needs:

- The command disables pydantic's plugins (``PYDANTIC_DISABLE_PLUGINS=__all__``, see
  :mod:`.command_line`), yet pydantic's plugin loader still imports :mod:`importlib.metadata`
  (email, zipfile, csv, ...: about 25 ms) before it reads that variable. With plugins disabled
  its only function returns no plugins, so the command puts a module in its place that does
  just that.
- Loading the modules makes some hundred thousand objects that live as long as the process;
  the cyclic garbage collector would walk them again and again while they are made (about 5 %
  of ``validate``). :func:`loading_modules` pauses it meanwhile and then freezes them.
"""

from __future__ import annotations

import contextlib
import gc
import importlib
import os
import sys
import types
from collections.abc import Iterable, Iterator, MutableMapping
from typing import Any

PLUGIN_LOADER = "pydantic.plugin._loader"
"""The module pydantic imports, when it builds its first validator, to find its plugins."""
PLUGINS_DISABLED = ("__all__", "1", "true")
"""Values of ``PYDANTIC_DISABLE_PLUGINS`` with which pydantic loads no plugin at all."""


def environment_defaults(environ: MutableMapping[str, str] = os.environ) -> None:
    """Set the variables the command's modules read as they load, where the user has not.

    MuJoCo picks its OpenGL backend when first imported; headless, only EGL can render video.
    baobab's models need no pydantic plugins, and looking for them reads the metadata of every
    installed package at start-up.
    """
    if not (environ.get("DISPLAY") or environ.get("WAYLAND_DISPLAY")):
        environ.setdefault("MUJOCO_GL", "egl")
    environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")


def skip_pydantic_plugin_discovery() -> bool:
    """Stand in for pydantic's plugin loader while plugins are disabled; True if it did.

    Nothing changes when the variable lets plugins load or the real loader is imported
    already. Any other name asked of the stand-in (a future pydantic's) loads the real loader.
    """
    if os.environ.get("PYDANTIC_DISABLE_PLUGINS") not in PLUGINS_DISABLED:
        return False
    if PLUGIN_LOADER in sys.modules:
        return False
    stand_in = types.ModuleType(PLUGIN_LOADER, "pydantic's plugin loader, plugins disabled")
    stand_in.__dict__["get_plugins"] = _no_plugins
    stand_in.__dict__["__getattr__"] = _from_real_loader
    sys.modules[PLUGIN_LOADER] = stand_in
    return True


def _no_plugins() -> Iterable[Any]:
    return ()


def _from_real_loader(name: str) -> Any:
    if name.startswith("__"):  # the import system asks for __path__ and the like: not there
        raise AttributeError(f"module {PLUGIN_LOADER!r} has no attribute {name!r}")
    stand_in = sys.modules.get(PLUGIN_LOADER)
    if stand_in is not None and vars(stand_in).get("__getattr__") is _from_real_loader:
        del sys.modules[PLUGIN_LOADER]
    return getattr(importlib.import_module(PLUGIN_LOADER), name)


@contextlib.contextmanager
def loading_modules() -> Iterator[None]:
    """Load a command's modules with the cyclic garbage collector paused, then freeze them.

    Only in a process that has not loaded pydantic yet, i.e. at the command's own start-up
    (with the collector enabled): in a process that has been running for a while (tests that
    call ``main()``), freezing would keep that process's uncollected garbage for good.
    """
    if "pydantic" in sys.modules or not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()  # what start-up made stays; later collections skip it
        gc.enable()

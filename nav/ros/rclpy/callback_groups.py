"""``rclpy.callback_groups``: accepted; the runtime runs one callback at a time anyway."""

from __future__ import annotations

__all__ = ["CallbackGroup", "MutuallyExclusiveCallbackGroup", "ReentrantCallbackGroup"]


class CallbackGroup:
    """A group of callbacks; baobab serves every callback in turn, deterministically."""


class MutuallyExclusiveCallbackGroup(CallbackGroup):
    """Callbacks that never overlap (all of baobab's never do)."""


class ReentrantCallbackGroup(CallbackGroup):
    """Callbacks that may overlap under a multi-threaded executor (baobab runs them in turn)."""

"""The ``pynput`` package, served by baobab: a keyboard whose keys a run presses at sim times."""

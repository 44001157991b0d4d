"""The ``builtin_interfaces`` package, served by baobab."""

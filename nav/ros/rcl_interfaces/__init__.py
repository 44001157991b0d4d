"""The ``rcl_interfaces`` package, served by baobab."""

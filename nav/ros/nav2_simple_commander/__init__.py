"""The ``nav2_simple_commander`` package, served by baobab."""

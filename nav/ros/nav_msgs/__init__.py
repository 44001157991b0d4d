"""The ``nav_msgs`` package, served by baobab."""

"""The ``geometry_msgs`` package, served by baobab."""

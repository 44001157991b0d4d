"""The ``nav2_msgs`` package, served by baobab."""

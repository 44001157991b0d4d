"""The ``action_msgs`` package, served by baobab."""

"""The ``std_msgs`` package, served by baobab."""

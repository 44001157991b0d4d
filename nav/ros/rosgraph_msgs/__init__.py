"""The ``rosgraph_msgs`` package, served by baobab."""

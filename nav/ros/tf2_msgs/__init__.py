"""The ``tf2_msgs`` package, served by baobab."""

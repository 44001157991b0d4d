"""The ``sensor_msgs`` package, served by baobab."""

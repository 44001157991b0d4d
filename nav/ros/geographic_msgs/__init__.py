"""The ``geographic_msgs`` package, served by baobab."""

"""The ``unique_identifier_msgs`` package, served by baobab."""

"""``ament_index_python``: installed ROS packages, which baobab does not have."""

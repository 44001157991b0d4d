"""``launch_ros``: the ``Node`` action (see :mod:`baobab.nav.ros.launch._entities`)."""

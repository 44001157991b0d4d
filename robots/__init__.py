"""The robots: one folder each, with its facts, its MuJoCo model and its own controllers.

- :mod:`.catalog`: :data:`~.catalog.ROBOTS`, the robots a mission may name with the facts
  validation needs before any physics, and the capability names.
- :mod:`.turtlebot3`: the TurtleBot3 Burger (``build_turtlebot3_sim``, ``DiffDriveBase``,
  go-to-goal, Bug2, keyboard teleop).
- :mod:`.panda`: the Franka Panda (``build_panda_sim``, ``ArmServer``, Cartesian impedance
  control, trajectories, gripper, pick).

Robots import only :mod:`baobab.sim`; navigation (:mod:`baobab.nav`) sits above them.
"""

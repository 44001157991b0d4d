"""The robots: the registry, the shared differential-drive code, and one folder per robot.

- :mod:`.catalog`: the robot registry, :data:`~.catalog.ROBOTS`: every robot a mission may name
  with its capabilities, its facts and the defaults derived from them (:mod:`.tuning`), the
  facts validation needs before any physics; :mod:`.robot_file`: a user's robot from YAML.
- :mod:`.footprint`: a footprint as Nav2 has one (radius or polygon, inscribed and
  circumscribed radii, clearance in a world).
- :mod:`.diff_drive`: what every differential-drive robot shares (facts record, generic MuJoCo
  body, base controller, go-to-goal, Bug2, keyboard teleop).
- :mod:`.arm_runtime`: what the runner asks of a fixed arm's runtime module.
- :mod:`.turtlebot3` (Burger, Waffle), :mod:`.turtlebot4`, :mod:`.panda`: each robot's facts
  with their sources, its own body or runtime.

Robots import only :mod:`baobab.sim`; navigation (:mod:`baobab.nav`) sits above them.
"""

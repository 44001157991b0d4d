"""The TurtleBot 4: an iRobot Create 3 base with an RPLIDAR A1M8 (:mod:`.facts`).

Its body is the generic differential-drive one (:mod:`baobab.robots.diff_drive.model`) built
from its facts; its entry in the registry is :mod:`baobab.robots.catalog`'s.
"""

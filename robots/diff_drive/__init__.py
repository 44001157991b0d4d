"""The differential-drive mobile robot any two-wheeled base shares: its base controller (cmd_vel,
limits, odometry), the compiled base loop, the footprint's clearance, the running robot's handle
and the tutorial controllers (go-to-goal, Bug2, keyboard teleop).
"""

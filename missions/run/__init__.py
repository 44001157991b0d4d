"""One run of a mission: the runner and its tick loop, the robot's rig, events and faults,
metrics, the trace, judging, recording, the plot and the terminal display."""

"""One run of a mission: :func:`.runner.run_mission` -> :class:`.runner.RunRecord`.

- :mod:`.runner`: build the rig, compile, loop, judge; :mod:`.tick_loop`: tick the tree,
  advance the sim, apply events, record, until the tree ends, a fault trips or time is up.
- :mod:`.rig`: the simulation and capability servers of the mission's robot
  (an arm's port comes from its runtime, :mod:`baobab.robots.arm_runtime`).
- :mod:`.events` (timed events) acting on :mod:`.event_targets` (obstacle slots, teleop
  input); :mod:`.faults` (injected faults) and :mod:`.fault_monitors` (what ends a run FAILED).
- :mod:`.metrics` (the registry), :mod:`.mobile_probe` and :mod:`.arm_probes` (what is
  measured); :mod:`.expectations`: the ``expect:`` block judged; :mod:`.exit_codes`.
- :mod:`.trace`: the sim-time trace and its digest; :mod:`.run_folder`: ``result.json``,
  ``trace.jsonl``, ``plot.png`` (:mod:`.plot_data`, :mod:`.plotting`);
  :mod:`.output_checks`: what a command will write, checked first.
- :mod:`.recording_hook`: ``--record``/``--live``/``--video``/``--btlog``/``--viewer``
  (:mod:`.recording_streams`, :mod:`.recording_topics`, :mod:`.video_caption`).
- :mod:`.progress_display`: the terminal's live progress and summary;
  :mod:`.child_process`: a run in a forked process; :mod:`.kernel_warmup`: the kernels
  compiled ahead of time (the wheel's build runs it).
"""

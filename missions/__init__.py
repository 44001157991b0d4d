"""Missions: the bundled mission files, and everything that loads, runs and judges a mission.

The ``*.yaml`` files here are the bundled missions (``baobab list``, ``baobab run NAME``);
``mission.schema.json`` is their JSON Schema for editors. The code is in five subpackages,
each importing only the ones below it (import-linter contracts in ``pyproject.toml``):

- :mod:`~baobab.missions.cli`: the ``baobab`` command line, one module per subcommand.
- :mod:`~baobab.missions.testing` and :mod:`~baobab.missions.campaigns`: missions as pytest
  scenario tests, and seeded sweeps of a mission.
- :mod:`~baobab.missions.run`: one run of a mission: rig, tick loop, events, faults, metrics,
  trace, judging, recording, plot.
- :mod:`~baobab.missions.language`: the mission format: load, validate, compile, export.

The few names to start from::

    from baobab.missions.language.loader import load_mission, Mission
    from baobab.missions.run.runner import run_mission, RunRecord
    from baobab.missions.language.errors import MissionError

This package imports nothing itself: the console script's signal handlers come first
(:mod:`baobab.missions.cli.entry`).
"""

"""Missions as tests: every mission with an ``expect:`` block is a pytest scenario.

- :mod:`.pytest_plugin`: the plugin (entry point ``pytest11``): ``pytest missions/``;
  :mod:`.pytest_junit`: missions in JUnit XML reports.
- :mod:`.scenario`: :func:`~.scenario.run_scenario`, one mission run, judged and kept.
- :mod:`.baseline`: performance baselines (``--baseline``, ``<stem>.baseline.json``);
  :mod:`.expectation_table`: expected against measured, as text.
"""

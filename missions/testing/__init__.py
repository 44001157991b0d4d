"""Missions as tests: the pytest plugin, scenario runs, expectation tables and baselines."""

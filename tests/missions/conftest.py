"""The YAML files here are fixtures of the loader and runner tests, not scenario tests.

Some carry ``expect:`` blocks that only make sense inside those tests, so the baobab pytest
plugin must not collect them as scenarios (it collects ``missions/`` when asked).
"""

collect_ignore_glob = ["*.yaml", "*.yml"]

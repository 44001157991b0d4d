"""The malformed files here are the corpus of ``tests/test_bad_inputs.py``, not scenarios.

Some carry ``expect:`` blocks, so the baobab pytest plugin must not collect them as scenario
tests; ``collect_ignore_glob`` is relative to this folder and its subfolders.
"""

collect_ignore_glob = ["*.yaml", "*.yml", "*/*.yaml", "*/*.yml"]

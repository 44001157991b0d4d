"""Suite-wide settings: hypothesis draws the same examples on every run (no flaky CI); no run
server."""

import os

from hypothesis import settings

# `baobab run` processes the tests start run on their own, as before the run server; its own
# tests (test_run_server.py) start servers of their own.
os.environ.setdefault("BAOBAB_RUN_SERVER", "0")

settings.register_profile("baobab", derandomize=True, deadline=None, print_blob=True)
settings.load_profile("baobab")

"""Suite-wide settings: hypothesis draws the same examples on every run (no flaky CI)."""

from hypothesis import settings

settings.register_profile("baobab", derandomize=True, deadline=None, print_blob=True)
settings.load_profile("baobab")

"""Campaigns: seeded sweeps of one mission, run in parallel (``baobab campaign``).

- :mod:`.vary`: what may vary (``--vary``/``--grid``) and the distributions;
  :mod:`.spec`: :func:`~.spec.build_spec`, the seeded plan of runs; :mod:`.variant`: one run's
  mission file.
- :mod:`.dispatch`: :func:`~.dispatch.run_campaign`; :mod:`.executors`: a local process pool
  (whose forkserver imports :mod:`.worker_preload`) or a Dask cluster.
- :mod:`.results`: the per-run SQLite table, the summary and its Wilson interval;
  :mod:`.outcomes_plot`: ``outcomes.png``.
"""

"""Benchmarks and studies of ergosim, beside the package and not installed with it (mink keeps its benchmarks
out of ``mink/``): what ``scripts/bench_*.py`` and the study scripts run. Each module measures one thing:

- :mod:`~benchmarks.planner`, :mod:`~benchmarks.planner_team`, :mod:`~benchmarks.planner_lookahead` (with
  :mod:`~benchmarks.planner_revision`, another revision's look-ahead), :mod:`~benchmarks.planner_plot`,
  :mod:`~benchmarks.planner_taskfile`: the planners and the task-file reader (``bench_planner.py``,
  ``bench_taskfile.py``);
- :mod:`~benchmarks.sim`, :mod:`~benchmarks.video`: the twin loop, the recording and the video
  (``bench_sim.py``);
- :mod:`~benchmarks.sweep`, :mod:`~benchmarks.gym`: sweeps and the Gym environment (``bench_sweep.py``,
  ``bench_gym.py``);
- :mod:`~benchmarks.replay`, :mod:`~benchmarks.replay_baseline`: ``ergosim replay`` of BVH recordings
  (``bench_bvh.py``);
- :mod:`~benchmarks.revision`: another git revision's modules loaded beside this checkout's;
- :mod:`~benchmarks.mode_study`: the allocation modes compared over a sweep
  (``compare_allocation_modes.py``).

Run from the repository's root (the scripts put it on ``sys.path``; pytest's ``pythonpath`` does for the
tests).
"""

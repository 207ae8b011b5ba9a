"""Design studies: sweeps over layouts, subjects and parameters, run locally or on a Ray cluster.

A sweep file (:mod:`ergosim.sweep.design`) names a base scenario and the axes of a design; every
(cell, subject, mode, seed) is one work unit (:mod:`ergosim.sweep.units`), run on a process pool or as Ray
tasks (:mod:`ergosim.sweep.executors`), written the moment it finishes (:mod:`ergosim.sweep.folder`) and
consolidated into ``results.parquet`` and ``cells.parquet`` (:mod:`ergosim.sweep.tables`,
:mod:`ergosim.sweep.stats`) with response plots and heat maps (:mod:`ergosim.sweep.plots`).
:mod:`ergosim.sweep.compare` compares two run or sweep folders, or two cells of a sweep. See docs/sweeps.md.
"""

from ergosim.sweep.design import Axis, Cell, Factor, Sampling, Sweep, load_sweep, parse_sweep
from ergosim.sweep.executors import EXECUTORS, LocalExecutor, RayExecutor, SweepError, make_executor
from ergosim.sweep.metrics import DEFAULT_METRICS, METRICS, metric_columns, unit_metrics
from ergosim.sweep.runner import EXIT_INCOMPLETE, SweepResult, run_sweep
from ergosim.sweep.stats import SMALL_N, mean_ci, metric_ci, paired_difference, share_ci, unpaired_difference
from ergosim.sweep.units import Unit, plan_units, run_unit, unit_id

__all__ = [
    "Axis", "Cell", "Factor", "Sampling", "Sweep", "load_sweep", "parse_sweep",
    "EXECUTORS", "LocalExecutor", "RayExecutor", "SweepError", "make_executor",
    "DEFAULT_METRICS", "METRICS", "metric_columns", "unit_metrics",
    "EXIT_INCOMPLETE", "SweepResult", "run_sweep",
    "SMALL_N", "mean_ci", "share_ci", "metric_ci", "paired_difference", "unpaired_difference",
    "Unit", "plan_units", "run_unit", "unit_id",
]

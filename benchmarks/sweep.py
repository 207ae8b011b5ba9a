"""Throughput of sweeps (``scripts/bench_sweep.py``): units per second and parallel efficiency against one
process, for the local pool and for Ray, measured side by side in one run (medians of repeats).

The study is a one-cell sweep of ``units`` subjects of a bundled scenario in one mode, one repetition
each. Every configuration runs it end to end into a fresh folder, start-up included (the process pool's
spawn and imports; for Ray, a local instance started and shut down by the sweep, as ``ergosim sweep
--executor ray`` does without an address), and the configurations are interleaved within each repeat so
they see the same machine load (the 1/5/15-minute load averages before and after are reported: other work
on the machine lowers the parallel figures). Parallel efficiency = units/s ÷ (workers × units/s of one
process). The steady-state figures leave the start-up out: units finished after the first ``workers``
ones, over the time from the ``workers``-th to the last (each unit records when it finished).
"""

from __future__ import annotations

import json
import os
import statistics
import tempfile
import time
from pathlib import Path

from ergosim.sweep.design import parse_sweep
from ergosim.sweep.runner import run_sweep

__all__ = ["bench_sweep", "CONFIGS"]

CONFIGS = (("local", 1), ("local", 2), ("ray", 2))
"""(executor, workers) measured; ("local", 1) runs the units in the benchmark's own process."""


def bench_sweep(scenario: str = "kwear-validation", units: int = 12, repeats: int = 3, mode: str = "hrc",
                seed: int = 0) -> dict:
    """Medians over ``repeats`` of wall time, units/s and parallel efficiency for each of :data:`CONFIGS`."""
    sweep = parse_sweep({"name": "bench", "scenario": scenario, "subjects": units, "seeds": [seed],
                         "modes": [mode], "set": {"repetitions": 1}}, source="bench_sweep")
    walls: dict[str, list[float]] = {f"{e}_{w}": [] for e, w in CONFIGS}
    unit_walls: dict[str, list[float]] = {k: [] for k in walls}
    steady: dict[str, list[float]] = {k: [] for k in walls}
    startups = []
    load_before = os.getloadavg()
    for _ in range(repeats):
        for executor, workers in CONFIGS:
            key = f"{executor}_{workers}"
            with tempfile.TemporaryDirectory() as tmp:
                t0 = time.perf_counter()
                res = run_sweep(sweep, Path(tmp), executor=executor, jobs=workers, progress=False)
                walls[key].append(time.perf_counter() - t0)
                if executor == "ray":
                    startups.append(res.executor["startup_s"])
                if res.finished != units or res.failed:
                    raise RuntimeError(f"{key}: {res.finished}/{units} units, {res.failed} failed")
                docs = [json.loads(p.read_text()) for p in (Path(tmp) / "units").glob("*.json")]
                unit_walls[key].append(statistics.median(d["wall_s"] for d in docs))
                done = sorted(d["finished_at"] for d in docs)
                steady[key].append((len(done) - workers) / (done[-1] - done[workers - 1]))
    serial = units / statistics.median(walls["local_1"])
    serial_steady = statistics.median(steady["local_1"])
    configs = {}
    for executor, workers in CONFIGS:
        key = f"{executor}_{workers}"
        wall = statistics.median(walls[key])
        rate = units / wall
        configs[key] = {"executor": executor, "workers": workers, "wall_s": wall, "units_per_s": rate,
                        "parallel_efficiency": rate / (workers * serial),
                        "steady_units_per_s": statistics.median(steady[key]),
                        "steady_parallel_efficiency":
                            statistics.median(steady[key]) / (workers * serial_steady),
                        "unit_wall_s": statistics.median(unit_walls[key]), "walls_s": walls[key]}
    return {"scenario": scenario, "mode": mode, "units": units, "repeats": repeats, "cores": os.cpu_count(),
            "configs": configs, "ray_startup_s": statistics.median(startups),
            "load_average": {"before": list(load_before), "after": list(os.getloadavg())}}

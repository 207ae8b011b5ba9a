"""Benchmark the worker's whole-body IK: time per ``WholeBodyIK.solve`` over a fixed set of problems.

The problems are a grid of hand targets in front of and beside a 1.75 m subject, each solved planted and
free to step, position-only and with a held orientation (the solves of :mod:`ergosim.worker.keyposes`).
Prints JSON: the median time per solve [ms] (the median over problems of each problem's median over
``--repeats``) and the total of the per-problem medians. With ``--baseline REV`` the solver modules of that
git revision (ik.py, ik_cost.py, gaze.py) run side by side, interleaved problem by problem so both see the
same machine load; the JSON then holds both, the speed-up, and whether every output is bit-identical.

    python scripts/bench_ik.py [--repeats 5] [--baseline main] [--json PATH]
"""

from __future__ import annotations

import argparse
import itertools
import json
import statistics
import time
import types

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed
import numpy as np
from scipy.spatial.transform import Rotation

from benchmarks.revision import modules_at
from ergosim.atomic import write_json
from ergosim.human import human_spec
from ergosim.worker import StandingArea, rest_angles
from ergosim.worker import ik as current_ik
from ergosim.worker.ik_prior import default_prior

FREE = StandingArea((-0.3, 0.15), (-0.35, 0.35), (-90.0, 90.0))
GRIP = Rotation.from_euler("xyz", [180.0, 0.0, -20.0], degrees=True).as_matrix()


def problems() -> list[tuple]:
    """(target (3,) [m], target_rot or None, area or None, max_iter or None), 108 of them."""
    out = []
    for x, y, z in itertools.product((0.25, 0.45, 0.65), (-0.45, -0.1, 0.3), (0.3, 0.9, 1.4)):
        for area in (None, FREE):
            out.append((np.array([x, y, z]), None, area, None))
            out.append((np.array([x, y, z]), GRIP, area, 40))
    return out


def solver_module(rev: str) -> types.ModuleType:
    """The IK module of git revision ``rev``, its cost and gaze modules loaded under private names."""
    return modules_at(rev, "ergosim.worker", ("gaze", "ik_cost", "ik"))["ik"]


def run(repeats: int, baseline: str | None) -> dict:
    model = human_spec(1.75).compile()
    impls = {"current": current_ik}
    if baseline:
        impls["baseline"] = solver_module(baseline)
    solvers = {k: m.WholeBodyIK(model, default_prior()) for k, m in impls.items()}
    rest = np.concatenate([rest_angles(), np.zeros(4)])
    probs = problems()
    times = {k: [[] for _ in probs] for k in impls}
    outputs = {k: [None] * len(probs) for k in impls}
    for _ in range(repeats):
        for i, (target, rot, area, max_iter) in enumerate(probs):
            for k, ik in solvers.items():
                t0 = time.perf_counter()
                sol = ik.solve(rest, target, "right", target_rot=rot, area=area, max_iter=max_iter)
                times[k][i].append(time.perf_counter() - t0)
                outputs[k][i] = sol
    res: dict = {"problems": len(probs), "repeats": repeats}
    for k in impls:
        per = [statistics.median(t) for t in times[k]]
        res[k] = {"median_solve_ms": 1e3 * statistics.median(per), "total_s": sum(per),
                  "mean_iterations": statistics.mean(s.iterations for s in outputs[k])}
    if baseline:
        res["baseline_rev"] = baseline
        res["speedup_median"] = res["baseline"]["median_solve_ms"] / res["current"]["median_solve_ms"]
        res["speedup_total"] = res["baseline"]["total_s"] / res["current"]["total_s"]
        res["bit_identical"] = all(
            a.body.tobytes() == b.body.tobytes() and a.iterations == b.iterations
            and all(float(x).hex() == float(y).hex() for x, y in zip(a[1:], b[1:], strict=True))
            for a, b in zip(outputs["current"], outputs["baseline"], strict=True))
    return res


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5, help="solves of each problem (medians)")
    parser.add_argument("--baseline", help="git revision whose IK runs side by side (e.g. main)")
    parser.add_argument("--json", dest="json_path", help="also write the result to this file")
    args = parser.parse_args()
    res = run(args.repeats, args.baseline)
    print(json.dumps(res, indent=2))
    if args.json_path:
        write_json(args.json_path, res)


if __name__ == "__main__":
    main()

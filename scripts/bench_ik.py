"""Benchmark the worker's planning: time to plan one action (stance, whole-body IK at the key poses, the
transitions), side by side with another git revision.

Plans every action of the bundled cells (kwear-validation, multi-subject, gearbox) for subject S01 of seed 0,
each part where the cell starts it, ``--repeats`` times. With ``--baseline REV`` the same plans run in a
checkout of REV (a temporary git worktree), each repeat of each tree in its own process, the two trees
interleaved repeat by repeat so both see the same machine load. Prints JSON: per tree the median over
repeats of the total planning time [s] and of the median time per action [ms], and the ratio baseline /
current (> 1: the current tree plans faster).

    python scripts/bench_ik.py [--repeats 5] [--baseline 6df92f7] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from ergosim.atomic import write_json

ROOT = Path(__file__).resolve().parents[1]
CELLS = ("kwear-validation", "multi-subject", "gearbox")

# Run in a fresh interpreter whose ergosim is the tree on PYTHONPATH; prints per-action seconds as JSON.
_PLAN = r"""
import json, sys, time
import numpy as np
from ergosim.scenes.cellbuild import action_geometry
from ergosim.scenes.registry import build_scene
from ergosim.worker.motion import Worker
from ergosim.worker.subjects import make_subjects

subject = make_subjects(1, 0)[0]
out = {}
for name in sys.argv[1:]:
    cell = build_scene(name, stature=subject.stature, human_scale=subject.scale)
    worker = Worker(subject)
    geoms = action_geometry(cell.config)
    rng = np.random.default_rng(0)
    worker.plan(cell, geoms[cell.config.actions[0].label], rng)  # warm-up: the cell's IK model is built once
    for action in cell.config.actions:
        t0 = time.perf_counter()
        worker.plan(cell, geoms[action.label], rng, action=action.label)
        out[f"{name}/{action.label}"] = time.perf_counter() - t0
print(json.dumps(out))
"""


def _plan_times(tree: Path) -> dict[str, float]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    done = subprocess.run([sys.executable, "-c", _PLAN, *CELLS], env=env, capture_output=True, text=True,
                          check=True, cwd=tree)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _summary(runs: list[dict[str, float]]) -> dict:
    totals = [sum(r.values()) for r in runs]
    per_action = [statistics.median(r.values()) * 1e3 for r in runs]
    return {"actions": len(runs[0]), "total_s": statistics.median(totals),
            "median_action_ms": statistics.median(per_action), "repeats": len(runs)}


def run(repeats: int, baseline: str | None) -> dict:
    trees = {"current": ROOT}
    tmp = None
    if baseline:
        tmp = tempfile.mkdtemp(prefix="ergosim-baseline-")
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", tmp, baseline], check=True,
                       capture_output=True)
        trees["baseline"] = Path(tmp)
    try:
        runs: dict[str, list] = {k: [] for k in trees}
        for _ in range(repeats):
            for name, tree in trees.items():
                runs[name].append(_plan_times(tree))
    finally:
        if tmp:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", tmp], check=False,
                           capture_output=True)
    out = {name: _summary(r) for name, r in runs.items()}
    if baseline:
        out["baseline"]["revision"] = baseline
        out["ratio_total"] = out["baseline"]["total_s"] / out["current"]["total_s"]
        out["ratio_median_action"] = out["baseline"]["median_action_ms"] / out["current"]["median_action_ms"]
    out["load_average"] = os.getloadavg()
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--baseline", default=None, help="git revision to run side by side")
    parser.add_argument("--json", type=Path, default=None, help="also write the JSON here")
    args = parser.parse_args()
    result = run(args.repeats, args.baseline)
    text = json.dumps(result, indent=2)
    print(text)
    if args.json:
        write_json(args.json, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

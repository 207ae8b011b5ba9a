"""Run a benchmark script here and in another git revision, interleaved, and compare their JSON.

    python scripts/bench_side_by_side.py REV [--repeats 3] [--json PATH] -- scripts/bench_sim.py --repeats 1

Each repeat runs ``SCRIPT ARGS --json FILE`` once in this checkout and once in a temporary worktree of REV
(each in its own process, whose ``ergosim`` is that tree's), one after the other, so both see the same
machine load. Prints JSON: for every numeric top-level field of the script's JSON, the median over repeats
in each tree and the ratio baseline / current.
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


def _run(tree: Path, script: str, args: list[str]) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "result.json"
        env = {**os.environ, "PYTHONPATH": str(tree)}
        subprocess.run([sys.executable, str(tree / script), *args, "--json", str(out)], cwd=tree, env=env,
                       check=True, stdout=subprocess.DEVNULL)
        return json.loads(out.read_text())


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("baseline", help="git revision")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", type=Path, default=None)
    argv = sys.argv[1:]
    if "--" not in argv or argv.index("--") == len(argv) - 1:
        parser.error("give the benchmark after --, e.g. -- scripts/bench_sim.py --repeats 1")
    cut = argv.index("--")
    a = parser.parse_args(argv[:cut])
    command = argv[cut + 1:]
    script, args = command[0], command[1:]
    tmp = tempfile.mkdtemp(prefix="ergosim-baseline-")
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", tmp, a.baseline], check=True,
                   capture_output=True)
    runs: dict[str, list[dict]] = {"current": [], "baseline": []}
    try:
        for _ in range(a.repeats):
            runs["current"].append(_run(ROOT, script, args))
            runs["baseline"].append(_run(Path(tmp), script, args))
    finally:
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", tmp], check=False,
                       capture_output=True)
    keys = [k for k, v in runs["current"][0].items() if isinstance(v, int | float) and not isinstance(v, bool)
            and k in runs["baseline"][0]]
    out = {"script": script, "args": args, "baseline_revision": a.baseline, "repeats": a.repeats,
           "load_average": os.getloadavg(), "fields": {}}
    for k in keys:
        cur = statistics.median(r[k] for r in runs["current"])
        base = statistics.median(r[k] for r in runs["baseline"])
        out["fields"][k] = {"current": cur, "baseline": base, "ratio_baseline_over_current":
                            base / cur if cur else None}
    print(json.dumps(out, indent=2))
    if a.json:
        write_json(a.json, out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

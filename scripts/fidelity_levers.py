"""The §7.1 levers of issue 23 (G(a1), a5's most-loaded joint), each measured; prints a markdown table.

    python scripts/fidelity_levers.py [--seeds 5]

The logic lives in ergosim.fidelity.levers; docs/fidelity.md reports the table.
"""

from __future__ import annotations

import argparse

from ergosim.fidelity import paper
from ergosim.fidelity.levers import run_levers


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=5)
    a = p.parse_args()
    rows = run_levers(seeds=range(a.seeds), log=lambda msg: print(msg, flush=True))
    want = " ".join(str(v) for v in paper.G_KWEAR_VALIDATION.values())
    print(f"| lever | what | G(a1..a5) (paper {want}) | most-loaded a1 / a2 / a5 "
          "(paper shoulder / neck / trunk) |")
    print("|---|---|---|---|")
    for r in rows:
        g = " ".join(f"{v:g}" for v in r.g.values())
        joints = " / ".join(r.loaded[a] for a in ("a1", "a2", "a5"))
        print(f"| {r.lever.name} | {r.lever.what} | {g} | {joints} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

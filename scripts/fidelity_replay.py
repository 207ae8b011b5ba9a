"""The paper's equations alone on a finished §7.2 run's measured inputs: its shares, and the wear a1 and a2
would need for the paper's split.

    python scripts/fidelity_replay.py RUN_DIR [--mode hrc]

RUN_DIR is a multi-subject run folder (e.g. the §7.2 seed of ``ergosim fidelity --out DIR``). Prints the
replay's robot share per action at the measured inputs (ergosim.fidelity.paper_model), then a scan of the
worker's wear per execution of a1 and a2 (each x1, x1.5, x2, x2.5, with the overall wear x1 and x1.25, as a
slower pace gives) under both tie rules, marking the rows that meet all four of docs/fidelity.md's share
bounds (30-46 %, a2 >= 60 % and the highest, a3 and a4 <= 25 %, a1 between a3/a4 and a2).
"""

from __future__ import annotations

import argparse
import itertools

from ergosim.fidelity.paper_model import inputs_from_run, scaled, simulate

ACTIONS = ("a1", "a2", "a3", "a4", "a5")


def _meets(total: float, by: dict[str, float]) -> bool:
    a1, a2, a3, a4 = (by[a] for a in ("a1", "a2", "a3", "a4"))
    return (0.30 <= total <= 0.46 and a2 >= 0.60 and a2 == max(by.values()) and a3 <= 0.25 and a4 <= 0.25
            and max(a3, a4) <= a1 <= a2)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("run", help="a multi-subject run folder")
    p.add_argument("--mode", default="hrc")
    a = p.parse_args()
    subjects = inputs_from_run(a.run, a.mode)
    print("| tie rule | overall wear | a1's wear | a2's wear | share | a1 / a2 / a3 / a4 | all four bounds |")
    print("|---|---|---|---|---|---|---|")
    for tie, overall, f1, f2 in itertools.product(("costliest-first", "cheapest-first"), (1.0, 1.25),
                                                  (1.0, 1.5, 2.0, 2.5), (1.0, 1.5, 2.0, 2.5)):
        factors = {act: overall for act in ACTIONS}
        factors["a1"], factors["a2"] = overall * f1, overall * f2
        shares = simulate([scaled(s, factors) for s in subjects], tie=tie)
        by = shares.by_action
        split = " / ".join(f"{100 * by[x]:.0f}" for x in ("a1", "a2", "a3", "a4"))
        print(f"| {tie} | x{overall:g} | x{f1:g} | x{f2:g} | {100 * shares.total:.0f} % | {split} % | "
              f"{'yes' if _meets(shares.total, by) else ''} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

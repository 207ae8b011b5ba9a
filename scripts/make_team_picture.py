"""A picture of parallel execution from a real run: both sub-assemblies of the gearbox built at once.

    python scripts/make_team_picture.py [--out docs/img/team_gearbox.png] [--scenario gearbox] [--seed 0]
                                        [--after 1.5] [--view NAME]

Runs one subject of the scenario in mode hrc with ``execution = "parallel"`` (two repetitions, body poses
kept), finds the first moment the worker and the robot both act, ``--after`` seconds into the later
attempt, and renders it with the video's overlay (one chip per attempt in progress).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ergosim.cli import headless_gl

headless_gl()  # before MuJoCo is imported

from PIL import Image  # noqa: E402

from ergosim.experiment.runner import run_subject  # noqa: E402
from ergosim.experiment.scenario import load_scenario  # noqa: E402
from ergosim.experiment.subject import scenario_subject, subject_cell  # noqa: E402
from ergosim.video.still import first_overlap, render_still  # noqa: E402

DEFAULT_OUT = Path(__file__).resolve().parents[1] / "docs" / "img" / "team_gearbox.png"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=DEFAULT_OUT)
    p.add_argument("--scenario", default="gearbox")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--after", type=float, default=1.5, help="seconds into the later attempt")
    p.add_argument("--view", default=None, help="a camera view of the workcell (default: its first)")
    a = p.parse_args()
    scenario = load_scenario(a.scenario, {"execution": "parallel", "modes": "hrc", "subjects": "1",
                                          "repetitions": "2"})
    result = run_subject(scenario, 0, a.seed, ("hrc",), record_mode="hrc")
    run = result.runs["hrc"]
    t = first_overlap(run, a.after)
    if t is None:
        print("no two agents acted at once in this run")
        return 1
    cell = subject_cell(scenario, scenario_subject(scenario, 0, a.seed))
    image = render_still(cell, run, t, view=a.view, header=f"{a.scenario}, parallel execution, subject 0")
    a.out.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(a.out)
    print(f"wrote {a.out} (t = {t:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Pictures of the worker: stills of planned actions in the paper's cells and a frame of a real run's video.

    python scripts/make_worker_pictures.py [--out docs/img] [--seed 0]

Writes ``worker_multi_subject.png`` and ``worker_kwear_validation.png`` (a1, a2 and a5 of the paper's two
cells), ``worker_pcb_enclosure.png`` (examples/pcb_enclosure: p1, the tray from the low bin; p3, the cover
from the 1.6 m shelf; p4, a screw on the bench), each action at the part, mid-carry and at its target, from
three quarters and from the side, and ``worker_video_frame.png``: a frame of the multi-subject HRC video
(subject 0, the worker fetching J in repetition 1), with the video's overlay.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ergosim.cli import headless_gl

headless_gl()  # before MuJoCo is imported

import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

from ergosim.experiment.runner import run_subject  # noqa: E402
from ergosim.experiment.scenario import load_scenario  # noqa: E402
from ergosim.experiment.subject import scenario_subject, subject_cell  # noqa: E402
from ergosim.twin.calibration import put_part  # noqa: E402
from ergosim.video.still import render_still  # noqa: E402
from ergosim.video.worker_stills import render_action_stills  # noqa: E402
from ergosim.worker import Worker  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_OUT = ROOT / "docs" / "img"
STILLS = {"multi-subject": ("a1", "a2", "a5"), "kwear-validation": ("a1", "a2", "a5"),
          str(ROOT / "examples" / "pcb_enclosure" / "pcb.toml"): ("p1", "p3", "p4")}
"""scenario -> the actions drawn"""
CAMERAS = {"three-quarter": dict(azimuth=215.0, elevation=-22.0, distance=2.6, lookat=(0.25, 0.0, 0.95)),
           "side": dict(azimuth=90.0, elevation=-8.0, distance=2.8, lookat=(0.25, 0.0, 0.95))}
"""The two views of each action: from the front left, and from the worker's right side."""


def _stills(scenario_name: str, actions: tuple[str, ...], seed: int) -> np.ndarray:
    scenario = load_scenario(scenario_name)
    subject = scenario_subject(scenario, 0, seed)
    cell = subject_cell(scenario, subject)
    worker = Worker(subject)
    rng = np.random.default_rng(seed)
    rows = []
    for name, geom in cell.actions.items():
        if name in actions:
            motion = worker.plan(cell, geom, rng, action=name)
            for view, camera in CAMERAS.items():
                rows.append(render_action_stills(cell, motion, geom.target, camera=camera,
                                                 title=f"{scenario.name} {name} ({view}): {motion.mtm}"))
            cell.reset()
            for done, g in cell.actions.items():  # the scene as the task leaves it before the next action
                if done == name:
                    break
                put_part(cell, g.part, *cell.site_pose(g.target))
                if g.seats:
                    cell.seat(g.part)
        put_part(cell, geom.part, *cell.site_pose(geom.target))
        if geom.seats:
            cell.seat(geom.part)
    return np.concatenate(rows, axis=0)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=DEFAULT_OUT)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    for scenario_name, actions in STILLS.items():
        path = a.out / f"worker_{load_scenario(scenario_name).name.replace('-', '_')}.png"
        Image.fromarray(_stills(scenario_name, actions, a.seed)).save(path)
        print(f"wrote {path}")
    scenario = load_scenario("multi-subject", {"subjects": "1", "repetitions": "1", "modes": "hrc"})
    run = run_subject(scenario, 0, a.seed, ("hrc",), record_mode="hrc").runs["hrc"]
    first = next(r for r in run.allocations if r.action == "a1")
    cell = subject_cell(scenario, scenario_subject(scenario, 0, a.seed))
    image = render_still(cell, run, first.t_start + 0.45 * (first.t_end - first.t_start),
                         header="multi-subject, HRC, subject 0: a1, the worker turns to the side table for J")
    path = a.out / "worker_video_frame.png"
    Image.fromarray(image).save(path)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

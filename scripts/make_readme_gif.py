"""Make the README's GIF from a real run: one HRC repetition in which the robot takes an action.

    python scripts/make_readme_gif.py [--out docs/img/hrc_repetition.gif] [--scenario multi-subject]
                                      [--seed 0] [--speed 6] [--width 480] [--fps 10]

Runs the twin (one subject, mode hrc), films the first repetition with a robot action offscreen
(MUJOCO_GL=egl is chosen on a machine without a display), and writes the GIF with ``<name>.json`` beside
it (parameters, the filmed attempts, the GIF's SHA-256). Rerun it whenever the simulation changes.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ergosim.cli import headless_gl

headless_gl()  # before MuJoCo is imported

from ergosim.experiment.clip import ClipSettings, repetition_clip  # noqa: E402

DEFAULT_OUT = Path(__file__).resolve().parents[1] / "docs" / "img" / "hrc_repetition.gif"


def main() -> int:
    d = ClipSettings()
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=DEFAULT_OUT)
    p.add_argument("--scenario", default=d.scenario)
    p.add_argument("--seed", type=int, default=d.seed)
    p.add_argument("--subject", type=int, default=d.subject)
    p.add_argument("--repetitions", type=int, default=d.repetitions, help="at most this many are simulated")
    p.add_argument("--speed", type=float, default=d.speed, help="× real time")
    p.add_argument("--width", type=int, default=d.width, help="GIF width [px]")
    p.add_argument("--fps", type=float, default=d.fps, help="GIF frames per second")
    p.add_argument("--quiet", action="store_true")
    a = p.parse_args()
    settings = ClipSettings(scenario=a.scenario, seed=a.seed, subject=a.subject, repetitions=a.repetitions,
                            speed=a.speed, width=a.width, fps=a.fps)
    doc = repetition_clip(a.out, settings, progress=not a.quiet)
    print(f"wrote {a.out} ({doc['bytes'] / 1e6:.2f} MB, {doc['gif_frames']} frames, repetition "
          f"{doc['repetition']}, simulated {doc['sim_time'][0]:.1f}-{doc['sim_time'][1]:.1f} s at "
          f"×{a.speed:g}) and {a.out.with_suffix('.json').name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

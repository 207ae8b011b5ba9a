"""Benchmark ``--video``: ms of wall and CPU per frame at 960x540, against another git revision side by side.

One subject's first repetition of the scenario (mode hrc) is run once with body poses kept; ``--seconds`` of
it are filmed at 30 fps ``--repeats`` times with this checkout's robot models and render settings, and with
``--baseline REV``'s (its ``models/`` and its default ``RenderQuality``), in turn, so both see the same
machine load. Each film is made with the default worker processes and in one process. Prints JSON: the
medians over repeats, the speed-up (baseline wall / current wall, paired by repeat) and the 1-minute load
average around each repeat. ``--stills DIR`` also writes the frames at ``--at`` seconds of both as PNGs
(``current_<t>.png``, ``baseline_<t>.png``), from the cell's first view and ``--close`` a close view of the
robot. Target (issue 38): <= 40 ms of wall per frame on 2 cores.

    python scripts/bench_video.py [--baseline 6df92f7] [--repeats 3] [--stills docs/img] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed

from ergosim.atomic import write_json
from ergosim.cli import headless_gl

headless_gl()  # offscreen rendering, before MuJoCo is imported

from PIL import Image  # noqa: E402

from benchmarks.video_baseline import baseline_cell, baseline_quality, compare_revisions, stills  # noqa: E402
from ergosim.atomic import write_bytes  # noqa: E402
from ergosim.experiment.runner import run_subject  # noqa: E402
from ergosim.experiment.scenario import load_scenario  # noqa: E402
from ergosim.experiment.subject import scenario_subject, subject_cell  # noqa: E402
from ergosim.scenes.cellspec import View  # noqa: E402
from ergosim.video.frames import RenderQuality  # noqa: E402
from ergosim.video.render_pool import default_workers  # noqa: E402

CLOSE = View("robot close-up", azimuth=250.0, elevation=-20.0, distance=1.3, lookat=(0.5, 0.45, 1.05))
"""A close view of the Panda on its side table (multi-subject), where decimated meshes would show first."""


def _png(image, path: Path) -> None:
    import io  # noqa: PLC0415

    buf = io.BytesIO()
    Image.fromarray(image).save(buf, format="PNG", optimize=True)
    write_bytes(path, buf.getvalue())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="multi-subject")
    parser.add_argument("--baseline", help="git revision filmed side by side (e.g. 6df92f7)")
    parser.add_argument("--repeats", type=int, default=3, help="films of each revision; medians")
    parser.add_argument("--seconds", type=float, default=10.0, help="simulated seconds filmed at x1")
    parser.add_argument("--stills", type=Path, help="also write still frames of both revisions here")
    parser.add_argument("--at", default="6,24", help="simulated times [s] of the stills, comma-separated")
    parser.add_argument("--close", action="store_true", help="stills also from a close view of the robot")
    parser.add_argument("--json", dest="json_path")
    args = parser.parse_args()
    sc = load_scenario(args.scenario).with_overrides({"repetitions": "1", "modes": "hrc"})
    subject = scenario_subject(sc, 0, 0)
    run = run_subject(sc, 0, 0, ("hrc",), record_mode="hrc").runs["hrc"]
    films = {"current": (subject_cell(sc, subject), RenderQuality())}
    if args.baseline:
        films["baseline"] = (baseline_cell(args.baseline, lambda: subject_cell(sc, subject)),
                             baseline_quality(args.baseline))
    res = {"scenario": args.scenario, "baseline_rev": args.baseline,
           **compare_revisions(films, run, repeats=args.repeats, window=(0.0, args.seconds),
                               size=(960, 540), speed=1.0, workers=default_workers())}
    if args.stills:
        times = [float(t) for t in args.at.split(",")]
        views = {"": None, "close_": CLOSE} if args.close else {"": None}
        for name, (cell, quality) in films.items():
            for tag, view in views.items():
                for t, image in zip(times, stills(cell, run, times, quality, view=view), strict=True):
                    _png(image, args.stills / f"video_{name}_{tag}{t:g}s.png")
    print(json.dumps(res, indent=2))
    if args.json_path:
        write_json(args.json_path, res)


if __name__ == "__main__":
    main()

"""``ergosim render SCENARIO --out PNG``: a still of a scenario's workcell from one of its named camera views.

The workcell is built as a run would build it (with any ``--set`` overrides) and rendered offscreen by
MuJoCo in its initial state: the worker at rest, the parts where they are laid out. Camera views are the
``[views.NAME]`` tables of the workcell file (azimuth, elevation, distance, look-at point).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ergosim.atomic import check_output_file
from ergosim.errors import ConfigError
from ergosim.overrides import parse_assignments

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    from ergosim.experiment.scenario import scenario_names  # noqa: PLC0415 - keep `ergosim --help` fast

    p = sub.add_parser(
        "render", help="render a still of a scenario's workcell (PNG) from one of its camera views",
        description="Build the scenario's workcell and render it offscreen with MuJoCo to a PNG. The views "
                    "are the [views.NAME] tables of the workcell file.",
    )
    p.add_argument("scenario", help=f"a scenario file (.toml) or one of: {', '.join(scenario_names())}")
    p.add_argument("--out", required=True, metavar="PNG", help="the PNG file to write")
    p.add_argument("--view", metavar="NAME", help="a camera view of the workcell (default: its first)")
    p.add_argument("--size", default="960x720", metavar="WxH", help="image size in pixels (default 960x720)")
    p.add_argument("--set", dest="assign", action="append", default=[], metavar="KEY=VALUE",
                   help="override a workcell field as in `ergosim run` (e.g. scene.shelf_height=1.6)")
    return p


def run(args) -> int:
    from ergosim.atomic import write_bytes  # noqa: PLC0415
    from ergosim.experiment.report.still import workcell_png  # noqa: PLC0415
    from ergosim.experiment.scenario import load_scenario  # noqa: PLC0415
    from ergosim.video.run_video import parse_size  # noqa: PLC0415

    out = Path(args.out)
    if out.suffix.lower() != ".png":
        raise ConfigError(f"the still is written as PNG: give a file name ending in .png, got {out.name!r}",
                          where="--out")
    check_output_file(out, where="--out")
    width, height = parse_size(args.size, where="--size")
    scenario = load_scenario(args.scenario, parse_assignments(args.assign))
    spec = scenario.cell()
    try:
        view = spec.view(args.view)
    except ConfigError as err:
        raise ConfigError(err.what, where="--view") from None
    png = workcell_png(spec, view=view.name, width=width, height=height)
    try:
        write_bytes(out, png)
    except OSError as err:
        raise ConfigError(f"cannot write {out}: {err.strerror or err}", where="--out") from None
    print(f"wrote {out} ({width}x{height}, view {view.name!r} of workcell {spec.name!r}; views: "
          f"{', '.join(v.name for v in spec.views)})")
    return 0

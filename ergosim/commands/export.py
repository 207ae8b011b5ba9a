"""``ergosim export SCENARIO --out DIR``: the scenario's compiled scene as a self-contained MJCF folder.

The workcell is built as a run would build it (with any ``--set`` overrides) and saved by MuJoCo with every
mesh it uses (:mod:`ergosim.scenes.export`); ``python -m mujoco.viewer --mjcf DIR/<cell>.xml`` opens it.
"""

from __future__ import annotations

import argparse

from ergosim.overrides import parse_assignments

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    from ergosim.experiment.scenario import scenario_names  # noqa: PLC0415 - keep `ergosim --help` fast

    p = sub.add_parser(
        "export", help="write a scenario's compiled scene as a self-contained MJCF folder (plain MuJoCo)",
        description="Build the scenario's workcell and save it as DIR/<cell>.xml with its meshes in "
                    "DIR/assets/, so that plain MuJoCo loads it (mujoco.MjModel.from_xml_path, "
                    "python -m mujoco.viewer --mjcf DIR/<cell>.xml).",
    )
    p.add_argument("scenario", help=f"a scenario file (.toml) or one of: {', '.join(scenario_names())}")
    p.add_argument("--out", required=True, metavar="DIR", help="the folder to write (created if needed)")
    p.add_argument("--set", dest="assign", action="append", default=[], metavar="KEY=VALUE",
                   help="override a workcell field as in `ergosim run` (e.g. scene.robots.robot.model=ur5)")
    return p


def run(args) -> int:
    from ergosim.experiment.scenario import load_scenario  # noqa: PLC0415
    from ergosim.scenes.export import export_cell  # noqa: PLC0415

    scenario = load_scenario(args.scenario, parse_assignments(args.assign))
    spec = scenario.cell()
    result = export_cell(spec, args.out)
    print(f"wrote {result.path} and {len(result.assets)} meshes in {result.path.parent / 'assets'}; open it "
          f"with: python -m mujoco.viewer --mjcf {result.path}")
    return 0

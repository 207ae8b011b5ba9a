"""``ergosim scenarios``: the scenarios ``ergosim run NAME`` knows, one line each.

ergosim scenarios [--json]

Each line gives the scenario's name, its protocol at a glance (subjects × repetitions, modes) and the
description from its file. The bundled scenarios live in ``ergosim/data/scenarios``; a scenario registered
from Python (:func:`ergosim.experiment.scenario.register_scenario`) is listed as well. Only the files are
read: nothing is built or simulated.
"""

from __future__ import annotations

import argparse
import json

__all__ = ["add_parser", "run", "scenario_lines"]


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "scenarios", help="list the scenarios `ergosim run` knows by name",
        description="List the bundled (and registered) scenarios, one line each: name, subjects × "
                    "repetitions, modes, description. Run one with `ergosim run NAME`.",
    )
    p.add_argument("--json", action="store_true", help="one JSON object per scenario instead of the table")
    return p


def _entries() -> list[dict]:
    from ergosim.experiment.scenario import scenario_info, scenario_names  # noqa: PLC0415

    return [scenario_info(name) for name in scenario_names()]


def scenario_lines(entries: list[dict]) -> list[str]:
    """The table of ``ergosim scenarios``: one line per entry of :func:`scenario_info`."""
    width = max((len(e["name"]) for e in entries), default=4)
    lines = []
    for e in entries:
        protocol = f"{e['subjects']} × {e['repetitions']}, {', '.join(e['modes'])}"
        lines.append(f"{e['name']:<{width}}  {protocol:<24}  {e['description']}".rstrip())
    return lines


def run(args) -> int:
    entries = _entries()
    if args.json:
        print(json.dumps(entries, indent=2, ensure_ascii=False))
    else:
        print("\n".join(scenario_lines(entries)))
    return 0

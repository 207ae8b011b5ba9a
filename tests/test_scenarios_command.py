"""``ergosim scenarios`` lists the scenarios ``ergosim run NAME`` knows, one line each (issue 12 §1)."""

from __future__ import annotations

import json

from ergosim.cli import main


def test_the_bundled_scenarios_one_line_each(capsys):
    assert main(["scenarios"]) == 0
    lines = capsys.readouterr().out.splitlines()
    names = [line.split()[0] for line in lines]
    assert {"gearbox", "kwear-validation", "multi-subject"} <= set(names) and len(set(names)) == len(names)
    by_name = dict(zip(names, lines, strict=True))
    assert "12 × 10, hrc, h-only" in by_name["multi-subject"] and "Paper §7.2" in by_name["multi-subject"]
    assert "1 × 4, hrc, rula" in by_name["kwear-validation"]
    assert "6 × 5, hrc, h-only" in by_name["gearbox"] and "two sub-assemblies" in by_name["gearbox"]


def test_the_list_as_json(capsys):
    assert main(["scenarios", "--json"]) == 0
    entries = {e["name"]: e for e in json.loads(capsys.readouterr().out)}
    gearbox = entries["gearbox"]
    assert gearbox["task"] == "gearbox" and gearbox["workcell"] == "gearbox"
    assert gearbox["subjects"] == 6 and gearbox["repetitions"] == 5 and gearbox["modes"] == ["hrc", "h-only"]
    assert gearbox["path"].endswith("ergosim/data/scenarios/gearbox.toml")

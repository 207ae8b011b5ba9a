"""Extension points, each in one place (issue 12 §4): a new mode with a new risk index is one new module
(``extension_mode.py``), and a new scenario is one ``register_scenario`` call; both run end to end through
the real loop, in worker processes too.
"""

from __future__ import annotations

import csv
import json

import extension_mode
import numpy as np
import pytest
from own_product import write_product

from ergosim import api
from ergosim.cli import main
from ergosim.experiment import scenario as scenariofile
from ergosim.plugins import extension_modules
from ergosim.viz.reason import reason_text


def test_a_new_mode_and_risk_index_are_registered_by_importing_one_module():
    assert "peak" in api.mode_names() and "kwear-peak" in api.risk_index_names()
    assert api.get_mode("peak").risk_index == "kwear-peak"
    assert extension_mode.__name__ in extension_modules()  # worker processes will import it too


@pytest.mark.slow
def test_the_new_mode_runs_end_to_end_in_worker_processes(tmp_path, capsys):
    """Two subjects in two spawned processes, which import extension_mode themselves."""
    out = tmp_path / "peak"
    sc = api.load("kwear-validation", modes=["peak"], subjects=2, repetitions=2, v_th=0.3, eta_max=3)
    res = api.run(sc, jobs=2, out=out)
    summary = json.loads((out / "summary.json").read_text())
    assert list(summary["modes"]) == ["peak"] and summary["complete"] and res.status == "complete"
    assert summary["modes"]["peak"]["repetitions_completed"] == 4
    with (out / "allocations.csv").open() as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "done"]
    assert len(rows) == 20
    gamma, robot_cost = sc.protocol.cost.gamma, sc.protocol.cost.robot_cost
    for r in rows:
        human = float(r["human_cost"])
        # one channel: max_i V̂_i < 1, or that plus Γ once it reaches V_th -- never a sum over joints
        assert human < 1.0 or gamma <= human < gamma + 1.0, r
        assert (r["agent"] == "robot") == (human > robot_cost), r
    assert any(r["agent"] == "robot" for r in rows)  # V_th 0.3 is crossed within two repetitions
    # and it says why, in its own words
    decisions = [d for run in res.runs("peak") for d in run.decisions]
    assert len(decisions) == 20
    for d in decisions:
        peak = float(np.max(d.v_hat[d.action]))
        text = reason_text(d)
        assert text.startswith(f"{d.action} → {d.agent}: peak predicted KWear {peak:.2f}"), text
    assert main(["run", "kwear-validation", "--mode", "peak", "--reps", "1", "--jobs", "1", "--quiet",
                 "--no-plots",
                 "--set", "eta_max=2", "--out", str(tmp_path / "cli")]) == 0  # --mode offers it too
    capsys.readouterr()


@pytest.mark.slow
def test_a_registered_scenario_is_listed_and_runs_by_name(tmp_path, capsys):
    path = write_product(tmp_path / "own", scenario=_scenario())
    api.register_scenario("my-bracket", path)
    try:
        assert main(["scenarios"]) == 0
        listed = capsys.readouterr().out
        line = next(x for x in listed.splitlines() if x.startswith("my-bracket"))
        assert "1 × 1, h-only, r-only" in line and "The bracket in its cell" in line
        out = tmp_path / "out"
        assert main(["run", "my-bracket", "--jobs", "1", "--quiet", "--no-plots", "--out", str(out)]) == 0
        summary = json.loads((out / "summary.json").read_text())
        assert summary["scenario"] == "bracket" and summary["complete"]
        assert summary["modes"]["r-only"]["robot_share"] == 1.0
        assert summary["modes"]["h-only"]["robot_share"] == 0.0
    finally:
        scenariofile.SCENARIOS.unregister("my-bracket")  # leave the registry as the other tests expect it


def _scenario() -> str:
    from own_product import SCENARIO  # noqa: PLC0415

    quick = 'modes = ["h-only", "r-only"]\neta_max = 2'  # modes without a risk index: a short calibration
    return SCENARIO.replace('modes = ["hrc", "h-only", "r-only"]', quick)

"""REBA in the twin: KWear driven by REBA part scores (mode hrc-reba) and the static REBA baseline (mode
reba) run end to end; ticks.csv gains the REBA columns only when a REBA index runs; the REBA-driven V
follows eq. 3-5 on the logged REBA part scores; the summary carries REBA's G(a_k)."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from ergosim import api
from ergosim.ergonomics.cost import CostParams
from ergosim.ergonomics.kwear import kwear_step
from ergosim.ergonomics.reba import REBA_JOINTS, REBA_PARTS
from ergosim.ergonomics.risk_index import RiskIndex
from ergosim.experiment.subject import scenario_subject
from ergosim.posture import ANGLE_NAMES
from ergosim.twin.features import REBA_COLUMNS
from ergosim.twin.modes import Mode, RiskIndexEntry, register_mode, register_risk_index
from ergosim.twin.records import TICK_COLUMNS
from ergosim.viz.reason import reason_text


@pytest.fixture(scope="module")
def reba_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("reba") / "run"
    sc = api.load("multi-subject", modes=["hrc-reba", "reba"], subjects=1, repetitions=2, eta_max=3)
    return sc, api.run(sc, out=out), out


def _ticks(out):
    with (out / "ticks.csv").open() as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


@pytest.mark.slow
def test_ticks_gain_the_reba_columns_and_kwear_legs(reba_run):
    _, _, out = reba_run
    header, rows = _ticks(out)
    assert tuple(header) == ("subject", "mode", *TICK_COLUMNS, *REBA_COLUMNS, "kwear_legs")
    col = {c: i for i, c in enumerate(header)}
    scores = np.array([[float(r[col[c]]) for c in REBA_COLUMNS] for r in rows])
    ok = np.isfinite(scores).all(axis=1)
    assert ok.mean() > 0.9  # dropouts aside
    for c, (lo, hi) in zip(REBA_COLUMNS, [(1, 6), (1, 2), (1, 3), (1, 3), (1, 5), (1, 4), (1, 15)],
                           strict=True):
        v = scores[ok, REBA_COLUMNS.index(c)]
        assert v.min() >= lo and v.max() <= hi, c
    assert (scores[ok, REBA_COLUMNS.index("reba_legs")] == 1).all()  # no knees yet: both feet, straight


def test_the_reba_driven_v_follows_eq_3_to_5_on_the_logged_scores(reba_run):
    sc, _, out = reba_run
    header, rows = _ticks(out)
    col = {c: i for i, c in enumerate(header)}
    mine = [r for r in rows if r[1] == "hrc-reba"]
    params = scenario_subject(sc, 0, 0).kwear_params()
    by_part = [col[f"reba_{p}"] for p in ("upper_arm", "lower_arm", "wrist", "trunk", "neck", "legs")]
    kwear = [col[f"kwear_{j}"] for j in REBA_JOINTS]
    v = np.zeros(len(REBA_JOINTS))
    dt = 1.0 / sc.protocol.sensing.ergonomics_rate
    for r in mine:
        acting = float(r[col["acting"]]) == 1.0
        g = np.array([float(r[i]) for i in by_part])
        if acting and np.isfinite(g).all():
            v = kwear_step(v, g, dt, params)
        elif not acting:
            v = kwear_step(v, np.zeros(6), dt, params, resting=True)
        np.testing.assert_allclose([float(r[i]) for i in kwear], v, rtol=1e-6, atol=1e-8)
    assert v[-1] >= 0 and max(float(r[col["kwear_legs"]]) for r in mine) > 0  # the legs wear too


def test_summary_has_reba_figures(reba_run):
    _, res, out = reba_run
    summary = json.loads((out / "summary.json").read_text())
    g = summary["reba_g_by_action"]
    assert set(g) == {"a1", "a2", "a3", "a4", "a5"} and all(1 <= x <= 15 for x in g.values())
    assert set(summary["calibration"]["reba_g_by_action"]) == set(g)
    assert set(summary["allocation_table"]) == {"kwear_reba", "reba"}
    # the static baseline: REBA's G(a_k) against G_th 8; every action here scores below the high-risk band
    reba_rows = [a for a in res.allocations if a.mode == "reba" and a.done]
    assert all(a.agent == "human" for a in reba_rows) and max(g.values()) < 8
    for d in (d for run in res.runs("reba") for d in run.decisions):
        assert "REBA G=" in reason_text(d)


@pytest.mark.slow
def test_the_static_reba_baseline_sends_actions_over_its_threshold_to_the_robot(tmp_path):
    sc = api.load("multi-subject", modes=["reba"], subjects=1, repetitions=1, eta_max=2, reba_threshold=1)
    res = api.run(sc, out=tmp_path / "low")
    robot = [a.action for a in res.allocations if a.done and a.agent == "robot"]
    assert robot == ["a1", "a2", "a3", "a4"]  # REBA G >= 1 always; a5 is the worker's alone


@pytest.mark.slow
def test_without_a_reba_index_ticks_stay_as_they_were(tmp_path):
    out = tmp_path / "plain"
    api.run(api.load("multi-subject", modes=["h-only"], subjects=1, repetitions=1, eta_max=2), out=out)
    header, _ = _ticks(out)
    assert tuple(header) == ("subject", "mode", *TICK_COLUMNS)
    summary = json.loads((out / "summary.json").read_text())
    assert "reba_g_by_action" not in summary and "reba_threshold" not in summary["config"]
    assert REBA_PARTS[-1] == "legs"


class TrunkAngleIndex(RiskIndex):
    """A user's index on raw joint angles: the worker's largest trunk flexion so far [deg] / 90, one
    channel; predict() adds nothing per action. It reads feature ``angles``."""

    features = "angles"
    joints = ANGLE_NAMES
    channels = ("trunk",)

    def _advance(self, g, dt, resting):
        if not resting:
            self._v[:] = np.maximum(self._v, np.abs(g))

    def predict(self, action):
        return np.array([self._v[0] / 90.0])


@pytest.mark.slow
def test_an_index_on_joint_angles_reads_the_angles(tmp_path):
    register_risk_index(RiskIndexEntry(
        "trunk-angle", lambda ctx: (TrunkAngleIndex(), CostParams(gamma=1.5, v_th=0.9, robot_cost=2.0,
                                                                  v_max=1.0)),
        features="angles"))
    register_mode(Mode("trunk", "largest trunk flexion", risk_index="trunk-angle"))
    sc = api.load("multi-subject", modes=["trunk"], subjects=1, repetitions=1, eta_max=2)
    res = api.run(sc, out=tmp_path / "angles")
    decisions = [d for run in res.runs("trunk") for d in run.decisions]
    assert decisions and all(d.basis.index == "trunk-angle" for d in decisions)
    peak = max(float(np.asarray(d.v_hat[d.action])[0]) for d in decisions)
    assert 0 < peak < 1  # some trunk flexion, in degrees / 90

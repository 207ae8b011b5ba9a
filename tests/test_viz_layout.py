"""The rerun layout of issue 16: V_th once, legends off the data, a 3-D view that frames the whole cell and
the worker, the decisions, failures and repetitions in the text log. The screenshot in docs/img shows it in
the web viewer (docs/visualisation.md says how it was made)."""

from __future__ import annotations

import csv
import math
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest
from rerun.chunk import RrdReader

from ergosim.experiment.scenario import load_scenario, scenario_names
from ergosim.experiment.subject import subject_cell
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS
from ergosim.scenes import build_cell
from ergosim.viz import RecordingReader, default_body_groups, open_recording
from ergosim.viz.blueprint import ARM_ANGLES, ARM_RANGE, KWEAR_RANGE, RULA_RANGE, TRUNK_RANGE
from ergosim.viz.eye import _FOV_DEG, _visible_bounds, _visible_corners, frame_scene
from ergosim.worker.subjects import make_subjects

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def recorded(forced_run):
    """A real run with a failure in it (L beyond the reach of a worker whose feet stay planted), recorded: the
    shared forced run (tests/conftest.py)."""
    assert forced_run.code == 0
    return forced_run.out, forced_run.rrd


def _blueprints(rrd: Path) -> list[dict[str, list]]:
    """Per blueprint in the recording (the one sent at open and the one with the 3-D eye, sent once the
    scene is known; their order in the file is not fixed): component -> values."""
    reader = RrdReader(rrd)
    out = []
    for store in reader.blueprints():
        found: dict[str, list] = defaultdict(list)
        for chunk in reader.stream(store=store).to_chunks():
            batch = chunk.to_record_batch()
            for name in batch.schema.names:
                if ":" in name:
                    found[name].extend(batch.column(batch.schema.names.index(name)).to_pylist())
        out.append(found)
    return out


def test_v_th_is_one_line_when_every_joint_shares_it(recorded):
    _, rrd = recorded
    reader = RecordingReader(rrd)
    t, v = reader.scalars("ergonomics/kwear_threshold")
    assert np.all(v == 0.8) and len(t) >= 2
    assert not [e for e in reader.entities if e.startswith("ergonomics/kwear_threshold/")]
    _, kwear = reader.scalars("ergonomics/kwear/shoulder")
    assert t.min() <= 0.05 and t.max() == pytest.approx(reader.scalars("ergonomics/kwear/shoulder")[0].max())
    assert kwear.max() < KWEAR_RANGE[1] - 0.3  # the band the legend sits in stays empty


def test_the_text_log_holds_every_decision_failure_and_repetition(recorded):
    out, rrd = recorded
    _, texts = RecordingReader(rrd).texts("allocation/log")
    with (out / "allocations.csv").open() as f:
        attempts = [r for r in csv.DictReader(f) if r["status"] != "pruned"]
    with (out / "failures.csv").open() as f:
        failures = list(csv.DictReader(f))
    decisions = [x for x in texts if " → " in x]
    assert len(decisions) == len(attempts)  # one decision per attempt, with its reason
    assert [x.split(":")[0] for x in decisions] == [f"{r['action']} → {r['agent']}" for r in attempts]
    assert failures and all(f"{r['status']}: {r['message']}" in texts for r in failures)
    assert texts.count("repetition 1 starts") == 1 and texts.count("repetition 2 starts") == 1
    assert sum(x.startswith("repetition 2 completed after") for x in texts) == 1


def test_legends_sit_in_bands_the_data_never_reach(recorded):
    out, rrd = recorded
    bps = _blueprints(rrd)
    assert len(bps) == 2
    for bp in bps:
        corners = [c for c in bp["PlotLegend:corner"] if c is not None]
        assert corners and set(np.ravel(corners)) == {1}  # LeftTop, over the empty band at each plot's top
        visible = np.ravel([v for v in bp["PlotLegend:visible"] if v is not None]).tolist()
        assert sorted(visible) == [False] * 2 + [True] * 4  # V̂ and costs (points, a series per candidate)
    with (out / "ticks.csv").open() as f:
        rows = list(csv.DictReader(f))

    def top(names):
        return max(float(r[n]) for r in rows for n in names if r[n] != "nan")
    assert top([f"kwear_{j}" for j in KWEAR_JOINTS]) <= 1.0 < KWEAR_RANGE[1] - 0.3
    assert top([c for c in rows[0] if c.startswith("rula_")]) <= 7 < RULA_RANGE[1] - 4
    assert top(ARM_ANGLES) <= 180 < ARM_RANGE[1] - 200
    assert top([n for n in ANGLE_NAMES if n not in ARM_ANGLES]) <= 90 < TRUNK_RANGE[1] - 100


@pytest.mark.parametrize("name", scenario_names())
def test_the_3d_view_frames_every_visible_geom_of_each_cell(name):
    """Every corner of every visible geom's box inside the view rerun draws (its measured field of view and
    aspect), the view centred on them and filled (issue 27: the view opened far out: the depth of a point
    entered the framing with the wrong sign)."""
    cell = build_cell(load_scenario(name).cell())
    view = cell.config.view()
    eye = frame_scene(cell.model, view.azimuth, view.elevation)
    corners = _visible_corners(cell.model)
    forward = np.subtract(eye.look_target, eye.position)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0, 0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = corners - np.asarray(eye.position)
    depth = rel @ forward
    tan_v = math.tan(math.radians(_FOV_DEG) / 2)
    v = (rel @ up) / depth / tan_v
    h = (rel @ right) / depth / (tan_v * 1.47)
    assert depth.min() > 0 and max(np.abs(v).max(), np.abs(h).max()) <= 1.0  # everything in view
    assert max(np.abs(v).max(), np.abs(h).max()) > 0.85  # and filling it
    assert abs(v.max() + v.min()) < 0.05 or abs(h.max() + h.min()) < 0.05  # centred where it is tight
    lo, hi = _visible_bounds(cell.model)
    human = [b for b, g in default_body_groups(cell.model, cell.parts).items() if g == "human"]
    assert human and all(np.all(lo - 1e-9 <= cell.data.xpos[cell.model.body(b).id]) for b in human)


def test_the_recordings_3d_view_starts_at_the_framing_eye(recorded):
    _, rrd = recorded
    cell = subject_cell(load_scenario("multi-subject", {"scene.l_xy": "0.14,0.88"}), make_subjects(1, 0)[0])
    view = cell.config.view()
    eye = frame_scene(cell.model, view.azimuth, view.elevation)
    positions = [p for bp in _blueprints(rrd) for p in bp["EyeControls3D:position"] if p is not None]
    assert len(positions) == 1 and np.allclose(np.ravel(positions[0]), eye.position, atol=1e-4)


def test_capsules_are_drawn_solid(tmp_path):
    cell = build_cell(load_scenario("kwear-validation").cell())
    path = tmp_path / "static.rrd"
    with open_recording(rrd=path) as rec:
        groups = default_body_groups(cell.model, cell.parts)
        rec.log_static(cell.model, v_th=np.full(5, 0.8), body_groups=groups)
    reader = RecordingReader(path)
    capsules = [e for e in reader.entities if e.endswith("/capsules")]
    assert capsules and all(reader.static(e, "Capsules3D:fill_mode") for e in capsules)


def test_the_committed_screenshot_and_its_command_are_documented():
    doc = (ROOT / "docs" / "visualisation.md").read_text()
    assert (ROOT / "docs" / "img" / "rerun_layout.png").is_file()
    assert "rrd_snapshot.py" in doc and "docs/img/rerun_layout.png" in doc

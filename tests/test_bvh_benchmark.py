"""The BVH replay benchmark's plumbing on a short recording (its timings are not checked here)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.replay import STAGES, bench_bvh, synthetic_angles, write_synthetic_bvh
from benchmarks.replay_baseline import OUTPUTS, side_by_side
from ergosim.human.joints import joint_spec
from ergosim.posture import HUMAN_JOINTS
from ergosim.worker.bvh import load_bvh


def test_synthetic_angles_move_inside_the_ranges_of_motion():
    angles = synthetic_angles(30.0, 60.0, np.random.default_rng(0))
    assert set(angles) == set(HUMAN_JOINTS)
    for name, q in angles.items():
        lo, hi = joint_spec(name).range_deg
        assert q.shape == (1800,) and lo <= q.min() and q.max() <= hi
        assert np.ptp(q) > 0.2 * (hi - lo)
    again = synthetic_angles(30.0, 60.0, np.random.default_rng(0))
    assert all(np.array_equal(angles[k], again[k]) for k in angles)


def test_the_written_recording_loads_back(tmp_path):
    path = write_synthetic_bvh(tmp_path / "s.bvh", duration_s=2.0, seed=1)
    rec = load_bvh(path)
    assert rec.n_frames == 120 and rec.rate_hz == 60.0
    np.testing.assert_allclose(rec.angles["shoulder_flexion"],
                               synthetic_angles(2.0, 60.0, np.random.default_rng(1))["shoulder_flexion"],
                               atol=1e-4)


def test_bench_bvh_reports_every_stage(tmp_path):
    res = bench_bvh(tmp_path, duration_s=3.0, repeats=2)
    assert res["recording"]["frames"] == 180 and res["repeats"] == 2 and len(res["runs"]) == 2
    assert list(res["stages_s"]) == list(STAGES) == list(res["stages_cpu_s"])
    assert res["end_to_end_s"] > 0.0 and res["end_to_end_cpu_s"] > 0.0
    assert (tmp_path / "replay" / "ticks.csv").read_text().count("\n") == 61  # header + 60 ticks


@pytest.mark.slow  # two processes, each importing ergosim
def test_side_by_side_replays_two_revisions_and_compares_their_outputs(tmp_path):
    path = write_synthetic_bvh(tmp_path / "s.bvh", duration_s=3.0, seed=2)
    res = side_by_side(path, tmp_path, "HEAD", repeats=1)
    assert res["baseline_rev"] == "HEAD" and (tmp_path / "baseline_src" / "ergosim" / "cli.py").is_file()
    for side in ("current", "baseline"):
        assert len(res[side]["runs"]) == 1 and res[side]["end_to_end_cpu_s"] > 0.0
        assert (tmp_path / f"out_{side}" / "ticks.csv").read_text().count("\n") == 61
    assert set(res["identical"]) == set(OUTPUTS) and all(res["identical"].values())

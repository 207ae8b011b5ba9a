"""What scripts/bench_sim.py measures (benchmarks.sim), not how fast: no timed test."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from benchmarks.sim import bench_repetition


@pytest.mark.slow
def test_one_repetition_is_timed_against_raw_stepping_of_the_same_simulated_time():
    res = bench_repetition("kwear-validation", "hrc", seed=0)
    assert res["sim_time"] >= 38.0 - 1e-9  # a repetition lasts at least the takt
    assert res["wall"] > 0 and res["raw_wall"] > 0 and res["failures"] == 0


@pytest.mark.slow
def test_script_writes_the_json_fields_scripts_rely_on(tmp_path):
    out = tmp_path / "bench.json"
    script = Path(__file__).resolve().parents[1] / "scripts" / "bench_sim.py"
    proc = subprocess.run([sys.executable, str(script), "--scenario", "kwear-validation", "--repeats", "1",
                           "--json", str(out)], check=False, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    res = json.loads(out.read_text())
    for key in ("realtime_factor", "overhead_ratio", "raw_realtime_factor", "realtime_factor_recording",
                "repetitions"):
        assert res[key] > 0, key
    # a difference of two timings: its sign is noise on a loaded machine, its presence is the contract
    assert np.isfinite(res["recording_cost"])
    assert "overhead ratio" in proc.stdout

"""The Python API for experiments (issue 12 §5): ``ergosim.api`` loads a scenario by name or path with
overrides, runs it, and hands back the summary and the per-attempt records as objects; the example script
that compares two layouts runs in a short form.
"""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import pytest
from own_product import SCENARIO, write_product

import ergosim.api as api
from ergosim.errors import ConfigError
from ergosim.twin.records import Allocation, SubjectRun

ROOT = Path(__file__).resolve().parents[1]
QUICK = SCENARIO.replace('modes = ["hrc", "h-only", "r-only"]', 'modes = ["h-only", "r-only"]\neta_max = 2')
"""The user's bracket in the two modes that need no risk index, with a short calibration."""


def test_every_public_name_exists():
    for name in api.__all__:
        assert hasattr(api, name), name
    assert len(set(api.__all__)) == len(api.__all__)


def test_load_by_name_or_path_with_overrides(tmp_path):
    sc = api.load("multi-subject", {"scene.l_xy": "0.20,0.82", "task.agents.robot.cost": 3.0},
                  subjects=2, repetitions=3, modes=["hrc"], takt=40)
    cfg = sc.protocol
    assert (cfg.population.subjects, cfg.pacing.repetitions, cfg.modes, cfg.pacing.takt) == \
        (2, 3, ("hrc",), 40.0)
    assert sc.cell().part("L").xy == (0.20, 0.82)
    assert sc.task().agents[1].cost == 3.0
    path = write_product(tmp_path / "own")
    assert api.load(path).name == "bracket"
    assert api.load(str(path)).protocol.modes == ("hrc", "h-only", "r-only")
    with pytest.raises(ConfigError, match="unknown key 'parts.L.xyz'"):
        api.load("multi-subject", {"scene.parts.L.xyz": "1,2"})
    with pytest.raises(TypeError, match="both as a keyword and in overrides"):
        api.load("multi-subject", {"takt": 40}, takt=41)


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    folder = tmp_path_factory.mktemp("api")
    return api.run(api.load(write_product(folder, scenario=QUICK), subjects=2), seed=3, jobs=1)


@pytest.mark.slow
def test_run_returns_the_summary_and_the_records_as_objects(results):
    assert results.status == "complete" and results.seed == 3 and results.out is None  # no folder kept
    assert results.summary["scenario"] == "bracket" and results.summary["complete"]
    assert [s.subject for s in results.subjects] == [0, 1]
    assert results.robot_share("r-only") == 1.0 and results.robot_share("h-only") == 0.0
    assert results.robot_share_by_action("r-only") == {f"b{k}": 1.0 for k in range(1, 6)}
    runs = results.runs("h-only")
    assert len(runs) == 2 and all(isinstance(r, SubjectRun) for r in runs)
    assert all(isinstance(a, Allocation) for a in results.allocations)
    assert len(results.allocations) == 2 * 2 * 5 and results.failures == []
    assert len(results.kwear_integral("h-only")) == 2
    row = dataclasses.asdict(results.allocations[0])  # plain data, ready for a DataFrame
    assert {"subject", "mode", "repetition", "action", "agent", "status", "t_start", "t_end"} <= set(row)
    with pytest.raises(KeyError, match="mode 'hrc' was not run; modes run: h-only, r-only"):
        results.runs("hrc")


@pytest.mark.slow
def test_the_same_seed_gives_the_same_records(results, tmp_path):
    again = api.run(api.load(write_product(tmp_path, scenario=QUICK), subjects=2), seed=3, jobs=2,
                    out=tmp_path / "out")
    assert repr(again.allocations) == repr(results.allocations)  # repr: NaN costs compare equal
    assert (tmp_path / "out" / "summary.json").exists() and again.out == tmp_path / "out"


def test_a_session_steps_one_action_at_a_time(tmp_path):
    session = api.session(write_product(tmp_path), "h-only", calibrate=False)
    outcome = session.perform("b1", "robot")
    assert outcome.ok and session.cell.action_done(session.cell.actions["b1"])
    with pytest.raises(ConfigError, match="needs the subject's calibration"):
        api.session(write_product(tmp_path), "hrc", calibrate=False)


@pytest.mark.slow
def test_the_layout_comparison_example_runs(tmp_path):
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "compare_layouts.py"), "--subjects", "1",
                           "--reps", "1", "--jobs", "1"], capture_output=True, text=True, timeout=600,
                          cwd=tmp_path, check=False)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0] == "layout A (as filed)"
    assert lines[3] == "layout B (scene.s1_xy=0.40,0.62 scene.s2_xy=0.52,0.66)"
    assert "robot share" in lines[1] and "a2" in lines[1] and "KWear integral" in lines[2]
    bad = subprocess.run([sys.executable, str(ROOT / "examples" / "compare_layouts.py"), "--set",
                          "scene.l_xy=1"], capture_output=True, text=True, timeout=120, check=False)
    assert bad.returncode == 1 and "Traceback" not in bad.stderr
    assert bad.stderr.startswith("compare_layouts: error: ") and "has 1 value, expected 2" in bad.stderr


# -- issue 27: docs/api.md's first example as a script, with and without its guard --------------------------
def _guide_example() -> str:
    guide = (Path(__file__).resolve().parents[1] / "docs" / "api.md").read_text()
    code = guide.split("```python\n", 1)[1].split("```", 1)[0]
    assert 'if __name__ == "__main__":' in code and "jobs=2" in code
    # the guide's study made small: two subjects, one repetition, a short calibration; still jobs=2
    return code.replace("subjects=4, repetitions=5", "subjects=2, repetitions=1, eta_max=2")


def _script(tmp_path, code: str) -> subprocess.CompletedProcess:
    path = tmp_path / "study.py"
    path.write_text(code)
    return subprocess.run([sys.executable, str(path)], capture_output=True, text=True, timeout=300,
                          cwd=tmp_path, check=False)


@pytest.mark.slow
def test_the_guide_example_runs_as_a_script_with_two_jobs(tmp_path):
    code = _guide_example() + '    print("share", res.robot_share("hrc"))\n'
    proc = _script(tmp_path, code)
    assert proc.returncode == 0, proc.stderr
    assert "share " in proc.stdout and "BrokenProcessPool" not in proc.stderr


@pytest.mark.slow
def test_a_parallel_run_at_a_scripts_top_level_is_refused_before_any_worker_starts(tmp_path):
    """Without the guard the workers re-ran the script and the caller got BrokenProcessPool."""
    lines = _guide_example().splitlines()
    code = "\n".join(line.removeprefix("    ") for line in lines if "__main__" not in line) + "\n"
    proc = _script(tmp_path, code)
    assert proc.returncode != 0
    assert "study.py line 4 starts worker processes from the script's top level" in proc.stderr
    assert 'if __name__ == "__main__":' in proc.stderr and "BrokenProcessPool" not in proc.stderr

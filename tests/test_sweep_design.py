"""Sweep files (issue 15): designs (grid, zip, random, Latin hypercube), units and their ids, and one-line
errors for bad files. Nothing here simulates."""

from __future__ import annotations

import importlib
import textwrap
from pathlib import Path

import numpy as np
import pytest

import ergosim.sweep as sweep_pkg
import ergosim.sweep.units as units_mod
from ergosim.cli import main
from ergosim.errors import ConfigError
from ergosim.experiment.scenario import scenario_path
from ergosim.sweep.design import MAX_CELLS, load_sweep, set_string
from ergosim.sweep.fingerprint import code_fingerprint
from ergosim.sweep.units import plan_units, unit_id

ROOT = Path(__file__).resolve().parents[1]
MODULES = ["design", "units", "executors", "folder", "tables", "stats", "plots", "runner", "metrics",
           "compare", "fingerprint", "benchmark"]


def _write(tmp_path, text: str, name: str = "s.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_package_and_module_names_exist():
    assert len(sweep_pkg.__all__) == len(set(sweep_pkg.__all__))
    for name in sweep_pkg.__all__:
        assert getattr(sweep_pkg, name) is not None, name
    for module in MODULES:
        mod = importlib.import_module(f"ergosim.sweep.{module}")
        for name in mod.__all__:
            assert hasattr(mod, name), f"{module}.{name}"


def test_grid_is_the_full_product_first_key_slowest(tmp_path):
    s = load_sweep(_write(tmp_path, """
        scenario = "kwear-validation"
        subjects = 2
        seeds = [0, 3]
        [set]
        repetitions = 1
        [grid]
        scene.shelf_height = [1.3, 1.45, 1.6]
        robot_cost = [25, 50]
    """))
    assert [a.key for a in s.axes] == ["scene.shelf_height", "robot_cost"]
    assert [dict(c.params) for c in s.cells][:3] == [
        {"scene.shelf_height": 1.3, "robot_cost": 25}, {"scene.shelf_height": 1.3, "robot_cost": 50},
        {"scene.shelf_height": 1.45, "robot_cost": 25}]
    assert len(s.cells) == 6 and s.n_units == 6 * 2 * 2 * 2  # modes: the scenario's hrc and rula
    assert s.cells[0].overrides == {"scene.shelf_height": "1.3", "robot_cost": "25"}
    assert s.scenarios[5].protocol.cost.robot_cost == 50.0 and s.scenarios[0].protocol.pacing.repetitions == 1
    assert s.scenarios[4].cell_overrides == {"shelf_height": "1.6"}
    assert s.name == "s" and s.modes == ("hrc", "rula") and s.subjects == (0, 1) and s.seeds == (0, 3)


def test_zip_takes_values_together_and_multiplies_with_the_grid(tmp_path):
    s = load_sweep(_write(tmp_path, """
        scenario = "multi-subject"
        modes = ["hrc"]
        [grid]
        takt = [38.0, 42.0]
        [zip]
        "scene.l_xy" = [[0.20, 0.82], [0.24, 0.86], [0.22, 0.84]]
        "scene.s1_xy" = [[0.30, 0.90], [0.34, 0.94], [0.32, 0.92]]
    """))
    assert len(s.cells) == 6
    assert s.cells[1].params["scene.l_xy"] == (0.24, 0.86)
    assert s.cells[1].params["scene.s1_xy"] == (0.34, 0.94)
    assert s.cells[1].overrides["scene.l_xy"] == "0.24,0.86"
    assert {c.params["takt"] for c in s.cells[:3]} == {38.0}


@pytest.mark.parametrize("method", ["random", "lhs"])
def test_sampled_designs_are_seeded(tmp_path, method):
    text = f"""
        scenario = "multi-subject"
        modes = ["hrc"]
        [sample]
        method = "{method}"
        n = 10
        seed = 4
        takt = [34.0, 42.0]
        repetitions = [1, 3]
        "scene.j_xy" = [[0.10, 0.70], [0.20, 0.80]]
    """
    a, b = load_sweep(_write(tmp_path, text, "a.toml")), load_sweep(_write(tmp_path, text, "b.toml"))
    assert [c.params for c in a.cells] == [c.params for c in b.cells]
    assert len(a.cells) == 10 and a.sampling.method == method
    takt = np.array([c.params["takt"] for c in a.cells])
    assert np.all((takt >= 34.0) & (takt < 42.0))
    reps = {c.params["repetitions"] for c in a.cells}
    assert reps <= {1, 2, 3} and all(isinstance(r, int) for r in reps)
    j = np.array([c.params["scene.j_xy"] for c in a.cells])
    assert j.shape == (10, 2) and np.all((j[:, 0] >= 0.1) & (j[:, 0] <= 0.2)) and np.all(j[:, 1] >= 0.7)
    if method == "lhs":  # one point per stratum in every dimension
        for values, (lo, hi) in ((takt, (34.0, 42.0)), (j[:, 0], (0.1, 0.2)), (j[:, 1], (0.7, 0.8))):
            strata = np.floor((values - lo) / (hi - lo) * 10).astype(int)
            assert sorted(strata) == list(range(10))
    other = load_sweep(_write(tmp_path, text.replace("seed = 4", "seed = 5"), "c.toml"))
    assert [c.params for c in other.cells] != [c.params for c in a.cells]


def test_coinciding_sample_points_are_one_cell(tmp_path):
    s = load_sweep(_write(tmp_path, """
        scenario = "kwear-validation"
        [sample]
        method = "random"
        n = 12
        seed = 0
        repetitions = [1, 2]
    """))
    assert sorted(c.params["repetitions"] for c in s.cells) == [1, 2]
    assert len({u.id for u in plan_units(s)}) == len(plan_units(s))


def test_no_axis_is_one_cell_and_subjects_can_be_a_range_or_a_list(tmp_path):
    s = load_sweep(_write(tmp_path, 'scenario = "kwear-validation"\nsubjects = "2:5"\nseeds = 7\n'))
    assert len(s.cells) == 1 and s.cells[0].label() == "base" and s.subjects == (2, 3, 4) and s.seeds == (7,)
    s = load_sweep(_write(tmp_path, 'scenario = "kwear-validation"\nsubjects = [4, 1]\n'))
    assert s.subjects == (4, 1)


def test_a_scenario_file_next_to_the_sweep_file(tmp_path):
    (tmp_path / "mine.toml").write_text(scenario_path("kwear-validation").read_text().replace(
        'task = "corner-joint:kwear-validation"', 'task = "corner-joint:kwear-validation"'))
    s = load_sweep(_write(tmp_path, 'scenario = "mine.toml"\n[grid]\nv_th = [0.7, 0.8]\n'))
    assert s.scenario == str(tmp_path / "mine.toml") and [c.params["v_th"] for c in s.cells] == [0.7, 0.8]


def test_mode_slots_follow_the_scenario_so_a_unit_equals_the_run(tmp_path):
    s = load_sweep(_write(tmp_path, 'scenario = "multi-subject"\nmodes = ["r-only", "h-only"]\n'))
    assert s.slots == {"h-only": 1, "r-only": 2}  # the scenario runs hrc (0), h-only (1)


def test_unit_ids_name_what_the_unit_depends_on(tmp_path):
    s = load_sweep(_write(tmp_path, """
        scenario = "kwear-validation"
        subjects = 2
        seeds = [0, 1]
        [grid]
        scene.shelf_height = [1.45, 1.6]
    """))
    units = plan_units(s)
    assert len(units) == s.n_units == 2 * 2 * 2 * 2 and len({u.id for u in units}) == len(units)
    assert [(u.cell, u.seed, u.subject, u.mode) for u in units[:4]] == [
        (0, 0, 0, "hrc"), (0, 0, 0, "rula"), (0, 0, 1, "hrc"), (0, 0, 1, "rula")]
    again = plan_units(load_sweep(_write(tmp_path, """
        scenario = "kwear-validation"
        subjects = 5
        seeds = [1, 0]
        modes = ["rula"]
        [grid]
        scene.shelf_height = [1.6, 1.45, 1.3]
    """, "grown.toml")))
    # the grown file plans the same units for the same (cell, subject, seed, mode): a resume finds them
    assert {u.id for u in units if u.mode == "rula"} <= {u.id for u in again}
    sc = s.scenarios[0]
    assert unit_id(sc, 0, 0, "hrc", 0) != unit_id(sc.with_overrides({"takt": "40"}), 0, 0, "hrc", 0)
    assert unit_id(sc, 0, 0, "hrc", 0) != unit_id(sc, 0, 0, "hrc", 1)


def test_set_strings_are_what_ergosim_run_takes():
    assert set_string(1.45, "x") == "1.45" and set_string(3, "x") == "3" and set_string(True, "x") == "true"
    assert set_string([0.2, 0.82], "x") == "0.2,0.82"
    assert set_string([["upper_arm", 1.1], ["forearm", 0.95]], "x") == "upper_arm:1.1,forearm:0.95"
    with pytest.raises(ConfigError):
        set_string({"a": 1}, "x")


BAD = [
    ('scenario = "kwear-validation"\nsweeps = 3\n', "unknown key 'sweeps'"),
    ('subjects = 2\n', "missing key 'scenario'"),
    ('scenario = "no-such-scenario"\n', "no scenario 'no-such-scenario'"),
    ('scenario = "kwear-validation"\n[grid]\nscene.shelf_heigth = [1.4, 1.5]\n', "shelf_heigth"),
    ('scenario = "kwear-validation"\n[grid]\nscene.shelf_height = ["high", 1.5]\n', "'high'"),
    ('scenario = "kwear-validation"\n[grid]\nscene.shelf_height = []\n', "non-empty list"),
    ('scenario = "kwear-validation"\n[grid]\nscene.shelf_height = 1.5\n', "list of values"),
    ('scenario = "kwear-validation"\n[grid]\nscene.shelf_height = [1.4, 1.4]\n', "listed twice"),
    ('scenario = "kwear-validation"\n[grid]\nscene.shelf_height = [1.4, 2.9]\n', "grid.scene.shelf_height"),
    ('scenario = "kwear-validation"\n[grid]\nscene.shelf_height = [1.45, 1.35]\n'
     'scene.shelf_low_height = [1.0, 1.1]\n', "cell 3 (scene.shelf_height=1.35, scene.shelf_low_height=1.1)"),
    ('scenario = "kwear-validation"\n[grid]\ntakt = [-1.0, 30.0]\n', "takt must be > 0"),
    ('scenario = "multi-subject"\n[zip]\n"scene.l_xy" = [[0.2, 0.8]]\n'
     '"scene.s1_xy" = [[0.3, 0.9], [0.3, 0.8]]\n', "one length"),
    ('scenario = "kwear-validation"\n[grid]\ntakt = [38.0]\n[zip]\ntakt = [40.0]\n', "both [grid] and [zip]"),
    ('scenario = "kwear-validation"\n[set]\ntakt = 40\n[grid]\ntakt = [38.0, 42.0]\n', "both fixed in [set]"),
    ('scenario = "kwear-validation"\n[grid]\nsubjects = [1, 2]\n', "use the sweep's top-level 'subjects'"),
    ('scenario = "kwear-validation"\n[set]\nmodes = "hrc"\n', "top-level 'modes'"),
    ('scenario = "kwear-validation"\n[set]\nscene.no_such_field = 1\n', "no_such_field"),
    ('scenario = "kwear-validation"\nsubjects = 0\n', "at least 1 subject"),
    ('scenario = "kwear-validation"\nsubjects = "5:2"\n', "'A:B'"),
    ('scenario = "kwear-validation"\nseeds = [0, -1]\n', "integers >= 0"),
    ('scenario = "kwear-validation"\nseeds = [1, 1]\n', "seed 1 is listed twice"),
    ('scenario = "kwear-validation"\nmodes = ["fast"]\n', "unknown mode 'fast'"),
    ('scenario = "kwear-validation"\nmetrics = ["robot_shares"]\n', "unknown metric 'robot_shares'"),
    ('scenario = "kwear-validation"\nmetrics = ["robot_share.a9"]\n', "unknown action 'a9'"),
    ('scenario = "kwear-validation"\n[sample]\nn = 4\ntakt = [30.0, 40.0]\n', "expected seed"),
    ('scenario = "kwear-validation"\n[sample]\nn = 0\nseed = 1\ntakt = [30.0, 40.0]\n', "expected n"),
    ('scenario = "kwear-validation"\n[sample]\nn = 4\nseed = 1\ntakt = [40.0, 30.0]\n', "low < high"),
    ('scenario = "kwear-validation"\n[sample]\nn = 4\nseed = 1\nmethod = "sobol"\ntakt = [30.0, 40.0]\n',
     "random, lhs"),
    ('scenario = "kwear-validation"\n[sample]\nn = 4\nseed = 1\n', "no ranges"),
    ('scenario = "kwear-validation"\n[grid]\ntakt = [38.0, \n', "invalid TOML"),
    ('scenario = "kwear-validation"\n[grid]\ntakt = ' + str([30.0 + i / 1000 for i in range(101)])
     + "\nv_th = " + str([0.5 + i / 1000 for i in range(100)]) + "\n", f"limit of {MAX_CELLS}"),
]


@pytest.mark.parametrize(("text", "needle"), BAD, ids=[b[1][:28] for b in BAD])
def test_bad_sweep_files_get_one_line_errors(tmp_path, capsys, text, needle):
    path = _write(tmp_path, text, "bad.toml")
    with pytest.raises(ConfigError) as info:
        load_sweep(path)
    assert needle in str(info.value) and "\n" not in str(info.value)
    code = main(["sweep", str(path), "--out", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("ergosim: error: ") and err.count("\n") == 1, err
    assert str(path) in err and needle in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()  # nothing simulated, no folder left


def test_cli_options_are_checked(tmp_path, capsys):
    path = _write(tmp_path, 'scenario = "kwear-validation"\n')
    for args, needle in ((["--jobs", "0"], "--jobs"),
                         (["--ray-address", "127.0.0.1:1"], "needs --executor ray")):
        assert main(["sweep", str(path), "--out", str(tmp_path / "o"), *args]) == 2
        err = capsys.readouterr().err
        assert needle in err and err.count("\n") == 1
    assert main(["sweep", str(path), "--out", str(tmp_path / "o"), "--dry-run"]) == 0
    out = capsys.readouterr().out
    assert "1 cell(s) × 1 subject(s) × 1 seed(s) × 2 mode(s) = 2 units (0 finished" in out


def test_a_run_folder_is_not_a_sweep_folder(tmp_path, capsys):
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "run.json").write_text("{}")
    path = _write(tmp_path, 'scenario = "kwear-validation"\n')
    assert main(["sweep", str(path), "--out", str(tmp_path / "run"), "--quiet"]) == 2
    assert "folder of an `ergosim run`" in capsys.readouterr().err


def _toml_blocks(path: Path) -> list[str]:
    text = path.read_text()
    return [b.split("```", 1)[0] for b in text.split("```toml\n")[1:]]


def test_the_documented_sweep_files_are_valid(tmp_path):
    """The example study, and every sweep file shown in README.md and docs/sweeps.md, reads and resolves."""
    s = load_sweep(ROOT / "examples" / "sweeps" / "shelf_height.toml")
    assert len(s.cells) == 18 and s.n_units == 90 and s.seeds == (0, 1, 2, 3, 4)
    blocks = [b for doc in ("README.md", "docs/sweeps.md") for b in _toml_blocks(ROOT / doc)
              if "\nscenario = " in "\n" + b]
    assert len(blocks) >= 3
    for k, block in enumerate(blocks):
        assert load_sweep(_write(tmp_path, block, f"doc{k}.toml")).cells


def test_units_are_tied_to_the_code_that_planned_them(tmp_path, monkeypatch):
    s = load_sweep(_write(tmp_path, 'scenario = "kwear-validation"\n'))
    before = plan_units(s)
    assert all(u.code == code_fingerprint() for u in before) and len(code_fingerprint()) == 16
    monkeypatch.setattr(units_mod, "code_fingerprint", lambda: "0123456789abcdef")
    after = plan_units(s)
    assert {u.id for u in before}.isdisjoint(u.id for u in after)  # other code: nothing is reused
    doc = units_mod.run_unit(s.scenarios[0], before[0], s.actions)  # a worker with other code refuses
    assert doc["status"] == "failed" and "runs other code" in doc["error"] and doc["metrics"] == {}

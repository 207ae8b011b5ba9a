"""Sweep files (issue 15): designs (grid, zip, random, Latin hypercube), units and their ids, and one-line
errors for bad files. Nothing here simulates."""

from __future__ import annotations

import importlib
import textwrap
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest

import ergosim.sweep as sweep_pkg
import ergosim.sweep.units as units_mod
from ergosim.cli import main
from ergosim.commands.sweep import _cells_text
from ergosim.errors import ConfigError
from ergosim.experiment.scenario import scenario_path
from ergosim.sweep.design import MAX_CELLS, load_sweep, set_string
from ergosim.sweep.fingerprint import code_fingerprint
from ergosim.sweep.plots import write_sweep_plots
from ergosim.sweep.stats import cell_statistics
from ergosim.sweep.tables import write_parquet
from ergosim.sweep.units import plan_units, unit_id

ROOT = Path(__file__).resolve().parents[1]
MODULES = ["design", "units", "executors", "folder", "tables", "stats", "plots", "runner", "metrics",
           "compare", "fingerprint"]


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
    ('scenario = "kwear-validation"\n[grid]\ntakt = [-1.0, 30.0]\n', "takt must be in (0, 3600] s"),
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


def test_the_fingerprint_covers_the_blas_kernel(monkeypatch):
    """Two BLAS kernels round the worker's IK differently (ergosim/blas_kernel.py): a cluster node whose
    numpy runs another kernel runs other code."""
    ours = code_fingerprint()
    monkeypatch.setattr("ergosim.sweep.fingerprint.kernel", lambda: "SkylakeX")
    code_fingerprint.cache_clear()
    try:
        assert code_fingerprint() != ours
    finally:
        code_fingerprint.cache_clear()  # the next call, after the patch is undone, is this process's own


# -- issue 27: a [zip] is one factor with named levels ------------------------------------------------------
LAYOUTS = """
    scenario = "multi-subject"
    modes = ["hrc", "h-only"]
    subjects = 3
    metrics = ["robot_share", "kwear_integral", "time_above_vth", "takt_overruns", "kwear_mean"]
    [grid]
    takt = [38.0, 42.0]
    [zip]
    name = "layout"
    levels = ["A", "B", "C"]
    "scene.l_xy" = [[0.20, 0.82], [0.24, 0.86], [0.22, 0.84]]
    "scene.s1_xy" = [[0.30, 0.90], [0.34, 0.94], [0.32, 0.92]]
"""


def test_a_zip_is_one_factor_with_named_levels(tmp_path):
    s = load_sweep(_write(tmp_path, LAYOUTS))
    assert [(f.name, f.block, f.keys) for f in s.factors] == [
        ("takt", "grid", ("takt",)), ("layout", "zip", ("scene.l_xy", "scene.s1_xy"))]
    assert s.factors[1].levels == ("A", "B", "C") and s.factors[1].column == "param.layout"
    assert [c.label() for c in s.cells[:3]] == ["takt=38.0, layout=A", "takt=38.0, layout=B",
                                                "takt=38.0, layout=C"]
    assert s.cells[1].settings() == ("takt=38.0, layout=B (takt=38.0, scene.l_xy=0.24,0.86, "
                                     "scene.s1_xy=0.34,0.94)")
    # without a name and levels: the keys joined, the values joined
    bare = load_sweep(_write(tmp_path, LAYOUTS.replace('name = "layout"\n', "").replace(
        'levels = ["A", "B", "C"]\n', ""), "bare.toml"))
    assert bare.factors[1].name == "scene.l_xy+scene.s1_xy"
    assert bare.factors[1].levels[0] == "0.2,0.82 / 0.3,0.9"


@pytest.mark.parametrize("change,needle", [
    (('levels = ["A", "B", "C"]', 'levels = ["A", "B"]'), "2 level names for 3 positions of the zip"),
    (('levels = ["A", "B", "C"]', 'levels = ["A", "A", "C"]'), "a level name is given twice"),
    (('name = "layout"', 'name = "takt"'), "the zip's name 'takt' is also an axis key"),
    (('name = "layout"', "name = 3"), "expected the zip's name as a non-empty string"),
])
def test_bad_zip_names_are_one_line_errors(tmp_path, capsys, change, needle):
    path = _write(tmp_path, LAYOUTS.replace(*change))
    assert main(["sweep", str(path), "--dry-run"]) == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1 and "s.toml: zip" in err


@pytest.mark.slow
def test_the_zip_is_one_axis_of_the_plots_and_the_heat_map_is_full(tmp_path):
    """At HEAD the zip's keys were separate axes: three response plots (two identical) and a heat map of
    l_xy × s1_xy with only its diagonal filled. Now: one response plot per factor, one full heat map."""

    s = load_sweep(_write(tmp_path, LAYOUTS))
    rows = _synthetic_rows(s)
    names = write_sweep_plots(tmp_path, s, rows)
    assert names == ["response_takt.png", "response_layout.png", "heatmap_takt__layout.png"]
    table = cell_statistics(s, rows, {c.index for c in s.cells}).to_pylist()
    assert [r["param.layout"] for r in table[:6]] == ["A", "A", "B", "B", "C", "C"]
    assert table[0]["label"] == "takt=38.0, layout=A"


def _synthetic_rows(s) -> list[dict]:
    rng = np.random.default_rng(0)
    rows = []
    for cell in s.cells:
        for subject in s.subjects:
            for mode in s.modes:
                rows.append({"cell": cell.index, "subject": subject, "seed": 0, "mode": mode,
                             "status": "complete", "param.layout": cell.levels["layout"],
                             **{a.column: list(v) if isinstance(v := cell.params[a.key], tuple) else v
                                for a in s.axes},
                             "robot_share": 0.0 if mode == "h-only" else 0.2 + 0.1 * rng.random(),
                             "actions": 10, "kwear_integral": 100 + 10 * rng.random(),
                             "time_above_vth": 0.0, "takt_overruns": int(rng.random() < 0.3),
                             "kwear_mean": 1.0 + rng.random()})
    return rows


def test_the_end_of_sweep_table_shows_every_metric(tmp_path):
    """At HEAD it showed the first four (commands/sweep.py:59): a fifth metric went missing."""

    s = load_sweep(_write(tmp_path, LAYOUTS))
    rows = _synthetic_rows(s)
    rows[0].update(status="abandoned", error="g2: no agent left", repetitions_completed=1)
    write_parquet(tmp_path / "cells.parquet", cell_statistics(s, rows, {c.index for c in s.cells}))
    results = {k: [r.get(k) for r in rows] for k in ("cell", "subject", "seed", "mode", "status", "error",
                                                     "repetitions_completed", "kwear_integral")}
    write_parquet(tmp_path / "results.parquet", pa.table(results))
    text = _cells_text(tmp_path, s)
    block = text.split("cell 0 ")[1].split("cell 1 ")[0]
    for metric in s.metrics:
        assert f"\n  {metric} " in block, metric
    assert "h-only − hrc (paired)" in block and "n=3" in block and "small n (< 6)" in block
    assert "(≥0.25)" in text  # three pairs: a Wilcoxon p cannot go below 0.25
    assert "1 unit(s) left out of the statistics" in text
    assert "cell 0 hrc subject 0 seed 0: abandoned after 1 completed repetition(s)" in text

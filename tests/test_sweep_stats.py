"""Sweep statistics (issue 15) against scipy's own intervals and tests, the per-cell table with two modes,
and the comparison of folders, on synthetic units (no simulation)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from ergosim.sweep.compare import Folder, compare_folders, comparison_text
from ergosim.sweep.design import load_sweep
from ergosim.sweep.stats import cell_statistics, mean_ci, paired_difference, unpaired_difference


def test_mean_ci_is_the_student_t_interval():
    x = [3.1, 2.7, 4.0, 3.3, 2.9, 3.8]
    s = mean_ci(x)
    lo, hi = stats.t.interval(0.95, len(x) - 1, loc=np.mean(x), scale=stats.sem(x))
    assert (s["mean"], s["n"]) == (pytest.approx(np.mean(x)), 6)
    assert s["ci_low"] == pytest.approx(lo) and s["ci_high"] == pytest.approx(hi)
    assert mean_ci([5.0])["ci_low"] is None and mean_ci([])["mean"] is None
    assert mean_ci([1.0, None, 3.0])["n"] == 2


def test_paired_difference_is_the_t_interval_of_differences_and_wilcoxon():
    rng = np.random.default_rng(0)
    a = rng.normal(10, 1, 12)
    b = a + 0.8 + rng.normal(0, 0.3, 12)
    d = paired_difference(list(a), list(b))
    ref = stats.ttest_rel(b, a).confidence_interval(0.95)
    assert d["diff"] == pytest.approx(np.mean(b - a)) and d["pairs"] == 12
    assert d["diff_ci_low"] == pytest.approx(ref.low) and d["diff_ci_high"] == pytest.approx(ref.high)
    assert d["wilcoxon_p"] == pytest.approx(stats.wilcoxon(b, a).pvalue) and d["wilcoxon_p"] < 0.01
    assert paired_difference([1.0, 2.0], [1.0, 2.0])["wilcoxon_p"] == 1.0


def test_unpaired_difference_is_welch_and_mann_whitney():
    rng = np.random.default_rng(1)
    a, b = rng.normal(5, 1, 9), rng.normal(6, 2, 14)
    d = unpaired_difference(list(a), list(b))
    ref = stats.ttest_ind(b, a, equal_var=False).confidence_interval(0.95)
    assert d["diff"] == pytest.approx(b.mean() - a.mean())
    assert d["diff_ci_low"] == pytest.approx(ref.low) and d["diff_ci_high"] == pytest.approx(ref.high)
    assert d["mannwhitney_p"] == pytest.approx(stats.mannwhitneyu(b, a, alternative="two-sided").pvalue)


@pytest.fixture(scope="module")
def two_mode_sweep(tmp_path_factory) -> object:
    path = Path(tmp_path_factory.mktemp("s")) / "s.toml"
    path.write_text(textwrap.dedent("""
        scenario = "multi-subject"
        subjects = 6
        metrics = ["kwear_integral", "robot_share"]
        [grid]
        takt = [38.0, 42.0]
    """))
    return load_sweep(path)


def _rows(sweep, shift: float, failed: tuple = ()) -> list[dict]:
    rng = np.random.default_rng(2)
    rows = []
    for cell in sweep.cells:
        for subject in sweep.subjects:
            base = 40 + rng.normal(0, 2)
            for mode in sweep.modes:
                status = "failed" if (cell.index, subject, mode) in failed else "complete"
                value = None if status == "failed" else base + (0 if mode == "hrc" else shift + 0.1 * subject)
                rows.append({"cell": cell.index, "subject": subject, "seed": 0, "mode": mode,
                             "status": status, "kwear_integral": value,
                             "robot_share": 0.0 if mode == "h-only" else 0.3,
                             "param.takt": cell.params["takt"], "label": cell.label(),
                             "cell_key": str(cell.index)})
    return rows


def test_cell_statistics_pair_each_mode_with_the_first(two_mode_sweep):
    sweep = two_mode_sweep
    rows = _rows(sweep, shift=3.0, failed=((1, 2, "h-only"),))
    table = cell_statistics(sweep, rows, complete_cells={0, 1}).to_pylist()
    assert [(r["cell"], r["mode"]) for r in table] == [(0, "hrc"), (0, "h-only"), (1, "hrc"),
                                                       (1, "h-only")]
    hrc, honly = table[0], table[1]
    assert hrc["baseline"] is None and honly["baseline"] == "hrc"
    mine = [r["kwear_integral"] for r in rows if r["cell"] == 0 and r["mode"] == "h-only"]
    assert honly["kwear_integral.mean"] == pytest.approx(np.mean(mine))
    assert honly["kwear_integral.diff"] == pytest.approx(3.0 + 0.25)  # shift + 0.1 * mean subject index
    assert honly["kwear_integral.pairs"] == 6 and honly["kwear_integral.wilcoxon_p"] < 0.05
    assert table[3]["units_failed"] == 1 and table[3]["kwear_integral.pairs"] == 5
    assert table[3]["kwear_integral.n"] == 5
    # only the cells whose every unit finished
    assert cell_statistics(sweep, rows, complete_cells={1}).num_rows == 2


def test_compare_pairs_matching_subjects_and_matches_cells_by_value(two_mode_sweep):
    sweep = two_mode_sweep

    def folder(shift: float, seed: int = 0) -> Folder:
        rows = _rows(sweep, shift)
        for r in rows:
            r["seed"] = seed
            r["cell"] = r["cell_key"]
        return Folder(Path(f"/x/{shift}"), "sweep", tuple(rows), sweep.actions, ("kwear_integral",))

    a, b = folder(0.0), folder(2.0)
    rows = compare_folders(a, b)
    assert len(rows) == 2 * 2  # cells x modes, one metric
    honly = [r for r in rows if r["mode"] == "h-only"]
    assert all(r["test"] == "wilcoxon" and r["n"] == 6 and r["diff"] == pytest.approx(2.0) for r in honly)
    assert all(r["diff"] == pytest.approx(0.0) for r in rows if r["mode"] == "hrc")
    text = comparison_text(a, b, rows)
    assert "B − A" in text and "wilcoxon" in text
    unpaired = compare_folders(a, folder(2.0, seed=9))  # other seed: other people, not paired
    assert {r["test"] for r in unpaired} == {"mann-whitney"}

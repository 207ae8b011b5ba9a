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
from ergosim.sweep.stats import (
    SMALL_N,
    cell_statistics,
    mean_ci,
    metric_ci,
    paired_difference,
    share_ci,
    unpaired_difference,
    wilcoxon_min_p,
    wilson_interval,
)


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


# -- issue 27: honest intervals, small n, abandoned units, a zip as one factor, compare ---------------------


@pytest.mark.parametrize("k,n", [(0, 5), (3, 12), (7, 7), (40, 96)])
def test_wilson_interval_is_scipys(k, n):
    ref = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    assert wilson_interval(k / n, n) == pytest.approx((ref.low, ref.high))


@pytest.mark.parametrize("shares,trials", [
    ([0.375, 0.625], [8, 8]),               # the n = 2: the t interval was [-1.09, 2.09]
    ([1 / 8, 0.0, 1 / 8], [16, 16, 16]),    # 3 subjects: the t interval's low end is -0.096
    ([0.0, 0.0, 0.0], [12, 12, 12]),
    ([1.0, 1.0], [4, 4]),
    ([0.0, 1.0, 0.0, 1.0], None),
])
def test_a_share_interval_stays_inside_0_1_and_holds_the_mean(shares, trials):
    s = share_ci(shares, trials)
    assert s["interval"] == "wilson" and s["n"] == len(shares)
    assert 0.0 <= s["ci_low"] <= s["mean"] <= s["ci_high"] <= 1.0
    t = mean_ci(shares)  # the t interval it replaces leaves [0, 1] at these n (or collapses to a point)
    assert t["ci_low"] < 0 or t["ci_high"] > 1 or t["ci_low"] == t["ci_high"]
    assert s["ci_high"] > s["ci_low"]  # units that agree exactly still leave an interval


def test_a_share_interval_narrows_with_subjects_and_widens_at_small_n():
    widths = []
    for n in (2, 3, 6, 12, 48):  # subjects of mean share 0.38 and standard deviation 0.1
        z = np.linspace(-1, 1, n)
        s = share_ci(list(0.38 + 0.1 * z / z.std(ddof=1)), [80] * n)
        widths.append(s["ci_high"] - s["ci_low"])
    assert widths == sorted(widths, reverse=True)
    assert widths[3] < 0.15 and widths[0] > 0.5  # 12 subjects of 80 actions: tight; 2 subjects: wide
    # few trials per unit bound the interval from below: 3 units of 12 actions, all at 0, do not prove 0
    assert share_ci([0.0, 0.0, 0.0], [12, 12, 12])["ci_high"] > share_ci([0.0] * 3, [800] * 3)["ci_high"] > 0


def test_a_mean_interval_is_clipped_to_the_metric_range():
    rows = [{"takt_overruns": v, "kwear_mean": w} for v, w in ((0, 4.9), (0, 5.0), (1, 4.95))]
    s = metric_ci(rows, "takt_overruns")  # t interval [-1.1, 1.77] at HEAD
    assert s["interval"] == "t" and s["ci_low"] == 0.0 and s["ci_high"] == pytest.approx(1.7676, abs=1e-3)
    assert metric_ci(rows, "kwear_mean")["ci_high"] == 5.0  # ΣV of five joints in [0, 1]


def test_the_smallest_wilcoxon_p_at_small_n():
    assert [wilcoxon_min_p(n) for n in (1, 3, 5, 6)] == [1.0, 0.25, 0.0625, 0.03125]
    for n in (3, 5, 6):  # every difference of one sign reaches exactly that bound
        assert stats.wilcoxon(np.arange(1.0, n + 1)).pvalue == pytest.approx(wilcoxon_min_p(n))
    assert SMALL_N == 6 and wilcoxon_min_p(SMALL_N - 1) > 0.05 > wilcoxon_min_p(SMALL_N)
    d = paired_difference([1.0, 2.0, 3.0], [2.0, 3.5, 5.0])
    assert d["wilcoxon_p"] == pytest.approx(0.25) and d["wilcoxon_min_p"] == 0.25


def test_abandoned_units_are_reported_apart_and_left_out_of_the_statistics(two_mode_sweep):
    """A unit abandoned partway (a partial KWear integral: 29 against 134) leaves the means and the pairs;
    the table counts it."""
    sweep = two_mode_sweep
    rows = _rows(sweep, shift=3.0)
    victim = next(r for r in rows if r["cell"] == 0 and r["mode"] == "h-only" and r["subject"] == 1)
    victim.update(status="abandoned", kwear_integral=29.0)
    table = cell_statistics(sweep, rows, complete_cells={0, 1}).to_pylist()
    honly = table[1]
    assert honly["units_abandoned"] == 1 and honly["units_counted"] == 5 and honly["units"] == 6
    kept = [r["kwear_integral"] for r in rows if r["cell"] == 0 and r["mode"] == "h-only"
            and r["status"] == "complete"]
    assert honly["kwear_integral.mean"] == pytest.approx(np.mean(kept)) and honly["kwear_integral.n"] == 5
    assert honly["kwear_integral.pairs"] == 5  # its pair left out too
    assert table[0]["small_n"] is False and honly["small_n"] is True  # 5 counted units < SMALL_N


def test_an_abandoned_unit_still_counts_for_what_its_calibration_set():
    """G(a_k) comes from the calibration before the run: whole in an abandoned unit, and leaving it out
    would drop the workers a cell is hardest for (the shelf study's shortest worker at 1.6 m)."""
    sweep = load_sweep(Path(__file__).resolve().parents[1] / "examples" / "sweeps" / "shelf_height.toml")
    rows = []
    for subject, (g, status) in enumerate([(3.0, "complete")] * 4 + [(7.0, "abandoned")]):
        rows.append({"cell": 0, "subject": 0, "seed": subject, "mode": "hrc", "status": status,
                     "rula_g.a1": g, "time_above_vth": 5.0 if status == "complete" else 1.0,
                     "robot_share.a1": 0.0, "actions.a1": 4, "first_robot_time": 80.0})
    row = cell_statistics(sweep, rows, {0}).to_pylist()[0]
    assert row["rula_g.a1.n"] == 5 and row["rula_g.a1.mean"] == pytest.approx(3.8)
    assert row["time_above_vth.n"] == 4 and row["time_above_vth.mean"] == 5.0


def test_cells_table_says_small_n_and_uses_each_metrics_interval(two_mode_sweep):
    sweep = two_mode_sweep
    rows = [r for r in _rows(sweep, shift=3.0) if r["subject"] < 3]
    for r in rows:
        r["actions"] = 10
    table = cell_statistics(sweep, rows, complete_cells={0}).to_pylist()
    assert all(r["small_n"] for r in table)
    assert {r["robot_share.interval"] for r in table} == {"wilson"}
    assert {r["kwear_integral.interval"] for r in table} == {"t"}
    honly = table[1]
    assert 0 <= honly["robot_share.ci_low"] <= honly["robot_share.ci_high"] <= 1
    assert honly["kwear_integral.wilcoxon_min_p"] == 0.25


def test_compare_says_when_a_paired_wilcoxon_cannot_reach_significance(two_mode_sweep):
    sweep = two_mode_sweep

    def folder(shift: float, subjects: int) -> Folder:
        rows = [r for r in _rows(sweep, shift) if r["subject"] < subjects]
        for r in rows:
            r["cell"] = r["cell_key"]
        return Folder(Path(f"/x/{shift}"), "sweep", tuple(rows), sweep.actions, ("kwear_integral",))

    rows = compare_folders(folder(0.0, 3), folder(2.0, 3))
    honly = next(r for r in rows if r["mode"] == "h-only")
    assert honly["p"] == pytest.approx(0.25) and honly["min_p"] == 0.25 and honly["n"] == 3
    text = comparison_text(folder(0.0, 3), folder(2.0, 3), rows)
    assert "(p ≥ 0.25 at n=3)" in text and "cannot give p below 2/2^n = 0.25" in text
    big = compare_folders(folder(0.0, 6), folder(2.0, 6))
    assert all(r["min_p"] < 0.05 for r in big if r["mode"] == "h-only")
    assert "p ≥" not in comparison_text(folder(0.0, 6), folder(2.0, 6), big)

"""The end-of-run summary explains each figure where it prints it: the two robot shares, the overruns against
the takt, the Wilcoxon test named by the modes the run compared and left out (and said why) when there are too
few pairs; an interval bound that is float round-off prints as 0."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import pytest  # noqa: E402

from ergosim.commands.sweep import _estimate  # noqa: E402
from ergosim.experiment.plots import modes_figure  # noqa: E402
from ergosim.experiment.plots.tables import SubjectRow  # noqa: E402
from ergosim.experiment.summary import too_few_pairs, wilcoxon_between, wilcoxon_min_p  # noqa: E402
from ergosim.experiment.summary_text import overrun_words, summary_text, wilcoxon_lines  # noqa: E402
from ergosim.sweep.compare import _ci  # noqa: E402
from ergosim.sweep.stats import interval_text  # noqa: E402


def _mode(durations, overruns, robot=(1, 8), chosen=(1, 2)) -> dict:
    return {"repetitions_completed": len(durations), "repetitions_abandoned": 0, "takt_overruns": overruns,
            "repetitions": [{"subject": 0, "repetition": k + 1, "outcome": "completed", "reason": "",
                             "duration_s": d} for k, d in enumerate(durations)],
            "robot_actions": robot[0], "actions": robot[1], "robot_share": robot[0] / robot[1],
            "robot_choices": chosen[0], "choices": chosen[1], "robot_share_chosen": chosen[0] / chosen[1],
            "robot_share_by_action": {"a1": robot[0] / robot[1]}, "allocation_rows": []}


def _summary(n: int = 1, modes=("hrc", "kwear-lookahead")) -> dict:
    tests = {m: {"metric": m, "statistic": 3.0, "p": 0.25, "n": n, "modes": [modes[1], modes[0]]}
             for m in ("kwear_integral", "time_above_vth")}
    return {"scenario": "x", "seed": 0, "action_labels": ["a1"], "config": {"takt": 38.0, "repetitions": 4,
                                                                          "modes": list(modes)},
            "modes": {modes[0]: _mode([75.0, 85.0, 80.0, 78.0], 4),
                      modes[1]: _mode([30.0, 36.0, 41.0, 37.0], 1, robot=(3, 23), chosen=(3, 4))},
            "wilcoxon_by_metric": tests, "wilcoxon": tests["kwear_integral"]}


def test_both_robot_shares_are_explained_under_the_table():
    text = summary_text(_summary(), None)
    assert " 13.0% (3/23)" in text and " 75.0% (3/4)" in text
    assert "robot share: of the completed actions that the task lets either agent do" in text
    assert "of choices: of the decisions at which the allocator could give the action to either agent" in text
    assert "robot share =" not in text  # the old one-liner left "of choices" unexplained


def test_overruns_are_told_against_the_takt():
    lines = overrun_words(_summary(), _summary()["config"])
    assert lines[0].startswith("takt 38 s: the time the line gives one repetition; the schedule is "
                               "4 × 38 s = 152 s")
    assert lines[1] == ("hrc: 4 of 4 repetition(s) over the 38 s takt (repetitions took 75.0-85.0 s (mean "
                        "79.5 s)), so this mode does not hold the takt in this cell")
    assert lines[2].startswith("kwear-lookahead: 1 of 4 repetition(s) over the 38 s takt (repetitions took "
                               "30.0-41.0 s")
    assert "so this mode" not in lines[2]
    text = summary_text(_summary(), None).replace("\n    ", " ")
    assert all(line in text for line in lines)


@pytest.mark.parametrize("n", [1, 5])
def test_too_few_pairs_print_no_statistic_and_say_so(n):
    lines = wilcoxon_lines(_summary(n))
    assert len(lines) == 1 and "W =" not in lines[0] and "p =" not in lines[0]
    assert lines[0].startswith("Wilcoxon signed-rank, kwear-lookahead vs hrc, subject by subject: not "
                               f"computed: n = {n} pair")
    assert "below 6 pairs its two-sided p cannot fall below 0.05" in lines[0]


def test_enough_pairs_print_the_test_with_the_runs_modes():
    lines = wilcoxon_lines(_summary(6, modes=("hrc", "kwear-lookahead")))
    assert lines == ["Wilcoxon signed-rank (kwear_integral, kwear-lookahead vs hrc, n=6): W = 3, p = 0.25",
                     "Wilcoxon signed-rank (time_above_vth, kwear-lookahead vs hrc, n=6): W = 3, p = 0.25"]
    assert "h-only" not in "\n".join(lines)


def test_the_threshold_of_too_few_is_the_tests_smallest_p():
    assert [too_few_pairs(n) for n in range(1, 8)] == [True] * 5 + [False] * 2
    assert wilcoxon_min_p(5) == 0.0625 and wilcoxon_min_p(6) == 0.03125
    for n in (5, 6):  # the smallest p scipy gives, every difference of one sign, is that bound
        assert wilcoxon_between([1.0 + k for k in range(n)], [0.0] * n, "m")["p"] == pytest.approx(
            wilcoxon_min_p(n))


def _rows(n: int) -> list[SubjectRow]:
    return [SubjectRow(s, f"S{s}", m, 10.0 + s + (m == "h-only") * (1 + s), 0.0)
            for s in range(n) for m in ("hrc", "h-only")]


def test_the_mode_figure_prints_no_statistic_for_one_subject():
    fig = modes_figure(_rows(1), ("hrc", "h-only"))
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert texts and not any("W =" in t or "p =" in t for t in texts)
    assert any(t.startswith("hrc vs h-only: no test,\nn = 1 pair, too few") for t in texts)
    fig = modes_figure(_rows(6), ("hrc", "h-only"))
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert any(t.startswith("hrc vs h-only: Wilcoxon W = 0, p = 0.031, n = 6") for t in texts), texts


def test_an_interval_bound_that_is_round_off_prints_as_zero():
    assert interval_text(5.551115123125783e-17, 0.31) == "0, 0.31"
    assert _ci(5.551115123125783e-17, 0.31) == "[0, 0.31]"
    assert _estimate(0.15, 5.551115123125783e-17, 0.31, 4) == "0.15 [0, 0.31] n=4"
    assert _estimate(-2.7755575615628914e-17, -0.2, 0.2, 4) == "0 [-0.2, 0.2] n=4"
    assert interval_text(1e-4, 0.31) == "0.0001, 0.31"  # a small figure that is not round-off stays
    assert interval_text(None, 0.31) == "-"

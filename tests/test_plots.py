"""The figures of a run (issue 16): each drawn from the CSV files beside it, checked artist by artist against
those files read independently here (csv.DictReader), never against the run's memory."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest
from conftest import KV_SHORT

from ergosim.cli import main
from ergosim.experiment.csv_files import SUBJECT_COLUMNS
from ergosim.experiment.plots import (
    actions_figure,
    allocation_figure,
    modes_figure,
    read_action_traces,
    read_attempts,
    read_run_info,
    read_subjects,
    read_ticks,
    timeline_figure,
)
from ergosim.experiment.plots.tables import SubjectRow
from ergosim.posture import KWEAR_JOINTS


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory) -> Path:
    """A real multi-subject run, shortened: 2 subjects, 2 repetitions, hrc and h-only."""
    out = tmp_path_factory.mktemp("plots") / "out"
    assert main(["run", "multi-subject", "--subjects", "2", "--reps", "2", "--jobs", "1", "--quiet",
                 "--out", str(out)]) == 0
    return out


def _rows(path: Path) -> list[dict]:
    with path.open() as f:
        return list(csv.DictReader(f))


def _by_gid(fig) -> dict:
    return {a.get_gid(): a for ax in fig.axes for a in ax.get_children() if a.get_gid()}


@pytest.mark.slow
def test_run_writes_every_figure_and_the_csvs_they_come_from(run_dir):
    names = {p.name for p in run_dir.iterdir()}
    assert {"subjects.csv", "kwear_actions.csv", "kwear_timeline_hrc.png", "kwear_timeline_h-only.png",
            "kwear_modes.png", "kwear_actions.png", "allocation_histogram.png"} <= names
    assert {f"kwear_a{k}.png" for k in range(1, 6)} <= names
    manifest = json.loads((run_dir / "run.json").read_text())
    new = {"subjects.csv", "kwear_actions.csv", "kwear_modes.png", "kwear_actions.png"}
    assert new <= set(manifest["files"])


def test_timeline_lines_bars_and_repetitions_equal_the_csvs(run_dir):
    info = read_run_info(run_dir)
    fig = timeline_figure(read_ticks(run_dir)["hrc"], [a for a in read_attempts(run_dir) if a.mode == "hrc"],
                          v_th=info.v_th, title="t")
    art = _by_gid(fig)
    ticks = [r for r in _rows(run_dir / "ticks.csv") if r["mode"] == "hrc"]
    allocs = [r for r in _rows(run_dir / "allocations.csv") if r["mode"] == "hrc" and r["status"] != "pruned"]
    for s in ("0", "1"):
        mine = [r for r in ticks if r["subject"] == s]
        for joint in KWEAR_JOINTS:
            x, y = art[f"kwear/{s}/{joint}"].get_data()
            assert np.array_equal(x, [float(r["t"]) for r in mine])
            assert np.array_equal(y, [float(r[f"kwear_{joint}"]) for r in mine])
        for r in (r for r in allocs if r["subject"] == s):
            bar = art[f"attempt/{s}/{r['repetition']}/{r['order']}"]
            assert bar.get_x() == pytest.approx(float(r["t_start"]))
            assert bar.get_width() == pytest.approx(float(r["t_end"]) - float(r["t_start"]))
            assert bar.get_hatch() == (None if r["status"] == "done" else "////")
        for rep in ("1", "2"):
            start = min(float(r["t_start"]) for r in allocs if r["subject"] == s and r["repetition"] == rep)
            assert art[f"rep/{s}/{rep}"].get_xdata()[0] == start
    assert [ax.get_ylabel() for ax in fig.axes[::2]] == ["subject 0\nKWear V", "subject 1\nKWear V"]
    v_th = [a for ax in fig.axes for a in ax.get_lines() if a.get_gid() == "v_th"]
    assert len(v_th) == 2 and all(line.get_ydata()[0] == info.v_th == 0.8 for line in v_th)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "a robot is acting" in labels and "failed attempt" in labels and not fig.legends[0].axes
    assert "grey" not in fig._suptitle.get_text()  # the old caption that sat on the wrong plot


def test_mode_figure_pairs_each_subject_and_quotes_the_summarys_test(run_dir):
    rows = _rows(run_dir / "subjects.csv")
    summary = json.loads((run_dir / "summary.json").read_text())
    assert tuple(rows[0]) == SUBJECT_COLUMNS
    fig = modes_figure(read_subjects(run_dir), ("hrc", "h-only"))
    art = _by_gid(fig)
    for metric, key in (("kwear_integral", "kwear_integral_by_subject"),
                        ("time_above_vth", "time_above_vth_by_subject")):
        for s in (0, 1):
            want = [float(r[metric]) for m in ("hrc", "h-only") for r in rows
                    if r["mode"] == m and r["subject"] == str(s)]
            assert list(art[f"{metric}/{s}"].get_ydata()) == want
            assert want == [summary["modes"][m][key][s] for m in ("hrc", "h-only")]  # exactly the summary's
    assert summary["wilcoxon"]["n"] == 2  # too few pairs for a statistic: the figure says so instead
    text = art["p/kwear_integral/h-only"].get_text()
    assert text.startswith("hrc vs h-only: no test") and "n = 2 pairs, too few" in text and "W =" not in text


def test_paper_figure_equals_kwear_actions_csv(run_dir):
    rows = [r for r in _rows(run_dir / "kwear_actions.csv") if r["subject"] == "1"]
    traces = {a: tv for (s, a), tv in read_action_traces(run_dir).items() if s == 1}
    assert list(traces) == ["a1", "a2", "a3", "a4", "a5"]
    art = _by_gid(actions_figure(traces, subject=1))
    for action in traces:
        mine = [r for r in rows if r["action"] == action]
        assert float(mine[0]["t"]) > 0 and all(float(mine[0][f"kwear_{j}"]) < 0.05 for j in KWEAR_JOINTS)
        for joint in KWEAR_JOINTS:
            x, y = art[f"action/1/{action}/{joint}"].get_data()
            assert np.array_equal(x, [float(r["t"]) for r in mine])
            assert np.array_equal(y, [float(r[f"kwear_{joint}"]) for r in mine])


def test_histogram_bars_and_counts_equal_allocations_csv(run_dir):
    rows = [r for r in _rows(run_dir / "allocations.csv")
            if r["status"] == "done" and r["allocatable"] == "1"]
    fig = allocation_figure(read_attempts(run_dir), ("hrc", "h-only"))
    art = _by_gid(fig)
    actions = sorted({r["action"] for r in rows})
    assert actions == ["a1", "a2", "a3", "a4"]  # a5 is the worker's alone: not allocatable
    for action in actions:
        mine = [r for r in rows if r["mode"] == "hrc" and r["action"] == action]
        robot = sum(r["agent"] == "robot" for r in mine)
        assert art[f"share/hrc/{action}"].get_height() == pytest.approx(100 * robot / len(mine))
        assert art[f"count/hrc/{action}"].get_text() == f"{robot}/{len(mine)}"
        assert f"share/h-only/{action}" not in art  # no robot can act in h-only: not an empty entry
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == ["hrc"]


@pytest.mark.slow
def test_plots_are_drawn_from_the_files_and_redrawn_for_chosen_subjects(run_dir, tmp_path, capsys):
    copy = tmp_path / "copy"
    shutil.copytree(run_dir, copy)
    ticks = (copy / "ticks.csv").read_text().splitlines()
    header = ticks[0].split(",")
    col = header.index("kwear_neck")
    changed = []
    for line in ticks[1:]:
        cells = line.split(",")
        if cells[:2] == ["0", "hrc"]:
            cells[col] = "0.99"  # a visible change in the file only
        changed.append(",".join(cells))
    (copy / "ticks.csv").write_text("\n".join([ticks[0], *changed]) + "\n")
    assert main(["plot", str(copy)]) == 0
    assert "kwear_timeline_hrc.png" in capsys.readouterr().out
    for name, same in (("kwear_timeline_hrc.png", False), ("kwear_timeline_h-only.png", True)):
        assert ((copy / name).read_bytes() == (run_dir / name).read_bytes()) is same, name
    both = matplotlib.image.imread(copy / "kwear_timeline_hrc.png").shape[0]
    assert main(["plot", str(copy), "--plot-subject", "1"]) == 0
    one = matplotlib.image.imread(copy / "kwear_timeline_hrc.png").shape[0]
    assert one < 0.7 * both
    assert main(["plot", str(copy), "--plot-subject", "5"]) == 2
    assert "--plot-subject: no subject 5" in capsys.readouterr().err
    assert main(["plot", str(tmp_path / "none")]) == 2


def test_no_plots_writes_the_same_files_and_plot_draws_the_figures_later(kv_run, tmp_path, capsys):
    """``ergosim run --no-plots`` (a faster run) writes every file but the PNGs; ``ergosim plot`` then draws
    the figures a run with plots writes, byte for byte. Against the shared kwear-validation run
    (tests/conftest.py), made with the same arguments and plots (its recording changes no output)."""
    out = tmp_path / "out"
    assert main(["run", "kwear-validation", "--reps", "1", "--mode", "hrc", "--jobs", "1", "--quiet",
                 *KV_SHORT, "--no-plots", "--out", str(out)]) == 0
    assert "kwear_state_*.json)" in capsys.readouterr().out  # the results line lists no *.png
    pngs = sorted(p.name for p in kv_run.out.glob("*.png") if p.name != "cell.png")  # the still: a run's
    assert len(pngs) >= 3 and not list(out.glob("*.png"))
    for name in ("summary.json", "ticks.csv", "allocations.csv", "kwear_actions.csv", "subjects.csv"):
        assert (out / name).read_bytes() == (kv_run.out / name).read_bytes(), name
    assert main(["plot", str(out)]) == 0
    assert sorted(p.name for p in out.glob("*.png")) == pngs
    assert [n for n in pngs if (out / n).read_bytes() != (kv_run.out / n).read_bytes()] == []


def test_run_plot_subject_chooses_the_panels(kv_two_subjects):
    """The shared two-subject run, made with --plot-subject 1 (tests/conftest.py)."""
    out = kv_two_subjects.out
    assert kv_two_subjects.code == 0
    fig = timeline_figure(read_ticks(out, (1,))["hrc"], [a for a in read_attempts(out) if a.mode == "hrc"],
                          v_th=0.8, title="")
    assert [ax.get_ylabel() for ax in fig.axes[::2]] == ["subject 1\nKWear V"]
    height = matplotlib.image.imread(out / "kwear_timeline_hrc.png").shape[0]
    assert height == pytest.approx(fig.get_figheight() * 110, abs=2)


def test_mode_figure_shows_the_peak_wear_and_says_why_the_time_above_v_th_is_zero(run_dir):
    """Issue 27: the README's right panel (time above V_th) was all zeros ("W = 0, p = 1"). The figure now
    draws the highest V each subject's joints reached against V_th; where no joint reached V_th the time
    panel is left out and the figure says why."""
    rows = read_subjects(run_dir)
    ticks = read_ticks(run_dir)
    peaks = {(m, s): float(np.max(t.kwear)) for m, by in ticks.items() for s, t in by.items()}
    assert all(r.time_above_vth == 0 for r in rows) and max(peaks.values()) < 0.8  # this short run
    fig = modes_figure(rows, ("hrc", "h-only"), peaks=peaks, v_th=0.8)
    art = _by_gid(fig)
    assert len(fig.axes) == 2 and "time_above_vth/0" not in art
    for s in (0, 1):
        assert list(art[f"peak_v/{s}"].get_ydata()) == [peaks[("hrc", s)], peaks[("h-only", s)]]
    assert art["v_th"].get_ydata()[0] == 0.8
    assert "no joint reached it in any mode" in art["note/peak_v"].get_text()
    assert art["p/peak_v/h-only"].get_text().startswith("hrc vs h-only: no test")
    # a subject above V_th brings the time panel back, with its test
    above = [SubjectRow(r.subject, r.worker, r.mode, r.kwear_integral, 4.0 * (r.mode == "h-only"))
             for r in rows]
    art = _by_gid(modes_figure(above, ("hrc", "h-only"), peaks=peaks, v_th=0.8))
    assert "time_above_vth/0" in art and "note/peak_v" in art
    assert "no joint reached" not in art["note/peak_v"].get_text()

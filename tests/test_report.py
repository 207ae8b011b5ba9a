"""report.html: written by every bundled scenario's run, self-contained, drawn the same by ``ergosim report
DIR``, and a page a browser draws whole (headless Chromium: the screenshot is not blank, the tables and every
image are there)."""

from __future__ import annotations

import csv
import json
import re
import shutil

import matplotlib.image
import numpy as np
import pytest
from conftest import KV_SHORT, shared_run
from headless_chromium import chromium, inspect_page

from ergosim.cli import main


@pytest.fixture(scope="session")
def gearbox_run(tmp_path_factory):
    """The gearbox cell, 1 subject, 1 repetition, hrc and h-only, calibrated on two executions per action."""
    args = ["gearbox", "--subjects", "1", "--reps", "1", "--jobs", "1", "--quiet", *KV_SHORT]
    return shared_run(tmp_path_factory, "gearbox", args)


def _page(out) -> str:
    return (out / "report.html").read_text(encoding="utf-8")


def _self_contained(html: str) -> None:
    """No address the page would fetch: every src is a data URI, and no stylesheet or script is linked."""
    sources = re.findall(r'\ssrc="([^"]*)"', html)
    assert sources and all(s.startswith("data:") for s in sources), [s[:40] for s in sources]
    assert "<link" not in html and "<script" not in html and "http://" not in html and "https://" not in html


def test_every_bundled_scenario_run_writes_its_report(kv_run, forced_run, gearbox_run):
    for run, scenario in ((kv_run, "kwear-validation"), (forced_run, "multi-subject"),
                          (gearbox_run, "gearbox")):
        assert run.code == 0
        html = _page(run.out)
        _self_contained(html)
        summary = json.loads((run.out / "summary.json").read_text())
        assert f"ergosim run: {scenario}</h1>" in html
        assert (run.out / "cell.png").is_file() and 'alt="the workcell"' in html
        for mode in summary["config"]["modes"]:
            assert f"<h3>{mode}</h3>" in html and f'alt="kwear_timeline_{mode}"' in html
        with (run.out / "decisions.csv").open(encoding="utf-8", newline="") as f:
            decisions = list(csv.DictReader(f))
        assert decisions and all(d["reason"].startswith(f"{d['action']} → {d['agent']}") for d in decisions)
        for d in decisions:  # each decision's reason is on the page
            assert d["reason"].replace("<", "&lt;").replace(">", "&gt;") in html
        assert "Takt and overruns" in html and f"takt {summary['config']['takt']:g} s" in html


def test_failures_and_robot_actions_are_on_the_page(forced_run):
    """The forced run's worker fails a2 each repetition and the robot then does it: every failure's message
    is in the failures table, and the allocation table has the forced robot cells."""
    html = _page(forced_run.out)
    with (forced_run.out / "failures.csv").open(encoding="utf-8", newline="") as f:
        failures = list(csv.DictReader(f))
    assert failures and "No failed attempt" not in html
    for x in failures:
        assert x["message"].replace("'", "&#x27;").replace('"', "&quot;") in html
    assert '<td class="R">R*!</td>' in html


def test_ergosim_report_writes_the_same_page_again(kv_run, tmp_path, capsys):
    folder = tmp_path / "run"
    shutil.copytree(kv_run.out, folder)
    (folder / "report.html").unlink()
    assert main(["report", str(folder)]) == 0
    assert "wrote " in capsys.readouterr().out
    assert (folder / "report.html").read_bytes() == (kv_run.out / "report.html").read_bytes()
    (folder / "cell.png").unlink()  # a folder without its still: the page says so
    assert main(["report", str(folder), "--quiet"]) == 0
    assert "No still of the workcell in this folder" in _page(folder)


@pytest.mark.parametrize("case", ["missing", "file", "empty", "video"])
def test_ergosim_report_refuses_what_is_not_a_run_folder(case, tmp_path, capsys):
    target = tmp_path / "x"
    args = []
    if case == "file":
        target.write_text("not a folder")
    elif case in ("empty", "video"):
        target.mkdir()
    if case == "video":
        (target / "run.json").write_text("{}")
        args = ["--video", str(tmp_path / "nope.mp4")]
    assert main(["report", str(target), *args]) == 2
    err = capsys.readouterr().err
    needle = {"missing": "is not a directory", "file": "is not a directory",
              "empty": "no run.json in", "video": "--video: no video file"}[case]
    assert err.count("\n") == 1 and needle in err and "Traceback" not in err, err
    assert not (target / "report.html").exists() if target.is_dir() else True


def test_the_report_draws_whole_in_headless_chromium(forced_run, tmp_path):
    """Chromium (Debian's package; .ci/run installs it) draws the page: the screenshot is far from blank,
    the text holds the sections and the allocation table, every table has rows and a height, every image
    decoded, and the page fetched nothing."""
    assert chromium(), "no chromium on PATH: apt-get install -y chromium (.ci/run does)"
    png = tmp_path / "report.png"
    facts = inspect_page(forced_run.out / "report.html", png, width=1200, max_height=3000)
    shot = matplotlib.image.imread(png)[..., :3]
    assert shot.shape[:2] == (3000, 1200)
    ink = np.mean(np.any(shot < 0.9, axis=-1))  # share of pixels that are not (near) white
    assert 0.05 < ink < 0.95 and float(shot.std()) > 0.1, (ink, float(shot.std()))
    text = facts["text"]
    for heading in ("The workcell", "What the run says", "Takt and overruns", "Allocation per mode",
                    "Per action: RULA score and KWear per execution", "Wear over the run",
                    "Failures and refusals", "Each decision and its reason"):
        assert heading in text, heading
    summary = json.loads((forced_run.out / "summary.json").read_text())
    rows = summary["modes"]["hrc"]["allocation_rows"]
    line = "\t".join(["subject 0 rep 1", *rows[0]["cells"].values(), "completed"])
    assert line in text, text[:2000]
    assert facts["tables"] and all(t["rows"] >= 2 for t in facts["tables"])
    assert all(t["height"] > 0 for t in facts["tables"][:4])
    assert facts["images"] and all(i["complete"] and i["width"] > 0 for i in facts["images"]), facts["images"]
    assert facts["external"] == []

"""The README's GIF (issue 16): cut from a real run by the committed script, under 3 MB, looping."""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

from ergosim.experiment.clip import MAX_GIF_BYTES, _attempts, robot_repetition
from ergosim.experiment.runner import run_subject
from ergosim.experiment.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[1]
GIF = ROOT / "docs" / "img" / "hrc_repetition.gif"
REGENERATE = "the simulation changed since the GIF was made: run `python scripts/make_readme_gif.py`"


def test_the_readme_shows_the_gif_near_the_top_and_explains_the_overlay():
    readme = (ROOT / "README.md").read_text()
    head = readme.split("## Quickstart")[0]
    assert "docs/img/hrc_repetition.gif" in head
    assert "## What you will see" in readme and "V_th" in readme.split("## What you will see")[1][:3000]


@pytest.mark.slow
def test_the_committed_gif_is_the_scripts_output_for_todays_simulation():
    doc = json.loads(GIF.with_suffix(".json").read_text())
    data = GIF.read_bytes()
    assert doc["made_by"] == "scripts/make_readme_gif.py" and (ROOT / doc["made_by"]).is_file()
    assert hashlib.sha256(data).hexdigest() == doc["sha256"] and len(data) == doc["bytes"] < MAX_GIF_BYTES
    with Image.open(GIF) as im:
        assert im.n_frames == doc["gif_frames"] > 30 and im.info.get("loop") == 0
        assert im.size[0] == doc["settings"]["width"]
    s = doc["settings"]
    scenario = load_scenario(s["scenario"], {"subjects": str(s["subject"] + 1),
                                             "repetitions": str(s["repetitions"]), "modes": "hrc"})
    run = run_subject(scenario, s["subject"], s["seed"], ("hrc",)).runs["hrc"]
    rep = robot_repetition(run)
    assert rep == doc["repetition"], REGENERATE
    assert _attempts(run, rep) == doc["attempts"], REGENERATE
    assert any(agent == "robot" and status == "done" for _, agent, status, *_ in doc["attempts"])


@pytest.mark.slow
def test_the_script_makes_a_looping_gif_with_its_provenance(tmp_path):
    out = tmp_path / "clip.gif"
    env = {**os.environ, "MUJOCO_GL": "egl"}
    done = subprocess.run([sys.executable, str(ROOT / "scripts" / "make_readme_gif.py"), "--out", str(out),
                           "--repetitions", "4", "--speed", "20", "--width", "160", "--fps", "4", "--quiet"],
                          capture_output=True, text=True, env=env, timeout=600, check=False)
    assert done.returncode == 0, done.stderr
    doc = json.loads(out.with_suffix(".json").read_text())
    with Image.open(out) as im:
        assert im.size[0] == 160 and im.n_frames == doc["gif_frames"] >= 5 and im.info.get("loop") == 0
    assert doc["settings"]["speed"] == 20 and hashlib.sha256(out.read_bytes()).hexdigest() == doc["sha256"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip.gif", "clip.json"]  # no temporary left

"""The video's render settings and the side-by-side film of another revision (issue 38): the quality reaches
the renderer and nothing else, a revision's models and settings are loaded beside this checkout's, and the
benchmark films both from one recorded run."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from benchmarks.revision import tree_at
from benchmarks.video_baseline import baseline_cell, baseline_quality, stills
from ergosim.errors import ConfigError
from ergosim.experiment.runner import run_subject
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import scenario_subject, subject_cell
from ergosim.robot import model as robot_model
from ergosim.scenes import build_cell
from ergosim.video import PoseRenderer, RenderQuality, VideoRequest, read_mp4, write_run_video

ROOT = Path(__file__).resolve().parents[1]
BEFORE = "6df92f7"
"""The revision issue 38 measured: 2048 px shadows, the Panda's full 134,300-triangle visual meshes."""


@pytest.fixture(scope="module")
def cell():
    return build_cell(load_scenario("multi-subject").cell())


def test_the_render_quality_reaches_the_renderers_copy_only(cell):
    m = cell.model
    before = (m.vis.quality.shadowsize, m.vis.quality.offsamples)
    assert RenderQuality().shadow_size == 1024
    for quality in (RenderQuality(), RenderQuality(shadow_size=512, multisamples=2)):
        with PoseRenderer(m, cell.config.view(), width=160, height=90, quality=quality) as pr:
            assert pr.model.vis.quality.shadowsize == quality.shadow_size
            assert pr.model.vis.quality.offsamples == quality.multisamples
            assert pr.render(cell.data.xpos, cell.data.xquat).shape == (90, 160, 3)
    assert (m.vis.quality.shadowsize, m.vis.quality.offsamples) == before


def test_a_revisions_settings_and_models_are_read_beside_ours(cell, tmp_path):
    assert baseline_quality(BEFORE) == RenderQuality(shadow_size=2048, multisamples=0, reflection=False)
    folder = tree_at(BEFORE, "models", tmp_path)
    assert (folder / "panda" / "panda.xml").is_file()
    assert len((folder / "panda/assets/link5_0.obj").read_text().splitlines()) > 20000  # the full mesh
    saved = robot_model.MODELS_DIR
    old = baseline_cell(BEFORE, lambda: build_cell(load_scenario("multi-subject").cell()))
    assert robot_model.MODELS_DIR == saved  # put back
    assert old.model.nbody == cell.model.nbody and old.model.njnt == cell.model.njnt
    assert old.model.nmeshface == 136600 > 4 * cell.model.nmeshface
    with pytest.raises(ConfigError, match="no-such-revision"):
        tree_at("no-such-revision", "models", tmp_path)


@pytest.mark.slow
def test_the_benchmark_films_both_revisions_and_writes_stills_that_look_alike(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "scripts" / "bench_video.py"), "--baseline", BEFORE,
                          "--repeats", "1", "--seconds", "0.2", "--stills", str(tmp_path), "--at", "6"],
                         capture_output=True, text=True, check=True, cwd=tmp_path)
    res = json.loads(out.stdout)
    assert res["frames"] == 7 and len(res["load_1min"]) == 1 and res["baseline_rev"] == BEFORE
    assert res["current"]["quality"]["shadow_size"] == 1024
    assert res["baseline"]["quality"]["shadow_size"] == 2048
    assert res["baseline"]["mesh_faces"] == 136600 > 4 * res["current"]["mesh_faces"]
    for name in ("current", "baseline"):
        assert res[name]["ms_per_frame"] > 0 < res[name]["cpu_ms_per_frame"] and res[name]["identical_mp4"]
    assert res["speedup"] > 0 and res["cpu_ratio"] > 0
    new, old = (np.asarray(Image.open(tmp_path / f"video_{k}_6s.png")) for k in ("current", "baseline"))
    diff = abs(new.astype(int) - old.astype(int))
    assert new.shape == old.shape == (540, 960, 3)
    assert 0 < diff.mean() < 3  # not the same picture, but the same scene


@pytest.mark.slow
def test_stills_are_the_video_frames(tmp_path):
    sc = load_scenario("multi-subject").with_overrides({"repetitions": "1", "modes": "hrc"})
    cell = subject_cell(sc, scenario_subject(sc, 0, 0))
    run = run_subject(sc, 0, 0, ("hrc",), record_mode="hrc").runs["hrc"]
    request = VideoRequest(tmp_path / "one.mp4", width=640, height=360)
    write_run_video(cell, run, request, window=(6.0, 6.0), workers=0)
    frame = read_mp4(request.path)[1][0].astype(int)
    same, other = (abs(frame - x.astype(int)).mean()
                   for x in stills(cell, run, (6.0, 24.0), RenderQuality(), size=(640, 360)))
    assert same < 4 and other > 2 * same  # the frame at 6 s, up to H.264's loss (3.5 levels on average)

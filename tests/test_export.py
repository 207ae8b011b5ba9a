"""`ergosim export`: every bundled scenario's scene, saved with its meshes, loads and steps in plain MuJoCo
from a clean folder, and is the scene a run simulates (same bodies, joints, geoms, actuators, welds)."""

import shutil
from pathlib import Path

import mujoco
import numpy as np
import pytest

from ergosim.cli import main
from ergosim.experiment.scenario import load_scenario, scenario_names
from ergosim.scenes import build_cell

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = [*scenario_names(), str(ROOT / "examples/own_workcell/bracket.toml")]


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda s: Path(s).stem)
def test_export_loads_and_steps_in_plain_mujoco(scenario, tmp_path, monkeypatch, capsys):
    assert main(["export", scenario, "--out", str(tmp_path / "out")]) == 0
    assert "python -m mujoco.viewer --mjcf" in capsys.readouterr().out
    clean = tmp_path / "elsewhere" / "scene"
    shutil.move(tmp_path / "out", clean)  # self-contained: nothing points back to the repository
    monkeypatch.chdir(tmp_path)
    (xml,) = clean.glob("*.xml")
    model = mujoco.MjModel.from_xml_path(str(xml))
    cell = build_cell(load_scenario(scenario).cell())
    ref = cell.model
    for attr in ("nq", "nv", "nbody", "njnt", "ngeom", "nu", "neq", "nkey", "nmocap", "nmesh", "nsite"):
        assert getattr(model, attr) == getattr(ref, attr), attr
    np.testing.assert_allclose(model.key_qpos, ref.key_qpos, atol=1e-5)  # MuJoCo writes 6 digits
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.keyframe("home").id)
    mujoco.mj_step(model, data, int(round(1.0 / model.opt.timestep)))
    assert not data.warning.number.any()
    assert np.isfinite(data.qpos).all() and np.isfinite(data.qvel).all()
    for part in cell.parts:  # the parts rest where they were laid out
        qa = model.joint(part).qposadr[0]
        np.testing.assert_allclose(data.qpos[qa:qa + 3], model.key_qpos[0][qa:qa + 3], atol=2e-3)


def test_export_refuses_a_file_as_folder(tmp_path, capsys):
    target = tmp_path / "file.xml"
    target.write_text("mine")
    assert main(["export", "gearbox", "--out", str(target)]) == 2
    assert "is a file" in capsys.readouterr().err
    assert target.read_text() == "mine"

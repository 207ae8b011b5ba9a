"""Every model in models/ and every registered scene compiles and steps 1 s: no MuJoCo warning, no NaN."""

from pathlib import Path

import mujoco
import numpy as np
import pytest

from ergosim.robot.model import load_mjcf
from ergosim.scenes import build_scene, scene_names

MODELS = sorted((Path(__file__).resolve().parents[1] / "models").glob("*/*.xml"))


def _step_one_second(model, data):
    if model.nkey:
        mujoco.mj_resetDataKeyframe(model, data, 0)
    for _ in range(int(round(1.0 / model.opt.timestep))):
        mujoco.mj_step(model, data)
    warned = [mujoco.mjtWarning(i).name for i in np.flatnonzero(data.warning.number)]
    assert not warned, warned
    assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel))


def test_models_found():
    names = {p.parent.name for p in MODELS}
    assert {"panda", "humanoid_upper"} <= names


@pytest.mark.parametrize("path", MODELS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_model_compiles_and_steps(path):
    model = load_mjcf(path)
    _step_one_second(model, mujoco.MjData(model))


@pytest.mark.parametrize("name", scene_names())
def test_scene_compiles_and_steps(name):
    wc = build_scene(name)
    _step_one_second(wc.model, wc.data)
    # parts rest where they were laid out
    for part in wc.parts:
        qa = wc.model.joint(part).qposadr[0]
        np.testing.assert_allclose(wc.data.qpos[qa:qa + 3], wc.model.key_qpos[0][qa:qa + 3], atol=2e-3)

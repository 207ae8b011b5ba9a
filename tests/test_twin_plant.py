"""The plant's control tick (ergosim.twin.loop): the worker's frames pose the scene's mocap human."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from ergosim.ergonomics.kwear import KWearParams
from ergosim.ergonomics.risk_index import KWearIndex
from ergosim.errors import ModelError
from ergosim.scenes import build_scene
from ergosim.twin.loop import Plant
from ergosim.twin.worker_track import WorkerTrack
from ergosim.worker import MocapStream, Subject, Worker


@pytest.fixture()
def plant():
    subject = Subject("T", variability_deg=0.0)
    cell = build_scene("kwear-validation", stature=subject.stature)
    track = WorkerTrack(Worker(subject), MocapStream(subject, np.random.default_rng(0)))
    return Plant(cell, track, KWearIndex(KWearParams(), {}), mocap_rate=60.0, ergonomics_rate=20.0,
                 physics_dt=1 / 240)


def _count_poses(plant, monkeypatch) -> list[int]:
    calls = []
    pose = plant.human.pose
    monkeypatch.setattr(plant.human, "pose", lambda d, q, qd=None: (calls.append(1), pose(d, q, qd)))
    return calls


def test_every_action_frame_poses_the_human_where_its_model_puts_it(plant, monkeypatch):
    cell, track = plant.cell, plant.track
    seg = track.start_action(track.worker.plan(cell, cell.actions["a1"], np.random.default_rng(1), "a1"))
    assert not seg.static
    calls = _count_poses(plant, monkeypatch)
    kin = mujoco.MjData(plant.human.kin_model)
    for _ in range(seg.n // 2):
        plant.step()
        k = track.index - 1
        plant.human.kin.set_angles(kin, seg.true[k])
        scene_hand = cell.data.site_xpos[plant.human.hand_site["right"]]
        np.testing.assert_allclose(scene_hand, kin.site_xpos[plant.human.kin.hand_site["right"]], atol=1e-12)
    assert len(calls) == seg.n // 2


def test_a_held_rest_is_posed_once(plant, monkeypatch):
    track = plant.track
    seg = track.start_rest(2.0)
    assert seg.static and seg.n == 121
    calls = _count_poses(plant, monkeypatch)
    for _ in range(seg.n):
        plant.step()
    assert len(calls) == 1
    kin = mujoco.MjData(plant.human.kin_model)
    plant.human.kin.set_angles(kin, seg.true[0])
    np.testing.assert_allclose(plant.data.mocap_pos, kin.xpos[1:], atol=1e-12)
    np.testing.assert_allclose(plant.data.mocap_quat, kin.xquat[1:], atol=1e-12)
    plant.step()  # the queue ran dry: a new rest chunk is measured and posed once more
    assert len(calls) == 2 and track.segment is not seg and track.segment.static


def test_a_workcell_without_a_human_is_refused():
    cell = build_scene("kwear-validation")
    cell.human = None
    with pytest.raises(ModelError, match="no human"):
        Plant(cell, None, None, mocap_rate=60.0, ergonomics_rate=20.0, physics_dt=1 / 240)

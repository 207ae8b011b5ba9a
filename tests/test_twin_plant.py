"""The plant's control tick (ergosim.twin.loop): the worker's frames pose the scene's mocap human."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from ergosim.ergonomics.kwear import KWearParams
from ergosim.ergonomics.risk_index import KWearIndex
from ergosim.errors import ModelError
from ergosim.scenes import build_scene
from ergosim.twin.loop import PLANT_HOOKS, Plant, PlantHook
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
        plant.human.kin.set_body(kin, seg.true[k], seg.stance[k])  # the stepping worker: posture and stance
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


def test_hooks_are_called_by_name_at_their_points_of_the_tick(plant):
    """A PlantHook's named methods (PLANT_HOOKS): the grasp and release on the segment's frames, then
    before_physics with the frame, after_step after every tick; in the order the hooks were added."""
    calls = []

    class Log(PlantHook):
        def __init__(self, name):
            self.name = name

        def on_grasp(self, p):
            calls.append((self.name, "on_grasp", p.ticks))

        def on_release(self, p):
            calls.append((self.name, "on_release", p.ticks))

        def before_physics(self, p, frame):
            calls.append((self.name, "before_physics", frame))

        def after_step(self, p):
            calls.append((self.name, "after_step", p.ticks))

    cell, track = plant.cell, plant.track
    seg = track.start_action(track.worker.plan(cell, cell.actions["a1"], np.random.default_rng(1), "a1"))
    plant.hooks += [Log("a"), Log("b")]
    for _ in range(seg.n):
        plant.step()
    assert PLANT_HOOKS == ("on_grasp", "on_release", "before_physics", "after_step")
    assert [c for c in calls if c[1] == "on_grasp"] == [("a", "on_grasp", seg.grasp_frame),
                                                       ("b", "on_grasp", seg.grasp_frame)]
    assert [c for c in calls if c[1] == "on_release"] == [("a", "on_release", seg.release_frame),
                                                         ("b", "on_release", seg.release_frame)]
    assert [c[2] for c in calls if c[:2] == ("a", "before_physics")] == list(range(seg.n))
    assert [c[2] for c in calls if c[:2] == ("b", "after_step")] == list(range(1, seg.n + 1))
    tick = [c[:2] for c in calls if c[1] != "after_step" or c[2] == seg.grasp_frame + 1]
    at_grasp = tick[tick.index(("a", "on_grasp")):][:6]
    assert at_grasp == [("a", "on_grasp"), ("b", "on_grasp"), ("a", "before_physics"),
                        ("b", "before_physics"), ("a", "after_step"), ("b", "after_step")]

"""The simulated worker: IK with natural priors, minimum-jerk motion, subjects, mocap stream, BVH recordings,
and the replay of recordings through RULA and KWear."""

from ergosim.worker.action_timing import ActionTiming, action_timing
from ergosim.worker.bvh import Recording, load_bvh, read_bvh_text, save_bvh
from ergosim.worker.ergonomics_tick import (
    REPLAY_COLUMNS,
    ReplayTrace,
    replay,
    replay_ticks,
    score_frames,
    tick_indices,
)
from ergosim.worker.ik import IKSolution, WholeBodyIK, log_so3
from ergosim.worker.ik_prior import BODY, IKPrior, default_prior
from ergosim.worker.minimum_jerk import interpolate_keyframes, min_jerk, min_jerk_velocity
from ergosim.worker.motion import ActionMotion, Phase, SceneView, Worker
from ergosim.worker.refusal import RefusalModel
from ergosim.worker.stance import StandingArea
from ergosim.worker.stream import MocapFrames, MocapStream, MotionPlayback
from ergosim.worker.subjects import Subject, make_subject, make_subjects, rest_angles

__all__ = [
    "RefusalModel",
    "Recording",
    "load_bvh",
    "read_bvh_text",
    "save_bvh",
    "IKPrior",
    "IKSolution",
    "WholeBodyIK",
    "BODY",
    "StandingArea",
    "default_prior",
    "log_so3",
    "ActionTiming",
    "action_timing",
    "interpolate_keyframes",
    "min_jerk",
    "min_jerk_velocity",
    "ActionMotion",
    "Phase",
    "SceneView",
    "Worker",
    "MocapFrames",
    "MocapStream",
    "MotionPlayback",
    "Subject",
    "make_subject",
    "make_subjects",
    "rest_angles",
    "REPLAY_COLUMNS",
    "ReplayTrace",
    "score_frames",
    "tick_indices",
    "replay",
    "replay_ticks",
]

"""Real recordings: load a BVH file onto the canonical angles, and export canonical angles as BVH.

``load_bvh(path)`` turns an Xsens MVN, Vicon, OptiTrack or CMU-style BVH into a :class:`Recording` of the
canonical angles of :mod:`ergosim.posture` (degrees, per frame), which replays through the same pipeline
as the synthetic stream: postures -> RULA -> KWear. ``save_bvh`` writes angle trajectories with the
project's own skeleton (:mod:`ergosim.worker.bvh_export`). docs/bvh.md has the mapping table and every
convention.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from ergosim.atomic import write_text
from ergosim.errors import RecordingError
from ergosim.posture import ANGLE_NAMES
from ergosim.worker.bvh_export import bvh_text
from ergosim.worker.bvh_mapping import map_skeleton, recording_angles
from ergosim.worker.bvh_parse import BvhData, parse_bvh, parse_bvh_text

__all__ = ["Recording", "load_bvh", "read_bvh_text", "recording_from_data", "save_bvh"]


@dataclass(frozen=True, eq=False)
class Recording:
    """Canonical angles of a recording.

    ``angles``: canonical name -> (n_frames,) [deg] (read-only); the left-arm names are present only if the
    file has a left arm. ``mapping``: role (pelvis, thorax, head, right_upper_arm, ...) -> BVH joint name.
    """

    rate_hz: float
    n_frames: int
    angles: Mapping[str, np.ndarray]
    source: str
    mapping: Mapping[str, str]
    frames: np.ndarray | None = None
    """Indices of the recording's frames that ``angles`` holds (a sample, e.g. a replay's ticks), or None
    for all ``n_frames``."""

    @property
    def t(self) -> np.ndarray:
        """Time of each frame in ``angles`` [s] from the first frame of the recording."""
        return (np.arange(self.n_frames) if self.frames is None else self.frames) / self.rate_hz

    def array(self, names: tuple[str, ...] = ANGLE_NAMES) -> np.ndarray:
        """(frames, len(names)) [deg]; ``HUMAN_JOINTS`` gives the human model's order (needs a left arm)."""
        missing = [n for n in names if n not in self.angles]
        if missing:
            raise RecordingError(f"the recording has no {', '.join(missing)} (no such segment was mapped)",
                                 where=self.source)
        return np.stack([self.angles[n] for n in names], axis=-1)


def recording_from_data(data: BvhData, name_map: Mapping[str, str] | None = None,
                        trunk_reference: str = "vertical", frames: np.ndarray | None = None) -> Recording:
    """:func:`load_bvh` of an already parsed file (:func:`~ergosim.worker.bvh_parse.parse_bvh`).

    ``frames``: increasing indices of the only frames to map (e.g. :func:`~ergosim.worker.tick_indices` of a
    replay); each gets the angles the whole recording's mapping gives it, bit for bit.
    """
    smap = map_skeleton(data, name_map)
    angles = recording_angles(data, smap, trunk_reference, frames)
    for a in angles.values():
        a.setflags(write=False)
    if frames is not None:
        frames = np.array(frames, dtype=np.int64)
        frames.setflags(write=False)
    return Recording(data.rate_hz, data.n_frames, MappingProxyType(angles), data.source,
                     MappingProxyType(dict(smap.names)), frames)


def load_bvh(path: str | os.PathLike[str], name_map: Mapping[str, str] | None = None,
             trunk_reference: str = "vertical") -> Recording:
    """Read a BVH file onto the canonical angles.

    ``name_map`` (role -> joint name) overrides the automatic role detection for any role of
    :data:`ergosim.worker.bvh_mapping.ROLES`. ``trunk_reference``: "vertical" (default; trunk angles from
    the upright, the pelvis's heading removed) or "pelvis" (relative to the pelvis segment).
    Raises :class:`RecordingError` naming the file (and line) for any problem.
    """
    return recording_from_data(parse_bvh(path), name_map, trunk_reference)


def read_bvh_text(text: str, source: str = "<string>", name_map: Mapping[str, str] | None = None,
                  trunk_reference: str = "vertical") -> Recording:
    """:func:`load_bvh` on BVH text held in memory."""
    return recording_from_data(parse_bvh_text(text, source), name_map, trunk_reference)


def save_bvh(path: str | os.PathLike[str], angles: Mapping[str, np.ndarray | float], rate_hz: float,
             stature: float = 1.75) -> None:
    """Write canonical ``angles`` (name -> (n,) [deg]) at ``rate_hz`` [Hz] as a BVH file, atomically.

    The skeleton is :func:`~ergosim.worker.bvh_export.export_skeleton` (``stature`` [m]); the pelvis stays
    upright at hip height.
    ``load_bvh`` of the file gives the same angles within 1e-4 deg except at shoulder abduction = +-90 deg
    exactly, where flexion and rotation are not separable (the arm's orientation is still exact).
    """
    write_text(path, bvh_text(angles, rate_hz, stature))

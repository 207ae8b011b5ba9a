"""Stills of one planned worker action in its workcell: the worker at the part, mid-carry and at the target.

For pictures of how the worker moves (docs/worker.md): the action is planned from the scene as it is
(:class:`~ergosim.worker.motion.Worker`), the scene's human is posed at chosen moments, posture and stance,
and the part follows the hand rigidly from the grasp (the picture does not show the part turning in the
fingers). Each still is captioned with the moment's phase, stance and RULA grand score.
"""

from __future__ import annotations

import mujoco
import numpy as np
from PIL import Image, ImageDraw, ImageFont

from ergosim.human.model import body_qpos
from ergosim.quat import to_mat
from ergosim.scenes.render import render_workcell
from ergosim.scenes.workcell import Workcell
from ergosim.worker.ergonomics_tick import score_frames
from ergosim.worker.motion import ActionMotion

__all__ = ["action_moments", "render_action_stills"]


def _font(size: int) -> ImageFont.ImageFont:
    return ImageFont.load_default(size)


def action_moments(motion: ActionMotion) -> list[tuple[str, float]]:
    """(label, time [s]) of three moments: the hand at the part, halfway through the carry, at the target."""
    phase = {p.name: p for p in motion.phases}
    take = motion.phases[1]
    carry = phase["carry"]
    fit = motion.phases[3]
    return [("at the part", take.start), ("carrying", 0.5 * (carry.start + carry.end)),
            (f"{fit.name} (fitting)", fit.start + 1e-3)]


def _set_body(cell: Workcell, body: str, pos: np.ndarray, quat: np.ndarray) -> None:
    m, d = cell.model, cell.data
    qa = m.jnt_qposadr[m.body_jntadr[m.body(body).id]]
    d.qpos[qa:qa + 3] = pos
    d.qpos[qa + 3:qa + 7] = quat


def _moved(pose: tuple[np.ndarray, np.ndarray], frm: tuple[np.ndarray, np.ndarray],
           to: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """``pose`` carried rigidly with a frame going from ``frm`` to ``to`` (positions, wxyz quaternions)."""
    r_from, r_to = to_mat(frm[1]), to_mat(to[1])
    pos = to[0] + r_to @ (r_from.T @ (pose[0] - frm[0]))
    inv, rel, quat = np.empty(4), np.empty(4), np.empty(4)
    mujoco.mju_negQuat(inv, frm[1])
    mujoco.mju_mulQuat(rel, inv, pose[1])
    mujoco.mju_mulQuat(quat, to[1], rel)
    return pos, quat


def _pose_part(cell: Workcell, motion: ActionMotion, k: int, grasp_k: int, at_grasp: dict,
               target: str | None = None) -> None:
    """Put the part, with whatever is seated in it, where the hand carries it at frame ``k`` (rigidly since
    ``grasp_k``), or with the part on ``target``. ``at_grasp``: body -> pose of the assembly at the grasp."""
    part_pose = at_grasp[motion.part]
    if target is not None:
        to = cell.site_pose(target)
    elif k < grasp_k:
        return
    else:
        hand = cell.hand_bodies[f"human_{motion.side}"]
        h0 = cell.human.segment_pose_at(motion.angles[grasp_k], hand, motion.stances[grasp_k])
        hk = cell.human.segment_pose_at(motion.angles[k], hand, motion.stances[k])
        to = _moved(part_pose, h0, hk)
    for body, pose in at_grasp.items():
        _set_body(cell, body, *_moved(pose, part_pose, to))


def render_action_stills(cell: Workcell, motion: ActionMotion, target: str, *, view: str | None = None,
                         width: int = 480, height: int = 400, title: str = "",
                         camera: dict | None = None) -> np.ndarray:
    """(height + caption, 3 width, 3) uint8: ``motion`` (planned in ``cell`` as it is now) at the three
    :func:`action_moments`, side by side, each captioned; at the last one the part is on its ``target`` site
    (it may have turned in the hand on the way). ``camera``: azimuth, elevation, distance, lookat overriding
    the cell's ``view``."""
    at_grasp = {b: tuple(np.array(x) for x in cell.body_pose(b)) for b in cell.assembly(motion.part)}
    grasp_k = int(np.searchsorted(motion.t, motion.t_grasp))
    _, grand, _ = score_frames(motion.angles)
    tiles = []
    moments = action_moments(motion)
    for i, (label, t) in enumerate(moments):
        k = min(int(np.searchsorted(motion.t, t)), len(motion.t) - 1)
        cell.human.pose(cell.data, body_qpos(motion.angles[k], motion.stances[k]))
        _pose_part(cell, motion, k, grasp_k, at_grasp, target if i == len(moments) - 1 else None)
        mujoco.mj_kinematics(cell.model, cell.data)
        image = Image.fromarray(render_workcell(cell, width=width, height=height, view=view,
                                                **(camera or {})))
        x, y, turn, knee = motion.stances[k][:4]
        caption = (f"{label}  t = {motion.t[k]:.1f} s  RULA {grand[k]:.0f}\n"
                   f"step ({x:+.2f}, {y:+.2f}) m  turn {turn:+.0f}°  knees {knee:.0f}°")
        band = Image.new("RGB", (width, 44), (250, 250, 250))
        ImageDraw.Draw(band).multiline_text((8, 4), caption, fill=(20, 20, 20), font=_font(14))
        tile = Image.new("RGB", (width, height + 44))
        tile.paste(image, (0, 0))
        tile.paste(band, (0, height))
        tiles.append(tile)
    head = 30 if title else 0
    out = Image.new("RGB", (width * len(tiles), height + 44 + head), (255, 255, 255))
    if title:
        ImageDraw.Draw(out).text((8, 6), title, fill=(20, 20, 20), font=_font(16))
    for i, tile in enumerate(tiles):
        out.paste(tile, (i * width, head))
    return np.asarray(out)

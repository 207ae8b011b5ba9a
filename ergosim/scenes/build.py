"""Building blocks of every workcell: the empty scene, furniture, the robots, the human, the welds.

Every weld a run may need is declared here, inactive: one per (holder, part) and one per part seated in a
slot. :class:`~ergosim.scenes.workcell.Workcell` switches them on with the relative pose of that moment.
"""

from __future__ import annotations

import contextlib
import warnings
from collections.abc import Iterator

import mujoco
import numpy as np

from ergosim.held_signals import signals_held
from ergosim.human.mjcf import HOME_POSTURE
from ergosim.human.mocap import add_mocap_segments
from ergosim.human.model import HAND_SITES, ROOT_BODY, HumanModel, human_spec
from ergosim.quat import from_yaw_deg
from ergosim.robot.handle import RobotHandle
from ergosim.robot.model import compile_spec, robot_spec
from ergosim.robot.robot_model import RobotModel
from ergosim.scenes.cellspec import Worker
from ergosim.scenes.park import ParkChoice, ParkRule, choose_park, robot_geoms
from ergosim.scenes.surface import Surface, turned

__all__ = ["weld_name", "seat_name", "receive_name", "new_spec", "add_table", "add_box",
           "attach_robot", "attach_human", "add_welds", "human_hand_bodies", "finish", "quiet_attach"]

WOOD = (0.72, 0.6, 0.45, 1.0)
METAL = (0.45, 0.47, 0.5, 1.0)


def weld_name(holder: str, part: str) -> str:
    return f"hold_{holder}_{part}"


def seat_name(part: str) -> str:
    return f"seat_{part}"


def receive_name(part: str) -> str:
    """The weld by which a receiver outside the cell holds ``part`` (the handover kind)."""
    return f"receive_{part}"


@contextlib.contextmanager
def quiet_attach() -> Iterator[None]:
    """Attach with an empty prefix (names must stay canonical) without MuJoCo's save-related warning.

    MuJoCo calls the warning handler, a Python function, from its C++: Ctrl-C and SIGTERM are held
    meanwhile (:func:`~ergosim.held_signals.signals_held`), since a handler raising inside it would abort
    the process."""
    previous = mujoco.get_mju_user_warning()
    other: list[str] = []
    with signals_held():
        mujoco.set_mju_user_warning(lambda msg: None if "empty prefix" in msg else other.append(msg))
        try:
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", message="Attaching a spec with an empty prefix")
                yield
        finally:
            mujoco.set_mju_user_warning(previous)
    for msg in other:
        warnings.warn(f"MuJoCo: {msg}", RuntimeWarning, stacklevel=3)


def new_spec(name: str, timestep: float) -> mujoco.MjSpec:
    """An empty scene: options (physics step ``timestep`` [s]), floor, light, skybox."""
    spec = mujoco.MjSpec()
    spec.modelname = name
    spec.compiler.degree = False
    spec.option.timestep = timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    # Bodies at rest (parts on a table, a seated assembly) sleep: the sim steps 2-3x faster. Writing qpos, a
    # contact or a weld wakes them. (The human is mocap segments and the actuated robot never sleeps.)
    spec.option.enableflags |= mujoco.mjtEnableBit.mjENBL_SLEEP
    spec.stat.center = [0.5, 0.0, 1.0]
    spec.stat.extent = 2.0
    spec.visual.global_.offwidth = 1280
    spec.visual.global_.offheight = 960
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.6, 0.6, 0.6]
    spec.add_texture(name="skybox", type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
                     builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT, rgb1=[0.3, 0.5, 0.7], rgb2=[0, 0, 0],
                     width=512, height=3072)
    spec.add_texture(name="floor", type=mujoco.mjtTexture.mjTEXTURE_2D,
                     builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER, rgb1=[0.55, 0.55, 0.55],
                     rgb2=[0.5, 0.5, 0.5], width=300, height=300)
    mat = spec.add_material(name="floor", texrepeat=[6, 6], texuniform=True, reflectance=0.05)
    mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = "floor"
    spec.worldbody.add_light(name="top", pos=[0.5, 0, 3.0], dir=[0, 0, -1],
                             type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL)
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05],
                            material="floor")
    return spec


def add_box(spec: mujoco.MjSpec, name: str, center, half, rgba=METAL, yaw: float = 0.0) -> None:
    """A static box geom at ``center`` (3,) [m] with ``half`` sizes (3,) [m], turned by ``yaw`` [deg]
    about z."""
    turn = {} if yaw == 0.0 else {"quat": from_yaw_deg(yaw)}  # unturned: the model of old, bit for bit
    spec.worldbody.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_BOX, pos=list(center), size=list(half),
                            rgba=list(rgba), **turn)


def add_table(spec: mujoco.MjSpec, surface: Surface, thickness: float = 0.04, legs: bool = True,
              rgba=WOOD) -> None:
    """A slab whose top is at ``surface.height``, on four legs down to the floor, turned by the surface's
    yaw about its centre."""
    (cx, cy), (sx, sy), h, yaw = surface.center, surface.size, surface.height, surface.yaw
    add_box(spec, surface.name, (cx, cy, h - thickness / 2), (sx / 2, sy / 2, thickness / 2), rgba, yaw)
    if legs:
        leg_h = (h - thickness) / 2
        for i, (dx, dy) in enumerate([(1, 1), (1, -1), (-1, 1), (-1, -1)]):
            if yaw == 0.0:
                x, y = cx + dx * (sx / 2 - 0.03), cy + dy * (sy / 2 - 0.03)
            else:
                x, y = turned(surface.center, (dx * (sx / 2 - 0.03), dy * (sy / 2 - 0.03)), yaw)
            add_box(spec, f"{surface.name}_leg{i}", (x, y, leg_h), (0.02, 0.02, leg_h), yaw=yaw)


def attach_robot(spec: mujoco.MjSpec, robot: RobotModel, base, yaw: float, timestep: float,
                 support_height: float | None = None, prefix: str = "") -> None:
    """``robot``'s base body at ``base`` (3,) [m] turned by ``yaw`` [deg]; a pedestal (``robot.mount``) fills
    any gap down to ``support_height`` [m]. ``prefix`` goes before every name of this robot (a cell's second
    robot: ``robot2.``; the first keeps the MJCF's names, :func:`~ergosim.robot.handle.robot_prefix`)."""
    x, y, z = base
    mount = robot.mount
    if support_height is not None and z - support_height > 0.005:
        half = (z - support_height) / 2
        add_box(spec, f"{prefix}robot_pedestal", (x + mount.offset_x, y, support_height + half),
                (*mount.pedestal, half))
    frame = spec.worldbody.add_frame(name=f"{prefix}robot_base", pos=list(base), quat=from_yaw_deg(yaw))
    arm = robot_spec(robot)
    for key, blob in arm.assets.items():
        spec.assets[key] = blob
    arm.option.timestep = timestep  # the scene's options win; equal values avoid a conflict notice
    with quiet_attach():
        frame.attach_body(arm.body(robot.base), prefix, "")
    # the first link turns just above its mount: its hull would only ever graze the support it stands on
    spec.add_exclude(bodyname1="world", bodyname2=f"{prefix}{mount.link}")


def attach_human(spec: mujoco.MjSpec, worker: Worker) -> mujoco.MjModel:
    """Add the kinematic human standing at the worker position; return its articulated model.

    The articulated model (the 22 canonical joints, placed in the scene's world frame) is what motion capture
    drives; the scene gets one mocap body per segment, posed from it every frame
    (:class:`~ergosim.human.mocap.MocapHuman`), here at the ``home`` posture.
    """
    kin_spec = mujoco.MjSpec()
    kin_spec.modelname = "human_kinematics"
    kin_spec.compiler.degree = False
    frame = kin_spec.worldbody.add_frame(name="worker", pos=[*worker.xy, 0.0], quat=from_yaw_deg(worker.yaw))
    human = human_spec(worker.stature, dict(worker.human_scale), keyframe=None)
    with quiet_attach():
        frame.attach_body(human.body(ROOT_BODY), "", "")
        kin = compile_spec(kin_spec, where="human")
    data = mujoco.MjData(kin)
    HumanModel(kin).set_posture(data, HOME_POSTURE)
    add_mocap_segments(spec, kin, data)
    return kin


def add_welds(spec: mujoco.MjSpec, hand_bodies: dict[str, str], parts, seats, received=()) -> None:
    """Inactive welds holder -> part for every holder in ``hand_bodies`` and every part in ``parts``, then
    host -> part for every ``(host, part)`` of ``seats`` (a part seated in its slot), then world -> part for
    every part in ``received`` (taken by a receiver outside the cell)."""
    weld = dict(type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY, active=False,
                solref=[0.005, 1.0], solimp=[0.99, 0.999, 0.001, 0.5, 2])
    for holder, body in hand_bodies.items():
        for part in parts:
            spec.add_equality(name=weld_name(holder, part), name1=body, name2=part, **weld)
    for host, part in seats:
        spec.add_equality(name=seat_name(part), name1=host, name2=part, **weld)
    for part in received:
        spec.add_equality(name=receive_name(part), name1="world", name2=part, **weld)


def human_hand_bodies(spec: mujoco.MjSpec) -> dict[str, str]:
    out = {}
    for side, site in HAND_SITES.items():
        s = spec.site(site)
        if s is not None:
            out[f"human_{side}"] = s.parent.name
    return out


def finish(spec: mujoco.MjSpec, where: str, robots: tuple[tuple[str, str, RobotModel, float], ...] = ()
           ) -> tuple[mujoco.MjModel, dict[str, ParkChoice]]:
    """Replace attached keyframes by one ``home`` and compile: every robot of ``robots`` ((name, prefix,
    model, park clearance [m]) tuples) parked for the worker (:func:`~ergosim.scenes.park.choose_park`, in
    order, each seeing the ones before) with its fingers open; parts laid out; the human's mocap segments
    keep their home posture. Returns the model and each robot's park choice."""
    for key in list(spec.keys):
        spec.delete(key)
    key = spec.add_key(name="home")  # filled in the compiled model: one compile, not two
    with quiet_attach():
        model = compile_spec(spec, where=where)
    data = mujoco.MjData(model)
    qpos = model.qpos0.copy()
    ctrl = np.zeros(model.nu)
    handles = [(RobotHandle.find(model, name, prefix, kind), clearance)
               for name, prefix, kind, clearance in robots]
    for robot, _ in handles:
        qpos[robot.arm_qpos] = robot.robot.home
        for adr, j in zip(robot.finger_qpos, robot.finger_joints, strict=True):
            qpos[adr] = model.jnt_range[j][1]
    parks = {}
    for i, (robot, clearance) in enumerate(handles):
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        others = [g for other, _ in handles[:i] + handles[i + 1:] for g in robot_geoms(model, other.base)]
        ranges = model.jnt_range[[model.joint(robot.prefix + j).id for j in robot.robot.arm_joints]]
        park = choose_park(model, data, robot.arm_qpos, robot.base, robot.robot.home,
                           robot.robot.tuck or robot.robot.home, ranges[:, 0], ranges[:, 1],
                           ParkRule(clearance=clearance), others=others)
        parks[robot.name] = park
        qpos[robot.arm_qpos] = park.q
        ctrl[robot.arm_ctrl] = park.q
        ctrl[robot.grip_ctrl] = robot.gripper_open(model)
    model.key_qpos[0], model.key_ctrl[0] = qpos, ctrl
    key.qpos, key.ctrl = qpos.tolist(), ctrl.tolist()  # the spec (and a scene exported from it) says the same
    return model, parks


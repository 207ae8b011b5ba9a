"""The robot contract: what a robot brings to a workcell, registered once under the workcell's
``robot.model`` name.

A :class:`RobotModel` is a small declarative record (robosuite's ``ur5e_robot.py``, playground's
``*_constants.py``): where its model comes from and how its MJCF is built, its tool frame, its gripper and
the gripper's actuation, its limits, speeds, home pose and reach. Everything else in ergosim (scenes,
kinematics, skills, checks, drawing) reads a robot through this record, so adding a robot is one new module
that calls :func:`register_robot` (docs/robots.md).

Frames. The TCP frame (the MuJoCo site ``tcp_site`` and the pinocchio frame ``tcp_frame``, at the same
pose) sits at the grasp centre between the finger pads: +z points out of the gripper (the approach
direction of a top-down grasp), the fingers close along its y axis.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from ergosim.registry import Registry
from ergosim.robot.mjcf import MjcfRecipe
from ergosim.robot.urdf import Urdf

__all__ = ["Gripper", "Mount", "AddedFrame", "RobotModel", "ROBOTS", "register_robot", "robot_names",
           "get_robot", "default_robot"]


@dataclass(frozen=True)
class Gripper:
    """A parallel gripper: ``max_opening`` [m] the widest gap between its pads, ``force`` [N] its grip
    force, ``bodies`` its two finger bodies (MJCF names). Its joints and actuator are in the recipe."""

    max_opening: float
    force: float
    bodies: tuple[str, str]


@dataclass(frozen=True)
class Mount:
    """How the robot stands in a cell: ``link`` the first moving link (its hull is not checked against the
    support it turns on); ``pedestal`` (half x, half y) [m] of the pedestal box under the base, centred
    ``offset_x`` [m] behind the base (base frame x)."""

    link: str
    pedestal: tuple[float, float] = (0.13, 0.11)
    offset_x: float = -0.04


@dataclass(frozen=True)
class AddedFrame:
    """A frame the URDF lacks, added to the pinocchio model: ``name``, its ``parent`` frame, and its
    placement there: ``pos`` (3,) [m], ``quat`` (4,) wxyz."""

    name: str
    parent: str
    pos: tuple[float, float, float]
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class RobotModel:
    """Everything ergosim needs to know about one robot model.

    ``urdf``: the URDF in example-robot-data (relative to its ``share`` directory), read by pinocchio
    (kinematics) and, edited by ``edit_urdf`` (additions a URDF does not hold, e.g. finger joints), by the
    MJCF builder with ``recipe``; ``tcp_frame``: the pinocchio frame of the TCP, ``add_frames`` the frames
    added when the URDF lacks them; ``base``/``hand``: the base body and the body a held part is welded
    to; ``gripper``; ``payload`` [kg]; ``reach`` [m] from the base's first joint axis to the TCP;
    ``max_speed`` [m/s], ``max_rotation`` [rad/s], ``max_rotation_accel`` [rad/s^2] the controller's
    Cartesian limits; ``mount``; ``tuck`` (n,) [rad] a compact posture, the arm folded over its base with
    the tool down, towards which a park pose may fold (:mod:`ergosim.scenes.park`); ``source`` and
    ``licence`` for the model's README.
    """

    name: str
    description: str
    urdf: str
    recipe: MjcfRecipe
    tcp_frame: str
    base: str
    hand: str
    gripper: Gripper
    payload: float
    reach: float
    max_speed: float
    max_rotation: float
    max_rotation_accel: float
    mount: Mount
    tuck: tuple[float, ...] = ()
    add_frames: tuple[AddedFrame, ...] = ()
    edit_urdf: Callable[[Urdf], Urdf] | None = field(default=None, compare=False)
    source: str = ""
    licence: str = ""

    @property
    def arm_joints(self) -> tuple[str, ...]:
        return self.recipe.arm_joints

    @property
    def arm_actuators(self) -> tuple[str, ...]:
        return self.recipe.actuators

    @property
    def finger_joints(self) -> tuple[str, str]:
        return self.recipe.gripper.joints

    @property
    def gripper_actuator(self) -> str:
        return self.recipe.gripper.actuator

    @property
    def tcp_site(self) -> str:
        return self.recipe.sites[next(iter(self.recipe.sites))]

    @property
    def home(self) -> tuple[float, ...]:
        return self.recipe.home


ROBOTS: Registry[RobotModel] = Registry("robot model", where="robot.model")
"""The robot models by name (a workcell's ``robots.NAME.model``)."""


def register_robot(model: RobotModel) -> RobotModel:
    """Make ``model`` available as a workcell's ``robot.model`` (in worker processes too); returns it."""
    ROBOTS.register(model.name, model)
    return model


def robot_names() -> tuple[str, ...]:
    return ROBOTS.names()


def default_robot() -> str:
    """The model a workcell's robot is when its file names none: the first registered (``ergosim.robot``
    registers its bundled robots first, in the order it imports them)."""
    return ROBOTS.names()[0]


def get_robot(name: str) -> RobotModel:
    """The registered robot model ``name``; ConfigError naming the choices."""
    return ROBOTS.get(name)

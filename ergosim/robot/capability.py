"""Can a robot do an action? Its contract against the part, before any physics.

Three limits of a :class:`~ergosim.robot.robot_model.RobotModel` decide it: the gripper's opening against
the width the fingers close across (``Part.grip_width``), the payload against the mass carried (the part,
with whatever is seated in it when the action moves an assembly), and the reach (an inverse-kinematics
solution for the grasp and the target, decided by the caller). :func:`refusal` returns the reason in
words, or None when the robot can do it.
"""

from __future__ import annotations

from ergosim.robot.robot_model import RobotModel

__all__ = ["refusal", "OUT_OF_REACH"]


OUT_OF_REACH = "is out of its reach"
"""How a refusal for the robot's reach ends (the check before any physics tells it from the others)."""


def refusal(robot: RobotModel, action: str, part: str, grip_width: float, mass: float | None,
            reachable: bool = True, unreachable: str = "") -> str | None:
    """Why ``robot`` cannot do ``action`` (moving ``part``: ``grip_width`` [m] across the fingers, ``mass``
    [kg] carried, None if unknown), or None. ``reachable`` False with ``unreachable`` the pose it misses."""
    if grip_width > robot.gripper.max_opening:
        return (f"{robot.name} cannot do {action}: {part} is {grip_width * 1000:.0f} mm wide and the gripper "
                f"opens {robot.gripper.max_opening * 1000:.0f} mm")
    if mass is not None and mass > robot.payload:
        return (f"{robot.name} cannot do {action}: it carries {mass:.2f} kg ({part}) and its payload is "
                f"{robot.payload:g} kg")
    if not reachable:
        return f"{robot.name} cannot do {action}: {unreachable or part} {OUT_OF_REACH}"
    return None

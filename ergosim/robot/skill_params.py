"""What shapes a robot skill besides its robot and its cell: waypoint layout, gripper timing, pauses.

The robot brings its kinematics (joint limits, home pose), its gripper (opening, finger pads) and its speeds
(:class:`~ergosim.robot.trajectory.MotionLimits`); the cell brings the poses (grasp sites, targets, the
hand-over pose). These parameters are the rest: lengths [m], times [s], angles [rad].
"""

from __future__ import annotations

from dataclasses import dataclass

from ergosim.robot.trajectory import MotionLimits

__all__ = ["SkillParams"]


@dataclass(frozen=True)
class SkillParams:
    """Waypoint layout, gripper timing and pauses of the skills. Lengths [m], times [s], angles [rad].

    ``approach``: stand-off of the pre-grasp and pre-place poses along the approach direction, where the
    transits end; ``contact_margin``: added to the contact zone, the TCP distance from the grasp at which
    the fingertips first reach the part (:meth:`~ergosim.robot.skill_plan.CarryPlanner.contact_zone`),
    that runs at the contact speed at the end of an approach and the start of a lift-off or a retreat;
    ``insert_approach``: the insertion stroke, all at the contact speed; ``lift``: extra height of the
    carry above both stand-offs; ``finger_speed`` [m/s] per finger; ``grasp_pause``: the pause on the
    grasp before the fingers close; ``settle``: the pause after closing, after the carry, after opening and
    after the way home; ``handover_timeout``: how long a hand-over waits for the worker; ``place_drop``:
    release height above the target; ``drop_check_every`` [physics steps] between checks that the part is
    still in the hand; ``dip_tolerance``: a joint-space transit whose TCP dips more than this below both
    its ends is replaced by a straight line; ``wrist_turns`` [rad]: the extra IK seeds, the last joint wound
    by these; ``close_overshoot``: fingers this far past the part's faces have missed it; ``close_stall``:
    fingers closed this long without touching both sides have missed it."""

    limits: MotionLimits = MotionLimits()
    approach: float = 0.10  # assumed: clears the parts' 3-4 cm heights and the fingertips below the TCP
    contact_margin: float = 0.01  # assumed: 1 cm of contact-speed travel before the first possible touch
    insert_approach: float = 0.06  # assumed: a profile's 3 cm sleeve engagement twice over
    lift: float = 0.05  # assumed
    finger_speed: float = 0.05  # assumed: 0.1 m/s of opening, frankx's Gripper::max_speed for the Franka Hand
    grasp_pause: float = 0.1  # assumed: the arm comes to rest on the grasp before the fingers close
    settle: float = 0.25  # assumed
    handover_timeout: float = 30.0  # assumed: a worker who has not taken the part by then will not
    place_drop: float = 0.002  # assumed: 2 mm, the part is let go just above its rest, never pressed into it
    drop_check_every: int = 25  # assumed: ~0.1 s at the scenes' 240 Hz physics
    dip_tolerance: float = 0.05  # assumed: 5 cm below both ends of a transit keeps clear of the tables
    wrist_turns: tuple[float, ...] = (-1.0, 1.0, -2.0, 2.0)  # assumed: a sixth of a turn, then a third
    close_overshoot: float = 0.004  # assumed: 4 mm per finger past a face is no grasp
    close_stall: float = 0.3  # assumed: fingers at rest this long without touching both sides

"""Entity paths of a twin recording: each names what it holds.

===================================  ==================================================================
entity path                          content
===================================  ==================================================================
``world``                            view coordinates: right-handed, z up, metres
``world/<group>/<body>``             a MuJoCo body's world pose (Transform3D); group is one of GROUPS
``world/<group>/<body>/<shape>``     the body's visual geometry in the body frame (static)
``ergonomics/kwear/<joint>``         KWear V_i(t) per monitored joint (paper eq. 3), dimensionless
``ergonomics/kwear_threshold/<j>``   the threshold V_th,i of eq. 11, drawn over the logged time span
``ergonomics/rula/<part>``           RULA score per body part; ``ergonomics/rula/grand`` the grand score
``ergonomics/angles/<name>``         canonical joint angles (ergosim.posture.ANGLE_NAMES) [deg]
``allocation/log``                   one TextLog per allocation decision: "a2 → robot: ..."
``allocation/v_now/<joint>``         KWear V(t_k) at the decision
``allocation/v_hat/<action>/<j>``    predicted KWear V̂_i(t_k+1) if the worker did <action> (eq. 10)
``allocation/costs/<action>/<ag>``   hyper-arc cost of <action> by agent <ag> (eq. 11 for the human)
===================================  ==================================================================

Timelines: ``sim_time`` (duration, seconds of simulated time) and ``repetition`` (sequence).
"""

from __future__ import annotations

import rerun as rr

__all__ = [
    "GROUPS",
    "SIM_TIME",
    "REPETITION",
    "WORLD",
    "KWEAR",
    "KWEAR_THRESHOLD",
    "RULA",
    "ANGLES",
    "ALLOCATION_LOG",
    "V_NOW",
    "V_HAT",
    "COSTS",
    "body_entity",
    "join",
]

GROUPS = ("robot", "human", "parts", "scene")
"""Groups of bodies under ``world/``; body_groups maps body name -> one of these."""

SIM_TIME = "simulated time"
"""The timeline of simulated seconds; its name is as wide as the log column of its values ("+62.916 667s")."""
REPETITION = "repetition"

WORLD = "world"
KWEAR = "ergonomics/kwear"
KWEAR_THRESHOLD = "ergonomics/kwear_threshold"
RULA = "ergonomics/rula"
ANGLES = "ergonomics/angles"
ALLOCATION_LOG = "allocation/log"
V_NOW = "allocation/v_now"
V_HAT = "allocation/v_hat"
COSTS = "allocation/costs"


def join(*parts: str) -> str:
    """An entity path from a fixed prefix and free-form names (escaped, so '/' or ' ' in a name is safe)."""
    head, *names = parts
    return "/".join([head, *(rr.escape_entity_path_part(n) for n in names)])


def body_entity(group: str, body: str) -> str:
    """``world/<group>/<segment>``: the body name without a redundant ``<group>_`` prefix
    (``human_right_forearm`` -> ``world/human/right_forearm``)."""
    segment = body[len(group) + 1:] if body.startswith(f"{group}_") and len(body) > len(group) + 1 else body
    return join(WORLD, group, segment)

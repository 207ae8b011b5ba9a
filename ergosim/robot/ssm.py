"""Speed and separation monitoring (SSM) after ISO/TS 15066:2016 §5.5.4: how fast the robot may move at
a given distance from the worker.

The protective separation distance (ISO/TS 15066 eq. 1, with constant speeds over the reaction and
stopping times and a linear stop, B = v_r T_s / 2) is

    S_p(v_r) = v_h (T_r + T_s) + v_r T_r + v_r T_s / 2 + C + Z_d + Z_r,

where v_h is the worker's speed towards the robot, v_r the robot's, T_r the reaction time of the monitor
and controller, T_s the robot's stopping time, C the intrusion distance and Z_d, Z_r the position
uncertainties of the worker's and the robot's models. Keeping S_p(v_r) at most the measured separation S
gives the largest allowed robot speed

    v_max(S) = (S - v_h (T_r + T_s) - C - Z_d - Z_r) / (T_r + T_s / 2),

and the robot follows its planned motion scaled by min(1, v_max / v_r,nominal); below S_p(0) it stops
(a protective stop, resumed when the worker has moved away). Distances [m], speeds [m/s], times [s].
"""

from __future__ import annotations

import dataclasses
from typing import Literal

from ergosim.errors import ConfigError

__all__ = ["SSMParams", "SSM_MODES", "protective_distance", "allowed_speed", "speed_scale"]

SSM_MODES = ("auto", "on", "off")


@dataclasses.dataclass(frozen=True)
class SSMParams:
    """The speed and separation monitoring of a workcell (its ``[safety]`` table).

    ``ssm``: ``auto`` (on in parallel execution, off in the paper's sequential one, where the worker rests
    while the robot moves), ``on`` or ``off``. The other fields are the terms of ISO/TS 15066 eq. 1."""

    ssm: Literal["auto", "on", "off"] = "auto"
    human_speed: float = 1.6
    """v_h [m/s] when the worker's speed is not measured: ISO 13855:2010 §6.2, K = 1600 mm/s."""
    measured_speed: bool = True
    """Use the tracked worker's speed towards the robot (the nearest segment's, from motion capture) for v_h,
    as ISO/TS 15066 §5.5.4.2.3 allows when the operator's speed is monitored; False: ``human_speed``."""
    reaction_time: float = 0.1
    """T_r [s]: sensing, monitoring and the controller's reaction. Assumed (a 60 Hz tracker, one frame of
    latency, and the robot controller's cycle)."""
    stopping_time: float = 0.3
    """T_s [s]: the robot's stopping time at the speeds used here (<= 0.25 m/s). Assumed: a category-1
    stop of a 7-axis collaborative arm at reduced speed."""
    intrusion: float = 0.05
    """C [m]: how far a body part may reach past its tracked model. Assumed: the fit of the capsule body
    model to a real arm and hand."""
    human_uncertainty: float = 0.02
    """Z_d [m]: position uncertainty of the tracked worker. Assumed: inertial motion capture segment error."""
    robot_uncertainty: float = 0.01
    """Z_r [m]: position uncertainty of the robot, including its capsule model. Assumed."""

    def validate(self, where: str) -> None:
        if self.ssm not in SSM_MODES:
            raise ConfigError(f"ssm must be one of {', '.join(SSM_MODES)}, got {self.ssm!r}", where=where)
        for name in ("human_speed", "reaction_time", "stopping_time", "intrusion", "human_uncertainty",
                     "robot_uncertainty"):
            if getattr(self, name) < 0:
                raise ConfigError(f"{name} must be >= 0, got {getattr(self, name)}", where=where)
        if self.reaction_time + self.stopping_time <= 0:
            raise ConfigError("reaction_time + stopping_time must be > 0 s", where=where)

    def enabled(self, execution: str) -> bool:
        """Whether the robot's speed is scaled in an ``execution`` ("sequential" or "parallel") run."""
        return self.ssm == "on" or (self.ssm == "auto" and execution == "parallel")

    @property
    def margin(self) -> float:
        """C + Z_d + Z_r [m]: the separation kept even with both at rest."""
        return self.intrusion + self.human_uncertainty + self.robot_uncertainty


def protective_distance(params: SSMParams, v_human: float, v_robot: float) -> float:
    """S_p [m] of ISO/TS 15066 eq. 1 for the worker's speed ``v_human`` and the robot's ``v_robot`` [m/s]."""
    t_r, t_s = params.reaction_time, params.stopping_time
    return v_human * (t_r + t_s) + v_robot * (t_r + t_s / 2) + params.margin


def allowed_speed(params: SSMParams, separation: float, v_human: float) -> float:
    """The largest robot speed [m/s] that keeps S_p at most ``separation`` [m]; 0 below S_p(0)."""
    t_r, t_s = params.reaction_time, params.stopping_time
    free = separation - v_human * (t_r + t_s) - params.margin
    return max(0.0, free / (t_r + t_s / 2))


def speed_scale(params: SSMParams, separation: float, v_human: float, v_nominal: float) -> float:
    """The factor in [0, 1] applied to the robot's planned motion whose nominal speed is ``v_nominal``."""
    if v_nominal <= 0:
        return 1.0
    return min(1.0, allowed_speed(params, separation, v_human) / v_nominal)

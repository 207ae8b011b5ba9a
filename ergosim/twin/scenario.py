"""Scenarios: a task, a workcell and a protocol, read from a scenario file (docs/workcell_format.md).

A scenario file names its task (a bundled task, a task file, or an inline ``[task]`` table), its workcell
(a bundled workcell, a workcell file, or an inline ``[workcell]`` table) and its ``[protocol]``: subjects,
repetitions, takt, modes, the cost parameters, rates, planner and calibration settings (the fields of
:class:`ScenarioConfig`). The paper's two experiments are bundled scenario files, run by name; any other
runs by path. Overrides (``--set``) address a protocol field by name (``takt=40``, or ``protocol.takt``)
and a workcell field by ``scene.`` or ``workcell.`` and its dotted path or alias (``scene.l_xy=0.2,0.8``,
``workcell.parts.L.yaw=0``).
"""

from __future__ import annotations

import dataclasses
from typing import Literal

from ergosim.errors import ConfigError
from ergosim.planner.tie_break import TIE_RULES
from ergosim.robot.trajectory import CONTACT_SPEED, TRANSIT_SPEED
from ergosim.twin.modes import mode_names

__all__ = ["ScenarioConfig", "EE_SPEED_MAX", "ETA_MAX_LIMIT", "TEAM_FIELDS"]

EE_SPEED_MAX = 1.7
"""Largest end-effector speed [m/s]: the Franka Emika Panda's Cartesian translation limit (Franka Control
Interface documentation, "Limits for Panda": 1.7 m/s)."""
ETA_MAX_LIMIT = 50
"""Largest eta_max (calibration passes, §5). Assumed: each pass performs every action once (about a minute
of simulated work), so 50 passes already take minutes of wall time per subject; the paper's η stay < 10."""


@dataclasses.dataclass(frozen=True)
class ScenarioConfig:
    """The protocol of one scenario. Times in seconds, rates in Hz, costs dimensionless. ``scene`` and
    ``task`` are labels (the workcell's name, the task file's name) for the outputs."""

    scene: str
    task: str
    subjects: int
    repetitions: int
    modes: tuple[str, ...]
    robot_cost: float
    """c_{h,w_r}: the constant cost of every robot hyper-arc (paper §4)."""
    takt: float = 38.0
    takt_paced: bool = False
    """Every repetition starts at its takt slot, in every mode (a paced line); False: only modes that wait
    for the takt (h-only) do, the others start the next repetition at once."""
    gamma: float = 100.0
    """Γ: penalty added to γ_i when V̂_i ≥ V_th (eq. 11)."""
    v_th: float = 0.8
    """V_th,i for every monitored joint (80 % of the KWear range, paper §7.1)."""
    rula_g_max: float = 9.0
    """G_max of the static RULA baseline; the paper takes 9, the top of Table A (§7.1)."""
    rula_threshold_fraction: float = 0.8
    ergonomics_rate: float = 20.0
    mocap_rate: float = 60.0
    physics_dt: float = 1.0 / 240.0
    """Nominal physics step [s]; the loop uses mocap period / round(mocap period / physics_dt)."""
    ee_speed: float = CONTACT_SPEED
    """Robot TCP speed of contact-critical motion [m/s] (approach, grasp, lift-off, place, insertion,
    retreat, the final approach into the handover pose); the paper's conservative 0.05 m/s (§7.2)."""
    transit_speed: float = TRANSIT_SPEED
    """Robot TCP speed of free-space transits [m/s]; ISO 10218-1:2011 §5.6 reduced speed (<= 0.25 m/s),
    at least ee_speed and at most EE_SPEED_MAX."""
    eta0: int = 2
    eta_max: int = 10
    v_des: float = 1e-3
    """Ṽ_des: target maximum KWear prediction error of the calibration (§5)."""
    online_alpha_weight: float = 0.0
    """Weight of the latest execution in the online α average (§5); 0 keeps the calibrated α."""
    noise_scale: float = 1.0
    """Multiplier of each subject's sensor noise (drifting bias and white noise): 0 none, 1 the subject's."""
    dropout_rate: float = 0.0
    planner: Literal["fast", "paper"] = "fast"
    tie_break: Literal["costliest-first", "task-order", "cheapest-first"] = "costliest-first"
    """Which ready action of an optimal plan goes first when plans of equal cost differ only in their order
    (ergosim.planner.tie_break): ``costliest-first`` is what the paper's Algorithm 1 returns."""
    female_fraction: float = 2.0 / 12.0
    """Share of women among the synthetic subjects: §7.2's cohort, "2 females and 10 males"."""
    pace: float = 1.0
    """Mean pace of the subjects: 1 = MTM-1 standard performance (ergosim.worker.action_timing)."""
    execution: Literal["sequential", "parallel"] = "sequential"
    """How the team works: ``sequential``, one action at a time (the paper's Algorithm 2); ``parallel``,
    every idle agent starts the best operation ready now (ergosim.twin.team_session)."""
    w_time: float = 0.0
    """Weight of the time term [cost per s]: w_time × the expected duration of the (action, agent) is added
    to its hyper-arcs (ergosim.twin.durations); 0 keeps the paper's cost (eq. 10-11)."""
    team_margin: float | None = None
    """Parallel execution: an idle agent does not start an operation whose cheapest plan costs at least this
    much more than the optimal plan (it leaves it to the agent that plan chose); None: Γ for modes with a
    threshold penalty, no limit for the others."""
    negotiation: bool = False
    """The worker may refuse an assignment (ergosim.worker.refusal); false keeps the paper's worker."""
    refusal_tolerance: float = 0.65
    """Mean over subjects of τ, the predicted KWear (most-loaded joint) at which a worker refuses half the
    time. Assumed."""
    refusal_tolerance_sd: float = 0.08
    """Standard deviation of τ between subjects. Assumed."""
    refusal_slope: float = 0.05
    """s of the logistic refusal curve, in KWear units. Assumed."""

    def validate(self, where: str = "scenario") -> None:
        def need(ok: bool, msg: str) -> None:
            if not ok:
                raise ConfigError(msg, where=where)

        need(self.subjects >= 1, f"subjects must be >= 1, got {self.subjects}")
        need(self.repetitions >= 1, f"repetitions must be >= 1, got {self.repetitions}")
        need(self.takt > 0, f"takt must be > 0 s, got {self.takt}")
        need(all(m in mode_names() for m in self.modes) and len(self.modes) > 0,
             f"modes must be among {', '.join(mode_names())}, got {','.join(self.modes)}")
        need(self.robot_cost > 0, f"robot_cost must be > 0, got {self.robot_cost}")
        need(self.gamma > 0, f"gamma must be > 0, got {self.gamma}")
        need(0 < self.v_th < 1, f"v_th must be in (0, 1), got {self.v_th}")
        need(self.mocap_rate > 0 and self.ergonomics_rate > 0, "rates must be > 0 Hz")
        ratio = self.mocap_rate / self.ergonomics_rate
        need(abs(ratio - round(ratio)) < 1e-9 and ratio >= 1,
             f"mocap_rate ({self.mocap_rate} Hz) must be a whole multiple of ergonomics_rate "
             f"({self.ergonomics_rate} Hz)")
        need(0 < self.physics_dt <= 1 / self.mocap_rate,
             f"physics_dt must be in (0, 1/mocap_rate], got {self.physics_dt}")
        need(0 < self.ee_speed <= EE_SPEED_MAX,
             f"ee_speed must be in (0, {EE_SPEED_MAX}] m/s (the Panda's Cartesian limit), "
             f"got {self.ee_speed}")
        need(0 < self.transit_speed <= EE_SPEED_MAX,
             f"transit_speed must be in (0, {EE_SPEED_MAX}] m/s (the Panda's Cartesian limit), "
             f"got {self.transit_speed}")
        need(self.ee_speed <= self.transit_speed,
             f"ee_speed ({self.ee_speed} m/s, contact-critical motion) must not exceed transit_speed "
             f"({self.transit_speed} m/s, free-space motion)")
        need(2 <= self.eta0 <= self.eta_max, f"need 2 <= eta0 <= eta_max, got {self.eta0}, {self.eta_max}")
        need(self.eta_max <= ETA_MAX_LIMIT, f"eta_max must be <= {ETA_MAX_LIMIT} calibration passes, "
             f"got {self.eta_max}")
        need(self.v_des > 0, f"v_des must be > 0, got {self.v_des}")
        need(0 <= self.online_alpha_weight <= 1, "online_alpha_weight must be in [0, 1]")
        need(self.noise_scale >= 0, "noise_scale must be >= 0")
        need(0 <= self.dropout_rate < 1, "dropout_rate must be in [0, 1)")
        need(0 < self.rula_threshold_fraction <= 1, "rula_threshold_fraction must be in (0, 1]")
        need(0 <= self.female_fraction <= 1, f"female_fraction must be in [0, 1], got {self.female_fraction}")
        need(0.1 <= self.pace <= 2.0, f"pace must be in [0.1, 2] (1 = MTM-1 standard performance), "
             f"got {self.pace}")
        need(self.tie_break in TIE_RULES, f"tie_break must be one of {', '.join(TIE_RULES)}, "
             f"got {self.tie_break!r}")
        need(self.execution in ("sequential", "parallel"),
             f"execution must be sequential or parallel, got {self.execution!r}")
        need(self.w_time >= 0, f"w_time must be >= 0 (cost per second), got {self.w_time}")
        need(self.team_margin is None or self.team_margin > 0,
             f"team_margin must be > 0 or none, got {self.team_margin}")
        need(0 < self.refusal_tolerance < 1,
             f"refusal_tolerance must be in (0, 1), got {self.refusal_tolerance}")
        need(self.refusal_tolerance_sd >= 0, f"refusal_tolerance_sd must be >= 0, got "
             f"{self.refusal_tolerance_sd}")
        need(self.refusal_slope > 0, f"refusal_slope must be > 0, got {self.refusal_slope}")

    def record(self) -> dict:
        """The protocol as the outputs record it (``summary.json`` ``config``, ``run.json``): every field,
        except the team-execution fields (:data:`TEAM_FIELDS`) while they keep their defaults, so a paper
        protocol's outputs stay as they were."""
        out = dict(vars(self))
        defaults = {f.name: f.default for f in dataclasses.fields(self) if f.name in TEAM_FIELDS}
        if all(out[k] == v for k, v in defaults.items()):
            for k in TEAM_FIELDS:
                out.pop(k)
        return out

    def team_settings(self) -> dict:
        """The team-execution fields and their values (``team.json``)."""
        return {k: getattr(self, k) for k in TEAM_FIELDS}

    @property
    def rula_threshold(self) -> float:
        """G_th = fraction × G_max (7.2 with the paper's values)."""
        return self.rula_threshold_fraction * self.rula_g_max


TEAM_FIELDS = ("execution", "w_time", "team_margin", "negotiation", "refusal_tolerance",
               "refusal_tolerance_sd", "refusal_slope")
"""The protocol fields of team execution (issue 17)."""

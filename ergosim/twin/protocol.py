"""What one session of the twin runs by: grouped, frozen configs (mujoco_playground's ``default_config()``).

A scenario file's ``[protocol]`` table (docs/workcell_format.md) and ``--set`` address every field by its
own flat name (``takt = 40``, ``--set v_th=0.7``); the fields live in groups by what they shape:

- :class:`CostConfig`, ``cost``: the hyper-arc costs (paper §4, eq. 10-11) and the static RULA and REBA
  baselines;
- :class:`RobotConfig`, ``robot``: the robot's TCP speeds;
- :class:`PacingConfig`, ``pacing``: the repetitions, the takt and who paces the line;
- :class:`TeamConfig`, ``team``: team execution and negotiation (issue 17);
- :class:`SensingConfig`, ``sensing``: the clocks and the mocap stream;
- :class:`CalibrationConfig`, ``calibration``: the calibration of α (§5);
- :class:`LookaheadConfig`, ``lookahead``: the ``kwear-lookahead`` mode's prices and search (issue 24).

:class:`SessionConfig` holds the groups with the planner and its tie rule: everything one session needs
(:mod:`ergosim.twin.rig` builds it). The experiment's protocol adds the scenario's labels, its modes and
its population (:class:`ergosim.experiment.protocol.ScenarioConfig`).
"""

from __future__ import annotations

import dataclasses
from typing import Literal

from ergosim.ergonomics.cost import CostParams, rula_baseline_params
from ergosim.errors import ConfigError
from ergosim.planner.tie_break import TIE_RULES
from ergosim.robot.trajectory import CONTACT_SPEED, TRANSIT_SPEED

__all__ = ["SessionConfig", "CostConfig", "RobotConfig", "PacingConfig", "TeamConfig", "SensingConfig",
           "CalibrationConfig", "LookaheadConfig", "EE_SPEED_MIN", "ETA_MAX_LIMIT", "PHYSICS_DT_MIN",
           "TAKT_MAX", "HORIZON_MAX", "W_TIME_MAX"]

ETA_MAX_LIMIT = 50
"""Largest eta_max (calibration passes, §5). Assumed: each pass performs every action once (about a minute
of simulated work), so 50 passes already take minutes of wall time per subject; the paper's η stay < 10."""
EE_SPEED_MIN = 1e-3
"""Slowest contact-critical TCP speed [m/s] (assumed): at 1 mm/s a few centimetres of approach already take
a minute, and a planned motion holds a joint target per physics step."""
PHYSICS_DT_MIN = 1e-4
"""Finest physics step [s] (assumed: 10 kHz, ten times the Panda's 1 kHz control rate; the default is
1/240 s). A finer one makes every simulated second cost tens of thousands of steps."""
TAKT_MAX = 3600.0
"""Longest takt [s] (assumed: a cycle of an hour is no longer a takt-timed line). The twin simulates the
rest until each repetition's takt slot."""
HORIZON_MAX = 86_400.0
"""Longest schedule, repetitions × takt [s] (a day); the run simulates all of it, rests included."""
W_TIME_MAX = 1e6
"""Largest weight of the time term [cost per second] (assumed: the other costs are of order 1, so at 10^6 time
already decides every choice; far larger weights overflow the costs)."""
def _need(ok: bool, msg: str, where: str) -> None:
    if not ok:
        raise ConfigError(msg, where=where)


@dataclasses.dataclass(frozen=True)
class CostConfig:
    """The hyper-arc costs (paper §4, eq. 10-11), the static RULA baseline (§7.1) and the static REBA
    baseline; dimensionless."""

    robot_cost: float = 1.0
    """c_{h,w_r}: the constant cost of every robot hyper-arc (paper §4); a scenario file must give it."""
    gamma: float = 100.0
    """Γ: penalty added to γ_i when V̂_i ≥ V_th (eq. 11)."""
    v_th: float = 0.8
    """V_th,i for every monitored joint (80 % of the KWear range, paper §7.1)."""
    rula_g_max: float = 9.0
    """G_max of the static RULA baseline; the paper takes 9, the top of Table A (§7.1)."""
    rula_threshold_fraction: float = 0.8
    reba_threshold: float = 8.0
    """G_th of the static REBA baseline (mode ``reba``): an action goes to the robot when its REBA score
    G(a_k) reaches it; 8, the first score of REBA's "high risk" band (action necessary soon, Hignett &
    McAtamney 2000). Its G_max is 15, the top REBA score."""

    @property
    def rula_threshold(self) -> float:
        """G_th = fraction × G_max (7.2 with the paper's values)."""
        return self.rula_threshold_fraction * self.rula_g_max

    def params(self, v_max: float) -> CostParams:
        """The cost model's constants (eq. 10-11) for a risk index whose largest value is ``v_max``."""
        return CostParams(gamma=self.gamma, v_th=self.v_th, robot_cost=self.robot_cost, v_max=v_max)

    def rula_params(self) -> CostParams:
        """The cost model's constants for the static RULA baseline (risk G / G_max, §7.1)."""
        return rula_baseline_params(self.robot_cost, self.gamma, g_th=self.rula_threshold,
                                    g_max=self.rula_g_max)

    def reba_params(self, g_max: float) -> CostParams:
        """The cost model's constants for the static REBA baseline (risk G / ``g_max``)."""
        return rula_baseline_params(self.robot_cost, self.gamma, g_th=self.reba_threshold, g_max=g_max)

    def validate(self, where: str) -> None:
        _need(self.robot_cost > 0, f"robot_cost must be > 0, got {self.robot_cost}", where)
        _need(self.gamma > 0, f"gamma must be > 0, got {self.gamma}", where)
        _need(0 < self.v_th < 1, f"v_th must be in (0, 1), got {self.v_th}", where)
        _need(0 < self.rula_threshold_fraction <= 1, "rula_threshold_fraction must be in (0, 1]", where)
        _need(1 <= self.reba_threshold <= 15, f"reba_threshold must be a REBA score in [1, 15], got "
              f"{self.reba_threshold}", where)


@dataclasses.dataclass(frozen=True)
class RobotConfig:
    """The robot's TCP speeds [m/s]."""

    ee_speed: float = CONTACT_SPEED
    """Contact-critical motion (approach, grasp, lift-off, place, insertion, retreat, the final approach into
    the handover pose); the paper's conservative 0.05 m/s (§7.2)."""
    transit_speed: float = TRANSIT_SPEED
    """Free-space transits; ISO 10218-1:2011 §5.6 reduced speed (<= 0.25 m/s), at least ee_speed and at most
    the cell's robots' Cartesian limit (``RobotModel.max_speed``, checked with the workcell)."""

    def validate(self, where: str) -> None:
        # the upper bound is each robot's Cartesian limit, checked against the cell's robots
        _need(self.ee_speed >= EE_SPEED_MIN, f"ee_speed must be at least {EE_SPEED_MIN:g} m/s, got "
              f"{self.ee_speed:g}", where)
        _need(self.transit_speed >= EE_SPEED_MIN, f"transit_speed must be at least {EE_SPEED_MIN:g} m/s, got "
              f"{self.transit_speed:g}", where)
        _need(self.ee_speed <= self.transit_speed, f"ee_speed ({self.ee_speed} m/s, contact-critical motion) "
              f"must not exceed transit_speed ({self.transit_speed} m/s, free-space motion)", where)


@dataclasses.dataclass(frozen=True)
class PacingConfig:
    """The production schedule: ``repetitions`` at ``takt`` [s] each, and who paces the line."""

    repetitions: int = 1
    takt: float = 38.0
    takt_paced: bool = False
    """Every repetition starts at its takt slot, in every mode (a paced line); False: only modes that wait
    for the takt (h-only) do, the others start the next repetition at once."""

    @property
    def horizon(self) -> float:
        """The length of the production schedule, repetitions × takt [s]."""
        return self.repetitions * self.takt

    def validate(self, where: str) -> None:
        _need(self.repetitions >= 1, f"repetitions must be >= 1, got {self.repetitions}", where)
        _need(0 < self.takt <= TAKT_MAX, f"takt must be in (0, {TAKT_MAX:g}] s, got {self.takt:g}", where)
        _need(self.horizon <= HORIZON_MAX, f"repetitions × takt must be at most {HORIZON_MAX:g} s (a day, "
              f"simulated rests included), got {self.repetitions} × {self.takt:g} s", where)


@dataclasses.dataclass(frozen=True)
class TeamConfig:
    """Team execution (issue 17): how the agents share the work, and whether the worker may refuse."""

    execution: Literal["sequential", "parallel"] = "sequential"
    """``sequential``, one action at a time (the paper's Algorithm 2); ``parallel``, every idle agent starts
    the best operation ready now (ergosim.twin.team_session)."""
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

    def validate(self, where: str) -> None:
        _need(self.execution in ("sequential", "parallel"),
              f"execution must be sequential or parallel, got {self.execution!r}", where)
        _need(0 <= self.w_time <= W_TIME_MAX, f"w_time must be in [0, {W_TIME_MAX:g}] (cost per second), got "
              f"{self.w_time:g}", where)
        _need(self.team_margin is None or self.team_margin > 0,
              f"team_margin must be > 0 or none, got {self.team_margin}", where)
        _need(0 < self.refusal_tolerance < 1, f"refusal_tolerance must be in (0, 1), got "
              f"{self.refusal_tolerance}", where)
        _need(self.refusal_tolerance_sd >= 0, f"refusal_tolerance_sd must be >= 0, got "
              f"{self.refusal_tolerance_sd}", where)
        _need(self.refusal_slope > 0, f"refusal_slope must be > 0, got {self.refusal_slope}", where)


@dataclasses.dataclass(frozen=True)
class SensingConfig:
    """The twin's clocks [Hz, s] and the mocap stream's imperfections."""

    ergonomics_rate: float = 20.0
    mocap_rate: float = 60.0
    physics_dt: float = 1.0 / 240.0
    """Nominal physics step [s]; the loop uses mocap period / round(mocap period / physics_dt)."""
    noise_scale: float = 1.0
    """Multiplier of each subject's sensor noise (drifting bias and white noise): 0 none, 1 the subject's."""
    dropout_rate: float = 0.0

    def validate(self, where: str) -> None:
        _need(self.mocap_rate > 0 and self.ergonomics_rate > 0, "rates must be > 0 Hz", where)
        ratio = self.mocap_rate / self.ergonomics_rate
        _need(abs(ratio - round(ratio)) < 1e-9 and ratio >= 1, f"mocap_rate ({self.mocap_rate} Hz) must be a "
              f"whole multiple of ergonomics_rate ({self.ergonomics_rate} Hz)", where)
        _need(PHYSICS_DT_MIN <= self.physics_dt <= 1 / self.mocap_rate,
              f"physics_dt must be in [{PHYSICS_DT_MIN:g}, 1/mocap_rate] s, got {self.physics_dt:g}", where)
        _need(self.noise_scale >= 0, "noise_scale must be >= 0", where)
        _need(0 <= self.dropout_rate < 1, "dropout_rate must be in [0, 1)", where)


@dataclasses.dataclass(frozen=True)
class CalibrationConfig:
    """The calibration of α with the adaptive η (paper §5)."""

    eta0: int = 2
    eta_max: int = 10
    v_des: float = 1e-3
    """Ṽ_des: target maximum KWear prediction error of the calibration (§5)."""
    online_alpha_weight: float = 0.0
    """Weight of the latest execution in the online α average (§5); 0 keeps the calibrated α."""

    def validate(self, where: str) -> None:
        _need(2 <= self.eta0 <= self.eta_max, f"need 2 <= eta0 <= eta_max, got {self.eta0}, {self.eta_max}",
              where)
        _need(self.eta_max <= ETA_MAX_LIMIT, f"eta_max must be <= {ETA_MAX_LIMIT} calibration passes, got "
              f"{self.eta_max}", where)
        _need(self.v_des > 0, f"v_des must be > 0, got {self.v_des}", where)
        _need(0 <= self.online_alpha_weight <= 1, "online_alpha_weight must be in [0, 1]", where)


@dataclasses.dataclass(frozen=True)
class LookaheadConfig:
    """The ``kwear-lookahead`` mode (issue 24): what its plans' time costs and how it searches
    (:mod:`ergosim.planner.lookahead`, :mod:`ergosim.twin.lookahead_allocator`)."""

    takt_weight: float | None = None
    """Cost per second by which a plan's predicted end passes the takt; None: Γ/takt (assumed: a whole takt
    of overrun costs as much as one joint past V_th, eq. 11)."""
    time_weight: float | None = None
    """Cost per second of a plan's predicted duration (its makespan, the critical path, in parallel
    execution); None: 0 in sequential execution (the paper's form: time within the takt is free on a paced
    line) and ``takt_weight`` in parallel (a parallel team exists to shorten the cycle: a second of makespan
    costs what a second past the takt costs; ergosim.twin.lookahead_allocator.PARALLEL_TIME_SHARE, and the
    sweep in docs/allocation_modes.md)."""
    lookahead_next: float = 1.0
    """Weight of the wear a plan leaves, priced as the next repetition would see it
    (ergosim.planner.wear_chain.next_cost); 0 ends the plan with its repetition."""
    lookahead_exact: int = 20_000
    """Search exactly when the remaining plan has at most this many sequences (orders × agents; assumed:
    every bundled task, the gearbox has 768; ergosim.planner.lookahead)."""
    lookahead_beam: int = 6
    """The beam's width otherwise (assumed; decision time in docs/allocation_modes.md,
    scripts/bench_planner.py --lookahead)."""

    def validate(self, where: str) -> None:
        _need(self.takt_weight is None or self.takt_weight >= 0,
              f"takt_weight must be >= 0 (cost per second past the takt) or none, got {self.takt_weight}",
              where)
        _need(self.time_weight is None or self.time_weight >= 0,
              f"time_weight must be >= 0 (cost per second) or none, got {self.time_weight}", where)
        _need(self.lookahead_next >= 0, f"lookahead_next must be >= 0, got {self.lookahead_next}", where)
        _need(self.lookahead_exact >= 0,
              f"lookahead_exact must be >= 0 sequences, got {self.lookahead_exact}", where)
        _need(self.lookahead_beam >= 1, f"lookahead_beam must be >= 1, got {self.lookahead_beam}", where)


@dataclasses.dataclass(frozen=True)
class SessionConfig:
    """What one session runs by. ``planner``: ``fast`` (bottom-up) or ``paper`` (Algorithm 1);
    ``tie_break``: which ready action of an optimal plan goes first when plans of equal cost differ only in
    their order (:mod:`ergosim.planner.tie_break`; ``costliest-first`` is what the paper's Algorithm 1
    returns). Every other field is in its group."""

    planner: Literal["fast", "paper"] = "fast"
    tie_break: Literal["costliest-first", "task-order", "cheapest-first"] = "costliest-first"
    cost: CostConfig = CostConfig()
    robot: RobotConfig = RobotConfig()
    pacing: PacingConfig = PacingConfig()
    team: TeamConfig = TeamConfig()
    sensing: SensingConfig = SensingConfig()
    calibration: CalibrationConfig = CalibrationConfig()
    lookahead: LookaheadConfig = LookaheadConfig()

    def validate(self, where: str = "scenario") -> None:
        self.pacing.validate(where)
        _need(self.tie_break in TIE_RULES, f"tie_break must be one of {', '.join(TIE_RULES)}, got "
             f"{self.tie_break!r}", where)
        self.cost.validate(where)
        self.sensing.validate(where)
        self.robot.validate(where)
        self.calibration.validate(where)
        self.team.validate(where)
        self.lookahead.validate(where)

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
from ergosim.machine import physical_memory
from ergosim.robot.trajectory import CONTACT_SPEED, TRANSIT_SPEED
from ergosim.twin.modes import mode_names

__all__ = ["ScenarioConfig", "EE_SPEED_MAX", "EE_SPEED_MIN", "ETA_MAX_LIMIT", "TEAM_FIELDS", "PHYSICS_DT_MIN",
           "TAKT_MAX", "HORIZON_MAX", "SUBJECTS_MAX", "W_TIME_MAX", "run_memory"]

EE_SPEED_MAX = 1.7
"""Largest end-effector speed [m/s]: the Franka Emika Panda's Cartesian translation limit (Franka Control
Interface documentation, "Limits for Panda": 1.7 m/s)."""
ETA_MAX_LIMIT = 50
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
SUBJECTS_MAX = 10_000
"""Most subjects of one run (a study has tens; each keeps its records in memory until the run ends)."""
_TICK_BYTES_PER_COLUMN = 2 * 8
"""Memory per logged tick and column [bytes]: a float64, in a log that grows by doubling."""
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

        need(1 <= self.subjects <= SUBJECTS_MAX,
             f"subjects must be in 1..{SUBJECTS_MAX}, got {self.subjects}")
        need(self.repetitions >= 1, f"repetitions must be >= 1, got {self.repetitions}")
        need(0 < self.takt <= TAKT_MAX, f"takt must be in (0, {TAKT_MAX:g}] s, got {self.takt:g}")
        need(self.repetitions * self.takt <= HORIZON_MAX,
             f"repetitions × takt must be at most {HORIZON_MAX:g} s (a day, simulated rests included), got "
             f"{self.repetitions} × {self.takt:g} s")
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
        need(PHYSICS_DT_MIN <= self.physics_dt <= 1 / self.mocap_rate,
             f"physics_dt must be in [{PHYSICS_DT_MIN:g}, 1/mocap_rate] s, got {self.physics_dt:g}")
        need(EE_SPEED_MIN <= self.ee_speed <= EE_SPEED_MAX,
             f"ee_speed must be in [{EE_SPEED_MIN:g}, {EE_SPEED_MAX}] m/s (the Panda's Cartesian limit), "
             f"got {self.ee_speed:g}")
        need(EE_SPEED_MIN <= self.transit_speed <= EE_SPEED_MAX,
             f"transit_speed must be in [{EE_SPEED_MIN:g}, {EE_SPEED_MAX}] m/s (the Panda's Cartesian "
             f"limit), got {self.transit_speed:g}")
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
        need(self.execution in ("sequential", "parallel"),
             f"execution must be sequential or parallel, got {self.execution!r}")
        need(0 <= self.w_time <= W_TIME_MAX, f"w_time must be in [0, {W_TIME_MAX:g}] (cost per second), got "
             f"{self.w_time:g}")
        need(self.team_margin is None or self.team_margin > 0,
             f"team_margin must be > 0 or none, got {self.team_margin}")
        need(0 < self.refusal_tolerance < 1,
             f"refusal_tolerance must be in (0, 1), got {self.refusal_tolerance}")
        need(self.refusal_tolerance_sd >= 0, f"refusal_tolerance_sd must be >= 0, got "
             f"{self.refusal_tolerance_sd}")
        need(self.refusal_slope > 0, f"refusal_slope must be > 0, got {self.refusal_slope}")
        held, memory = run_memory(self), physical_memory()
        need(held <= memory / 2,
             f"subjects × modes × repetitions × takt = {self.subjects} × {len(self.modes)} × "
             f"{self.repetitions} × {self.takt:g} s of records at {self.ergonomics_rate:g} Hz need about "
             f"{held / 1e9:.3g} GB in memory; this machine has {memory / 1e9:.3g} GB (at most half of it "
             "is used)")

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


def run_memory(cfg: ScenarioConfig) -> float:
    """Bytes a whole run of ``cfg`` holds in memory at its end: every subject's per-tick records of every
    mode over the schedule (repetitions × takt at the ergonomics rate)."""
    from ergosim.twin.records import TICK_COLUMNS  # noqa: PLC0415

    ticks = cfg.repetitions * cfg.takt * cfg.ergonomics_rate
    return float(cfg.subjects) * len(cfg.modes) * ticks * len(TICK_COLUMNS) * _TICK_BYTES_PER_COLUMN

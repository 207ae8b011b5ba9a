"""Which reading of RULA's "standard method" matches the paper's observers in both experiments (issue 23).

G(a_k) scores a whole action from its per-tick grand scores by one rule
(:mod:`ergosim.ergonomics.rula_action`).
This module records the subjects' calibration executions, exactly as the twin does for its own G(a_k)
(:class:`~ergosim.twin.calibration.SceneCalibration`, the subjects of the scenario's population, the mocap
stream's noise), and scores them under every rule, so that the rules can be compared with §7.1's Table 1
(5 3 3 4 4) and §7.2's protocol (4 5 3 3 4) on the same executions.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ergosim.ergonomics.kwear import alpha_of
from ergosim.ergonomics.rula_action import G_RULES, grand_scores_by_rule, most_loaded_joint
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import scenario_subject, subject_cell
from ergosim.fidelity import paper
from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.calibration import SceneCalibration

__all__ = ["RuleFit", "Measured", "measure", "g_by_rule", "rule_fits"]


@dataclasses.dataclass(frozen=True)
class Measured:
    """What the subjects' calibration executions give: ``g`` rule -> action -> median G(a_k); ``loaded``
    action -> the joint with the largest 1 - α for most subjects (eq. 9, as summary.json reports it)."""

    g: dict[str, dict[str, float]]
    loaded: dict[str, str]


def measure(scenario: str, seeds: Sequence[int], subjects: int | None = None, passes: int = 3,
            overrides: Mapping[str, str] | None = None, subject_fields: Mapping[str, float] | None = None,
            log: Callable[[str], None] = lambda _msg: None) -> Measured:
    """Record ``passes`` executions of every action (the paper's η = 3) for the scenario's subjects of
    ``seeds`` and score them. ``subject_fields`` multiply subject fields (e.g. ``{"trunk_use": 2.0}``), a
    what-if of the worker's style."""
    sc = load_scenario(scenario, dict(overrides or {}))
    cfg = sc.protocol
    n = cfg.population.subjects if subjects is None else subjects
    actions = sc.task().actions
    per_rule: dict[str, dict[str, list[float]]] = {r: {} for r in G_RULES}
    loaded: dict[str, list[str]] = {a: [] for a in actions}
    for seed in seeds:
        for index in range(n):
            subject = scenario_subject(sc, index, seed)
            cell = subject_cell(sc, subject)
            scaled = {k: getattr(subject, k) * f for k, f in (subject_fields or {}).items()}
            subject = dataclasses.replace(subject, handedness=cell.config.worker.hand, **scaled)
            rng = np.random.default_rng([seed, index, 23])
            cal = SceneCalibration.for_subject(cell, subject, rng, mocap_rate=cfg.sensing.mocap_rate,
                                               ergonomics_rate=cfg.sensing.ergonomics_rate, actions=actions,
                                               noise=cfg.sensing.noise_scale)
            cal.execute(actions[0], passes - 1)
            params = subject.kwear_params()
            for action in actions:
                runs = [p[action].grand for p in cal.passes]
                for rule, g in grand_scores_by_rule(runs, dt=cal.dt_tick).items():
                    per_rule[rule].setdefault(action, []).append(g)
                alpha = np.mean([alpha_of(p[action].g, cal.dt_tick, params) for p in cal.passes], axis=0)
                loaded[action].append(most_loaded_joint(alpha, KWEAR_JOINTS))
            log(f"{scenario} seed {seed} subject {index}")
    majority = {a: max(KWEAR_JOINTS, key=lambda j, v=v: (v.count(j), -KWEAR_JOINTS.index(j)))
                for a, v in loaded.items()}
    return Measured({r: {a: float(np.median(v)) for a, v in by.items()} for r, by in per_rule.items()},
                    majority)


def g_by_rule(scenario: str, seeds: Sequence[int], subjects: int | None = None, passes: int = 3,
              overrides: Mapping[str, str] | None = None,
              log: Callable[[str], None] = lambda _msg: None) -> dict[str, dict[str, float]]:
    """rule -> action -> the median over the subjects of ``seeds`` of G(a_k) from ``passes`` recorded
    executions each (the paper's η = 3)."""
    return measure(scenario, seeds, subjects, passes, overrides, log=log).g


@dataclasses.dataclass(frozen=True)
class RuleFit:
    """How one rule's G(a1..a5) compare with the paper's in one experiment."""

    rule: str
    section: str
    g: dict[str, float]
    within: int
    """actions within ±1 of the paper's score."""
    riskiest_ok: bool | None
    """§7.2: a2 alone has the highest G (None for §7.1, whose text names no riskiest action)."""


def rule_fits(kv: Mapping[str, Mapping[str, float]], ms: Mapping[str, Mapping[str, float]]) -> list[RuleFit]:
    """Every rule against §7.1's and §7.2's published G(a_k)."""
    out = []
    for rule in G_RULES:
        for section, got, want in (("§7.1", kv[rule], paper.G_KWEAR_VALIDATION),
                                   ("§7.2", ms[rule], paper.G_MULTI_SUBJECT)):
            within = sum(abs(got[a] - want[a]) <= 1 for a in want)
            riskiest = None
            if section == "§7.2":
                top = max(got.values())
                riskiest = got["a2"] == top and sum(v == top for v in got.values()) == 1
            out.append(RuleFit(rule, section, dict(got), within, riskiest))
    return out

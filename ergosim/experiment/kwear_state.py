"""The worker's KWear state as a file: what a run ends with, what ``ergosim plan --state`` prices with.

``ergosim run`` writes ``kwear_state_s<subject>_<mode>.json`` per subject and mode at the end of the run
(format ``ergosim-kwear-state/1``, docs/task_format.md "KWear state files")::

    {
      "format": "ergosim-kwear-state/1",
      "scenario": "multi-subject", "task": "multi-subject", "seed": 0,
      "subject": 0, "worker": "S01", "mode": "hrc",
      "time_s": 76.0,                                   # simulated time of the state [s]
      "joints": ["shoulder", "elbow", "wrist", "trunk", "neck"],
      "v": [0.12, 0.05, 0.01, 0.08, 0.02],              # KWear V_i(t) per joint (eq. 3-5), in [0, 1)
      "alpha": {"a1": [5 values], "a2": [...], ...},    # the worker's calibrated alpha per action (§5)
      "kwear_params": {"t_max": 600.0, "v_max": 0.993, "g_avg": 3.0},
      "cost": {"gamma": 100.0, "v_th": 0.8, "robot_cost": 2.5}
    }

:func:`state_costs` turns a state into the human hyper-arc costs of eq. 9-11: V̂ = 1 − α(1 − V) per
action, γ_i = V̂_i (+ Γ when V̂_i ≥ V_th), c = Σ_i γ_i; every robot gets ``cost.robot_cost``.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from ergosim.errors import ConfigError
from ergosim.posture import KWEAR_JOINTS

__all__ = ["STATE_FORMAT", "KWearState", "state_document", "read_state", "state_costs"]

STATE_FORMAT = "ergosim-kwear-state/1"
_MAX_BYTES = 1 << 20  # a state file is a few hundred bytes; anything far larger is not one


class KWearState:
    """A parsed state file: ``v`` (5,) KWear, ``alpha`` action -> (5,), the cost constants."""

    def __init__(self, v: np.ndarray, alpha: dict[str, np.ndarray], *, gamma: float, v_th: float,
                 robot_cost: float, v_max: float, source: str) -> None:
        self.v = v
        self.alpha = alpha
        self.gamma = gamma
        self.v_th = v_th
        self.robot_cost = robot_cost
        self.v_max = v_max
        self.source = source


def state_document(*, scenario: str, task: str, seed: int, subject: int, worker: str, mode: str,
                   time_s: float, v: Iterable[float], alpha: dict[str, Iterable[float]], kwear_params,
                   gamma: float, v_th: float, robot_cost: float) -> dict:
    """The JSON object of a state file (see the module docstring)."""
    return {
        "format": STATE_FORMAT, "scenario": scenario, "task": task, "seed": seed, "subject": subject,
        "worker": worker, "mode": mode, "time_s": float(time_s), "joints": list(KWEAR_JOINTS),
        "v": [float(x) for x in v],
        "alpha": {a: [float(x) for x in values] for a, values in sorted(alpha.items())},
        "kwear_params": {"t_max": float(kwear_params.t_max), "v_max": float(kwear_params.v_max),
                         "g_avg": float(kwear_params.g_avg)},
        "cost": {"gamma": float(gamma), "v_th": float(v_th), "robot_cost": float(robot_cost)},
    }


def _number(doc: dict, key: str, where: str, low: float, high: float) -> float:
    value = doc.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ConfigError(f"{key} must be a finite number, got {value!r}", where=where)
    if not low < value <= high:
        raise ConfigError(f"{key} must be in ({low:g}, {high:g}], got {value!r}", where=where)
    return float(value)


def _vector(value: object, key: str, where: str, low: float, high: float) -> np.ndarray:
    n = len(KWEAR_JOINTS)
    if (not isinstance(value, list) or len(value) != n
            or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in value)):
        got = f"{len(value)} values" if isinstance(value, list) else repr(value)
        raise ConfigError(f"{key} must be a list of {n} numbers ({', '.join(KWEAR_JOINTS)}), got {got}",
                          where=where)
    x = np.array(value, dtype=float)
    if not (np.all(np.isfinite(x)) and np.all(x >= low) and np.all(x <= high)):
        raise ConfigError(f"{key} values must be in [{low:g}, {high:g}], got {value}", where=where)
    return x


def read_state(path: str | os.PathLike[str]) -> KWearState:
    """Read and check a state file; every problem is a ConfigError naming the file and the key."""
    p = Path(path)
    src = str(p)
    if not p.exists():
        raise ConfigError("no such file", where=src)
    if not p.is_file():
        raise ConfigError("not a regular file, expected a KWear state .json", where=src)
    if p.stat().st_size > _MAX_BYTES:
        raise ConfigError(f"{p.stat().st_size} bytes, more than a state file's limit of {_MAX_BYTES}",
                          where=src)
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as err:
        raise ConfigError(f"cannot read the state file: {err}", where=src) from None
    if not isinstance(doc, dict) or doc.get("format") != STATE_FORMAT:
        got = doc.get("format") if isinstance(doc, dict) else type(doc).__name__
        raise ConfigError(f"format must be {STATE_FORMAT!r}, got {got!r}", where=src)
    joints = doc.get("joints", list(KWEAR_JOINTS))
    if joints != list(KWEAR_JOINTS):
        raise ConfigError(f"joints must be {list(KWEAR_JOINTS)}, got {joints!r}", where=f"{src}: joints")
    v = _vector(doc.get("v"), "v", f"{src}: v", 0.0, 1.0)
    table = doc.get("alpha")
    if not isinstance(table, dict) or not table:
        raise ConfigError("alpha must be a table action -> 5 numbers", where=f"{src}: alpha")
    alpha = {str(a): _vector(x, f"alpha.{a}", f"{src}: alpha.{a}", 0.0, 1.0) for a, x in table.items()}
    cost = doc.get("cost")
    params = doc.get("kwear_params")
    if not isinstance(cost, dict):
        raise ConfigError(f"cost must be a table, got {cost!r}", where=f"{src}: cost")
    if not isinstance(params, dict):
        raise ConfigError(f"kwear_params must be a table, got {params!r}", where=f"{src}: kwear_params")
    return KWearState(
        v, alpha, gamma=_number(cost, "gamma", f"{src}: cost.gamma", 0.0, 1e12),
        v_th=_number(cost, "v_th", f"{src}: cost.v_th", 0.0, 1.0),
        robot_cost=_number(cost, "robot_cost", f"{src}: cost.robot_cost", 0.0, 1e12),
        v_max=_number(params, "v_max", f"{src}: kwear_params.v_max", 0.0, 1.0), source=src,
    )


def state_costs(state: KWearState, actions: Iterable[str], human: str,
                robots: Iterable[str]) -> tuple[dict[tuple[str, str], float], dict[str, np.ndarray]]:
    """Hyper-arc costs (action, agent) -> cost of eq. 9-11 for ``actions``, and V̂ per action (5,)."""
    from ergosim.ergonomics.cost import CostParams, hyperarc_costs  # noqa: PLC0415
    from ergosim.ergonomics.kwear import predict  # noqa: PLC0415

    actions = list(actions)
    missing = [a for a in actions if a not in state.alpha]
    if missing:
        raise ConfigError(f"no alpha for action(s) {', '.join(missing)}; the state has "
                          f"{', '.join(sorted(state.alpha))}", where=f"{state.source}: alpha")
    v_hat = {a: predict(state.v, state.alpha[a]) for a in actions}
    params = CostParams(gamma=state.gamma, v_th=state.v_th, robot_cost=state.robot_cost, v_max=state.v_max)
    return hyperarc_costs(v_hat, human, list(robots), params), v_hat

"""Per-worker parameter store (paper §5: a database of subject-parameter correspondences).

One JSON file per worker, ``<directory>/<worker_id>.json``, written atomically. It holds the worker's
KWear constants (eq. 6-7), the calibrated alpha_{k,i} per action (eq. 9, in KWEAR_JOINTS order), the static
RULA score G(a_k) and the calibration's eta. Loading a missing or corrupt file raises ConfigError naming
the file and the entry.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType

import numpy as np

from ergosim.atomic import write_json
from ergosim.ergonomics.calibration import Calibration
from ergosim.ergonomics.kwear import KWearParams
from ergosim.errors import ConfigError, ErgosimError
from ergosim.posture import KWEAR_JOINTS

__all__ = ["WorkerParams", "ParamStore", "FORMAT", "VERSION"]

FORMAT = "ergosim-worker-params"
VERSION = 1
_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")


@dataclass(frozen=True)
class WorkerParams:
    """One worker's parameters. ``alphas``: action -> (5,) alpha per joint in (0, 1];
    ``rula_scores``: action -> G(a_k); ``eta``: action -> executions used by the calibration."""

    worker_id: str
    kwear: KWearParams = KWearParams()
    alphas: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    rula_scores: Mapping[str, float] = field(default_factory=dict)
    eta: Mapping[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.worker_id, str) or not _ID.match(self.worker_id):
            raise ConfigError(f"worker id must be 1-64 letters, digits, '_', '.', '-' (not starting with "
                              f"'.' or '-'), got {self.worker_id!r}", where="worker_id")
        alphas = {}
        for action, a in self.alphas.items():
            arr = np.asarray(a, dtype=float)
            if arr.shape != (len(KWEAR_JOINTS),) or not np.all((arr > 0) & (arr <= 1)):
                raise ConfigError(f"alpha of action {action!r} must be {len(KWEAR_JOINTS)} values in (0, 1] "
                                  f"({', '.join(KWEAR_JOINTS)}), got {a!r}", where=f"alphas.{action}")
            alphas[str(action)] = tuple(float(x) for x in arr)
        object.__setattr__(self, "alphas", MappingProxyType(alphas))
        object.__setattr__(self, "rula_scores", MappingProxyType({str(k): float(v)
                                                                  for k, v in self.rula_scores.items()}))
        object.__setattr__(self, "eta", MappingProxyType({str(k): int(v) for k, v in self.eta.items()}))

    @classmethod
    def from_calibration(cls, worker_id: str, calibration: Calibration) -> WorkerParams:
        return cls(worker_id, calibration.params, calibration.alphas, calibration.rula_scores,
                   calibration.eta)

    def alpha(self, action: str) -> np.ndarray:
        """(5,) alpha of ``action``; ConfigError if the action was never calibrated for this worker."""
        try:
            return np.array(self.alphas[action])
        except KeyError:
            raise ConfigError(f"worker {self.worker_id!r} has no calibrated alpha for action {action!r}; "
                              f"calibrated: {sorted(self.alphas)}", where="alphas") from None

    def with_alpha(self, action: str, alpha) -> WorkerParams:
        """A copy with ``action``'s alpha replaced (e.g. after the online update)."""
        return replace(self, alphas={**self.alphas, action: tuple(np.asarray(alpha, dtype=float))})

    def to_dict(self) -> dict:
        return {
            "format": FORMAT,
            "version": VERSION,
            "worker_id": self.worker_id,
            "joints": list(KWEAR_JOINTS),
            "kwear": {"t_max": self.kwear.t_max, "v_max": self.kwear.v_max, "g_avg": self.kwear.g_avg},
            "actions": {
                a: {"alpha": list(self.alphas.get(a, ())) or None,
                    "rula_grand": (None if a not in self.rula_scores or math.isnan(self.rula_scores[a])
                                   else self.rula_scores[a]),
                    "eta": self.eta.get(a)}
                for a in sorted(set(self.alphas) | set(self.rula_scores) | set(self.eta))
            },
        }

    @classmethod
    def from_dict(cls, data: Mapping, where: str = "worker parameters") -> WorkerParams:
        def need(ok: bool, what: str, entry: str) -> None:
            if not ok:
                raise ConfigError(what, where=f"{where}: {entry}" if entry else where)

        need(isinstance(data, Mapping), "expected a JSON object", "")
        need(data.get("format") == FORMAT, f"not an ergosim worker-parameter file (format "
             f"{data.get('format')!r}, expected {FORMAT!r})", "format")
        need(data.get("version") == VERSION,
             f"unsupported version {data.get('version')!r}, expected {VERSION}", "version")
        need(data.get("joints") == list(KWEAR_JOINTS), f"joints must be {list(KWEAR_JOINTS)}", "joints")
        kw = data.get("kwear")
        need(isinstance(kw, Mapping) and set(kw) <= {"t_max", "v_max", "g_avg"},
             "expected an object with t_max, v_max, g_avg", "kwear")
        actions = data.get("actions")
        need(isinstance(actions, Mapping), "expected an object action -> {alpha, rula_grand, eta}", "actions")
        alphas, scores, eta = {}, {}, {}
        for a, entry in actions.items():
            need(isinstance(entry, Mapping), "expected an object", f"actions.{a}")
            if entry.get("alpha") is not None:
                alphas[a] = entry["alpha"]
            if entry.get("rula_grand") is not None:
                need(isinstance(entry["rula_grand"], (int, float)), "expected a number",
                     f"actions.{a}.rula_grand")
                scores[a] = entry["rula_grand"]
            if entry.get("eta") is not None:
                need(isinstance(entry["eta"], int) and entry["eta"] >= 1, "expected an integer >= 1",
                     f"actions.{a}.eta")
                eta[a] = entry["eta"]
        try:
            return cls(data.get("worker_id"), KWearParams(**kw), alphas, scores, eta)
        except (ErgosimError, TypeError, ValueError) as err:
            raise ConfigError(str(err), where=where) from None


class ParamStore:
    """Directory of per-worker parameter files, selected by worker id."""

    def __init__(self, directory: str | Path) -> None:
        self.directory = Path(directory)

    def path(self, worker_id: str) -> Path:
        WorkerParams(worker_id)  # validates the id: no path separators can reach the file system
        return self.directory / f"{worker_id}.json"

    def exists(self, worker_id: str) -> bool:
        return self.path(worker_id).is_file()

    def workers(self) -> list[str]:
        """Ids of the workers with a parameter file, sorted."""
        if not self.directory.is_dir():
            return []
        return sorted(p.stem for p in self.directory.glob("*.json") if _ID.match(p.stem))

    def save(self, params: WorkerParams) -> Path:
        """Write ``<directory>/<worker_id>.json`` atomically; returns the path."""
        path = self.path(params.worker_id)
        write_json(path, params.to_dict())
        return path

    def load(self, worker_id: str) -> WorkerParams:
        path = self.path(worker_id)
        try:
            text = path.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise ConfigError(f"no parameters for worker {worker_id!r}; run the calibration first "
                              f"(known workers: {self.workers()})", where=str(path)) from None
        except OSError as err:
            raise ConfigError(f"cannot read worker parameters: {err.strerror}", where=str(path)) from None
        try:
            data = json.loads(text)
        except json.JSONDecodeError as err:
            raise ConfigError(f"corrupt JSON: {err.msg}", where=f"{path}:{err.lineno}:{err.colno}") from None
        params = WorkerParams.from_dict(data, where=str(path))
        if params.worker_id != worker_id:
            raise ConfigError(f"file holds worker {params.worker_id!r}, expected {worker_id!r}",
                              where=f"{path}: worker_id")
        return params

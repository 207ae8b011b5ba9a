"""What summary.json says about the subjects' calibration (paper §5): η, errors, α, G(a_k), loaded joints.

Per subject as recorded, and per action over the subjects: ``rula_g_by_action`` is the median of the
subjects' G(a_k) (:mod:`ergosim.ergonomics.rula_action`; ``reba_g_by_action`` the same on REBA when a mode
reads REBA), ``most_loaded_joint_by_action`` the joint with the
largest 1 - α_i for most subjects (ties: the first in ``KWEAR_JOINTS`` order), ``mtm_by_action`` the MTM-1
analysis of the first subject's first execution.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

import numpy as np

from ergosim.ergonomics.rula_action import most_loaded_joint
from ergosim.posture import KWEAR_JOINTS

__all__ = ["calibration_summary"]


def calibration_summary(results: Sequence) -> dict:
    """The ``calibration`` object of summary.json from :class:`~ergosim.experiment.subject.SubjectResult` s in
    subject order."""
    actions = list(results[0].alphas) if results else []
    loaded = [{a: most_loaded_joint(r.alphas[a], KWEAR_JOINTS) for a in actions} for r in results]
    by_action = {}
    for a in actions:
        counts = Counter(m[a] for m in loaded)
        top = max(counts.values())
        by_action[a] = next(j for j in KWEAR_JOINTS if counts.get(j) == top)
    reba = [r for r in results if getattr(r, "reba_g", None) is not None]
    extra = {} if not reba else {  # a run whose modes read REBA: G(a_k) on REBA too
        "reba_g_by_subject": [r.reba_g for r in reba],
        "reba_g_by_action": {a: float(np.median([r.reba_g[a] for r in reba])) for a in actions},
    }
    return {
        **extra,
        "eta_by_subject": [r.eta for r in results],
        "max_error_by_subject": [r.calibration_errors for r in results],
        "rula_g_by_subject": [r.rula_g for r in results],
        "alpha_by_subject": [r.alphas for r in results],
        "most_loaded_joint_by_subject": loaded,
        "rula_g_by_action": {a: float(np.median([r.rula_g[a] for r in results])) for a in actions},
        "most_loaded_joint_by_action": by_action,
        "mtm_by_action": dict(results[0].mtm) if results else {},
    }

"""A simulated worker who may refuse an assignment (negotiation, issue 17).

The probability that the worker refuses an action rises with the predicted wear of its most-loaded joint,
max_i V̂_i (eq. 9), as a logistic curve around the worker's own tolerance τ:

    p(refuse) = 1 / (1 + exp(-(max_i V̂_i - τ) / s)).

τ is drawn once per subject from N(mean, sd) (clipped to [0.05, 0.99]), so workers differ in how much wear
they accept; ``s`` sets how sharply a worker turns from accepting to refusing. Every draw comes from the
generator passed in, so a seed gives the same refusals bit for bit. The values are assumptions (no study of
refusal rates against KWear exists); they are protocol fields (``refusal_tolerance``,
``refusal_tolerance_sd``, ``refusal_slope``).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

__all__ = ["RefusalModel"]


@dataclasses.dataclass(frozen=True)
class RefusalModel:
    """One worker's refusal curve: ``tolerance`` τ (V̂ at which refusal is as likely as not) and ``slope``
    s (in V̂ units)."""

    tolerance: float
    slope: float

    @classmethod
    def for_subject(cls, rng: np.random.Generator, *, mean: float, sd: float, slope: float) -> RefusalModel:
        """A subject's model, τ drawn from N(``mean``, ``sd``) with ``rng``."""
        return cls(float(np.clip(rng.normal(mean, sd), 0.05, 0.99)), float(slope))

    def probability(self, v_hat) -> float:
        """p(refuse) for the predicted risk ``v_hat`` (p,) of the action (its largest entry counts)."""
        x = (float(np.max(v_hat)) - self.tolerance) / self.slope
        return 1.0 / (1.0 + math.exp(-x)) if x > -700 else 0.0

    def refuses(self, v_hat, rng: np.random.Generator) -> tuple[bool, float]:
        """(refused, probability) for one offer; one uniform draw from ``rng``."""
        p = self.probability(v_hat)
        return bool(rng.random() < p), p

"""Negotiation in the loop: the allocator offers the worker an action, the worker may refuse it.

Each time the allocator gives the worker an action that another agent could also do, the worker's
:class:`~ergosim.worker.refusal.RefusalModel` is asked with the worker's own predicted KWear for that action
(eq. 9, from the plant's index whatever the mode prices with). A refusal prunes the worker's hyper-arc for
that decision only, and the allocator re-plans (Algorithm 2 with one more pruned hyper-arc). Every offer is
kept (:class:`Offer`): refusals become ``refused`` rows of ``allocations.csv`` and lines of the recording's
log, and the offers give the refusal rate against V̂.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ergosim.posture import KWEAR_JOINTS
from ergosim.worker.refusal import RefusalModel

__all__ = ["Offer", "Negotiator"]


@dataclasses.dataclass(frozen=True)
class Offer:
    """One action offered to the worker at sim time ``time`` [s]: the most-loaded joint's predicted KWear
    ``v_hat`` (and which joint), the refusal probability, and whether the worker refused."""

    time: float
    repetition: int
    action: str
    joint: str
    v_hat: float
    probability: float
    refused: bool

    @property
    def message(self) -> str:
        verb = "refused" if self.refused else "accepted"
        return (f"{self.action} {verb} by the worker: V̂ {self.v_hat:.2f} on the {self.joint} "
                f"(p(refuse) = {self.probability:.2f})")


class Negotiator:
    """Asks the worker's ``model`` about offers, predicting with ``kwear`` (the worker's
    :class:`~ergosim.ergonomics.risk_index.KWearIndex`) and drawing from ``rng``."""

    def __init__(self, model: RefusalModel, kwear, rng: np.random.Generator) -> None:
        self.model = model
        self.kwear = kwear
        self.rng = rng
        self.offers: list[Offer] = []

    def offer(self, time: float, repetition: int, action: str) -> Offer:
        v = np.asarray(self.kwear.predict(action), dtype=float)
        joint = int(np.argmax(v))
        refused, p = self.model.refuses(v, self.rng)
        out = Offer(time, repetition, action, KWEAR_JOINTS[joint], float(v[joint]), p, refused)
        self.offers.append(out)
        return out

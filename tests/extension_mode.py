"""A user's new mode with its own risk index, in one module (issue 12 §4): importing it registers both.

``peak``: the worker's hyper-arc of an action costs the predicted KWear of the most-loaded joint alone,
max_i V̂_i (eq. 9), plus Γ once it reaches V_th (eq. 11 with one channel). With the robot's cost between V_th
and Γ, the robot gets an action exactly when some joint is predicted to cross V_th, whatever the other
joints do -- unlike ``hrc``, which sums the joints. Nothing outside this module knows about it.
"""

from __future__ import annotations

import numpy as np

from ergosim.ergonomics.risk_index import RiskIndex
from ergosim.twin.modes import Mode, RiskIndexEntry, register_mode, register_risk_index
from ergosim.viz.reason import register_reason


class PeakKWear(RiskIndex):
    """The most-loaded joint's predicted KWear, read from the subject's KWear index (which the plant
    advances every ergonomics tick)."""

    channels = ("peak",)

    def __init__(self, kwear: RiskIndex) -> None:
        super().__init__()
        self.kwear = kwear

    @property
    def value(self) -> np.ndarray:
        return self.kwear.value

    def _advance(self, g, dt, resting) -> None:  # the KWear index is advanced by the plant itself
        return None

    def _reset(self) -> None:
        return None

    def predict(self, action: str) -> np.ndarray:
        return np.array([float(np.max(self.kwear.predict(action)))])


def _build(ctx):
    return PeakKWear(ctx.kwear), ctx.protocol.cost.params(ctx.kwear.params.v_max)


def _reason(d) -> str:
    peak = float(np.asarray(d.v_hat[d.action])[0])
    rel = "≥" if peak >= d.basis.v_th else "<"
    return f"{d.action} → {d.agent}: peak predicted KWear {peak:.2f} {rel} V_th {d.basis.v_th:g}"


register_risk_index(RiskIndexEntry("kwear-peak", _build))
register_reason("kwear-peak", _reason)
register_mode(Mode("peak", "the most-loaded joint's predicted KWear against V_th", risk_index="kwear-peak"))

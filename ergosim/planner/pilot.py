"""The beam's estimate of the rest of a sequence: one concrete completion per candidate split, cheapest of.

For a partial sequence in configuration Θ with wear V, its r needed actions are ranked by how much they wear
the worker (Σ_i (1 − α_i)), the worker's own actions first and the robots' own last. For every split m,
robots do the r − m heaviest first (the worker rests over their durations, eq. 5) and the worker then does
the m lightest, lightest first (the chain of eq. 9, priced by eq. 10-11); the estimate is the cheapest split
with its robot costs, the next repetition's price of the V it leaves (the worker doing every action:
linear in V) and the takt and time terms.
Precedence is ignored: it is a guess that sees the chain grow, not a bound.

Everything but V and the clock depends only on Θ and the model, so it is computed once per configuration
(:class:`PilotTable`, kept on the graph's :class:`~ergosim.planner.transitions.Transitions` per model) and
a beam level costs a few array operations on its rows.
"""

from __future__ import annotations

import hashlib

import numpy as np

__all__ = ["PilotTable", "pilot_table"]


class PilotTable:
    """Per configuration id, one row of ``data`` (A+1 splits m = 0..A, padded), field-major: ``[0:p]`` the
    weight of each joint's V in the split's cost, ``[p:2p]`` Π_{j≤m+1} α (the chain's next step, for Γ),
    ``[2p]`` the split's cost at V = 0 without Γ and takt terms (inf where the split is not allowed),
    ``[2p+1]`` the completion's duration [s]; ``r`` the needed count. Rows grow by doubling.

    With S_m = Σ_{k≤m} Π_{j≤k} α (the worker's chain sums, per joint), P_m = Π_{j≤m} α, ρ_m the rest factor
    of the robots' seconds (eq. 5) and ā = Σ_a α_a, a split costs p·m − Σ_p S_m + c_m + w_n·(A·p − P_m·ā)
    + w_t·D_m + Σ_p V_p·ρ_m·(S_m + w_n·P_m·ā)_p (w_n: ``next_weight``, w_t: ``time_weight``, c_m: the robots'
    costs, D_m: the duration): linear in V, so the rows hold its constant and its weights."""

    def __init__(self, pricing) -> None:
        n_a, p = pricing.alpha.shape
        self.shape = (n_a, p)
        self.slot = np.full(64, -1, dtype=np.int64)  # configuration id -> row, -1: not yet
        self.data = np.zeros((64, 2 * p + 2, n_a + 1))  # field-major: each field's splits contiguous
        self.r = np.zeros(64, dtype=np.int64)
        self.size = 0
        self.later = np.triu(np.full((n_a + 1, n_a + 1), float(pricing.model.cost.gamma)), 1)
        """Γ where split m is after step j (j < m): a split's Γ terms are its matrix product with the joint
        counts at V_th after each step."""

    def rows(self, pricing, cids: np.ndarray, need: np.ndarray) -> np.ndarray:
        """The slots of configurations ``cids`` (n,), computing those not seen yet from ``need`` (n, A)."""
        top = int(cids.max()) + 1
        if top > len(self.slot):
            grow = max(top, 2 * len(self.slot)) - len(self.slot)
            self.slot = np.concatenate([self.slot, np.full(grow, -1)])
        ix = self.slot[cids]
        missing = np.flatnonzero(ix < 0)
        if len(missing):
            fresh, first = np.unique(cids[missing], return_index=True)
            self._add(pricing, fresh, need[missing[first]])
            ix = self.slot[cids]
        return ix

    def _add(self, pr, cids: np.ndarray, need: np.ndarray) -> None:
        n, (n_a, p) = len(cids), self.shape
        model = pr.model
        human, robot = pr.human_ok[None], np.isfinite(pr.robot_min)[None]
        wear = (1.0 - pr.alpha).sum(axis=1)
        key = np.where(need, wear[None] + np.where(robot, 0.0, -1e9) + np.where(human, 0.0, 1e9), np.inf)
        order = np.argsort(key, axis=1)
        took = np.take_along_axis(need, order, axis=1)
        prod = np.cumprod(np.where(took[:, :, None], pr.alpha[order], 1.0), axis=1)
        zeros, ones = np.zeros((n, 1, p)), np.ones((n, 1, p))

        def ranked(x):
            return np.where(took, x[order], 0.0)

        def suffix(x):  # split m: Σ over ranks >= m, the robots' share
            return np.concatenate([np.cumsum(x[:, ::-1], axis=1)[:, ::-1], np.zeros((n, 1))], axis=1)

        cost = suffix(ranked(pr.robot_min))
        worker_s = np.cumsum(ranked(pr.duration[:, pr.human]), axis=1)
        seconds = np.concatenate([np.zeros((n, 1)), worker_s], axis=1) + suffix(ranked(pr.robot_duration))
        r = need.sum(axis=1)
        m = np.arange(n_a + 1)[None, :]
        ok = (m <= r[:, None]) & np.isfinite(cost) & (m >= (need & ~robot).sum(axis=1)[:, None]) & (
            r[:, None] - m >= (need & ~human).sum(axis=1)[:, None])
        sums = np.concatenate([zeros, np.cumsum(prod, axis=1)], axis=1)  # (n, split, p)
        prods = np.concatenate([ones, prod], axis=1)
        rest = np.exp(-pr.k * suffix(ranked(pr.max_rest)))  # V after the robots' rests: V·rest
        flat = m * p - sums.sum(axis=2) + np.where(np.isfinite(cost), cost, 0.0) \
            + model.next_weight * (pr.next_flat - prods @ pr.next_alpha) + model.time_weight * seconds
        block = np.concatenate([
            (rest[:, :, None] * (sums + model.next_weight * prods * pr.next_alpha)).transpose(0, 2, 1),
            np.concatenate([prod, prod[:, -1:]], axis=1).transpose(0, 2, 1),
            np.where(ok, flat, np.inf)[:, None], seconds[:, None]], axis=1)
        end = self.size + n
        if end > len(self.r):
            grow = max(end, 2 * len(self.r))
            self.data = np.resize(self.data, (grow,) + self.data.shape[1:])
            self.r = np.resize(self.r, grow)
        self.data[self.size:end] = block
        self.r[self.size:end] = r
        self.slot[cids] = np.arange(self.size, end)
        self.size = end

    def estimate(self, pr, cids: np.ndarray, need: np.ndarray, v: np.ndarray, t: np.ndarray) -> np.ndarray:
        """The estimate (n,) of the module docstring for rows in configurations ``cids`` with wear ``v``
        (n, p) at ``t`` [s from the repetition's start], priced by ``pr`` (the
        :class:`~ergosim.planner.chain_pricing.Pricing` of this decision)."""
        ix = self.rows(pr, cids, need)
        top = int(self.r[ix].max()) + 1  # splits past the most needed actions are empty
        p = v.shape[1]
        rows = self.data[ix][:, :, :top]  # (n, field, split); whole rows gather faster than a slice
        model = pr.model
        total = rows[:, 2 * p] + (v[:, None, :] @ rows[:, :p])[:, 0]
        # the worker's V after its (m + 1)-th step (without rest), 1 − (1 − V)·Π α, grows with m: Γ for each
        # joint from the step it reaches V_th, where Π α <= (1 − V_th)/(1 − V) (from the start at V = 1);
        # Σ_{j<m} #{joints there after step j + 1}
        w = 1.0 - v
        reach = np.divide(1.0 - model.v_th, w, out=np.full_like(w, np.inf), where=w > 0)
        hot = np.einsum("npm->nm", (rows[:, p:2 * p] <= reach[:, :, None]).view(np.uint8))  # <= p: fits
        total += hot @ self.later[:top, :top]
        if model.takt_weight:  # the seconds the completion adds past the takt
            late = np.add(t[:, None], rows[:, 2 * p + 1])
            np.maximum(late, model.takt, out=late)
            late -= np.maximum(t, model.takt)[:, None]
            late *= model.takt_weight
            total += late
        return total.min(axis=1)


def pilot_table(pricing) -> PilotTable:
    """The :class:`PilotTable` of ``pricing``'s model on its graph, kept on the graph's transitions while the
    arrays it depends on stay the same (a run re-prices the same configurations every repetition)."""
    if pricing.pilot is not None:
        return pricing.pilot
    digest = hashlib.blake2b(digest_size=16)
    model = pricing.model
    for arr in (pricing.alpha, pricing.max_rest, pricing.robot_min, pricing.duration[:, pricing.human],
                pricing.robot_duration, pricing.human_ok,
                np.array([pricing.k, model.next_weight, model.time_weight, model.cost.gamma])):
        digest.update(np.ascontiguousarray(arr).tobytes())
    tables = pricing.view.pilots
    key = digest.digest()
    table = tables.get(key)
    if table is None:
        if len(tables) >= 8:  # keep the last few models' tables
            tables.pop(next(iter(tables)))
        table = tables[key] = PilotTable(pricing)
    pricing.pilot = table
    return table

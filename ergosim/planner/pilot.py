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
    """Per configuration id, one row of ``data`` (A+1 splits m = 0..A, padded): columns ``[0:p]`` Σ_{k≤m}
    Π_{j≤k} α (the worker's chain sums), ``[p:2p]`` Π_{j≤m} α, ``[2p:3p]`` Π_{j≤m+1} α (the chain's next
    step, for Γ), then the robots' rest seconds, their costs, the completion's duration and Σ_p of the
    chain sums; ``ok`` the split is allowed; ``r`` the needed count. Rows grow by doubling."""

    def __init__(self, pricing) -> None:
        n_a, p = pricing.alpha.shape
        self.shape = (n_a, p)
        self.slot = np.full(64, -1, dtype=np.int64)  # configuration id -> row, -1: not yet
        self.data = np.zeros((64, 3 * p + 4, n_a + 1))  # field-major: each field's splits contiguous
        self.ok = np.zeros((64, n_a + 1), dtype=bool)
        self.r = np.zeros(64, dtype=np.int64)
        self.size = 0

    def rows(self, pricing, cids: np.ndarray, need: np.ndarray) -> np.ndarray:
        """The slots of configurations ``cids`` (n,), computing those not seen yet from ``need`` (n, A)."""
        top = int(cids.max()) + 1
        if top > len(self.slot):
            grow = max(top, 2 * len(self.slot)) - len(self.slot)
            self.slot = np.concatenate([self.slot, np.full(grow, -1)])
        missing = np.flatnonzero(self.slot[cids] < 0)
        if len(missing):
            fresh, first = np.unique(cids[missing], return_index=True)
            self._add(pricing, fresh, need[missing[first]])
        return self.slot[cids]

    def _add(self, pr, cids: np.ndarray, need: np.ndarray) -> None:
        n, (n_a, p) = len(cids), self.shape
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
        seconds = np.concatenate([np.zeros((n, 1)), worker_s], axis=1)
        r = need.sum(axis=1)
        m = np.arange(n_a + 1)[None, :]
        ok = (m <= r[:, None]) & np.isfinite(cost) & (m >= (need & ~robot).sum(axis=1)[:, None]) & (
            r[:, None] - m >= (need & ~human).sum(axis=1)[:, None])
        sums = np.concatenate([zeros, np.cumsum(prod, axis=1)], axis=1)
        block = np.concatenate([
            sums,
            np.concatenate([ones, prod], axis=1),
            np.concatenate([prod, prod[:, -1:]], axis=1),
            suffix(ranked(pr.max_rest))[:, :, None],
            np.where(np.isfinite(cost), cost, 0.0)[:, :, None],
            (seconds + suffix(ranked(pr.robot_duration)))[:, :, None],
            sums.sum(axis=2)[:, :, None]], axis=2)
        end = self.size + n
        if end > len(self.r):
            grow = max(end, 2 * len(self.r))
            self.data = np.resize(self.data, (grow,) + self.data.shape[1:])
            self.ok = np.resize(self.ok, (grow,) + self.ok.shape[1:])
            self.r = np.resize(self.r, grow)
        self.data[self.size:end] = block.transpose(0, 2, 1)
        self.ok[self.size:end], self.r[self.size:end] = ok, r
        self.slot[cids] = np.arange(self.size, end)
        self.size = end

    def estimate(self, pr, cids: np.ndarray, need: np.ndarray, v: np.ndarray, t: np.ndarray) -> np.ndarray:
        """The estimate (n,) of the module docstring for rows in configurations ``cids`` with wear ``v``
        (n, p) at ``t`` [s from the repetition's start], priced by ``pr`` (the
        :class:`~ergosim.planner.chain_pricing.Pricing` of this decision)."""
        ix = self.rows(pr, cids, need)
        top = int(self.r[ix].max()) + 1  # splits past the most needed actions are empty
        p = v.shape[1]
        rows = self.data[ix, :, :top]  # (n, field, split)
        model = pr.model
        rest = np.exp(-pr.k * rows[:, 3 * p])  # V after the robots' rests: V·rest
        m = np.arange(top)
        # Σ_p (1 − V·rest)·S = Σ_p S − rest·Σ_p V·S
        total = m * p - rows[:, 3 * p + 3] + rest * np.einsum("npm,np->nm", rows[:, :p], v) \
            + rows[:, 3 * p + 1]
        w = 1.0 - v
        # the worker's V after its (m + 1)-th step (without rest) grows with m: Γ once a joint's reaches V_th
        hot = 1.0 - w * rows[:, 2 * p:3 * p, -1] >= model.v_th  # (n, p): the joint gets there at all
        if hot.any():
            h = np.flatnonzero(hot.any(axis=1))
            chain = 1.0 - w[h, :, None] * rows[h, 2 * p:3 * p]
            first = np.where(hot[h], np.argmax(chain >= model.v_th[:, None], axis=2), top)  # (h, p)
            count = np.bincount((np.arange(len(h))[:, None] * (top + 1) + first).ravel(),
                                minlength=len(h) * (top + 1)).reshape(len(h), top + 1)
            # Σ_p max(0, m − first_p) = Σ_{j<m} #{p: first_p <= j}
            total[h, 1:] += model.cost.gamma * np.cumsum(np.cumsum(count[:, :top - 1], axis=1), axis=1)
        if model.next_weight:  # the next repetition's order-free price of the V left, uncapped: linear
            prods = rows[:, p:2 * p]
            left = np.einsum("npm,p->nm", prods, pr.next_alpha) \
                - rest * np.einsum("npm,np->nm", prods, v * pr.next_alpha[None])
            total += model.next_weight * (pr.next_flat - left)
        end = t[:, None] + rows[:, 3 * p + 2]
        total += model.takt_weight * (np.maximum(0.0, end - model.takt)
                                      - np.maximum(0.0, t - model.takt)[:, None])
        total += model.time_weight * rows[:, 3 * p + 2]
        return np.where(self.ok[ix, :top], total, np.inf).min(axis=1)


def pilot_table(pricing) -> PilotTable:
    """The :class:`PilotTable` of ``pricing``'s model on its graph, kept on the graph's transitions while the
    arrays it depends on stay the same (a run re-prices the same configurations every repetition)."""
    if pricing.pilot is not None:
        return pricing.pilot
    digest = hashlib.blake2b(digest_size=16)
    for arr in (pricing.alpha, pricing.max_rest, pricing.robot_min, pricing.duration[:, pricing.human],
                pricing.robot_duration, pricing.human_ok):
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

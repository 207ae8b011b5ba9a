"""The read-only containers of a compiled graph: arrays nobody can write and a dict nobody can change.

One exception: the index arrays handed to ``ufunc.reduceat`` and ``ufunc.at`` on every replan (the segment
starts of the bottom-up pass, the child columns of the outside pass) stay writeable, because numpy copies a
read-only index array on each such call (1 µs a call, 2 % of a replan on ``scarce:20``). Nothing writes to
them.
"""

from __future__ import annotations

import numpy as np

__all__ = ["FrozenDict", "read_only"]


def read_only(a: np.ndarray) -> np.ndarray:
    """``a``, made read-only in place."""
    a.flags.writeable = False
    return a


class FrozenDict(dict):
    """A dict that cannot change once built (a subclass of dict keeps the planners' lookups at C speed)."""

    def _refuse(self, *args, **kwargs):
        raise TypeError("a compiled graph is frozen: its mappings cannot change")

    __setitem__ = __delitem__ = __ior__ = clear = pop = popitem = setdefault = update = _refuse

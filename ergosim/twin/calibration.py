"""Calibrating a subject in a scene (paper §5): recorded executions of every action, from zero wear.

Each calibration pass is the worker doing the whole task alone, in the task's fixed order, in the real
workcell (physics on, so the parts end up where the previous action put them: J is on the bench before L
is inserted). For each action, the measured RULA part scores G_i of its acting ticks are one execution;
its coefficient α = exp(-∫G/C) is V after the action from zero wear (eq. 4, 9). Passes are recorded lazily,
as many as the adaptive-η procedure of :func:`ergosim.ergonomics.calibration.calibrate` asks for.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ergosim.ergonomics.calibration import Calibration, Execution, calibrate
from ergosim.ergonomics.kwear import KWearParams
from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.records import TICK_COLUMNS

__all__ = ["SceneCalibration", "G_COLUMNS"]

G_COLUMNS = tuple(
    TICK_COLUMNS.index(f"rula_{p}") for p in ("upper_arm", "lower_arm", "wrist", "trunk", "neck")
)
"""Tick-log columns holding G_i in KWEAR_JOINTS order (shoulder=upper arm, elbow=lower arm, ...)."""
_GRAND = TICK_COLUMNS.index("rula_grand")
_ACTING = TICK_COLUMNS.index("acting")
_T = TICK_COLUMNS.index("t")
assert len(G_COLUMNS) == len(KWEAR_JOINTS)


class SceneCalibration:
    """Records calibration passes with ``do_action(action) -> (t_start, t_end, ok)`` on a plant.

    ``reset()`` lays the parts out again before each pass. ``log`` is the plant's tick log; executions are
    cut from it by time.
    """

    def __init__(self, actions: Sequence[str], do_action: Callable[[str], tuple[float, float, bool]],
                 reset: Callable[[], None], log, dt_tick: float) -> None:
        self.actions = tuple(actions)
        self.do_action = do_action
        self.reset = reset
        self.log = log
        self.dt_tick = dt_tick
        self.passes: list[dict[str, Execution]] = []

    def _record_pass(self) -> None:
        self.reset()
        executions: dict[str, Execution] = {}
        for action in self.actions:
            t0, t1, ok = self.do_action(action)
            rows = self.log.rows
            sel = (rows[:, _T] > t0 + 1e-9) & (rows[:, _T] <= t1 + 1e-9) & (rows[:, _ACTING] > 0.5)
            g = rows[sel][:, G_COLUMNS]
            if not ok or len(g) == 0:
                from ergosim.errors import ErgosimError  # noqa: PLC0415

                raise ErgosimError(f"the worker could not complete {action} during calibration pass "
                                   f"{len(self.passes) + 1}", where="calibration")
            executions[action] = Execution(g, self.dt_tick, rows[sel][:, _GRAND])
        self.passes.append(executions)

    def execute(self, action: str, l: int) -> Execution:  # noqa: E741 - the paper's index
        while len(self.passes) <= l:
            self._record_pass()
        return self.passes[l][action]

    def run(self, params: KWearParams, *, eta0: int, eta_max: int, v_des: float) -> Calibration:
        return calibrate(self.actions, self.execute, params, eta0=eta0, eta_max=eta_max, v_des=v_des)


def alpha_table(cal: Calibration) -> dict[str, list[float]]:
    return {a: [float(x) for x in np.asarray(c.alpha)] for a, c in cal.actions.items()}

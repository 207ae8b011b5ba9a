"""The paper's KWear figure (§7.1): V of the five joints over one execution of each action from zero wear.

``kwear_actions.png`` puts every action side by side on one V axis, so which joint an action loads, and
how fast, compares at a glance (the paper shows a1, a2 and a5: "a1 stressed the shoulder, a2 the neck, a5
the trunk"); ``kwear_<action>.png`` is each panel alone. Both come from ``kwear_actions.csv``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ergosim.experiment.plots.style import COLOURS, plt
from ergosim.posture import KWEAR_JOINTS

__all__ = ["actions_figure", "action_figure"]


def _panel(ax, action: str, t: np.ndarray, v: np.ndarray, subject: int) -> None:
    for j, joint in enumerate(KWEAR_JOINTS):
        ax.plot(t, v[:, j], color=COLOURS[joint], lw=1.4, label=joint,
                gid=f"action/{subject}/{action}/{joint}")
    ax.set_title(action, fontsize=10)
    ax.set_xlabel("time from the action's start [s]", fontsize=8)
    ax.set_xlim(0, float(t[-1]) if len(t) else 1.0)
    ax.grid(alpha=0.3)
    ax.tick_params(labelsize=7)


def actions_figure(traces: Mapping[str, tuple[np.ndarray, np.ndarray]], *, subject: int, worker: str = "",
                   scenario: str = ""):
    """One panel per action (in ``traces`` order: action -> (t (n,) [s], V (n, 5))), shared V axis from 0."""
    n = max(len(traces), 1)
    fig, axes = plt.subplots(1, n, figsize=(min(2.6 * n, 13.0) + 0.6, 3.1), sharey=True, squeeze=False)
    top = max((float(np.nanmax(v)) for _, v in traces.values() if v.size), default=1.0)
    for ax, (action, (t, v)) in zip(axes[0], traces.items(), strict=False):
        _panel(ax, action, t, v, subject)
    axes[0][0].set_ylim(0, top * 1.08 if top > 0 else 1.0)
    axes[0][0].set_ylabel("KWear V", fontsize=9)
    who = f"subject {subject}" + (f" ({worker})" if worker else "")
    fig.suptitle(f"{scenario + ': ' if scenario else ''}KWear during one execution of each action from zero "
                 f"wear, {who}", fontsize=10)
    fig.legend(*axes[0][0].get_legend_handles_labels(), loc="lower center", ncol=len(KWEAR_JOINTS),
               frameon=False, fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 0.95))
    return fig


def action_figure(action: str, t: np.ndarray, v: np.ndarray, *, subject: int, worker: str = ""):
    """One action alone (``kwear_<action>.png``)."""
    fig, ax = plt.subplots(figsize=(5.0, 3.2))
    _panel(ax, action, t, v, subject)
    ax.set_ylim(bottom=0)
    ax.set_ylabel("KWear V", fontsize=9)
    who = f"subject {subject}" + (f" ({worker})" if worker else "")
    ax.set_title(f"KWear during {action} from zero wear, {who}", fontsize=10)
    ax.legend(fontsize=7, loc="upper left", frameon=False)
    fig.tight_layout()
    return fig

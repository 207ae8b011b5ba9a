"""``kwear_timeline_<mode>.png``: KWear per joint over the whole run, one panel per subject.

Each panel shows the five joints' V(t) with the V_th line, grey where a robot is acting (the worker rests),
dotted lines where a repetition starts, and below it a strip with every attempt as a bar in its agent's
colour, labelled with its action where the bar is wide enough (a failed attempt hatched). The legend sits
above the panels, never over the data.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.transforms as mtransforms
import numpy as np
from matplotlib.patches import Patch

from ergosim.experiment.plots.style import COLOURS, agent_colour, plt
from ergosim.experiment.plots.tables import Attempt, TickTable
from ergosim.posture import KWEAR_JOINTS

__all__ = ["timeline_figure"]

_PANEL_IN, _STRIP_IN, _GAP_IN = 1.6, 0.28, 0.32
_LABEL_PT = 6.5


def timeline_figure(ticks: Mapping[int, TickTable], attempts: Sequence[Attempt] | None, *, v_th: float,
                    title: str, width_in: float = 10.0, xlabel: str = "simulated time [s]"):
    """The figure (not saved). ``ticks``: subject -> its tick table, one panel each in that order;
    ``attempts``: the rows of allocations.csv of this mode (None: no attempt strip, as for a replayed
    recording). Artists carry gids for the tests: ``kwear/<subject>/<joint>``, ``attempt/<subject>/<rep>/
    <order>``, ``rep/<subject>/<rep>``."""
    subjects = list(ticks)
    strip = attempts is not None
    top_in, bottom_in, rep_in, left, right = 0.80, 0.45, 0.16, 0.075, 0.985
    per = rep_in + _PANEL_IN + (_STRIP_IN if strip else 0.0) + _GAP_IN
    height = top_in + bottom_in + per * max(len(subjects), 1) - _GAP_IN
    fig = plt.figure(figsize=(width_in, height))
    t_max = max((float(tt.t[-1]) for tt in ticks.values() if len(tt.t)), default=1.0)
    axes, shared = [], None
    y = height - top_in

    def place(h_in: float):
        nonlocal y
        y -= h_in
        return fig.add_axes((left, y / height, right - left, h_in / height), sharex=shared)

    for s in subjects:
        y -= rep_in
        ax = place(_PANEL_IN)
        shared = shared or ax
        axes.append(ax)
        mine = [a for a in attempts or () if a.subject == s]
        _kwear_panel(ax, s, ticks[s], mine, v_th)
        if strip:
            axes.append(place(_STRIP_IN))
            _attempt_strip(axes[-1], s, mine, t_max, width_in * (right - left) * 72)
        y -= _GAP_IN
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    axes[-1].set_xlabel(xlabel, fontsize=8)
    shared.set_xlim(0, t_max)
    fig.suptitle(title, y=1 - 0.10 / height, fontsize=11)
    fig.legend(handles=_legend(v_th, strip), loc="upper center", ncol=6 if strip else 7, frameon=False,
               fontsize=8, bbox_to_anchor=(0.5, 1 - 0.30 / height))
    return fig


def _kwear_panel(ax, subject: int, tt: TickTable, attempts: Sequence[Attempt], v_th: float) -> None:
    for j, joint in enumerate(KWEAR_JOINTS):
        ax.plot(tt.t, tt.kwear[:, j], color=COLOURS[joint], lw=0.9, gid=f"kwear/{subject}/{joint}")
    ax.axhline(v_th, color="k", ls="--", lw=0.8, gid="v_th")
    for a in attempts:
        if a.robot:
            ax.axvspan(a.t_start, a.t_end, color="0.88", lw=0, zorder=0)
    starts = _repetition_starts(tt, attempts)
    above = mtransforms.blended_transform_factory(ax.transData, ax.transAxes)
    for rep, t in starts.items():
        ax.axvline(t, color="0.3", lw=0.8, ls=":", gid=f"rep/{subject}/{rep}")
        ax.text(t, 1.01, str(rep), transform=above, fontsize=7, va="bottom", ha="left", color="0.3")
    if starts:
        ax.text(-0.005, 1.01, "repetition", transform=ax.transAxes, fontsize=7, va="bottom", ha="right",
                color="0.3")
    ax.set_ylim(0, 1.02)
    ax.set_ylabel(f"subject {subject}\nKWear V", fontsize=8)
    ax.grid(alpha=0.25)
    ax.tick_params(labelsize=7)


def _repetition_starts(tt: TickTable, attempts: Sequence[Attempt]) -> dict[int, float]:
    """Repetition -> start [s]: its first attempt (the allocator's first decision), else its first tick."""
    starts: dict[int, float] = {}
    for a in attempts:
        starts[a.repetition] = min(starts.get(a.repetition, np.inf), a.t_start)
    if not starts and len(tt.t):
        for rep in np.unique(tt.repetition):
            if rep > 0:
                starts[int(rep)] = float(tt.t[np.argmax(tt.repetition == rep)])
    return dict(sorted(starts.items()))


def _attempt_strip(ax, subject: int, attempts: Sequence[Attempt], t_max: float, width_pt: float) -> None:
    for a in attempts:
        if a.status == "pruned":
            continue
        color = agent_colour(a.agent)
        done = a.done
        (bar,) = ax.barh(0, a.t_end - a.t_start, left=a.t_start, height=0.8,
                         color=color if done else "white", edgecolor="white" if done else color,
                         hatch=None if done else "////", lw=0.8)
        bar.set_gid(f"attempt/{subject}/{a.repetition}/{a.order}")
        wide = (a.t_end - a.t_start) / max(t_max, 1e-9) * width_pt
        if wide > len(a.action) * _LABEL_PT * 0.62 + 2:
            ax.text((a.t_start + a.t_end) / 2, 0, a.action, ha="center", va="center", fontsize=_LABEL_PT,
                    color="white" if done else color, clip_on=True)
    ax.set_ylim(-0.5, 0.5)
    ax.set_yticks([])
    ax.set_ylabel("actions", fontsize=7, rotation=0, ha="right", va="center")
    ax.tick_params(labelsize=7)
    for side in ("top", "right", "left"):
        ax.spines[side].set_visible(False)


def _legend(v_th: float, strip: bool) -> list:
    handles = [plt.Line2D([], [], color=COLOURS[j], lw=1.5, label=j) for j in KWEAR_JOINTS]
    handles.append(plt.Line2D([], [], color="k", ls="--", lw=0.8, label=f"V_th = {v_th:.2f}"))
    if strip:
        handles += [
            plt.Line2D([], [], color="0.3", ls=":", lw=0.8, label="repetition starts"),
            Patch(color="0.88", label="a robot is acting"),
            Patch(color=agent_colour("human"), label="worker's action"),
            Patch(color=agent_colour("robot"), label="robot's action"),
            Patch(facecolor="white", edgecolor="0.3", hatch="////", label="failed attempt"),
        ]
    return handles

"""``allocation_histogram.png``: how often a robot completed each action, per mode (paper §7.2 Fig.).

Only completed actions that more than one agent may do count (the denominator of ``robot_share`` in
``summary.json``); each bar is labelled with its count, robot completions / completions, so a 0 % bar reads
as a measured zero (``0/4``) rather than a missing entry.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ergosim.experiment.plots.style import mode_colour, plt
from ergosim.experiment.plots.tables import Attempt

__all__ = ["allocation_figure", "robot_counts", "robots_may_act"]


def robot_counts(attempts: Sequence[Attempt], mode: str, actions: Sequence[str]) -> list[tuple[int, int]]:
    """Per action: (completed by a robot, completed) over the completed allocatable attempts of ``mode``."""
    done = [a for a in attempts if a.mode == mode and a.done and a.allocatable]
    return [(sum(a.robot for a in done if a.action == x),
             sum(a.action == x for a in done)) for x in actions]


def robots_may_act(mode: str) -> bool:
    """False for a mode in which no robot acts (``h-only``): its bars would be zero by design."""
    from ergosim.twin.modes import mode_or_default  # noqa: PLC0415

    return mode_or_default(mode).uses_robot


def allocation_figure(attempts: Sequence[Attempt], modes: Sequence[str], *, scenario: str = ""):
    """The figure (not saved); bars carry gids ``share/<mode>/<action>``, their count labels
    ``count/<mode>/<action>``."""
    actions = sorted({a.action for a in attempts if a.done and a.allocatable})
    ran = [m for m in modes if any(a.mode == m for a in attempts)]
    modes = [m for m in ran if robots_may_act(m)] or ran
    left_out = [m for m in ran if m not in modes]
    fig, ax = plt.subplots(figsize=(max(5.5, 0.45 * len(actions) * max(len(modes), 1) + 2.5), 3.6))
    width = 0.8 / max(len(modes), 1)
    for k, mode in enumerate(modes):
        counts = robot_counts(attempts, mode, actions)
        share = [100.0 * r / n if n else 0.0 for r, n in counts]
        xs = np.arange(len(actions)) + (k - (len(modes) - 1) / 2) * width
        bars = ax.bar(xs, share, width * 0.92, label=mode, color=mode_colour(mode, k))
        for bar, x, action, (r, n) in zip(bars, xs, actions, counts, strict=True):
            bar.set_gid(f"share/{mode}/{action}")
            ax.text(x, bar.get_height() + 1.5, f"{r}/{n}", ha="center", va="bottom", fontsize=7,
                    gid=f"count/{mode}/{action}")
    ax.set_xticks(np.arange(len(actions)), actions)
    ax.set_ylim(0, 112)
    ax.set_ylabel("completed by a robot [%]")
    ax.set_title(f"{scenario + ': ' if scenario else ''}robot share per action (labels: robot / completed)",
                 fontsize=10)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False, title="mode",
              title_fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    if left_out:
        note = "not shown:\n" + "\n".join(left_out) + "\n(no robot\nacts)"
        ax.text(1.01, 0.0, note, transform=ax.transAxes, fontsize=7, va="bottom", color="0.35")
    fig.tight_layout()
    return fig

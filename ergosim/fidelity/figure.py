"""The fidelity figure: the twin's Table 1 beside the paper's, and the §7.2 robot shares against the paper's.

Drawn from ``fidelity.json`` (what :func:`~ergosim.fidelity.report.write_report` writes), never from the
runs in memory, so the picture shows exactly the figures the report states.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ergosim.atomic import atomic_open  # noqa: E402
from ergosim.fidelity import paper  # noqa: E402

__all__ = ["fidelity_figure"]

_COLORS = {"H": (0.55, 0.85, 0.55), "R": (0.95, 0.55, 0.55), "-": (0.85, 0.85, 0.85)}


def _table(ax, reps: list[str], rula: str, title: str) -> None:
    rows = [*reps, rula]
    labels = [f"rp{i + 1}" for i in range(len(reps))] + ["RULA"]
    for i, rep in enumerate(rows):
        for j, cell in enumerate(rep):
            ax.add_patch(plt.Rectangle((j, -i), 1, 1, facecolor=_COLORS.get(cell, _COLORS["-"]),
                                       edgecolor="white", linewidth=2))
            ax.text(j + 0.5, -i + 0.5, cell, ha="center", va="center", fontsize=12, fontweight="bold")
    ax.set_xlim(0, 5)
    ax.set_ylim(-len(rows) + 1, 1)
    ax.set_xticks(np.arange(5) + 0.5, paper.ACTIONS)
    ax.set_yticks(-np.arange(len(rows)) + 0.5, labels)
    ax.tick_params(length=0)
    for side in ax.spines.values():
        side.set_visible(False)
    ax.set_title(title, fontsize=11)


def fidelity_figure(doc: Mapping, path: Path) -> None:
    """Write the figure of the fidelity document ``doc`` to ``path`` (PNG), atomically."""
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2), gridspec_kw={"width_ratios": [1, 1, 1.5]})
    _table(axes[0], list(paper.TABLE1_KWEAR), paper.TABLE1_RULA, "§7.1 Table 1, paper")
    kv = doc["kwear_validation"]
    seed = min(kv, key=int)
    _table(axes[1], kv[seed]["hrc"], kv[seed]["rula"][0] if kv[seed]["rula"] else "-----",
           f"§7.1 Table 1, twin (seed {seed})")
    ax = axes[2]
    actions = ("a1", "a2", "a3", "a4")
    x = np.arange(len(actions))
    ax.bar(x - 0.2, [paper.ROBOT_SHARE_BY_ACTION[a] * 100 for a in actions], 0.4, color=(0.4, 0.4, 0.4),
           label="paper (12 subjects)")
    shares = doc["multi_subject"]["robot_share_by_action"]
    seeds = sorted(shares, key=int)
    twin = np.array([[shares[s].get(a, 0.0) * 100 for a in actions] for s in seeds])
    mean = twin.mean(axis=0)
    ax.bar(x + 0.2, mean, 0.4, color=(0.84, 0.15, 0.16),
           label=f"twin (mean of {len(seeds)} seed{'s' if len(seeds) > 1 else ''})")
    if len(seeds) > 1:
        ax.errorbar(x + 0.2, mean, yerr=[mean - twin.min(axis=0), twin.max(axis=0) - mean], fmt="none",
                    ecolor="black", capsize=4, linewidth=1)
    top = twin.max(axis=0)  # the label sits above the seeds' range
    for xi, v, t in zip(x + 0.2, mean, top, strict=True):
        ax.text(xi, t + 1.5, f"{v:.0f}", ha="center", fontsize=9)
    for xi, a in zip(x - 0.2, actions, strict=True):
        ax.text(xi, paper.ROBOT_SHARE_BY_ACTION[a] * 100 + 1.5, f"{paper.ROBOT_SHARE_BY_ACTION[a] * 100:.0f}",
                ha="center", fontsize=9)
    overall = doc["multi_subject"]["robot_share"]
    ax.set_xticks(x, actions)
    ax.set_ylabel("actions given to the robot [%]")
    ax.set_ylim(0, 105)
    ax.set_title(f"§7.2 robot share by action (overall: paper {paper.ROBOT_SHARE:.0%}, twin "
                 f"{np.mean([overall[s] for s in seeds]):.0%})", fontsize=11)
    ax.legend(loc="upper right", frameon=False)
    ax.spines[["top", "right"]].set_visible(False)
    fig.tight_layout()
    with atomic_open(path, "wb") as f:
        fig.savefig(f, format="png", dpi=110)
    plt.close(fig)

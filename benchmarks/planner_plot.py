"""Plot of the planner benchmark, like the paper's computational-time figures (log time vs pieces/agents)."""

from __future__ import annotations

import os

from matplotlib.figure import Figure

from benchmarks.planner import OVER_BUDGET, OVER_CAP, BenchRow
from ergosim.atomic import atomic_open

__all__ = ["plot_benchmark"]

_STYLE = {"sequential": "tab:blue", "scarce": "tab:orange"}
STOPPED = (OVER_CAP, OVER_BUDGET)


def plot_benchmark(rows: list[BenchRow], path: str | os.PathLike[str]) -> None:
    """Write a PNG: replan time [ms, log scale] against pieces (2 agents) and against agents (10 pieces).

    The first size where the paper planner stopped (time cap or memory budget) is named in its legend.

    Uses a bare :class:`matplotlib.figure.Figure` (Agg canvas), so no pyplot backend is touched.
    """
    fig = Figure(figsize=(11, 4.2), layout="constrained")
    by_pieces, by_agents = fig.subplots(1, 2)
    for shape, colour in _STYLE.items():
        for planner, marker, line in (("fast", "o", "-"), ("paper", "s", "--")):
            key = "fast_ms" if planner == "fast" else "paper_ms"
            pts = sorted(
                (r.pieces, getattr(r, key))
                for r in rows
                if r.shape == shape and r.agents == 2 and getattr(r, key)
            )
            stopped = [
                f"{r.pieces}: {r.paper_note}"
                for r in rows
                if planner == "paper" and r.shape == shape and r.agents == 2 and r.paper_note in STOPPED
            ]
            if pts:
                label = f"{planner}, {shape}" + (f" ({stopped[0]})" if stopped else "")
                by_pieces.plot(*zip(*pts, strict=True), line, marker=marker, color=colour, label=label)
            pts = sorted(
                (r.agents, getattr(r, key))
                for r in rows
                if r.shape == shape and r.pieces == 10 and getattr(r, key)
            )
            if pts:
                by_agents.plot(
                    *zip(*pts, strict=True), line, marker=marker, color=colour, label=f"{planner}, {shape}"
                )
    many = sorted(
        (r.pieces, r.fast_ms) for r in rows if r.shape == "sequential" and r.agents == 30 and r.pieces > 10
    )
    if many:
        by_pieces.plot(
            *zip(*many, strict=True), ":", marker="^", color="tab:green", label="fast, sequential, 30 agents"
        )
    by_pieces.set(
        yscale="log",
        xlabel="pieces",
        ylabel="replan time [ms]",
        title="replan time vs pieces, 2 agents (cf. paper §6)",
    )
    by_agents.set(
        yscale="log",
        xlabel="agents",
        ylabel="replan time [ms]",
        title="replan time vs agents, 10 pieces (cf. paper §6)",
    )
    for ax in (by_pieces, by_agents):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    with atomic_open(path, "wb") as f:
        fig.savefig(f, format="png", dpi=120)

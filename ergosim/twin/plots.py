"""The scenario's PNG figures (matplotlib, headless Agg backend), each written atomically.

- ``kwear_<action>.png``: KWear per joint while the worker performs an action from zero wear (the first
  calibration execution), as in the paper's KWear figure for a1, a2 and a5 (§7.1);
- ``kwear_timeline_<mode>.png``: KWear per joint over the first subject's repetitions, with V_th;
- ``allocation_histogram.png``: how often the robot got each action, per mode (§7.2).
"""

from __future__ import annotations

import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ergosim.atomic import write_bytes  # noqa: E402
from ergosim.posture import KWEAR_JOINTS  # noqa: E402

__all__ = ["write_plots", "save_figure", "kwear_timeline", "allocation_histogram"]

COLOURS = {"shoulder": "#1f77b4", "elbow": "#ff7f0e", "wrist": "#2ca02c", "trunk": "#d62728",
           "neck": "#9467bd"}


def save_figure(fig, path: Path) -> None:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    plt.close(fig)
    write_bytes(path, buf.getvalue())


def _action_trace(out: Path, action: str, t: np.ndarray, v: np.ndarray, subject: str) -> None:
    fig, ax = plt.subplots(figsize=(5.0, 3.2))
    for i, j in enumerate(KWEAR_JOINTS):
        ax.plot(t, v[:, i], label=j, color=COLOURS[j])
    ax.set(title=f"KWear during {action} from zero wear ({subject})", xlabel="time [s]", ylabel="V")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, out / f"kwear_{action}.png")


def _timeline(out: Path, mode: str, run, v_th: float) -> None:
    rows = run.ticks.rows
    if len(rows) == 0:
        return
    t, v = rows[:, 1], run.ticks.kwear
    fig, ax = plt.subplots(figsize=(8.0, 3.2))
    for i, j in enumerate(KWEAR_JOINTS):
        ax.plot(t, v[:, i], label=j, color=COLOURS[j], lw=1)
    ax.axhline(v_th, color="k", ls="--", lw=0.8, label="V_th")
    for a in run.allocations:
        if a.agent != "human":
            ax.axvspan(a.t_start, a.t_end, color="0.85", lw=0)
    ax.set(title=f"KWear, first subject, {mode} (grey: robot acting)", xlabel="time [s]", ylabel="V")
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=6, loc="upper left")
    fig.tight_layout()
    save_figure(fig, out / f"kwear_timeline_{mode}.png")


def kwear_timeline(path: Path, t: np.ndarray, v: np.ndarray, v_th: float, title: str) -> None:
    """KWear per joint over time with the V_th line, as ``kwear_timeline_<mode>.png`` of a run: ``t`` (n,)
    [s], ``v`` (n, 5) in KWEAR_JOINTS order."""
    fig, ax = plt.subplots(figsize=(8.0, 3.2))
    for i, j in enumerate(KWEAR_JOINTS):
        ax.plot(t, v[:, i], label=j, color=COLOURS[j], lw=1)
    ax.axhline(v_th, color="k", ls="--", lw=0.8, label="V_th")
    ax.set(title=title, xlabel="time [s]", ylabel="V")
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=6, loc="upper left")
    fig.tight_layout()
    save_figure(fig, path)


def _histogram(out: Path, results, modes) -> None:
    actions = sorted({a.action for r in results for m in modes if m in r.runs for a in r.runs[m].allocations
                      if a.done and a.allocatable})
    if not actions:
        return
    fig, ax = plt.subplots(figsize=(5.5, 3.2))
    width = 0.8 / max(len(modes), 1)
    for k, mode in enumerate(modes):
        allocs = [a for r in results if mode in r.runs for a in r.runs[mode].allocations
                  if a.done and a.allocatable]  # completed actions, as robot_share in summary.json
        share = [np.mean([a.agent != "human" for a in allocs if a.action == x] or [0.0]) for x in actions]
        ax.bar(np.arange(len(actions)) + k * width, np.array(share) * 100, width, label=mode)
    ax.set_xticks(np.arange(len(actions)) + width * (len(modes) - 1) / 2, actions)
    ax.set(ylabel="completed by the robot [%]", title="Allocation per action", ylim=(0, 100))
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    save_figure(fig, out / "allocation_histogram.png")


def write_plots(out: Path, scenario: str, results, cfg) -> None:
    if not results:
        return
    first = results[0]
    for action, (t, v) in sorted(first.traces.items()):
        _action_trace(out, action, t, v, first.name)
    for mode, run in first.runs.items():
        _timeline(out, mode, run, cfg.v_th)
    allocation_histogram(out, results, cfg.modes)


def allocation_histogram(out: Path, results, modes) -> None:
    """``allocation_histogram.png`` of ``results`` (subject results or records with ``runs[mode]``) for
    ``modes`` but h-only (where the robot takes nothing)."""
    _histogram(out, results, [m for m in modes if m not in ("h-only",)])

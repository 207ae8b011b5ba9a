"""Colours and file writing shared by every figure: the joints' and agents' colours of the rerun recording and
the video (:mod:`ergosim.viz.styles`), so a joint or an agent looks the same everywhere."""

from __future__ import annotations

import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ergosim.atomic import write_bytes  # noqa: E402
from ergosim.colors import JOINT_COLORS, PALETTE, agent_color  # noqa: E402
from ergosim.posture import KWEAR_JOINTS  # noqa: E402

__all__ = ["COLOURS", "MODE_COLOURS", "agent_colour", "mode_colour", "save_figure", "plt"]


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*rgb)


COLOURS: dict[str, str] = {j: _hex(JOINT_COLORS[j]) for j in KWEAR_JOINTS}
"""Joint -> colour (matplotlib's tab10, as in the recording)."""

MODE_COLOURS: dict[str, str] = {"hrc": _hex(PALETTE[2]), "h-only": _hex(PALETTE[7]), "rula": _hex(PALETTE[4]),
                                "r-only": _hex(PALETTE[5])}


def mode_colour(mode: str, index: int = 0) -> str:
    return MODE_COLOURS.get(mode, _hex(PALETTE[(index + 6) % len(PALETTE)]))


def agent_colour(agent: str) -> str:
    """Blue for the worker, red for a robot (the recording's and the video's colours)."""
    return _hex(agent_color(agent))


def save_figure(fig, path: Path, dpi: int = 110) -> None:
    """Write ``fig`` as PNG atomically (no timestamp in the file, so equal figures give equal bytes)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
    plt.close(fig)
    write_bytes(path, buf.getvalue())

"""The colours of the plotted series (joints, RULA parts, angles, agents), shared by the figures, the
recordings and the video, so a joint or an agent looks the same everywhere. No plotting library here: the
figures (matplotlib) and the recordings (rerun) each import it without the other."""

from __future__ import annotations

from ergosim.ergonomics.rula import RULA_PARTS
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS

__all__ = ["Color", "PALETTE", "JOINT_COLORS", "RULA_COLORS", "ANGLE_COLORS", "AGENT_COLORS", "agent_color"]

Color = tuple[int, int, int]

PALETTE: tuple[Color, ...] = (
    (31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
    (140, 86, 75), (227, 119, 194), (127, 127, 127), (188, 189, 34), (23, 190, 207),
)
"""Ten distinguishable colours (matplotlib's tab10), cycled."""

JOINT_COLORS: dict[str, Color] = {j: PALETTE[i] for i, j in enumerate(KWEAR_JOINTS)}
RULA_COLORS: dict[str, Color] = {p: PALETTE[i % len(PALETTE)] for i, p in enumerate(RULA_PARTS)}
RULA_COLORS["grand"] = (20, 20, 20)
ANGLE_COLORS: dict[str, Color] = {n: PALETTE[i % len(PALETTE)] for i, n in enumerate(ANGLE_NAMES)}
AGENT_COLORS: dict[str, Color] = {"human": (31, 119, 180), "robot": (214, 39, 40)}


def agent_color(agent: str) -> Color:
    """Blue for a human, red for a robot (by name or kind), grey for anything else."""
    for kind, color in AGENT_COLORS.items():
        if kind in agent.lower():
            return color
    return PALETTE[7]

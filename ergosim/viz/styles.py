"""Names and colours of the plotted series, so every panel and every recording looks the same."""

from __future__ import annotations

import rerun as rr

from ergosim.colors import AGENT_COLORS, ANGLE_COLORS, JOINT_COLORS, PALETTE, RULA_COLORS, Color, agent_color

__all__ = ["PALETTE", "JOINT_COLORS", "RULA_COLORS", "ANGLE_COLORS", "AGENT_COLORS", "agent_color",
           "kwear_style", "threshold_style", "rula_style", "angle_style", "decision_style"]


def kwear_style(joint: str) -> rr.SeriesLines:
    return rr.SeriesLines(colors=[JOINT_COLORS[joint]], names=[joint], widths=[2.0])


def threshold_style(joint: str | None) -> rr.SeriesLines:
    """The V_th line: the joint's colour, faded and thin; ``None``: the one line shared by every joint, dark
    grey."""
    if joint is None:
        return rr.SeriesLines(colors=[(60, 60, 60, 200)], names=["V_th"], widths=[1.5])
    return rr.SeriesLines(colors=[(*JOINT_COLORS[joint], 140)], names=[f"V_th {joint}"], widths=[1.0])


def rula_style(part: str) -> rr.SeriesLines:
    """RULA scores are integers held between ticks: drawn as steps."""
    width = 3.0 if part == "grand" else 1.5
    return rr.SeriesLines(colors=[RULA_COLORS[part]], names=[part], widths=[width],
                          interpolation_mode="StepAfter")


def angle_style(name: str) -> rr.SeriesLines:
    return rr.SeriesLines(colors=[ANGLE_COLORS[name]], names=[f"{name} [deg]"], widths=[1.5])


def decision_style(name: str, color: Color) -> rr.SeriesPoints:
    """Decisions are instants, not signals: points, not lines."""
    return rr.SeriesPoints(colors=[color], names=[name], markers=["circle"], marker_sizes=[4.0])

"""The viewer layout, built in code: the workcell in 3-D beside KWear, the decision log under them.

::

    +-------------------------------+------------------------------------+
    |                               | KWear V(t) and V_th                |
    |  Workcell (3-D)               |   (legend in the band above V = 1) |
    |                               |                                    |
    +-------------------------------+------------------------------------+
    | Decisions and failures        | [RULA | Arm angles | Trunk & neck  |
    |  (sim time, repetition, text) |  | V̂ per action | Hyper-arc costs] |
    +-------------------------------+------------------------------------+

Legends never sit on the data: each time series' y axis runs past its data's range (KWear V ≤ 1, RULA
scores ≤ 7), and the legend sits in that empty band; the point series of the decisions (V̂ and costs, one
series per candidate, coloured by joint and by agent) hide theirs, and hovering a point names it. The
side panels start collapsed and the time panel compact, so the views get the screen.
"""

from __future__ import annotations

import rerun.blueprint as rrb
from rerun.blueprint import encodings as rre

from ergosim.posture import ANGLE_NAMES
from ergosim.viz import paths
from ergosim.viz.eye import Eye

__all__ = ["build_blueprint", "ARM_ANGLES", "ARM_RANGE", "TRUNK_RANGE", "KWEAR_RANGE", "RULA_RANGE"]

KWEAR_RANGE = (0.0, 1.4)
"""KWear V is in [0, 1] (eq. 3); the band above 1 holds the legend."""
RULA_RANGE = (0.0, 13.0)
"""RULA part and grand scores are at most 7; the band above holds the legend of eight series."""
ARM_RANGE = (-60.0, 420.0)
"""Arm angles stay within about -60..180 deg; the band above holds the legend."""
TRUNK_RANGE = (-90.0, 210.0)
"""Trunk and neck angles stay within about -90..90 deg; the band above holds the legend."""
ARM_ANGLES = tuple(n for n in ANGLE_NAMES if n.split("_")[0] in ("shoulder", "elbow", "forearm", "wrist"))
"""The dominant arm's angles; the other view of angles holds the trunk's and the neck's."""


def _legend_top() -> rrb.PlotLegend:
    return rrb.PlotLegend(corner="LeftTop", visible=True)


def _whole_run() -> rrb.VisibleTimeRange:
    """Plots show the whole recording, not a window around the time cursor."""
    return rrb.VisibleTimeRange(paths.SIM_TIME, start=rrb.TimeRangeBoundary.infinite(),
                                end=rrb.TimeRangeBoundary.infinite())


def _series(**kw) -> rrb.TimeSeriesView:
    whole = rrb.TimeRange(start=rrb.TimeRangeBoundary.infinite(), end=rrb.TimeRangeBoundary.infinite())
    return rrb.TimeSeriesView(time_ranges=_whole_run(), axis_x=rrb.TimeAxis(view_range=whole), **kw)


def _angles(name: str, names: tuple[str, ...], y_range: tuple[float, float]) -> rrb.TimeSeriesView:
    return _series(name=name, origin=paths.ANGLES,
                   contents=[paths.join(paths.ANGLES, n) for n in names],
                   axis_y=rrb.ScalarAxis(range=y_range), plot_legend=_legend_top())


def build_blueprint(eye: Eye | None = None, active_tab: int = 0,
                    cost_range: tuple[float, float] | None = None) -> rrb.Blueprint:
    """The blueprint sent with every recording (the viewer's "reset blueprint" returns to it); ``eye``: where
    the 3-D view's camera starts (:func:`ergosim.viz.eye.frame_scene`), else the viewer's own choice;
    ``active_tab``: the tab open beside the decision log (0 RULA, 1 and 2 the angles, 3 V̂, 4 the costs);
    ``cost_range``: the y range of the hyper-arc costs (their scale depends on c_r and Γ), else automatic."""
    controls = None
    if eye is not None:
        controls = rrb.EyeControls3D(kind="Orbital", position=eye.position, look_target=eye.look_target,
                                     eye_up=(0.0, 0.0, 1.0))
    workcell = rrb.Spatial3DView(name="Workcell", origin=paths.WORLD, line_grid=rrb.LineGrid3D(visible=True),
                                 eye_controls=controls)
    kwear = _series(
        name="KWear V(t) and V_th",
        origin="ergonomics",
        contents=[f"+ {paths.KWEAR}/**", f"+ {paths.KWEAR_THRESHOLD}/**", f"+ {paths.KWEAR_THRESHOLD}"],
        axis_y=rrb.ScalarAxis(range=KWEAR_RANGE),
        plot_legend=_legend_top(),
    )
    rula = _series(name="RULA", origin=paths.RULA, axis_y=rrb.ScalarAxis(range=RULA_RANGE),
                   plot_legend=_legend_top())
    trunk = tuple(n for n in ANGLE_NAMES if n not in ARM_ANGLES)
    log = rrb.TextLogView(
        name="Decisions and failures", origin=paths.ALLOCATION_LOG,
        columns=rrb.TextLogColumns(
            timeline_columns=[rre.TimelineColumn(paths.SIM_TIME, visible=True),
                              rre.TimelineColumn(paths.REPETITION, visible=True)],
            text_log_columns=[rre.TextLogColumn("LogLevel", visible=False),
                              rre.TextLogColumn("Body", visible=True),
                              rre.TextLogColumn("EntityPath", visible=False)]),
    )
    hidden = rrb.PlotLegend(visible=False)
    details = rrb.Tabs(
        rula,
        _angles("Arm angles [deg]", ARM_ANGLES, ARM_RANGE),
        _angles("Trunk & neck angles [deg]", trunk, TRUNK_RANGE),
        _series(name="Predicted KWear V̂", origin="allocation",
                contents=[f"+ {paths.V_HAT}/**", f"+ {paths.V_NOW}/**"],
                axis_y=rrb.ScalarAxis(range=(0.0, 1.0)), plot_legend=hidden),
        _series(name="Hyper-arc costs", origin=paths.COSTS, plot_legend=hidden,
                axis_y=rrb.ScalarAxis(range=cost_range) if cost_range else None),
        active_tab=active_tab,
    )
    return rrb.Blueprint(
        rrb.Vertical(
            rrb.Horizontal(workcell, kwear, column_shares=[1, 1]),
            rrb.Horizontal(log, details, column_shares=[3, 2]),
            row_shares=[3, 2],
        ),
        rrb.BlueprintPanel(state="collapsed"),
        rrb.SelectionPanel(state="collapsed"),
        rrb.TimePanel(timeline=paths.SIM_TIME, state="collapsed"),
    )

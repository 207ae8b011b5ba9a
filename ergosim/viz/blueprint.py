"""The viewer layout, built in code: the workcell in 3-D beside the ergonomics traces and the allocations.

::

    +--------------------+-------------------+-------------------------+
    |                    | KWear + V_th      | Allocations (text log)  |
    |  Workcell (3-D)    | RULA              +-------------------------+
    |                    | Joint angles      | V̂ per action | costs    |
    +--------------------+-------------------+-------------------------+
"""

from __future__ import annotations

import rerun.blueprint as rrb

from ergosim.viz import paths

__all__ = ["build_blueprint"]


def build_blueprint() -> rrb.Blueprint:
    """The default blueprint sent with every recording (the viewer's "reset blueprint" returns to it)."""
    workcell = rrb.Spatial3DView(name="Workcell", origin=paths.WORLD, line_grid=rrb.LineGrid3D(visible=True))
    kwear = rrb.TimeSeriesView(
        name="KWear V(t) and V_th",
        origin="ergonomics",
        contents=[f"+ {paths.KWEAR}/**", f"+ {paths.KWEAR_THRESHOLD}/**"],
        axis_y=rrb.ScalarAxis(range=(0.0, 1.0)),
        plot_legend=rrb.PlotLegend(corner="LeftTop"),
    )
    rula = rrb.TimeSeriesView(name="RULA", origin=paths.RULA, axis_y=rrb.ScalarAxis(range=(0.0, 7.5)),
                              plot_legend=rrb.PlotLegend(corner="LeftTop"))
    angles = rrb.TimeSeriesView(name="Joint angles [deg]", origin=paths.ANGLES,
                                plot_legend=rrb.PlotLegend(corner="LeftTop"))
    log = rrb.TextLogView(name="Allocations", origin=paths.ALLOCATION_LOG)
    decisions = rrb.Tabs(
        rrb.TimeSeriesView(name="Predicted KWear V̂", origin="allocation",
                           contents=[f"+ {paths.V_HAT}/**", f"+ {paths.V_NOW}/**"]),
        rrb.TimeSeriesView(name="Hyper-arc costs", origin=paths.COSTS),
    )
    return rrb.Blueprint(
        rrb.Horizontal(
            workcell,
            rrb.Vertical(kwear, rula, angles),
            rrb.Vertical(log, decisions, row_shares=[1, 1]),
            column_shares=[3, 3, 2],
        ),
        rrb.TimePanel(timeline=paths.SIM_TIME),
        collapse_panels=False,
    )

"""A still of a workcell as PNG bytes: built as a run builds it, rendered offscreen by MuJoCo in its initial
state (the worker at rest, the parts where they are laid out), from one of its named camera views."""

from __future__ import annotations

import io
import logging

from ergosim.errors import RenderError

__all__ = ["workcell_png", "run_still"]

log = logging.getLogger(__name__)

STILL_SIZE = (640, 480)
"""The run's still [px]: small enough to keep report.html a few hundred KB (assumed)."""


def workcell_png(spec, *, view: str | None = None, width: int = 960, height: int = 720) -> bytes:
    """PNG bytes of the workcell ``spec`` (a :class:`~ergosim.scenes.cellspec.CellSpec`) from ``view`` (its
    first by default), ``width`` × ``height`` px; a one-line :class:`~ergosim.errors.RenderError` when no
    OpenGL context can be opened (set ``MUJOCO_GL=egl`` on a machine without a display)."""
    import matplotlib.image  # noqa: PLC0415 - the PNG encoder, only where a still is made

    from ergosim.scenes import build_cell, render_workcell  # noqa: PLC0415
    from ergosim.video.frames import open_renderer  # noqa: PLC0415

    cell = build_cell(spec)
    cell.model.vis.global_.offwidth = max(int(cell.model.vis.global_.offwidth), width)
    cell.model.vis.global_.offheight = max(int(cell.model.vis.global_.offheight), height)
    open_renderer(cell.model, 64, 64).close()  # a one-line error when there is no OpenGL context
    image = render_workcell(cell, width=width, height=height, view=view)
    buf = io.BytesIO()
    matplotlib.image.imsave(buf, image, format="png", metadata={"Software": None})
    return buf.getvalue()


def run_still(scenario) -> bytes:
    """The still of ``scenario``'s workcell that a run keeps (``cell.png``), or b"" with a warning when this
    machine cannot render (the report then says so)."""
    try:
        return workcell_png(scenario.cell(), width=STILL_SIZE[0], height=STILL_SIZE[1])
    except RenderError as err:
        log.warning("no still of the workcell in the report: %s", err)
        return b""

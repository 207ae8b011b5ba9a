"""A horizontal surface that carries parts and targets, and the turn of a point by a furniture's yaw.

Lengths in metres, angles in degrees, world frame as in :mod:`ergosim.scenes.cellspec` (z up). A surface
turned by a yaw keeps its ``size`` along its own axes; points given to it (a part's ``xy``) are in the world
frame and are asked about in the surface's own frame.
"""

from __future__ import annotations

import dataclasses
import math

__all__ = ["Surface", "turned"]


@dataclasses.dataclass(frozen=True)
class Surface:
    """A horizontal support: centre (x, y) [m], size (along its own x, along its own y) [m], top height [m],
    turned by ``yaw`` [deg] about its centre."""

    name: str
    center: tuple[float, float]
    size: tuple[float, float]
    height: float
    yaw: float = 0.0

    def local(self, xy) -> tuple[float, float]:
        """The world point ``xy`` [m] in the surface's own frame (origin at its centre, turned by its yaw)."""
        dx, dy = xy[0] - self.center[0], xy[1] - self.center[1]
        if self.yaw == 0.0:
            return dx, dy
        c, s = math.cos(math.radians(self.yaw)), math.sin(math.radians(self.yaw))
        return c * dx + s * dy, -s * dx + c * dy

    def contains(self, xy, margin: float = 0.0) -> bool:
        """Whether the world point ``xy`` [m] lies on the surface, at least ``margin`` [m] inside its edges
        (measured in its own turned frame)."""
        d = self.local(xy)
        return all(abs(d[i]) <= self.size[i] / 2 - margin for i in range(2))

    def clamp(self, xy, margin: float = 0.0) -> tuple[float, float]:
        """The world point ``xy`` [m] moved onto the surface, at least ``margin`` [m] inside its edges (or at
        its centre line where it is narrower), clamped in its own turned frame."""
        half = [max(self.size[i] / 2 - margin, 0.0) for i in range(2)]
        if self.yaw == 0.0:  # in world coordinates, as before turned surfaces: the same bits
            return (min(max(xy[0], self.center[0] - half[0]), self.center[0] + half[0]),
                    min(max(xy[1], self.center[1] - half[1]), self.center[1] + half[1]))
        d = self.local(xy)
        return turned(self.center, [min(max(d[i], -half[i]), half[i]) for i in range(2)], self.yaw)


def turned(center, offset, yaw: float) -> tuple[float, float]:
    """The world point (x, y) [m] at ``offset`` (x, y) [m] from ``center`` in a frame turned by ``yaw``
    [deg]."""
    if yaw == 0.0:
        return center[0] + offset[0], center[1] + offset[1]
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    return center[0] + c * offset[0] - s * offset[1], center[1] + s * offset[0] + c * offset[1]

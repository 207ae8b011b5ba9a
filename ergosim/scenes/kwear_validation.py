"""Workcell of the KWear validation experiment (paper §7.1, Fig. "setup2").

A workbench in front of the worker, shared with the robot; a shelf at the worker's right with J on its top
ledge; the finished assembly goes onto the shelf's lower ledge. The shelf is stepped (the top ledge covers
only its back part) so both ledges are reachable from above. Actions: a1 J from the top ledge to the bench
near the worker; a2-a4 insert L (right hollow), S1 (upper hollow), S2 (left hollow); a5 the assembly to
the lower ledge.
"""

from __future__ import annotations

import dataclasses

from ergosim.errors import ConfigError
from ergosim.scenes import build
from ergosim.scenes.config import Hollow, Surface, WorkcellConfig
from ergosim.scenes.parts import rest_height
from ergosim.scenes.workcell import ActionGeometry, Workcell

__all__ = ["NAME", "KWearValidationConfig", "default_config", "build_workcell"]

NAME = "kwear-validation"


@dataclasses.dataclass(frozen=True)
class KWearValidationConfig(WorkcellConfig):
    """Shelf footprint centre (x, y) and size [m]; ledge heights [m]; ``top_ledge_depth`` [m] from the
    shelf's back (its -y side). Part placements: (x, y) [m] and yaw [deg]."""

    robot_base: tuple[float, float, float] = (0.64, -0.36, 1.05)
    bench_size: tuple[float, float] = (0.64, 1.0)
    carry_height: float = 1.38
    shelf_center: tuple[float, float] = (0.03, -0.62)
    shelf_size: tuple[float, float] = (0.50, 0.50)
    shelf_height: float = 1.45
    """Top ledge (where J starts) [m]."""
    shelf_low_height: float = 1.0
    """Lower ledge (where the assembly goes) [m]."""
    top_ledge_depth: float = 0.25
    hollow_L: Hollow = "x"
    hollow_S1: Hollow = "z"
    hollow_S2: Hollow = "y"
    j_xy: tuple[float, float] = (0.18, -0.74)
    j_yaw: float = -45.0
    l_xy: tuple[float, float] = (0.36, -0.14)
    l_yaw: float = 90.0
    s1_xy: tuple[float, float] = (0.36, 0.33)
    s1_yaw: float = 90.0
    s2_xy: tuple[float, float] = (0.48, 0.33)
    s2_yaw: float = 90.0
    j_place_xy: tuple[float, float] = (0.42, 0.08)
    """a1: where J goes on the bench, near the worker [m]."""
    j_place_yaw: float = -45.0
    assembly_xy: tuple[float, float] = (0.15, -0.46)
    """a5: where J (with the profiles) goes on the lower ledge [m]."""
    assembly_yaw: float = 180.0

    def shelf_ledges(self) -> tuple[Surface, Surface]:
        (cx, cy), (sx, sy) = self.shelf_center, self.shelf_size
        low = Surface("shelf_low", (cx, cy), (sx, sy), self.shelf_low_height)
        back = cy - sy / 2
        top = Surface("shelf_top", (cx, back + self.top_ledge_depth / 2), (sx, self.top_ledge_depth),
                      self.shelf_height)
        return top, low

    def surfaces(self) -> dict[str, Surface]:
        top, low = self.shelf_ledges()
        return {**super().surfaces(), "shelf_top": top, "shelf_low": low}

    def placements(self) -> dict[str, tuple[str, tuple[float, float], float]]:
        return {"J": ("shelf_top", self.j_xy, self.j_yaw), "L": ("bench", self.l_xy, self.l_yaw),
                "S1": ("bench", self.s1_xy, self.s1_yaw), "S2": ("bench", self.s2_xy, self.s2_yaw)}

    def validate(self, where: str = "kwear-validation") -> None:
        super().validate(where)
        if not self.shelf_height - self.shelf_low_height >= 0.3:
            raise ConfigError(f"the top ledge must be >= 0.3 m above the lower one, got {self.shelf_height} "
                              f"and {self.shelf_low_height}", where=where)
        if not 0.1 <= self.top_ledge_depth <= self.shelf_size[1] - 0.1:
            raise ConfigError(f"top_ledge_depth must leave >= 0.1 m of the lower ledge open, got "
                              f"{self.top_ledge_depth}", where=where)
        surfaces = self.surfaces()
        for key, surf in (("j_place_xy", "bench"), ("assembly_xy", "shelf_low")):
            if not surfaces[surf].contains(getattr(self, key), margin=0.02):
                raise ConfigError(f"{key}={getattr(self, key)} is not on the {surf}", where=where)


def default_config() -> KWearValidationConfig:
    return KWearValidationConfig()


def _add_shelf(spec, cfg: KWearValidationConfig) -> None:
    top, low = cfg.shelf_ledges()
    build.add_table(spec, low, thickness=0.03, legs=True)
    build.add_table(spec, top, thickness=0.03, legs=False)
    (cx, _), (sx, _) = top.center, top.size
    front = top.center[1] + top.size[1] / 2 - 0.02
    back = top.center[1] - top.size[1] / 2 + 0.02
    rise = (top.height - low.height) / 2
    for i, (x, y) in enumerate([(cx - sx / 2 + 0.02, front), (cx + sx / 2 - 0.02, front),
                                (cx - sx / 2 + 0.02, back), (cx + sx / 2 - 0.02, back)]):
        build.add_box(spec, f"shelf_post{i}", (x, y, low.height + rise), (0.02, 0.02, rise))


def build_workcell(cfg: KWearValidationConfig | None = None) -> Workcell:
    cfg = cfg or default_config()
    cfg.validate()
    spec = build.new_spec(NAME, cfg)
    build.add_table(spec, cfg.surfaces()["bench"])
    _add_shelf(spec, cfg)
    build.attach_panda(spec, cfg, support_height=cfg.bench_height)
    hands = {"robot": "panda_hand"}
    human = build.attach_human(spec, cfg)
    hands.update(build.human_hand_bodies(spec))
    build.add_parts(spec, cfg)
    j_rest = rest_height(cfg.dims, "J")
    spec.worldbody.add_site(name="bench_target", pos=[*cfg.j_place_xy, cfg.bench_height + j_rest],
                            quat=build.yaw_quat(cfg.j_place_yaw), group=4)
    spec.worldbody.add_site(name="shelf_target", pos=[*cfg.assembly_xy, cfg.shelf_low_height + j_rest],
                            quat=build.yaw_quat(cfg.assembly_yaw), group=4)
    build.add_welds(spec, hands)
    model = build.finish(spec, where=NAME)
    actions = {
        "a1": ActionGeometry("a1", "J", "place", "bench_target"),
        "a2": ActionGeometry("a2", "L", "insert", "J_hollow_L"),
        "a3": ActionGeometry("a3", "S1", "insert", "J_hollow_S1"),
        "a4": ActionGeometry("a4", "S2", "insert", "J_hollow_S2"),
        "a5": ActionGeometry("a5", "J", "place", "shelf_target"),
    }
    return Workcell(NAME, model, cfg, actions, hands, human=human)

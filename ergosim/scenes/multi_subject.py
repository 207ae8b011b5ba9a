"""Workcell of the multi-subject experiment (paper §7.2, Fig. "exp_setup_3").

The pieces and the robot are on a side table at the worker's left; the assembly area and the allocation
monitor are in front of the worker. A robot action is a handover at a pre-planned pose between the robot
and the worker, who then places or inserts the part. a5 (always the worker's) moves the assembly away to
the outfeed on the right, where a second operator takes it.
"""

from __future__ import annotations

import dataclasses

from ergosim.errors import ConfigError
from ergosim.scenes import build
from ergosim.scenes.config import Hollow, Surface, WorkcellConfig
from ergosim.scenes.parts import rest_height
from ergosim.scenes.workcell import ActionGeometry, Workcell

__all__ = ["NAME", "MultiSubjectConfig", "default_config", "build_workcell"]

NAME = "multi-subject"


@dataclasses.dataclass(frozen=True)
class MultiSubjectConfig(WorkcellConfig):
    """Side table (centre, size, height) [m]; monitor centre (x, y, z) and half sizes [m]; handover
    position (x, y, z) [m] and yaw [deg] of the handed part; placements (x, y) [m], yaw [deg]."""

    robot_base: tuple[float, float, float] = (0.62, 0.82, 0.85)
    robot_yaw: float = -120.0
    bench_size: tuple[float, float] = (0.64, 1.0)
    side_table_center: tuple[float, float] = (0.36, 0.80)
    side_table_size: tuple[float, float] = (0.76, 0.50)
    side_table_height: float = 0.85
    monitor_center: tuple[float, float, float] = (0.88, 0.0, 1.28)
    monitor_half: tuple[float, float, float] = (0.025, 0.27, 0.17)
    hollow_L: Hollow = "z"
    hollow_S1: Hollow = "y"
    hollow_S2: Hollow = "x"
    j_xy: tuple[float, float] = (0.30, 0.66)
    j_yaw: float = -45.0
    l_xy: tuple[float, float] = (0.26, 0.76)
    """L lies farthest from the worker, on the side table, still within reach of a 1.6 m subject who bends
    and twists (paper §7.2: a2 grasps the object in the furthest location)."""
    l_yaw: float = 90.0
    s1_xy: tuple[float, float] = (0.48, 0.34)
    """S1 and S2 lie close to the worker, on the near-left edge of the bench (paper §7.2: a3, a4)."""
    s1_yaw: float = 0.0
    s2_xy: tuple[float, float] = (0.50, 0.43)
    s2_yaw: float = 0.0
    assembly_xy: tuple[float, float] = (0.42, 0.0)
    assembly_yaw: float = -45.0
    handover_pos: tuple[float, float, float] = (0.36, 0.38, 1.12)
    handover_yaw: float = 0.0
    outfeed_xy: tuple[float, float] = (0.50, -0.38)

    def surfaces(self) -> dict[str, Surface]:
        side = Surface("side_table", self.side_table_center, self.side_table_size, self.side_table_height)
        return {**super().surfaces(), "side_table": side}

    def placements(self) -> dict[str, tuple[str, tuple[float, float], float]]:
        """Each part rests on the surface under its (x, y): the side table, or the bench's near-left edge."""
        bench = self.surfaces()["bench"]

        def on(xy: tuple[float, float]) -> str:
            return "bench" if bench.contains(xy) else "side_table"

        return {"J": (on(self.j_xy), self.j_xy, self.j_yaw), "L": (on(self.l_xy), self.l_xy, self.l_yaw),
                "S1": (on(self.s1_xy), self.s1_xy, self.s1_yaw),
                "S2": (on(self.s2_xy), self.s2_xy, self.s2_yaw)}

    def validate(self, where: str = "multi-subject") -> None:
        super().validate(where)
        bench = self.surfaces()["bench"]
        for key in ("assembly_xy", "outfeed_xy"):
            if not bench.contains(getattr(self, key), margin=0.02):
                raise ConfigError(f"{key}={getattr(self, key)} is not on the bench", where=where)
        if not self.handover_pos[2] > self.bench_height + 0.1:
            raise ConfigError(f"handover_pos must be >= 0.1 m above the bench, got {self.handover_pos}",
                              where=where)


def default_config() -> MultiSubjectConfig:
    return MultiSubjectConfig()


def build_workcell(cfg: MultiSubjectConfig | None = None) -> Workcell:
    cfg = cfg or default_config()
    cfg.validate()
    spec = build.new_spec(NAME, cfg)
    surfaces = cfg.surfaces()
    build.add_table(spec, surfaces["bench"])
    build.add_table(spec, surfaces["side_table"])
    mx, my, mz = cfg.monitor_center
    hx, hy, hz = cfg.monitor_half
    build.add_box(spec, "monitor", (mx, my, mz), (hx, hy, hz), rgba=(0.08, 0.08, 0.1, 1))
    stand = (mz - hz - cfg.bench_height) / 2
    build.add_box(spec, "monitor_stand", (mx + 0.01, my, cfg.bench_height + stand), (0.015, 0.04, stand))
    build.attach_panda(spec, cfg, support_height=cfg.side_table_height)
    hands = {"robot": "panda_hand"}
    human = build.attach_human(spec, cfg)
    hands.update(build.human_hand_bodies(spec))
    build.add_parts(spec, cfg)
    j_rest = rest_height(cfg.dims, "J")
    spec.worldbody.add_site(name="assembly_area", pos=[*cfg.assembly_xy, cfg.bench_height + j_rest],
                            quat=build.yaw_quat(cfg.assembly_yaw), group=4)
    spec.worldbody.add_site(name="outfeed", pos=[*cfg.outfeed_xy, cfg.bench_height + j_rest],
                            quat=build.yaw_quat(cfg.assembly_yaw), group=4)
    spec.worldbody.add_site(name="handover", pos=list(cfg.handover_pos),
                            quat=build.yaw_quat(cfg.handover_yaw), group=4)
    build.add_welds(spec, hands)
    model = build.finish(spec, where=NAME)
    actions = {
        "a1": ActionGeometry("a1", "J", "place", "assembly_area", handover="handover"),
        "a2": ActionGeometry("a2", "L", "insert", "J_hollow_L", handover="handover"),
        "a3": ActionGeometry("a3", "S1", "insert", "J_hollow_S1", handover="handover"),
        "a4": ActionGeometry("a4", "S2", "insert", "J_hollow_S2", handover="handover"),
        "a5": ActionGeometry("a5", "J", "remove", "outfeed"),
    }
    return Workcell(NAME, model, cfg, actions, hands, human=human)

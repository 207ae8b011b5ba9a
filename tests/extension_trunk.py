"""A new ergonomic index with a posture feature of its own, in one module: importing it registers the
feature, the risk index and a mode that prices the worker with it. Nothing outside this module knows it.

The feature is the trunk inclination zone of ISO 11226:2000 §4.2.1 (evaluation of static working
postures): 1 for a forward inclination of 0-20° (acceptable), 2 for 20-60° (acceptable depending on the
holding time), 3 beyond 60° or bent backwards (not acceptable without full trunk support); NaN for a mocap
dropout. The index is a static baseline on it: an action whose zone G(a_k) (held longest over the
calibration, as the RULA baseline's) reaches 3 goes to the robot.
"""

from __future__ import annotations

import numpy as np

from ergosim.ergonomics.cost import rula_baseline_params
from ergosim.ergonomics.features import Feature, FeatureScores, Frames, register_feature
from ergosim.ergonomics.risk_index import StaticRulaIndex
from ergosim.posture import ANGLE_NAMES
from ergosim.twin.modes import Mode, RiskIndexEntry, register_mode, register_risk_index

ZONE_EDGES = (0.0, 20.0, 60.0)
"""Trunk inclination zones' edges [deg] (ISO 11226:2000 §4.2.1)."""
NOT_ACCEPTABLE = 3.0


def trunk_zone(frames: Frames) -> FeatureScores:
    """The zone (n,) of each frame's trunk flexion [deg], as the index's one input and its whole score."""
    flexion = np.asarray(frames.angles, dtype=float)[:, ANGLE_NAMES.index("trunk_flexion")]
    inside = [flexion <= ZONE_EDGES[1], flexion <= ZONE_EDGES[2]]
    zone = np.where(flexion < ZONE_EDGES[0], NOT_ACCEPTABLE, np.select(inside, [1.0, 2.0], NOT_ACCEPTABLE))
    zone[np.isnan(flexion)] = np.nan
    return FeatureScores(zone[:, None], zone[:, None], zone)


register_feature(Feature("iso-trunk", ("trunk",), "iso_trunk_zone", "ISO 11226 trunk inclination zone, 1..3",
                         ("iso_trunk_zone",), trunk_zone))


class TrunkZoneIndex(StaticRulaIndex):
    """The static rule of the RULA baseline on the trunk zone G(a_k) of each action (G_max 3)."""

    features = "iso-trunk"
    joints = ("trunk",)
    channels = ("iso-trunk",)
    score_name = "ISO 11226 trunk zone"


def _build(ctx):
    cost = ctx.protocol.cost
    return (TrunkZoneIndex(ctx.calibration.grand_scores, g_max=NOT_ACCEPTABLE),
            rula_baseline_params(cost.robot_cost, cost.gamma, g_th=NOT_ACCEPTABLE, g_max=NOT_ACCEPTABLE))


register_risk_index(RiskIndexEntry("iso-trunk-static", _build, features="iso-trunk"))
register_mode(Mode("iso-trunk", "ISO 11226 trunk zone baseline (zone 3 goes to the robot)",
                   risk_index="iso-trunk-static"))

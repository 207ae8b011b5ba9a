"""Ergonomic assessment (paper §4-5): RULA and REBA per body part, the Kinematic Wear index, its calibration,
the per-worker parameter store, risk indices and the hyper-arc cost model."""

from __future__ import annotations

from ergosim.ergonomics.calibration import (
    ActionCalibration,
    Calibration,
    Execution,
    calibrate,
    calibrate_action,
    execution_from_angles,
    online_alpha,
)
from ergosim.ergonomics.cost import (
    G_MAX_PAPER,
    CostParams,
    CostRangeWarning,
    gamma_terms,
    human_cost,
    hyperarc_costs,
    risk_costs,
    rula_baseline_agent,
    rula_baseline_params,
)
from ergosim.ergonomics.features import FEATURES, Feature, feature
from ergosim.ergonomics.kwear import V_CEIL, KWearParams, alpha_of, kwear_step, kwear_trajectory, predict
from ergosim.ergonomics.param_store import ParamStore, WorkerParams
from ergosim.ergonomics.reba import (
    KNEE_ANGLES,
    REBA_INPUTS,
    REBA_JOINTS,
    REBA_PARTS,
    RebaResult,
    RebaThresholds,
    reba,
    reba_part_scores,
    reba_table_a,
    reba_table_b,
    reba_table_c,
)
from ergosim.ergonomics.reba_parts import COUPLINGS, coupling_score, grip_coupling, load_score
from ergosim.ergonomics.reba_tables import risk_level
from ergosim.ergonomics.risk_index import (
    REBA_G_HIGH,
    REBA_G_MAX,
    KWearIndex,
    RiskIndex,
    StaticRebaIndex,
    StaticRulaIndex,
)
from ergosim.ergonomics.rula import (
    RULA_INPUTS,
    RULA_PARTS,
    RulaResult,
    RulaThresholds,
    action_level,
    part_scores,
    rula,
    table_a,
    table_b,
    table_c,
)
from ergosim.ergonomics.rula_action import action_grand_score, most_loaded_joint

__all__ = [
    # RULA
    "RULA_INPUTS",
    "RULA_PARTS",
    "RulaResult",
    "RulaThresholds",
    "rula",
    "table_a",
    "table_b",
    "table_c",
    "action_level",
    "part_scores",
    "action_grand_score",
    "most_loaded_joint",
    # REBA
    "REBA_INPUTS",
    "REBA_PARTS",
    "REBA_JOINTS",
    "KNEE_ANGLES",
    "RebaResult",
    "RebaThresholds",
    "reba",
    "reba_table_a",
    "reba_table_b",
    "reba_table_c",
    "reba_part_scores",
    "risk_level",
    "COUPLINGS",
    "coupling_score",
    "grip_coupling",
    "load_score",
    # KWear
    "KWearParams",
    "V_CEIL",
    "kwear_step",
    "kwear_trajectory",
    "alpha_of",
    "predict",
    # calibration and parameters
    "Execution",
    "ActionCalibration",
    "Calibration",
    "execution_from_angles",
    "calibrate_action",
    "calibrate",
    "online_alpha",
    "WorkerParams",
    "ParamStore",
    # risk indices and costs
    "RiskIndex",
    "KWearIndex",
    "StaticRulaIndex",
    "StaticRebaIndex",
    "REBA_G_MAX",
    "REBA_G_HIGH",
    "Feature",
    "FEATURES",
    "feature",
    "CostParams",
    "CostRangeWarning",
    "G_MAX_PAPER",
    "gamma_terms",
    "human_cost",
    "hyperarc_costs",
    "risk_costs",
    "rula_baseline_params",
    "rula_baseline_agent",
]


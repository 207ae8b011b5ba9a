"""What the paper reports about its two experiments (shared/paper.tex §7), as data for the fidelity report.

Every figure carries the place it is printed. The twin is compared with these in
:mod:`ergosim.fidelity.checks`; nothing here feeds the simulation.
"""

from __future__ import annotations

from types import MappingProxyType

__all__ = ["TABLE1_KWEAR", "TABLE1_RULA", "G_KWEAR_VALIDATION", "LOADED_JOINT_KWEAR_VALIDATION",
           "G_MULTI_SUBJECT", "ROBOT_SHARE", "ROBOT_SHARE_BY_ACTION", "TAKT_S", "ROBOT_ONLY_S",
           "STATS_P_MAX", "ACTIONS"]

ACTIONS = ("a1", "a2", "a3", "a4", "a5")

TABLE1_KWEAR = ("HHHHH", "RHHHR", "HHHRH", "HRHHH")
"""§7.1, Table 1 (bottom): the KWear allocation of a1..a5 in rp1..rp4 (H worker, R robot)."""
TABLE1_RULA = "HHHHH"
"""§7.1, Table 1 (bottom): the static RULA baseline, the same in every repetition."""
G_KWEAR_VALIDATION = MappingProxyType({"a1": 5, "a2": 3, "a3": 3, "a4": 4, "a5": 4})
"""§7.1, Table 1 (top): RULA grand score G(a_k) of each action."""
LOADED_JOINT_KWEAR_VALIDATION = MappingProxyType({"a1": "shoulder", "a2": "neck", "a5": "trunk"})
"""§7.1 "Results" and Fig. KWear125: a1 raised the arm (shoulder), a2 bent the neck, a5 twisted the trunk."""
G_MULTI_SUBJECT = MappingProxyType({"a1": 4, "a2": 5, "a3": 3, "a4": 3, "a5": 4})
"""§7.2 "Experimental Setup and Protocol": G(a2) = 5, G(a3) = G(a4) = 3, G(a1) = G(a5) = 4."""
ROBOT_SHARE = 179 / 480
"""§7.2 "Results": 179 of the 480 allocated actions (12 subjects x 10 repetitions x a1..a4) to the robot."""
ROBOT_SHARE_BY_ACTION = MappingProxyType({"a1": 0.51, "a2": 0.78, "a3": 0.10, "a4": 0.10})
"""§7.2 "Results": a1 51 %, a2 78 %, a3 and a4 10 % to the robot."""
TAKT_S = 38.0
"""§7.2: T_takt = 38 s."""
ROBOT_ONLY_S = 38.0
"""§7.2: the takt was "the average time the robot took to execute the whole assembly" at 0.05 m/s."""
STATS_P_MAX = 0.01
"""§7.2: physical demand lower in HRC, Wilcoxon signed-rank p < 0.01 (W = 1.5, 12 subjects)."""

"""Task planning: AND/OR graphs with per-agent hyper-arcs, task files, generators and the planners.

``load_task``/``parse_task`` read TOML task files, ``generate_task`` builds the complexity-study tasks,
``corner_joint_task`` the bundled corner joint; :meth:`AndOrGraph.plan` re-plans from any configuration
with the ``fast`` (bottom-up) or ``paper`` (Algorithm 1) planner.
"""

from ergosim.planner.agents import Agent, Operation
from ergosim.planner.bundled import BUNDLED_TASKS, CORNER_JOINT_VARIANTS, bundled_task, corner_joint_task
from ergosim.planner.generators import generate_task
from ergosim.planner.graph import PLANNERS, AndOrGraph
from ergosim.planner.liaisons import Liaison
from ergosim.planner.paper_search import SearchBudgetExceeded
from ergosim.planner.plan import Plan, PlanStep, replan_until_done
from ergosim.planner.taskfile import load_task, parse_task

__all__ = [
    "AndOrGraph",
    "Agent",
    "Operation",
    "Liaison",
    "Plan",
    "PlanStep",
    "PLANNERS",
    "load_task",
    "parse_task",
    "generate_task",
    "corner_joint_task",
    "bundled_task",
    "BUNDLED_TASKS",
    "CORNER_JOINT_VARIANTS",
    "replan_until_done",
    "SearchBudgetExceeded",
]

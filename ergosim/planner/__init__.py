"""Task planning: AND/OR graphs with per-agent hyper-arcs, task files, generators and the planners.

``load_task``/``parse_task`` read TOML task files, ``generate_task`` builds the complexity-study tasks,
``bundled_task`` the bundled tasks (the paper's corner joint, a gearbox); :meth:`AndOrGraph.plan`
re-plans from any configuration with the ``fast`` (bottom-up) or ``paper`` (Algorithm 1) planner;
``team_assign`` gives every idle agent of a team its best ready operation (parallel execution).
"""

from ergosim.planner.agents import Agent, Operation
from ergosim.planner.bundled import BUNDLED_TASKS, bundled_task, bundled_task_source, bundled_task_text
from ergosim.planner.compiled import CompiledGraph
from ergosim.planner.generators import generate_task
from ergosim.planner.graph import PLANNERS, AndOrGraph
from ergosim.planner.liaisons import Liaison
from ergosim.planner.op_table import OperationTable
from ergosim.planner.outside import outside_costs, through_costs
from ergosim.planner.paper_search import SearchBudgetExceeded, SearchMemoryExceeded
from ergosim.planner.plan import Plan, PlanStep
from ergosim.planner.replan import replan_until_done
from ergosim.planner.taskfile import load_task, parse_task, task_from_dict
from ergosim.planner.team import TeamAssignment, TeamStep, team_assign

__all__ = [
    "AndOrGraph",
    "CompiledGraph",
    "OperationTable",
    "Agent",
    "Operation",
    "Liaison",
    "Plan",
    "PlanStep",
    "PLANNERS",
    "load_task",
    "parse_task",
    "task_from_dict",
    "generate_task",
    "bundled_task_source",
    "bundled_task_text",
    "bundled_task",
    "BUNDLED_TASKS",
    "replan_until_done",
    "SearchBudgetExceeded",
    "SearchMemoryExceeded",
    "team_assign",
    "TeamStep",
    "TeamAssignment",
    "outside_costs",
    "through_costs",
]

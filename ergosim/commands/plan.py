"""``ergosim plan``: the optimal allocation plan of a task file, a bundled task or a generated task.

ergosim plan TASK.toml [--done OP,OP,...] [--planner fast|paper] [--json]
ergosim plan corner-joint[:multi-subject|:kwear-validation] [...]
ergosim plan --generate sequential:N|scarce:N --agents K [--seed S] [--json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ergosim.errors import ConfigError
from ergosim.planner import BUNDLED_TASKS, PLANNERS, AndOrGraph, Plan, bundled_task, generate_task, load_task

__all__ = ["add_parser", "run", "resolve_task", "plan_json", "plan_table"]


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "plan",
        help="optimal allocation plan of an assembly task",
        description=(
            "Plan an assembly task with the AO* role allocator: which operation comes next and which agent "
            "does it. TASK is a task file (.toml) or a bundled task: " + ", ".join(BUNDLED_TASKS) + "."
        ),
    )
    parser.add_argument("task", nargs="?", metavar="TASK", help="task file or bundled task name")
    parser.add_argument(
        "--generate", metavar="SPEC", help="generate sequential:N or scarce:N instead of reading TASK"
    )
    parser.add_argument("--agents", type=int, help="agents of a generated task (default 2)")
    parser.add_argument("--seed", type=int, help="seed of a generated task's costs (default 0)")
    parser.add_argument("--done", default="", metavar="OP,OP,...", help="operations already done")
    parser.add_argument("--planner", choices=PLANNERS, default="fast", help="planner (default fast)")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    return parser


def resolve_task(task: str) -> AndOrGraph:
    """A task file path, else a bundled task name."""
    if Path(task).is_file() or task.endswith(".toml"):
        return load_task(task)
    if task in BUNDLED_TASKS:
        return bundled_task(task)
    raise ConfigError(
        f"no such task file or bundled task {task!r}; bundled tasks are {list(BUNDLED_TASKS)}", where="TASK"
    )


def plan_json(graph: AndOrGraph, plan: Plan) -> dict[str, object]:
    """``{"cost", "next", "plan", "nodes", "hyperarcs"}``; hyper-arcs are counted per agent."""
    return {**plan.to_dict(), "nodes": graph.n_nodes, "hyperarcs": graph.n_hyperarcs}


def plan_table(graph: AndOrGraph, plan: Plan, done: list[str], planner: str) -> str:
    """The plan as a readable table."""
    lines = [
        f"task {graph.name}: {len(graph.parts)} parts, {len(graph.agents)} agents, "
        f"{graph.n_nodes} nodes, {graph.n_hyperarcs} hyper-arcs; planner {planner}",
        "done: " + (", ".join(done) if done else "-"),
    ]
    if plan.next is None:
        lines.append("assembly complete: nothing left to do")
        return "\n".join(lines)
    rows = [("#", "operation", "action", "agent", "cost")]
    rows += [(str(i), s.operation, s.action, s.agent, f"{s.cost:.4g}") for i, s in enumerate(plan.steps, 1)]
    widths = [max(len(r[k]) for r in rows) for k in range(5)]
    for r in rows:
        cells = [r[0].rjust(widths[0])] + [r[k].ljust(widths[k]) for k in (1, 2, 3)] + [r[4].rjust(widths[4])]
        lines.append("  ".join(cells).rstrip())
    step = plan.next
    lines.append(f"total cost {plan.cost:.6g}; next: {step.action} ({step.operation}) by {step.agent}")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    if args.generate is not None:
        if args.task is not None:
            raise ConfigError("give either TASK or --generate, not both", where="--generate")
        graph = generate_task(
            args.generate, 2 if args.agents is None else args.agents, 0 if args.seed is None else args.seed
        )
    else:
        if args.task is None:
            raise ConfigError(
                f"give a task file, a bundled task ({', '.join(BUNDLED_TASKS)}) or --generate", where="TASK"
            )
        if args.agents is not None or args.seed is not None:
            raise ConfigError("--agents and --seed only apply to --generate", where="--agents/--seed")
        graph = resolve_task(args.task)
    done = [op.strip() for op in args.done.split(",") if op.strip()]
    plan = graph.plan(done=done, planner=args.planner)
    if args.json:
        print(json.dumps(plan_json(graph, plan), allow_nan=False))
    else:
        print(plan_table(graph, plan, done, args.planner))
    return 0

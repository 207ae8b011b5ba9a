"""``ergosim plan``: the optimal allocation plan of a task file, a bundled task or a generated task.

ergosim plan TASK.toml [--done OP|ACTION,...] [--planner fast|paper] [--json]
ergosim plan corner-joint[:multi-subject|:kwear-validation] [--state kwear_state_s0_hrc.json] [...]
ergosim plan TASK [--costs human.a2=3.1,robot.a3=0.5]
ergosim plan --generate sequential:N|scarce:N --agents K [--seed S] [--json]

``--state`` takes a KWear state file as ``ergosim run`` writes it (:mod:`ergosim.experiment.kwear_state`): the
worker's KWear V and calibrated α. Every human hyper-arc of a remaining action is then priced with eq. 9-11
(V̂ = 1 − α(1 − V); c = Σ_i V̂_i + Γ [V̂_i ≥ V_th]) and every robot hyper-arc with the run's c_r, which is the
allocation the twin would make from that state. ``--costs`` overrides single (agent, action) costs after
that, for quick what-ifs.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ergosim.errors import ConfigError
from ergosim.planner import BUNDLED_TASKS, PLANNERS, AndOrGraph, Plan, bundled_task, generate_task, load_task

__all__ = ["add_parser", "run", "resolve_task", "resolve_done", "parse_costs", "state_costs_for", "plan_json",
           "plan_table"]


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
    parser.add_argument("--done", default="", metavar="OP,OP,...",
                        help="operations already done, by operation name (area+J) or action label (a1)")
    parser.add_argument("--state", metavar="FILE.json",
                        help="price the human's hyper-arcs from a KWear state written by `ergosim run` "
                             "(kwear_state_s<subject>_<mode>.json; eq. 9-11)")
    parser.add_argument("--costs", default="", metavar="AGENT.ACTION=COST,...",
                        help="override hyper-arc costs, e.g. human.a2=3.1,robot.a3=0.5")
    parser.add_argument("--max-states", type=int, metavar="N",
                        help="memory budget of --planner paper: configurations it may create "
                             "(default 1000000)")
    parser.add_argument("--planner", choices=PLANNERS, default="fast", help="planner (default fast)")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    return parser


def resolve_task(task: str) -> AndOrGraph:
    """A task file path, else a bundled task name."""
    if Path(task).exists() or task.endswith(".toml"):  # load_task refuses directories, devices and pipes
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


def resolve_done(graph: AndOrGraph, items: list[str]) -> list[str]:
    """Operation names from ``--done`` items: an operation name stays, an action label becomes the one
    operation of that action that fits the configuration reached by the items before it."""
    names = {op.name for op in graph.operations}
    done: list[str] = []
    for item in items:
        if item in names:
            done.append(item)
            continue
        ops = [op.name for op in graph.operations if op.action == item]
        if not ops:
            raise ConfigError(f"{item!r} is neither an operation nor an action of task {graph.name!r}; "
                              f"actions are {', '.join(graph.actions)}", where="--done")
        fits = []
        for name in ops:
            try:
                graph.configuration([*done, name])
            except ConfigError:
                continue
            fits.append(name)
        if len(fits) != 1:
            why = "none fits" if not fits else f"{len(fits)} fit ({', '.join(fits)}); give the operation name"
            raise ConfigError(f"action {item!r} is done by operations {', '.join(ops)}: {why} after "
                              f"{', '.join(done) or 'nothing'}", where="--done")
        done.append(fits[0])
    return done


def parse_costs(text: str, graph: AndOrGraph) -> dict[tuple[str, str], float]:
    """``human.a2=3.1,robot.a3=0.5`` -> {("a2", "human"): 3.1, ("a3", "robot"): 0.5}."""
    from ergosim.overrides import finite_float  # noqa: PLC0415
    from ergosim.planner.agents import COST_MAX  # noqa: PLC0415

    agents = [a.name for a in graph.agents]
    out: dict[tuple[str, str], float] = {}
    for item in (p.strip() for p in text.split(",")):
        if not item:
            continue
        key, sep, raw = item.partition("=")
        agent, dot, action = key.strip().partition(".")
        if not sep or not dot:
            raise ConfigError(f"expected AGENT.ACTION=COST, got {item!r}", where="--costs")
        if agent not in agents:
            raise ConfigError(f"unknown agent {agent!r} in {item!r}; agents are {', '.join(agents)}",
                              where="--costs")
        if action not in graph.actions:
            raise ConfigError(f"unknown action {action!r} in {item!r}; actions are "
                              f"{', '.join(graph.actions)}", where="--costs")
        value = finite_float(raw.strip(), key.strip(), where="--costs")
        if not 0 <= value <= COST_MAX:
            raise ConfigError(f"{item!r}: a cost must be finite, >= 0 and <= {COST_MAX:g}", where="--costs")
        out[(action, agent)] = value
    return out


def state_costs_for(graph: AndOrGraph, path: str, done: list[str]) -> dict[tuple[str, str], float]:
    """Costs of eq. 9-11 from the KWear state file ``path`` for the actions not yet done."""
    from ergosim.experiment.kwear_state import read_state, state_costs  # noqa: PLC0415

    state = read_state(path)
    humans = [a.name for a in graph.agents if a.kind == "human"]
    robots = [a.name for a in graph.agents if a.kind == "robot"]
    if len(humans) != 1:
        raise ConfigError(f"--state prices one human's hyper-arcs; task {graph.name!r} has {len(humans)} "
                          "human agents", where="--state")
    finished = {graph.operation(o).action for o in done}
    remaining = [a for a in graph.actions if a not in finished]
    costs, _ = state_costs(state, remaining, humans[0], robots)
    # only the pairs the task has (an action a robot may not do keeps no robot cost)
    allowed = {(op.action, agent) for op in graph.operations for agent in op.agents}
    return {k: v for k, v in costs.items() if k in allowed}


def run(args: argparse.Namespace) -> int:
    if args.seed is not None and args.seed < 0:
        raise ConfigError(f"must be an integer >= 0, got {args.seed}", where="--seed")
    if args.max_states is not None and args.max_states < 1:
        raise ConfigError(f"must be >= 1, got {args.max_states}", where="--max-states")
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
    done = resolve_done(graph, [op.strip() for op in args.done.split(",") if op.strip()])
    costs = state_costs_for(graph, args.state, done) if args.state else {}
    costs.update(parse_costs(args.costs, graph))
    plan = graph.plan(done=done, costs=costs or None, planner=args.planner, max_states=args.max_states)
    if args.json:
        print(json.dumps(plan_json(graph, plan), allow_nan=False))
    else:
        print(plan_table(graph, plan, done, args.planner))
    return 0

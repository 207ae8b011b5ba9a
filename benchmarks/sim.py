"""Speed of the twin loop (``scripts/bench_sim.py``): real-time factor, overhead over raw MuJoCo stepping,
and the cost of the rerun recording, measured side by side in one run (medians of repeats).

One repetition of the scenario's task is run headless for one calibrated subject; ``raw`` steps the
same compiled workcell with ``mj_step`` only, for the same simulated time and timestep.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

from ergosim.experiment.recording import record_run
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import rig_spec, scenario_subject
from ergosim.twin.rig import build_rig, calibrate, make_allocator
from ergosim.twin.session import Session
from ergosim.viz import open_recording

__all__ = ["bench_repetition", "bench_sim", "bench_full", "bench_video"]


def bench_repetition(scenario: str, mode: str = "hrc", seed: int = 0,
                     record: bool = False, scene_overrides: dict | None = None, repetitions: int = 1) -> dict:
    """Time ``repetitions`` repetitions of one subject (after calibration, which is not timed). Returns wall
    [s], simulated time [s], and the raw mj_step wall for the same simulated time."""
    sc = load_scenario(scenario, {f"scene.{k}": v for k, v in (scene_overrides or {}).items()})
    sc = sc.with_overrides({"repetitions": str(repetitions), "modes": mode})
    spec, cfg = rig_spec(sc), sc.protocol.session
    subject = scenario_subject(sc, 0, seed)
    calibration = calibrate(spec, subject, np.random.default_rng([seed, 1])).calibrations["rula"]
    rng = np.random.default_rng([seed, 2])
    rig = build_rig(spec, subject, rng, record_bodies=record, alphas=calibration.alphas)
    session = Session(cfg=cfg, mode=mode, subject_index=0, worker=rig.worker, plant=rig.plant,
                      robot=rig.robots, allocator=make_allocator(cfg, mode, rig, calibration), rng=rng)
    t0 = time.perf_counter()
    run = session.run(repetitions)
    if record:
        with tempfile.TemporaryDirectory() as tmp:
            rec = open_recording(rrd=Path(tmp) / "bench.rrd")
            record_run(rec, rig.cell.model, run, cfg.cost.v_th, rig.cell.parts)
            rec.close()
    wall = time.perf_counter() - t0
    sim = rig.plant.time
    # raw: the same model, same timestep, mj_step only, same simulated time
    model = rig.cell.model
    data = mujoco.MjData(model)
    n = int(round(sim / model.opt.timestep))
    t1 = time.perf_counter()
    mujoco.mj_step(model, data, nstep=n)
    raw = time.perf_counter() - t1
    return {"wall": wall, "sim_time": sim, "raw_wall": raw, "failures": len(run.failures),
            "robot_actions": sum(run.by_robot(a.agent) for a in run.allocations)}


def bench_sim(scenario: str, mode: str = "hrc", repeats: int = 3, seed: int = 0,
              repetitions: int = 1) -> dict:
    """Medians over ``repeats`` (subjects of seeds ``seed``, ``seed`` + 1, ...) of: real-time factor and
    overhead ratio of ``repetitions`` repetitions, logging off and on."""
    rows = {"off": [], "on": []}
    for r in range(repeats):
        for key in ("off", "on"):  # interleaved, so both see the same machine load
            rows[key].append(bench_repetition(scenario, mode, seed + r, record=key == "on",
                                              repetitions=repetitions))

    def med(key: str, f) -> float:
        return statistics.median(f(x) for x in rows[key])

    rtf = med("off", lambda x: x["sim_time"] / x["wall"])
    rtf_on = med("on", lambda x: x["sim_time"] / x["wall"])
    return {
        "scenario": scenario, "mode": mode, "repeats": repeats, "repetitions": repetitions,
        "sim_time_s": med("off", lambda x: x["sim_time"]),
        "wall_s": med("off", lambda x: x["wall"]),
        "realtime_factor": rtf,
        "raw_realtime_factor": med("off", lambda x: x["sim_time"] / x["raw_wall"]),
        "overhead_ratio": med("off", lambda x: x["wall"] / x["raw_wall"]),
        "realtime_factor_recording": rtf_on,
        "overhead_ratio_recording": med("on", lambda x: x["wall"] / x["raw_wall"]),
        "recording_cost": rtf / rtf_on - 1.0,
        "robot_actions": [x["robot_actions"] for x in rows["off"]],
    }


def bench_full(scenario: str, jobs: int = 2, seed: int = 0) -> dict:
    """Wall time of the whole scenario (e.g. 12 subjects x 10 repetitions x 2 modes), ``jobs`` processes."""
    from ergosim.experiment.scenario_run import run_scenario  # noqa: PLC0415

    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        res = run_scenario(load_scenario(scenario), seed=seed, out=Path(tmp), jobs=jobs, progress=False)
        wall = time.perf_counter() - t0
    modes = res.summary["modes"]
    return {"scenario": scenario, "jobs": jobs, "wall_s": wall,
            "repetitions": sum(m["repetitions_completed"] for m in modes.values())}


def bench_video(scenario: str = "multi-subject", seed: int = 0, repeats: int = 3, seconds: float = 10.0,
                size: tuple[int, int] = (960, 540), speed: float = 1.0) -> dict:
    """Cost of ``--video``, measured on one recorded repetition: ``seconds`` of simulated time filmed at
    ``speed`` (30 fps), ``repeats`` times (medians). Returns ms per frame for each stage (scene render,
    overlay, encoder), the wall time per second of simulated time, and the same repetition's simulation
    wall time with and without body poses kept (what ``--video`` adds to the run itself). Each film is made
    with the default worker processes and, side by side, in one process (:mod:`benchmarks.video`):
    wall and CPU time per frame of both, the speed-up, and whether the MP4 files are byte-identical."""

    sc = load_scenario(scenario).with_overrides({"repetitions": "1", "modes": "hrc"})
    spec, cfg = rig_spec(sc), sc.protocol.session
    subject = scenario_subject(sc, 0, seed)
    calibration = calibrate(spec, subject, np.random.default_rng([seed, 1])).calibrations["rula"]
    sims = {"off": [], "on": []}
    run = rig = None
    for _ in range(repeats):
        for key in ("off", "on"):
            rng = np.random.default_rng([seed, 2])
            rig = build_rig(spec, subject, rng, record_bodies=key == "on", alphas=calibration.alphas)
            session = Session(cfg=cfg, mode="hrc", subject_index=0, worker=rig.worker, plant=rig.plant,
                              robot=rig.robots, allocator=make_allocator(cfg, "hrc", rig, calibration),
                              rng=rng)
            t0 = time.perf_counter()
            r = session.run(1)
            sims[key].append(time.perf_counter() - t0)
            if key == "on":
                run = r
    from benchmarks.video import compare_workers  # noqa: PLC0415
    from ergosim.video.render_pool import default_workers  # noqa: PLC0415

    workers = default_workers()
    films = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(repeats):
            films.append(compare_workers(rig.cell, run, Path(tmp), (0.0, seconds), size, speed,
                                         workers, tag=str(k)))
    frames = films[0]["pool"]["frames"]

    def med(key: str, f) -> float:
        return statistics.median(f(x[key]) for x in films)

    single = {"ms_per_frame": 1000 * med("single", lambda x: x["wall_s"] / x["frames"]),
              "cpu_ms_per_frame": 1000 * med("single", lambda x: x["cpu_s"] / x["frames"])}
    return {
        "scenario": scenario, "repeats": repeats, "size": list(size), "speed": speed, "frames": frames,
        "sim_seconds": seconds, "workers": workers,
        "render_ms_per_frame": 1000 * med("pool", lambda x: x["render_s"] / x["frames"]),
        "overlay_ms_per_frame": 1000 * med("pool", lambda x: x["overlay_s"] / x["frames"]),
        "encode_ms_per_frame": 1000 * med("pool", lambda x: x["encode_s"] / x["frames"]),
        "ms_per_frame": 1000 * med("pool", lambda x: x["wall_s"] / x["frames"]),
        "cpu_ms_per_frame": 1000 * med("pool", lambda x: x["cpu_s"] / x["frames"]),
        "one_process": single,
        "speedup_over_one_process": statistics.median(x["single"]["wall_s"] / x["pool"]["wall_s"]
                                                      for x in films),
        "identical_mp4": all(x["identical"] for x in films),
        "wall_per_sim_second": med("pool", lambda x: x["wall_s"] / seconds),
        "sim_wall_s": statistics.median(sims["off"]),
        "sim_wall_s_with_poses": statistics.median(sims["on"]),
        "poses_cost": statistics.median(sims["on"]) / statistics.median(sims["off"]) - 1.0,
        "sim_time_s": rig.plant.time,
        # measured side by side, so machine load cancels: filming one simulated second at x1 against
        # simulating it
        "video_over_simulation": med("pool", lambda x: x["wall_s"] / seconds)
        / (statistics.median(sims["off"]) / rig.plant.time),
    }

"""``ergosim replay FILE.bvh``: a real motion-capture recording through RULA and KWear (paper eq. 3-5).

ergosim replay FILE.bvh [--out DIR] [--rate HZ] [--worker ID --store PATH] [--map MAP.toml]
                        [--side right|left|both] [--rrd FILE]

The BVH skeleton is mapped onto the canonical angles (docs/bvh.md; ``--map`` names the joints of a skeleton
that is not recognised), sampled at the ergonomics rate and replayed through :func:`ergosim.worker.replay`,
the path the twin's own recordings take: RULA per body part per tick, then KWear per joint from zero wear.
RULA scores one arm at a time: ``--side`` picks the right (default, the paper's dominant arm), the left, or
both, each replayed on its own. A recording carries no action boundaries, so every tick counts as acting
(wear, eq. 3-4). Writes ``DIR/ticks.csv`` (``ticks_right.csv`` and ``ticks_left.csv`` with ``--side both``;
:data:`~ergosim.worker.REPLAY_COLUMNS`), ``DIR/summary.json`` and ``DIR/kwear_timeline_<side>.png``, all
atomically, and with ``--rrd`` a rerun recording of the angles, RULA and KWear.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from ergosim.errors import ConfigError, RecordingError

__all__ = ["add_parser", "run", "replay_summary", "summary_lines", "write_ticks"]

_DEFAULT_OUT = Path("results") / "replay"
SIDES = ("right", "left", "both")
_V_TH = 0.8  # V_th drawn on the plots and in the recording: the paper's 80 % of the KWear range (§7.1)


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "replay", help="replay a BVH motion-capture recording through RULA and KWear",
        description="Load a BVH recording (Xsens, Vicon, OptiTrack, ...) onto the canonical angles, score "
                    "RULA per body part at the ergonomics rate and integrate KWear per joint from zero wear; "
                    "write ticks.csv and summary.json to --out.",
    )
    p.add_argument("file", metavar="FILE.bvh", help="the recording")
    p.add_argument("--out", default=None, metavar="DIR",
                   help=f"output directory (default {_DEFAULT_OUT}/<file name without .bvh>)")
    p.add_argument("--rate", type=float, default=20.0, metavar="HZ",
                   help="ergonomics rate [Hz] (default 20, as in the paper)")
    p.add_argument("--worker", metavar="ID", help="take the KWear constants of this worker from --store")
    p.add_argument("--store", metavar="PATH", help="parameter-store directory (with --worker)")
    p.add_argument("--map", metavar="MAP.toml",
                   help="joint names for a skeleton that is not recognised: role = \"JointName\" lines "
                        "(docs/bvh.md)")
    p.add_argument("--side", choices=SIDES, default="right",
                   help="arm scored by RULA: right (default, the paper's dominant arm), left or both")
    p.add_argument("--rrd", metavar="FILE", help="also save a rerun recording of angles, RULA and KWear")
    return p


def _kwear_params(args):
    """(KWearParams, worker id or None): the stored worker's constants, else the paper's defaults."""
    from ergosim.ergonomics.kwear import KWearParams  # noqa: PLC0415 - keep `ergosim --help` fast
    from ergosim.ergonomics.param_store import ParamStore  # noqa: PLC0415

    if (args.worker is None) != (args.store is None):
        raise ConfigError("give --worker and --store together (or neither, for the paper's KWear constants)",
                          where="--worker" if args.store is None else "--store")
    if args.worker is None:
        return KWearParams(), None
    return ParamStore(args.store).load(args.worker).kwear, args.worker


def _load(path: Path, map_file: str | None, rate: float):
    """The recording at the frames the ticks at ``rate`` [Hz] use: the others are never mapped."""
    from ergosim.worker import tick_indices  # noqa: PLC0415
    from ergosim.worker.bvh import recording_from_data  # noqa: PLC0415
    from ergosim.worker.bvh_map_file import read_name_map  # noqa: PLC0415
    from ergosim.worker.bvh_mapping import map_skeleton  # noqa: PLC0415
    from ergosim.worker.bvh_parse import parse_bvh  # noqa: PLC0415

    name_map = read_name_map(map_file) if map_file else None
    if not path.exists():
        raise RecordingError("no such file", where=str(path))
    if path.is_dir():
        raise RecordingError("is a directory, expected a BVH file", where=str(path))
    data = parse_bvh(path)
    map_skeleton(data, name_map)  # a skeleton it cannot map is the first error, as for load_bvh
    if rate > data.rate_hz:
        raise ConfigError(f"ergonomics rate {rate:g} Hz is above the recording's frame rate "
                          f"{data.rate_hz:g} Hz", where="--rate")
    return recording_from_data(data, name_map, frames=tick_indices(data.n_frames, data.rate_hz, rate))


def side_angles(recording, side: str) -> np.ndarray:
    """(frames, 14) RULA input for one ``side``: trunk and neck, then that arm's angles (same anatomical
    signs, ergosim.posture). RecordingError if the file has no such arm."""
    from ergosim.posture import ANGLE_NAMES, ARM  # noqa: PLC0415

    if side == "right":
        return recording.array(ANGLE_NAMES)
    names = tuple(f"left_{n}" if n in ARM else n for n in ANGLE_NAMES)
    if not all(n in recording.angles for n in names):
        raise RecordingError("the recording has no complete left arm (clavicle optional, upper arm, forearm "
                             "and hand needed); use --side right or name its joints with --map",
                             where=str(recording.source))
    return recording.array(names)


def _stat(x: np.ndarray) -> dict[str, float | None]:
    """Mean and max over the valid (non-NaN) ticks; None if there are none (JSON has no NaN)."""
    x = x[np.isfinite(x)]
    if x.size == 0:
        return {"mean": None, "max": None}
    return {"mean": float(x.mean()), "max": float(x.max())}


def replay_summary(trace, recording, params, worker: str | None) -> dict:
    """summary.json of a replay: the recording, the ergonomics settings, dropouts, RULA mean/max per body part
    (valid ticks) and grand, and KWear V per joint after the last tick."""
    from ergosim.ergonomics.rula import RULA_PARTS  # noqa: PLC0415
    from ergosim.posture import KWEAR_JOINTS  # noqa: PLC0415

    return {
        "source": str(recording.source),
        "frames": int(recording.n_frames),
        "frame_rate_hz": float(recording.rate_hz),
        "duration_s": recording.n_frames / recording.rate_hz,
        "ergonomics_rate_hz": trace.rate,
        "ticks": trace.n,
        "dropouts": trace.dropouts,
        "mapping": dict(recording.mapping),
        "kwear": {
            "worker": worker,
            "params": {"t_max": params.t_max, "v_max": params.v_max, "g_avg": params.g_avg},
            "final": {j: float(v) for j, v in zip(KWEAR_JOINTS, trace.v_end, strict=True)},
        },
        "rula": {
            "parts": {p: _stat(trace.rula[:, i]) for i, p in enumerate(RULA_PARTS)},
            "grand": _stat(trace.grand),
        },
    }


def write_ticks(path: Path, trace) -> None:
    """ticks.csv: :data:`REPLAY_COLUMNS`, one row per ergonomics tick (NaN = dropout), atomically."""
    from ergosim.atomic import atomic_open  # noqa: PLC0415
    from ergosim.g9_csv import g9_csv  # noqa: PLC0415
    from ergosim.worker import REPLAY_COLUMNS  # noqa: PLC0415

    # 9 significant digits, as the twin's ticks.csv: the bytes of np.savetxt(fmt="%.9g"), built in bulk
    text = g9_csv(trace.table())
    with atomic_open(path, "wb") as f:
        f.write((",".join(REPLAY_COLUMNS) + "\n").encode())
        f.write(text)


def _fmt(x: float | None, spec: str) -> str:
    return "-" if x is None or not math.isfinite(x) else format(x, spec)


def summary_lines(summary: dict) -> list[str]:
    """The summary as a few readable lines."""
    s, kw = summary, summary["kwear"]
    p = kw["params"]
    who = (f"worker {kw['worker']}" if kw["worker"] else "paper defaults")
    lines = [
        f"replayed {Path(s['source']).name}: {s['frames']} frames at {s['frame_rate_hz']:g} Hz "
        f"({s['duration_s']:.2f} s) -> {s['ticks']} ticks at {s['ergonomics_rate_hz']:g} Hz, "
        f"{s['dropouts']} dropouts",
        f"KWear constants: {who} (T_max {p['t_max']:g} s, V_max {p['v_max']:g}, G_avg {p['g_avg']:g})",
        "RULA          mean  max",
    ]
    rows = [*s["rula"]["parts"].items(), ("grand", s["rula"]["grand"])]
    lines += [f"  {name:<11} {_fmt(st['mean'], '5.2f')} {_fmt(st['max'], '4.0f')}" for name, st in rows]
    lines.append("KWear V at the end: " + ", ".join(f"{j} {v:.4f}" for j, v in kw["final"].items()))
    return lines


def _record(path: str, traces: dict, name: str) -> None:
    """A rerun recording of each side's trace: angles, RULA and KWear (``repetition`` = 1 right, 2 left)."""
    from ergosim.viz import open_recording  # noqa: PLC0415

    rec = open_recording(rrd=path, recording_name=f"ergosim replay {name}")
    committed = False
    try:
        rec.log_ergonomics_static(v_th=np.full(5, _V_TH))
        for k, trace in enumerate(traces.values(), start=1):
            n = trace.n
            rec.log_ticks(k, trace.t, np.zeros((n, 0, 3)), np.zeros((n, 0, 4)), (), trace.angles, trace.rula,
                          trace.grand, trace.v)
        committed = True
    finally:
        rec.close(commit=committed)


def run(args) -> int:
    from ergosim.atomic import write_json  # noqa: PLC0415
    from ergosim.experiment.plots import kwear_timeline  # noqa: PLC0415
    from ergosim.worker import replay_ticks  # noqa: PLC0415

    if not (math.isfinite(args.rate) and args.rate > 0):
        raise ConfigError(f"must be a positive number of Hz, got {args.rate:g}", where="--rate")
    params, worker = _kwear_params(args)
    path = Path(args.file)
    out = Path(args.out) if args.out else _DEFAULT_OUT / path.stem
    if out.exists() and not out.is_dir():
        raise ConfigError(f"{out} exists and is not a directory", where="--out")
    if args.rrd is not None and Path(args.rrd).is_dir():
        raise ConfigError(f"{args.rrd} is a directory; expected the path of the .rrd file to write",
                          where="--rrd")
    recording = _load(path, args.map, args.rate)
    sides = ("right", "left") if args.side == "both" else (args.side,)
    traces = {s: replay_ticks(side_angles(recording, s), recording.frames, params, rate=args.rate)
              for s in sides}
    first = traces[sides[0]]
    if first.n == 0:
        raise RecordingError(f"the recording lasts {recording.n_frames / recording.rate_hz:.3g} s, shorter "
                             f"than one ergonomics tick ({1.0 / args.rate:.3g} s)", where=str(path))
    summary = replay_summary(first, recording, params, worker)
    summary["side"] = args.side
    summary["by_side"] = {s: {k: v for k, v in replay_summary(t, recording, params, worker).items()
                              if k in ("rula", "kwear")} for s, t in traces.items()}
    names = {s: "ticks.csv" if len(sides) == 1 else f"ticks_{s}.csv" for s in sides}
    try:
        for s, trace in traces.items():
            write_ticks(out / names[s], trace)
            kwear_timeline(out / f"kwear_timeline_{s}.png", trace.t, trace.v, _V_TH,
                           f"KWear, {path.name}, {s} arm (RULA of that side)")
        write_json(out / "summary.json", summary)
    except OSError as err:
        raise ConfigError(f"cannot write the results: {err.strerror or err}", where=str(out)) from None
    if args.rrd:
        _record(args.rrd, traces, path.name)
    lines = summary_lines(summary)
    if len(sides) > 1:
        lines.insert(2, f"{sides[0]} arm:")
        for s in sides[1:]:
            lines += [f"{s} arm:", *summary_lines({**summary, **summary["by_side"][s]})[2:]]
    print("\n".join(lines))
    files = ", ".join([*names.values(), "summary.json", *(f"kwear_timeline_{s}.png" for s in sides)])
    print(f"\nresults: {out.resolve()} ({files})")
    if args.rrd:
        print(f"recording: {Path(args.rrd).resolve()}  (open it with: rerun {args.rrd})")
    return 0

"""Write tests/data/reach_overhead.bvh: a 1 s overhead reach (30 Hz) exported with ergosim's BVH exporter.

The worker bends and twists the trunk a little, looks up at the target, and raises the right arm forward and
sideways with internal rotation, a flexed elbow, a pronated forearm and a bent wrist, while the left arm
swings back; every angle follows a minimum-jerk profile from the neutral posture (all 0) to ``TARGET``.
tests/test_bvh.py loads the file and compares it with :func:`reach_angles`.

    python scripts/make_test_bvh.py [--out tests/data/reach_overhead.bvh]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from ergosim.worker.bvh import save_bvh
from ergosim.worker.minimum_jerk import min_jerk

RATE_HZ = 30.0
N_FRAMES = 31
TARGET = {
    "trunk_flexion": 15.0, "trunk_lateral_bend": -8.0, "trunk_rotation": 12.0,
    "neck_flexion": -25.0, "neck_lateral_bend": 5.0, "neck_rotation": 20.0,
    "shoulder_elevation": 15.0, "shoulder_flexion": 120.0, "shoulder_abduction": 40.0,
    "shoulder_rotation": 30.0, "elbow_flexion": 60.0, "forearm_pronation": 50.0,
    "wrist_flexion": -30.0, "wrist_deviation": 15.0,
    "left_shoulder_flexion": -35.0, "left_shoulder_abduction": 10.0, "left_shoulder_rotation": -20.0,
    "left_elbow_flexion": 25.0, "left_forearm_pronation": -40.0, "left_wrist_flexion": 20.0,
}
"""Final posture [deg]; every other canonical angle stays 0."""


def reach_angles() -> dict[str, np.ndarray]:
    """Canonical angles [deg], name -> (N_FRAMES,), of the reach at RATE_HZ."""
    s = min_jerk(np.linspace(0.0, 1.0, N_FRAMES))
    return {name: value * s for name, value in TARGET.items()}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = Path(__file__).parents[1] / "tests" / "data" / "reach_overhead.bvh"
    parser.add_argument("--out", type=Path, default=default)
    args = parser.parse_args()
    save_bvh(args.out, reach_angles(), RATE_HZ, stature=1.75)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

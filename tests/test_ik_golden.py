"""The whole-body IK's numbers, bit for bit: a fixed set of solves against golden values.

The solver may be rewritten for speed with the promise that every output stays bit-identical; these solves
cover its paths (a stance on the spot, stepped and turned, a 6-D target, a gaze beyond the eyes, a squat,
a target out of reach, furniture in the way). A change in any floating-point operation of the solve changes
one of these digests. The golden values come from the mink solver of the stance-first worker on numpy's
bundled OpenBLAS: a different BLAS kernel may round the small matrix products differently, in which case
regenerate them with ``_print_golden`` only after checking that the solver itself did not change.
"""

from __future__ import annotations

import hashlib

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from ergosim.human import human_spec
from ergosim.worker import WholeBodyIK, rest_angles
from ergosim.worker.ik_prior import default_prior, squat_prior
from ergosim.worker.obstacles import ik_model

ROT = Rotation.from_euler("xyz", [170.0, 10.0, -30.0], degrees=True).as_matrix()
BENCH = (np.array([0.62, 0.0, 0.88]), np.array([0.32, 0.5, 0.02]), 0.0)
# name: (side, target [m], target_rot, gaze point [m] or None, stance (x, y, turn), squat, max_iter)
PROBLEMS = {
    "reach": ("right", (0.45, -0.2, 1.0), None, None, (0.0, 0.0, 0.0), False, None),
    "grip_6d": ("right", (0.35, -0.25, 0.75), ROT, None, (0.0, 0.0, 0.0), False, 40),
    "gaze_aside": ("left", (0.4, 0.3, 1.2), None, (0.3, 1.2, 1.7), (0.0, 0.0, 0.0), False, None),
    "step_aside": ("right", (0.2, -0.7, 0.9), None, None, (0.05, -0.3, -70.0), False, None),
    "behind": ("right", (-0.35, -0.55, 0.95), None, None, (0.0, -0.1, -90.0), False, None),
    "low": ("right", (0.45, -0.05, 0.2), None, None, (0.1, 0.0, 0.0), True, None),
    "out_of_reach": ("right", (1.3, -0.1, 1.1), None, None, (0.0, 0.0, 0.0), False, None),
    "grip_6d_turned": ("right", (0.5, 0.1, 0.9), ROT, (0.6, 0.0, 0.8), (0.0, 0.0, 20.0), False, 25),
    "over_the_bench": ("right", (0.6, -0.25, 0.92), None, None, (0.1, 0.0, 0.0), False, None),
}
GOLDEN = {  # (iterations, pos_error, rot_error_deg, cost, digest of the body): _print_golden's output
    'behind':
        (9, '0x1.53ca0e87bd786p-17', '0x0.0p+0', '0x1.31db593797320p+1', '579dbbc9216cb932'),
    'gaze_aside':
        (25, '0x1.fece19f4e5c43p-17', '0x0.0p+0', '0x1.65122831d29e4p+2', '135f3ed38580ad97'),
    'grip_6d':
        (43, '0x1.2217f124fc294p-11', '0x1.2b55b168b7838p+1', '0x1.039c12aef5d55p+6', 'e92381e289c4c5ca'),
    'grip_6d_turned':
        (25, '0x1.5bc06fbca08aep-13', '0x1.95a42233370acp-1', '0x1.3e1ec0085f7dfp+5', 'd37604d03c9cdbe3'),
    'low':
        (70, '0x1.3702ce7aad140p-14', '0x0.0p+0', '0x1.956fe657cf23dp+3', '2d8bbb290e5e88d0'),
    'out_of_reach':
        (60, '0x1.518727bc2ce39p-5', '0x0.0p+0', '0x1.05a5b7a595ba0p+7', '7e7c066f6b0a4145'),
    'over_the_bench':
        (8, '0x1.6bbfe0bc45778p-17', '0x0.0p+0', '0x1.d0ee1c65799c4p+0', '39ac5471735aba4b'),
    'reach':
        (10, '0x1.38b14fa3ffec8p-18', '0x0.0p+0', '0x1.a8dba8d8d9c92p+0', '865e325a903d70b0'),
    'step_aside':
        (14, '0x1.c211d48bb3806p-16', '0x0.0p+0', '0x1.89c9cd798d48ep+1', 'b647e37e21eacc25'),
}


def _digest(body: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(body, dtype="<f8").tobytes()).hexdigest()[:16]


def _solve(ik: WholeBodyIK, rest: np.ndarray, name: str):
    side, target, rot, gaze, stance, squat, max_iter = PROBLEMS[name]
    start = rest.copy()
    start[22:25] = stance
    prior = squat_prior(ik.prior) if squat else ik.prior
    if squat:
        start[25], start[26] = prior.pref[25], prior.pref[26]
    s = ik.solve(start, np.array(target), side, target_rot=rot, gaze=None if gaze is None else np.array(gaze),
                 prior=prior, max_iter=max_iter)
    return (s.iterations, float(s.pos_error).hex(), float(s.rot_error_deg).hex(), float(s.cost).hex(),
            _digest(s.body))


def _ik() -> WholeBodyIK:
    built = ik_model(human_spec(1.75), [BENCH])
    return WholeBodyIK(built.model, default_prior(), segments=built.segments, obstacles=built.obstacles,
                       forearms=built.forearms)


@pytest.fixture(scope="module")
def ik():
    return _ik()


@pytest.fixture(scope="module")
def rest():
    return np.concatenate([rest_angles(), np.zeros(5)])


@pytest.mark.parametrize("name", sorted(PROBLEMS))
def test_the_ik_gives_the_same_bits(ik, rest, name):
    assert _solve(ik, rest, name) == GOLDEN[name]


def _print_golden() -> None:
    ik = _ik()
    rest = np.concatenate([rest_angles(), np.zeros(5)])
    for name in sorted(PROBLEMS):
        print(f"    {name!r}:\n        {_solve(ik, rest, name)!r},")


if __name__ == "__main__":
    _print_golden()

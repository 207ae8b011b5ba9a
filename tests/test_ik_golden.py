"""The whole-body IK's numbers, bit for bit: a fixed set of solves against golden values.

The solver is rewritten for speed from time to time (issue 28) with the promise that every output stays
bit-identical; these solves cover its paths (planted and free stance, the turned start and the planted
retry, a 6-D target, a gaze beyond the eyes, bent knees, a bound that freezes a joint, a target out of
reach). A change in any floating-point operation of the solve changes one of these digests. The golden
values come from the solver as of issue 23 on numpy's bundled OpenBLAS: a different BLAS kernel may round
the small matrix products differently, in which case regenerate them with ``_print_golden`` only after
checking that the solver itself did not change.
"""

from __future__ import annotations

import hashlib

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from ergosim.human import human_spec
from ergosim.worker import StandingArea, WholeBodyIK, rest_angles
from ergosim.worker.ik_prior import default_prior

FREE = StandingArea((-0.3, 0.15), (-0.35, 0.35), (-90.0, 90.0))
ROT = Rotation.from_euler("xyz", [170.0, 10.0, -30.0], degrees=True).as_matrix()
PROBLEMS = {  # name: (side, target [m], target_rot, gaze point [m] or None, area, max_iter)
    "reach": ("right", (0.45, -0.2, 1.0), None, None, None, None),
    "grip_6d": ("right", (0.35, -0.25, 0.75), ROT, None, None, 40),
    "gaze_aside": ("left", (0.4, 0.3, 1.2), None, (0.3, 1.2, 1.7), None, None),
    "step_aside": ("right", (0.2, -0.7, 0.9), None, None, FREE, None),
    "behind": ("right", (-0.35, -0.55, 0.95), None, None, FREE, None),
    "low": ("right", (0.45, -0.05, 0.2), None, None, FREE, None),
    "out_of_reach": ("right", (1.3, -0.1, 1.1), None, None, None, None),
    "grip_6d_free": ("right", (0.5, 0.1, 0.9), ROT, (0.6, 0.0, 0.8), FREE, 25),
}
GOLDEN = {  # (iterations, pos_error, rot_error_deg, cost, digest of the body): _print_golden's output
    'behind':
        (47, '0x1.1f6b67bc4b76bp-16', '0x0.0p+0', '0x1.3470816f51354p+3', '67f353a38c6a8e38'),
    'gaze_aside':
        (16, '0x1.77821d455b186p-17', '0x0.0p+0', '0x1.66a20ebe156ebp+2', 'aac4487f6dd63c1b'),
    'grip_6d':
        (20, '0x1.1ed1cdd0d3cbdp-12', '0x1.02c1738a9be9dp+0', '0x1.e5eeb0fb64c60p+5', 'e99de55eb3642fa7'),
    'grip_6d_free':
        (24, '0x1.94e7dccf6144bp-14', '0x1.1c60219e21c21p-1', '0x1.1006a889266f6p+5', 'a6ab791393779904'),
    'low':
        (17, '0x1.58d557fc2ec3ep-14', '0x0.0p+0', '0x1.7950da66a2642p+4', '0fbda8f370902c46'),
    'out_of_reach':
        (46, '0x1.e77421d62f7bdp-5', '0x0.0p+0', '0x1.fbab6c9535260p+6', 'f249ce3858cb2f7e'),
    'reach':
        (29, '0x1.12a0059e8521bp-18', '0x0.0p+0', '0x1.5aca7ee304ee7p+1', '05e74baa0850bf68'),
    'step_aside':
        (22, '0x1.d21284eec0015p-16', '0x0.0p+0', '0x1.4d243caded721p+2', '9073ac4f27bc58ac'),
}


def _digest(body: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(body, dtype="<f8").tobytes()).hexdigest()[:16]


def _solve(ik: WholeBodyIK, rest: np.ndarray, name: str):
    side, target, rot, gaze, area, max_iter = PROBLEMS[name]
    s = ik.solve(rest, np.array(target), side, target_rot=rot, gaze=None if gaze is None else np.array(gaze),
                 area=area, max_iter=max_iter)
    return (s.iterations, float(s.pos_error).hex(), float(s.rot_error_deg).hex(), float(s.cost).hex(),
            _digest(s.body))


@pytest.fixture(scope="module")
def ik():
    return WholeBodyIK(human_spec(1.75).compile(), default_prior())


@pytest.fixture(scope="module")
def rest():
    return np.concatenate([rest_angles(), np.zeros(4)])


@pytest.mark.parametrize("name", sorted(PROBLEMS))
def test_the_ik_gives_the_same_bits(ik, rest, name):
    assert _solve(ik, rest, name) == GOLDEN[name]


def _print_golden() -> None:
    ik = WholeBodyIK(human_spec(1.75).compile(), default_prior())
    rest = np.concatenate([rest_angles(), np.zeros(4)])
    for name in sorted(PROBLEMS):
        print(f"    {name!r}:\n        {_solve(ik, rest, name)!r},")


if __name__ == "__main__":
    _print_golden()

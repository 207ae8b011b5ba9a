"""§7.2's calibration fact against the twin (ergosim/fidelity/calibration_eta.py): the scan calibrates as a
run does, and the band of a lever is where every calibration ends by η = 3."""

from __future__ import annotations

import pytest

from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import calibrate_subject
from ergosim.fidelity.calibration_eta import PAPER_ETA, EtaRow, allowed_band, eta_scan


def _row(noise: float, etas: list[int]) -> EtaRow:
    return EtaRow(noise, 1.0, {"a1": etas, "a2": [2] * len(etas)}, {"a1": [0.0] * len(etas),
                                                                  "a2": [0.0] * len(etas)})


def test_the_band_ends_below_the_first_scale_with_a_calibration_past_eta_3():
    rows = [_row(0.0, [2, 2]), _row(0.1, [2, 3]), _row(0.25, [2, 10]), _row(0.5, [2, 2])]
    assert allowed_band(rows, "noise_scale") == (0.0, 0.1)
    assert allowed_band([_row(0.0, [10, 2])], "noise_scale") is None
    assert rows[2].within == pytest.approx(3 / 4) and rows[2].subjects_within == pytest.approx(1 / 2)
    assert PAPER_ETA == 3


@pytest.mark.slow
def test_without_suit_error_or_variability_two_executions_are_the_same():
    """The scan's calibration is the run's (the same subject, stream and procedure), and with nothing to
    tell two executions apart the procedure stops at η0 = 2 with no prediction error."""
    (row,) = eta_scan([(0.0, 0.0)], [0], subjects=1)
    assert all(e == [2] for e in row.eta.values()), row.eta
    assert all(err == [0.0] for err in row.max_error.values()), row.max_error
    sc = load_scenario("multi-subject")
    _, cal, _ = calibrate_subject(sc, 0, 0)
    eta = {a: c.eta for a, c in cal["rula"].actions.items()}
    assert eta != row.eta  # the default subject's suit and variability tell executions apart
    assert max(eta.values()) == PAPER_ETA == sc.protocol.calibration.eta_max  # as §7.2's subjects, 3 at most

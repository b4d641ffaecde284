"""The first-slip ensemble of benchmarks.events_bench: mbm (trapped scenes ended early,
docs/guide/events.md) finds the slipping scenes of heyoka long double (the benchmark's
reference) at their first-slip times, near the slip threshold γ ≈ 0.775 included."""

import math

import numpy as np
import pytest

import mbm

pytest.importorskip("heyoka")

from benchmarks import events_bench  # noqa: E402


def test_first_slips_near_the_threshold_are_heyokas():
    gamma = np.r_[0.3, np.linspace(0.72, 0.8, 9), 0.7745, 0.775, 1.2]
    ref = events_bench._first_slips_reference(gamma).astype(float)
    r = mbm.solve_batch(events_bench.BETA, gamma, 1.0, [0.0, 0.0], (0.0, events_bench.T_END), [], rtol=1e-9,
                        atol=1e-9, events=mbm.angle_event(math.pi, terminal=True))
    first = np.where(r.n_events[:, 0] > 0, r.t_events[:, 0, 0], np.nan)
    np.testing.assert_array_equal(np.isnan(first), np.isnan(ref))
    never = np.isnan(ref)
    assert never[gamma < 0.77].all() and not never[gamma > 0.78].any()
    np.testing.assert_allclose(first, ref, rtol=0, atol=1e-9)
    # Ended early: at once below γ ≈ 0.725 (from rest, below both barriers), after a swing or more above.
    assert np.all(r.regime[never] == "locked") and np.all(r.t_regime[never] < 50.0)
    assert np.all(r.t_regime[never & (gamma > 0.73)] > 1.0)


@pytest.mark.slow
@pytest.mark.parametrize("slipping_only", [False, True])
def test_first_slip_rows_agree_with_heyoka(slipping_only):
    rows = events_bench.first_slip_rows(120, 1, slipping_only=slipping_only)
    mbm_rows = [r for r in rows if r[0].startswith("mbm")]
    heyoka_rows = [r for r in rows if r[0].startswith("heyoka")]
    assert len(mbm_rows) == len(events_bench.MBM_RTOLS) and len(heyoka_rows) == len(events_bench.HEYOKA_TOLS)
    slips = {r[4] for r in rows}
    assert len(slips) == 1 and 0 < slips.pop() <= 120
    for name, tol, ms, err, n in mbm_rows:
        # err is NaN where the slipping scenes differ from the reference's
        assert math.isfinite(err) and err < 1e3 * tol and ms > 0.0, (name, tol, err)

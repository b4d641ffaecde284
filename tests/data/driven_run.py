"""Helpers shared by the driven-run tests (tests/regimes/test_strobe.py, tests/regimes/test_subharmonic.py):
the window loop run by hand with θ wrapped, θ in long double, the driven model."""

import numpy as np
import pytest

import mbm
import oracle_heyoka
from mbm.core import controller, loop, record
from mbm import status

LD = np.longdouble
TWO_PI_LD = 2 * LD(np.pi)

needs_oracle = pytest.mark.skipif(
    not oracle_heyoka.available(),
    reason="the oracle needs heyoka (the test extra) and an 80-bit long double (x86-64)")


def run(params, y0, T, t, tol, regimes_on=1, call_windows=0):
    """The loop by hand (mbm.solve's defaults), θ wrapped with its winding count."""
    beta, gamma, omega, amp, freq, phase = params
    ap, kind, karg = mbm.frontends.solve.compiled(mbm.get_approximant("taylor"))
    p = record.new_run(record.RunModel(beta, gamma, omega, amp, freq, phase), record.RunState(0.0, y0[0], y0[1], T),
                       record.RunControl(kind, karg, controller.CONTROLLER_ADAPTIVE, -1.0, np.inf, np.inf, tol, tol,
                                         int(ap.error_order)),
                       10**8, call_windows=call_windows, regimes=regimes_on)
    out = np.full((3, t.size), np.nan)
    while True:
        loop.run(p, t, out, np.empty(0), np.empty((0, 2)), np.empty((0, 0)), np.zeros(1, np.int64))
        if record.flat(p)[0]["status"] != status.STATUS_PAUSED:
            break
    assert record.flat(p)[0]["status"] == 0
    return out, record.flat(p)[0]


def theta_ld(out):
    """θ = 2π·winding + φ, in long double (no rounding of the wound angle)."""
    return out[2].astype(LD) * TWO_PI_LD + out[0].astype(LD)


def model(params):
    """The driven Pendulum of (β, γ, ω, A, Ω, φ)."""
    return mbm.Pendulum(*params[:3], drive_amplitude=params[3], drive_frequency=params[4],
                        drive_phase=params[5])


def assert_switch_within_tolerance(on, off, ref, t, ts, tol, omega):
    """The phase-locked switch's accuracy claims, shared by test_strobe and test_subharmonic.

    ``on``/``off`` are a run with and without the regime switch (at time ``ts``) at the
    times ``t``, ``ref`` the long-double reference.  Before the switch the two runs agree
    bit for bit; both meet tolerance proportionality (scipy's scale) on both sides; after
    it, θ' and ωθ (S5's norm) stay within the unswitched run's error plus the switch's
    share (regimes.SWITCH_SAFETY).
    """
    from mbm import regimes

    pre, post = t <= ts, t > ts
    np.testing.assert_array_equal(on[:, pre], off[:, pre])
    scale_theta = tol + tol * np.abs(ref[0].astype(float))
    scale_v = tol + tol * np.abs(ref[1].astype(float))
    errs = {}
    for name, out in (("on", on), ("off", off)):
        e_theta = np.abs((theta_ld(out) - ref[0]).astype(float))
        e_v = np.abs((out[1].astype(LD) - ref[1]).astype(float))
        errs[name] = e_theta, e_v
        assert np.max(e_theta / scale_theta) <= 1.0 and np.max(e_v / scale_v) <= 1.0, name
    for k, w in ((0, omega), (1, 1.0)):
        e_on = np.max(w * errs["on"][k][post] / scale_v[post])
        e_off = np.max(w * errs["off"][k][post] / scale_v[post])
        assert e_on <= e_off + regimes.SWITCH_SAFETY, (k, e_on, e_off)

"""Integrator.solve's compiled entry (the loop's own, mbm.core.loop.entry_for): one dispatch
checks t_eval, sets up the run record and runs the loop.  They must refuse what check_t_eval refuses,
with its messages and in the same order of checks, resume a paused run bit for bit and
never make numba compile the loop again for an unusual t_eval."""

import functools
import math

import numpy as np
import pytest

import mbm
from mbm.frontends import solve as fast
from mbm.core import loop, record, window
from mbm import status
from mbm.validate import check_t_eval

DAMPED = mbm.Pendulum(0.1, 0.3)
Y0 = [0.5, 0.0]

# One Integrator per compiled kind (each has entries of its own).
KINDS = {
    "taylor": (DAMPED, dict(rtol=1e-8, atol=1e-8)),
    "exact": (mbm.Pendulum(0.0, 0.0), dict()),
    "split": (DAMPED, dict(approximant="split4", tau=0.25)),
    "salas-torque": (DAMPED, dict(approximant="salas-torque", tau=0.25)),
}

# (span, t_eval, the message check_t_eval gives)
BAD_T_EVAL = [
    ((0.0, 1.0), [0.5, math.nan], "t_eval must be finite"),
    ((0.0, 1.0), [math.inf], "t_eval must be finite"),
    ((0.0, 1.0), [0.5, -math.inf], "t_eval must be finite"),
    ((0.0, 1.0), [0.5, 1.5], "t_eval must lie within t_span (0.0, 1.0)"),
    ((0.0, 1.0), [-1e-12, 0.5], "t_eval must lie within t_span (0.0, 1.0)"),
    ((1.0, 0.0), [0.5, 2.0], "t_eval must lie within t_span (1.0, 0.0)"),
    ((0.0, 1.0), [0.5, 0.25], "t_eval must be sorted in the direction of integration (increasing)"),
    ((1.0, 0.0), [0.25, 0.5], "t_eval must be sorted in the direction of integration (decreasing)"),
    # the first problem met, in t_eval's order, is the one named
    ((0.0, 1.0), [0.75, 0.5, math.nan], "t_eval must be sorted in the direction of integration (increasing)"),
    ((0.0, 1.0), [2.0, math.nan], "t_eval must lie within t_span (0.0, 1.0)"),
]


@pytest.mark.parametrize("kind", sorted(KINDS))
@pytest.mark.parametrize("span,t_eval,message", BAD_T_EVAL)
def test_entries_refuse_bad_t_eval_as_check_t_eval(kind, span, t_eval, message):
    model, kw = KINDS[kind]
    ig = mbm.Integrator(model, **kw)
    # the entry of a fresh run of its kind and regime set (mbm.core.loop.regime_set)
    words = ig._words.view(record.RUN)[0]
    kind, karg = window.kind_of(ig.approximant)
    assert loop.entry_for(kind, loop.set_of(words), karg) is ig._entry
    with pytest.raises(ValueError) as want:
        check_t_eval(t_eval, *span)
    assert str(want.value) == message
    for te in (t_eval, np.array(t_eval)):
        with pytest.raises(ValueError) as got:
            ig.solve(span, Y0, t_eval=te)
        assert str(got.value) == message
        with pytest.raises(ValueError) as got:
            mbm.solve(model, span, Y0, t_eval=te, **kw)
        assert str(got.value) == message
    # a refused call leaves the Integrator as it was
    good = np.linspace(*span, 5)
    np.testing.assert_array_equal(ig.solve(span, Y0, t_eval=good).y,
                                  mbm.Integrator(model, **kw).solve(span, Y0, t_eval=good).y)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_entries_accept_edges_of_the_span_and_repeats(kind):
    model, kw = KINDS[kind]
    ig = mbm.Integrator(model, **kw)
    for span, te in (((0.0, 1.0), [0.0, 0.5, 0.5, 1.0]), ((1.0, 0.0), [1.0, 0.5, 0.5, 0.0]),
                     ((0.0, 1.0), []), ((0.25, 0.25), [0.25])):
        r = ig.solve(span, Y0, t_eval=te)
        assert r.success and r.y.shape == (2, len(te))
        np.testing.assert_array_equal(r.t, te)


def test_order_of_checks_is_kept():
    ig = mbm.Integrator(DAMPED)
    bad_te = [0.5, math.nan]
    with pytest.raises(ValueError, match="t_span must be finite"):
        ig.solve((0.0, math.nan), Y0, t_eval=bad_te, wrap="yes")
    with pytest.raises(ValueError, match="y0 must be finite"):
        ig.solve((0.0, 1.0), [math.nan, 0.0], t_eval=bad_te, wrap="yes")
    with pytest.raises(ValueError, match="t_eval must be finite"):
        ig.solve((0.0, 1.0), Y0, t_eval=bad_te, wrap="yes")
    with pytest.raises(ValueError, match="wrap must be True or False"):
        ig.solve((0.0, 1.0), Y0, t_eval=[0.5], wrap="yes")
    with pytest.raises(ValueError, match="wrap=True needs t_eval"):
        ig.solve((0.0, 1.0), Y0, wrap=True)
    with pytest.raises(TypeError, match="t_eval must be a real number or an array of real numbers"):
        ig.solve((0.0, 1.0), Y0, t_eval=["a"])
    # mbm.solve: its own checks first, then the Integrator's
    with pytest.raises(ValueError, match="t_span must be finite"):
        mbm.solve(DAMPED, (0.0, math.inf), Y0, t_eval=bad_te, rtol=-1.0)
    with pytest.raises(ValueError, match="rtol"):
        mbm.solve(DAMPED, (0.0, 1.0), Y0, t_eval=bad_te, rtol=-1.0)


def test_unusual_t_eval_arrays_give_the_same_bits_and_compile_nothing():
    ig = mbm.Integrator(DAMPED, rtol=1e-8, atol=1e-8)
    te = np.linspace(0.0, 10.0, 21)
    want = ig.solve((0.0, 10.0), Y0, t_eval=te)
    signatures = len(loop.SIMD_RUNNERS[loop.RS_DAMPED].signatures)
    read_only = te.copy()
    read_only.flags.writeable = False
    unaligned = np.frombuffer(bytearray(b"\0" + te.tobytes()), dtype=np.float64, offset=1)
    assert not unaligned.flags.aligned and unaligned.flags.writeable
    strided = np.repeat(te, 2)[::2]
    for arg in (read_only, unaligned, strided, np.broadcast_to(te, (21,)), list(te), tuple(te),
                te.reshape(1, -1), te.astype(te.dtype.newbyteorder())):
        r = ig.solve((0.0, 10.0), Y0, t_eval=arg)
        np.testing.assert_array_equal(r.t, te)
        np.testing.assert_array_equal(r.y, want.y)
    assert len(loop.SIMD_RUNNERS[loop.RS_DAMPED].signatures) == signatures
    # a plain float64 array is used as it is (no copy): the result's t is it
    assert ig.solve((0.0, 10.0), Y0, t_eval=te).t is te


@pytest.fixture
def small_chunks(monkeypatch):
    # Runs pause every 7 windows and the window store starts at 3; mbm.solve's cache of
    # Integrators is replaced for the test (its Integrators were built with the old budget).
    monkeypatch.setattr(fast, "CALL_WINDOWS", 7)
    monkeypatch.setattr(fast, "ENDS_CAPACITY", 3)
    monkeypatch.setattr(fast, "_integrator", functools.lru_cache(maxsize=8)(fast._integrator.__wrapped__))


def _counting(fn, calls):
    def wrapped(*args):
        calls.append(args[1])  # fresh
        return fn(*args)
    return wrapped


@pytest.mark.parametrize("wrap", [False, True])
def test_paused_runs_resume_bit_for_bit(small_chunks, monkeypatch, wrap):
    model, y0, T = mbm.Pendulum(0.1, 1.2), [0.0, 0.0], 100.0
    te = np.linspace(0.0, T, 201)
    kw = dict(rtol=1e-9, atol=1e-9)
    whole = mbm.Integrator(model, **kw)
    whole._words[record.WORD["call_windows"]] = 0  # no budget: one call
    want = whole.solve((0.0, T), y0, t_eval=te, wrap=wrap)
    monkeypatch.setattr(fast, "ENDS_CAPACITY", 10**5)  # a store for every window: one call
    want_ends = whole.solve((0.0, T), y0)
    monkeypatch.setattr(fast, "ENDS_CAPACITY", 3)
    ig = mbm.Integrator(model, **kw)
    calls = []
    ig._entry = _counting(ig._entry, calls)
    # a regime switch resumes through its own set's entry: counted too
    entry_at = fast._entry_at
    monkeypatch.setattr(fast, "_entry_at", lambda ig, regime: _counting(entry_at(ig, regime), calls))
    got = ig.solve((0.0, T), y0, t_eval=te, wrap=wrap)
    assert calls[0] is True and calls.count(False) >= want.n_windows // 7 - 1 > 5
    for key in want:
        if isinstance(want[key], np.ndarray):
            np.testing.assert_array_equal(got[key], want[key])
        elif isinstance(want[key], float) and math.isnan(want[key]):
            assert math.isnan(got[key])
        else:
            assert got[key] == want[key], key
    calls.clear()
    ends = ig.solve((0.0, T), y0)
    assert calls.count(False) >= want_ends.n_windows // 7 - 1 > 5
    np.testing.assert_array_equal(ends.t, want_ends.t)
    np.testing.assert_array_equal(ends.y, want_ends.y)
    assert ends.n_windows == want_ends.n_windows == ends.t.size - 1
    # through mbm.solve (its cache was emptied: chunked as well)
    np.testing.assert_array_equal(mbm.solve(model, (0.0, T), y0, t_eval=te, wrap=wrap, **kw).y, want.y)


def test_result_keys_and_regime_fields():
    # The result's keys in their order, and the regime fields both with a regime
    # (a running cycle: period, ⟨θ'⟩) and without (nan).
    model = mbm.Pendulum(0.1, 1.2)
    ig = mbm.Integrator(model, rtol=1e-8, atol=1e-8)
    r = ig.solve((0.0, 1000.0), [0.0, 0.0], t_eval=[1000.0])
    assert list(r) == list(fast._RESULT_KEYS)
    assert r.regime == "running" and r.period > 0 and r.mean_velocity == 2 * math.pi / r.period
    assert r.t_regime < 1000.0 and r.winding is None and r.reason == ig.reason
    short = ig.solve((0.0, 1.0), [0.0, 0.0], t_eval=[1.0])
    assert short.regime is None and math.isnan(short.t_regime)
    assert math.isnan(short.period) and math.isnan(short.mean_velocity)
    assert short.message == status.STATUS_MESSAGES[0] and short.success and short.status == 0

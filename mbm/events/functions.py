"""Event functions of your own: a ``numba.njit`` function g(t, θ, θ') watched on the windows.

:func:`mbm.solve` and :meth:`mbm.Integrator.solve` take, besides the built-in events of
:mod:`mbm.events.compiled`, any ``numba.njit`` function ``g(t, theta, theta_dot) -> float``
with scipy's optional attributes ``terminal`` (bool or int n: stop at the n-th
occurrence) and ``direction`` (> 0: only g increasing through 0, < 0: only
decreasing, 0 both; along the integration).  An event is a sign change of g on the
dense output, located as scipy's ``solve_ivp`` does it but on each window's own
formula:

* g is sampled at :data:`SAMPLES_PER_WINDOW` points of every window (its end
  included), on the window's formula (the dense output);
* a sign change between two samples is refined by Brent's method on that formula to
  a few ulps of t (:data:`TIME_ULPS`); the state is the dense output there;
* a zero that does not change sign (a tangency) is not an event, nor is a zero at the
  start; the run's end is an event where g reaches 0 there.

Unlike the built-in events, whose crossings are bounded from the window's polynomial,
g is a black box: two roots closer than a sample spacing (a window over
SAMPLES_PER_WINDOW) cancel and are missed, as two roots within one step are by scipy.
The windows of such a run are the approximant's throughout: no regime switch (a
running cycle's or a libration's stored period gives the built-in events by shifts
per turn, not g's, which may depend on t).

The locator is compiled for each event function (numba cannot cache a kernel that
takes another function as an argument): about 1.2 s on a function's first call in a
process on 2 cores (``python -m benchmarks.compile_profile``), then it is reused.
"""

import collections
import math
import numbers

import numba
import numpy as np
from numba.core.dispatcher import Dispatcher

from ..approximants.taylor import HEADER, taylor_eval_kernel
from ..core.window import theta_of

__all__ = ["is_event_function", "event_function_options", "function_crossings", "SAMPLES_PER_WINDOW"]

# Samples of g per window: a Taylor window of the controller spans well under a
# swing or a turn (its series' radius), so 8 samples resolve the roots of g's of the
# state that are a few degrees apart, at ~8 polynomial evaluations per window.
SAMPLES_PER_WINDOW = 8
# The refinement's tolerance in units of the spacing of the doubles at the event's time
# (the built-in events' own, mbm.core.event_watch.TIME_ULPS).
TIME_ULPS = 2.0
# Iterations of Brent's method before it stops (it converges in ~10; bisection alone
# would take ~60 for round-off).
BRENT_ITERATIONS = 100
# Rows reserved for one window's crossings (the buffer doubles as it fills).
ROWS_CAPACITY = 64
_EPS = 2.0 ** -52
_TWO_PI = 2.0 * math.pi


def is_event_function(obj):
    """Whether ``obj`` is a ``numba.njit`` function (taken as an event g(t, θ, θ'))."""
    return isinstance(obj, Dispatcher)


def event_function_options(g):
    """``(direction, terminal count)`` of an event function's scipy attributes: the
    sign of ``g.direction`` (default 0) and ``g.terminal`` as a count (True 1, False or
    absent 0, an int n >= 1 itself), or a TypeError/ValueError naming the attribute."""
    direction = getattr(g, "direction", 0.0)
    if isinstance(direction, (bool, np.bool_)) or not isinstance(direction, numbers.Real):
        raise TypeError(f"an event function's direction must be a real number, got {direction!r}")
    if not math.isfinite(float(direction)):
        raise ValueError(f"an event function's direction must be finite, got {direction!r}")
    terminal = getattr(g, "terminal", False)
    if terminal is True or terminal is False or isinstance(terminal, np.bool_):
        return float(np.sign(direction)), float(bool(terminal))
    if not isinstance(terminal, numbers.Integral):
        raise TypeError(f"an event function's terminal must be True, False or an int >= 1, got {terminal!r}")
    if terminal < 1:
        raise ValueError(f"an event function's terminal must be True, False or an int >= 1, got {terminal!r}")
    return float(np.sign(direction)), float(terminal)


#: A run's stored Taylor windows, as :func:`function_crossings` reads them: their start
#: times ``starts`` (n + 1, the last the end of window n − 1), the unwound θ at each start
#: ``start_theta``, their coefficient vectors ``coefs`` (one a row) and their count ``n``
#: (a plain tuple of the four, in this order, serves as well).
StoredWindows = collections.namedtuple("StoredWindows", ("starts", "start_theta", "coefs", "n"))


@numba.njit
def _value(g, c, t_w, k, s):
    # g on the window's formula at s from its anchor, and the state there.
    a, b = taylor_eval_kernel(c, s)
    th = theta_of(k, a)
    return float(g(t_w + s, th, b)), th, b


@numba.njit
def _brent(g, window, xa, xb, fa, fb, xtol):
    """The root of g's sign change on [xa, xb] (values fa, fb of opposite signs or one
    zero) by Brent's method, as scipy's brentq (Zeros/brentq.c); ``window`` is the
    Taylor window's (coefficients c, start time t_w, winding k) that :func:`_value` reads."""
    c, t_w, k = window
    xpre, xcur, fpre, fcur = xa, xb, fa, fb
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    xblk = fblk = spre = scur = 0.0
    for _ in range(BRENT_ITERATIONS):
        if fpre != 0.0 and fcur != 0.0 and (fpre < 0.0) != (fcur < 0.0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = 0.5 * xtol
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0.0 else -delta)
        fcur = _value(g, c, t_w, k, xcur)[0]
    return xcur


@numba.njit
def _window_samples(c, ss, m, th_s, v_s):
    """θ (unwound: the polynomial's φ) and θ' of a Taylor window at its ``m`` sample
    times ``ss`` from the anchor, all at once: the samples' Horner chains interleaved
    (independent, so they run in parallel), each the operations of
    :func:`mbm.approximants.taylor.taylor_eval_kernel` in its order: the same bits."""
    n = int(c[1])
    a = c[HEADER:]
    for j in range(m):
        th_s[j] = a[n]
        v_s[j] = n * a[n]
    for q in range(n - 1, 1, -1):
        aq, qaq = a[q], q * a[q]
        for j in range(m):
            th_s[j] = th_s[j] * ss[j] + aq
            v_s[j] = v_s[j] * ss[j] + qaq
    for j in range(m):
        th_s[j] = a[0] + ss[j] * (th_s[j] * ss[j] + a[1])
        v_s[j] = v_s[j] * ss[j] + a[1]


@numba.njit
def _push(rows, count, t, th, v, window):
    if count == rows.shape[0]:
        grown = np.empty((2 * count, 4))
        grown[:count] = rows
        rows = grown
    rows[count, 0], rows[count, 1], rows[count, 2], rows[count, 3] = t, th, v, window
    return rows, count + 1


@numba.njit
def function_crossings(g, want, windows, ref, first, last):
    """The sign changes of g(t, θ, θ') on ``n`` stored Taylor windows, in time order.

    ``windows`` is the :data:`StoredWindows` (starts, start_theta, coefs, n).

    ``ref`` carries the last sample with g ≠ 0 across calls: (s-time t, g, 1 if known,
    the window index it lies in relative to this call, −1 before it); ``first``: the
    first window is the run's (its start sampled to set ``ref``); ``last``: the last
    window is the run's (a zero of g at its end counts).  ``want`` is the direction
    (0 both).  Returns rows (t, θ, θ', window) and their count, or count −1 where g
    was not finite (the row 0 its t).
    """
    starts, start_theta, coefs, n = windows
    rows = np.empty((ROWS_CAPACITY, 4))
    count = 0
    ss = np.empty(SAMPLES_PER_WINDOW + 1)
    th_s = np.empty(SAMPLES_PER_WINDOW + 1)
    v_s = np.empty(SAMPLES_PER_WINDOW + 1)
    for i in range(n):
        t_w = starts[i]
        h = starts[i + 1] - t_w
        c = coefs[i]
        k = float(round((start_theta[i] - c[HEADER]) / _TWO_PI))
        xtol = TIME_ULPS * _EPS * max(abs(t_w), abs(t_w + h))
        j0 = 0 if (first and i == 0) else 1
        for j in range(j0, SAMPLES_PER_WINDOW + 1):
            ss[j - j0] = h if j == SAMPLES_PER_WINDOW else h * (j / SAMPLES_PER_WINDOW)
        _window_samples(c, ss, SAMPLES_PER_WINDOW + 1 - j0, th_s, v_s)
        for j in range(j0, SAMPLES_PER_WINDOW + 1):
            s = ss[j - j0]
            gs = float(g(t_w + s, theta_of(k, th_s[j - j0]), v_s[j - j0]))
            if not math.isfinite(gs):
                rows[0, 0] = t_w + s
                return rows, -1
            end = last and i == n - 1 and j == SAMPLES_PER_WINDOW
            if ref[2] != 0.0 and (gs * ref[1] < 0.0 or (gs == 0.0 and end)):
                up = ref[1] < 0.0
                if want == 0.0 or (want > 0.0) == up:
                    # The bracket on this window: from the reference sample if it lies
                    # here, else from the anchor (g kept the reference's sign up to it).
                    lo = ref[0] - t_w if ref[3] == i else 0.0
                    flo = ref[1] if ref[3] == i else _value(g, c, t_w, k, 0.0)[0]
                    if flo * gs > 0.0:
                        x = lo
                    else:
                        x = _brent(g, (c, t_w, k), lo, s, flo, gs, xtol)
                    t = starts[i + 1] if x == h else t_w + x
                    a, b = taylor_eval_kernel(c, t - t_w)  # the dense output at t
                    rows, count = _push(rows, count, t, theta_of(k, a), b, float(i))
            if gs != 0.0:
                ref[0], ref[1], ref[2], ref[3] = starts[i + 1] if j == SAMPLES_PER_WINDOW else t_w + s, gs, 1.0, float(i)
    ref[3] -= float(n)  # the next call's windows are numbered from 0
    return rows, count

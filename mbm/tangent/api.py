"""The options ``error_estimate`` and ``sensitivities`` and the fields they add to a result."""

import collections
import warnings

import numpy as np
from numba import njit

from ..approximants.taylor_series import HEADER, N_EXTRA
from ..core.window import KIND_TAYLOR
from ..validate import RTOL_FLOOR
from .series import workspace
from .reference import REF_DEGREE
from .transport import TANGENT_DEGREE, carry_arrays, transport

#: The sensitivities one may ask for, in the order of their series' columns
#: (:mod:`mbm.tangent.series`): the initial state, then the parameters.
SENSITIVITY_NAMES = ("theta0", "v0", "beta", "gamma", "omega", "drive_amplitude", "drive_frequency", "drive_phase")

#: The estimate is reported as a warning past this many times the tolerance
#: (atol + rtol·|y|): within it the run honours its tolerance as a local error control can.
WARN_FACTOR = 10.0

#: Past this |estimate of θ| (rad) the linear transport no longer holds: the error is of
#: the size of the scale over which sin θ bends, and in chaos it saturates at the
#: attractor's size while Φ keeps growing.  The estimate is then a companion run's.
SATURATION = 1.0

#: The companion run's tolerances, this factor tighter than the run's: its error is then
#: a thousandth of the run's while both are linear, of the same size once both saturate,
#: so y − y_companion measures y − y_true either way (RKSUITE's global error assessment
#: by a second, tighter run, taken only where the linear estimate fails).
COMPANION_FACTOR = 1e-3

#: What a call asked of the pass: the error estimate (bool) and the sensitivities' names.
Request = collections.namedtuple("Request", ("error_estimate", "names"))


class AccuracyWarning(UserWarning):
    """A result's error estimate exceeds its requested tolerance many times over."""


def request(error_estimate, sensitivities):
    """The :class:`Request` of a call's options, or None when neither is asked.

    Raises
    ------
    TypeError
        ``error_estimate`` not a bool, ``sensitivities`` a string or not a sequence.
    ValueError
        An unknown or repeated sensitivity name (the allowed ones named).
    """
    if error_estimate is not True and error_estimate is not False:
        raise TypeError(f"error_estimate must be True or False, got {error_estimate!r}")
    names = ()
    if sensitivities is not None:
        if isinstance(sensitivities, str) or not isinstance(sensitivities, (tuple, list)):
            raise TypeError("sensitivities must be a tuple or list of names from "
                            f"{SENSITIVITY_NAMES}, got {sensitivities!r}")
        names = tuple(sensitivities)
        for name in names:
            if name not in SENSITIVITY_NAMES:
                raise ValueError(f"sensitivities: unknown name {name!r}; the names are {SENSITIVITY_NAMES}")
        if len(set(names)) != len(names):
            raise ValueError(f"sensitivities: a name is repeated in {names}")
    if not error_estimate and not names:
        return None
    return Request(error_estimate, names)


def coefficient_width(kind, karg):
    """Width of the window store's coefficient rows the pass reads for a run of kind id
    ``kind`` and kind argument ``karg``: a Taylor window's whole layout (the pass follows
    the run's own series and its tail), else 0 (every window by the reference series)."""
    return HEADER + karg + N_EXTRA + 1 if kind == KIND_TAYLOR else 0


def attach(r, ig, req, windows):
    """Run the tangent pass along a result's windows and add its fields to ``r``.

    Parameters
    ----------
    r : SolveResult
        The run's result (``t``, ``y`` the outputs reached).
    ig : Integrator
        What ran it (model and tolerances).
    req : Request
    windows : (ndarray, ndarray, ndarray)
        The run's window ends: times (n + 1,), states (n + 1, 2), and the windows'
        coefficients (n, :func:`coefficient_width`).

    Adds ``error_estimate`` (the shape of ``y``: an estimate of y_computed − y_true at
    each output; the transported local errors, or where their θ part passes SATURATION,
    y − a companion run's y: :func:`companion_error`), and ``sensitivities`` (len(names), 2, n_out) with
    ``sensitivity_names``, as asked; warns (:class:`AccuracyWarning`) where the
    estimate exceeds WARN_FACTOR times the tolerance.
    """
    sc, codes, rows, n_order, kt = _setup(ig, req.names, windows[2].shape[1] > 0)
    t_out = r["t"]
    y_out = r["y"][:2]
    if not (t_out.flags.c_contiguous and y_out.flags.c_contiguous):
        t_out, y_out = np.ascontiguousarray(t_out), np.ascontiguousarray(y_out)
    err = np.empty((2, t_out.size))
    sens = np.empty((rows.size, 2, t_out.size))
    win_t, win_y, win_c = windows
    if ig.approximant.exact and not req.names:
        # An exact flow's windows are exact to round-off: no local error to transport.
        err[:] = 0.0
        taken = 0
    else:
        sign = 1.0 if win_t[-1] >= win_t[0] else -1.0
        # An exact flow's local error is not measured (over such long windows the
        # reference's own error would be); the run's own Taylor windows end where a
        # regime's formula takes over.
        t_measured = -np.inf * sign if ig.approximant.exact else np.inf * sign
        t_taylor = r["t_regime"] if r["t_regime"] == r["t_regime"] else np.inf * sign
        # Plain tuples in Track's, Control's and Report's order (transport's signature).
        ctl = ((ig.rtol, ig.atol), t_measured, t_taylor, n_order, kt, r["period"])
        track, report = (win_t, win_y, win_c, t_out, y_out), (err, sens, rows)
        pool, (ws, carry) = _buffers(ig, codes.size, rows.size, max(REF_DEGREE, int(n_order) + 2), r["period"])
        carry[2][0] = -1  # a fresh pass: transport's first call starts it
        taken = 1
        while taken == 1:  # chunked: Ctrl-C gets in between
            taken = transport(sc, codes, track, ctl, report, ws, carry)
        pool.append((ws, carry))  # read: the next pass's
    if taken < 0:
        err[:] = np.nan
        sens[:] = np.nan
        warnings.warn("the tangent pass met a non-finite state: error_estimate and sensitivities are NaN",
                      AccuracyWarning, stacklevel=5)
    if req.error_estimate:
        how = ""
        if taken >= 0 and np.abs(err[0]).max() > SATURATION:
            companion = companion_error(r, ig, (win_t[0], win_y[0], win_t[-1]))
            if companion is not None:
                err = companion
                how = (f" (from a companion run at {COMPANION_FACTOR:g} times the tolerances: the linear "
                       f"estimate passed {SATURATION:g} rad)")
        r["error_estimate"] = err
        ratio, row, col = worst_ratio(err, y_out, ig.rtol, ig.atol)
        if ratio > WARN_FACTOR:
            which = ("theta", "theta'")[row]
            warnings.warn(f"the error estimate of {which} reaches {ratio:.3g} times the tolerance "
                          f"(atol + rtol*|y|) at t = {t_out[col]:.6g} (estimated error {err[row, col]:.3g}){how}; "
                          "a tighter rtol/atol reduces it", AccuracyWarning, stacklevel=5)
    if req.names:
        r["sensitivities"] = sens
        r["sensitivity_names"] = req.names


def companion_error(r, ig, start):
    """y − y_companion at the outputs of result ``r``: the estimate where the linear one
    fails (SATURATION), from a run of ``ig``'s model at COMPANION_FACTOR times its
    tolerances (the default approximant; ``ig``'s max_step and max_windows) over the same
    span from the same state; ``start`` = (t0, (θ0, θ'0), the end reached).  θ compared
    unwrapped where the outputs are wrapped.  None where the tolerances cannot be made
    ten times tighter (rtol at its floor) or the companion run fails: the linear estimate
    stands then."""
    rtol = max(ig.rtol * COMPANION_FACTOR, RTOL_FLOOR)
    if rtol > 0.1 * ig.rtol:
        return None
    t0, y0, t_end = start
    t_out = np.ascontiguousarray(r["t"], dtype=float)
    comp = type(ig)(ig.model, rtol=rtol, atol=ig.atol * COMPANION_FACTOR, max_step=ig.max_step,
                    max_windows=ig._max_windows)
    wrapped = r.get("winding") is not None
    c = comp.solve((float(t0), float(t_end)), [float(y0[0]), float(y0[1])], t_eval=t_out, wrap=wrapped)
    if not c["success"] or c["t"].size != t_out.size:
        return None
    y, yc = np.array(r["y"][:2], dtype=float), np.array(c["y"][:2], dtype=float)
    if wrapped:
        y[0] += 2 * np.pi * r["winding"]
        yc[0] += 2 * np.pi * c["winding"]
    return y - yc


def _setup(ig, names, own):
    # (sc, codes, rows, n_order, kt) of a pass over ig's runs for ``names``; cached on ig
    # (an Integrator's model and approximant do not change).
    key = (names, own)
    cache = ig.__dict__.setdefault("_tangent_setups", {})
    if key not in cache:
        m = ig.model
        params = sorted({SENSITIVITY_NAMES.index(n) for n in names} - {0, 1})
        index = [SENSITIVITY_NAMES.index(n) for n in names]
        rows = np.array([i if i < 2 else 2 + params.index(i) for i in index], np.int64)
        n_order = int(ig._karg) if own else -1
        # Only the error: the tangent map at TANGENT_DEGREE; sensitivities: the run's degree.
        kt = n_order if names or n_order < 0 else min(TANGENT_DEGREE, n_order)
        cache[key] = (tuple(float(x) for x in m.params + m.drive), np.array([0, 1] + params, np.int64), rows,
                      float(n_order), kt)
    return cache[key]


def _buffers(ig, n_codes, n_sens, nt, period):
    # (the pool of ig's passes of this shape, (workspace, carry)): a previous pass's
    # arrays (set afresh by start: no allocations, no arrays boxed out of compiled code),
    # else new ones; the caller puts them back into the pool.
    key = (n_codes, n_sens, nt, period == period)
    pool = ig.__dict__.setdefault("_tangent_buffers", {}).setdefault(key, [])
    try:
        return pool, pool.pop()
    except IndexError:  # none yet, or other threads hold them
        return pool, (workspace(nt, n_codes), carry_arrays(n_sens, n_codes, nt, period))


@njit(cache=True)
def worst_ratio(err, y, rtol, atol):
    """(max |err|/(atol + rtol·|y|), its row, its column); (0, 0, 0) when empty."""
    best, row, col = 0.0, 0, 0
    for i in range(err.shape[0]):
        for j in range(err.shape[1]):
            q = abs(err[i, j]) / (atol + rtol * abs(y[i, j]))
            if q > best:
                best, row, col = q, i, j
    return best, row, col

"""The options ``error_estimate`` and ``sensitivities`` and the fields they add to a result."""

import collections
import warnings

import numpy as np

from .series import workspace
from .transport import REF_DEGREE, Report, Track, transport

#: The sensitivities one may ask for, in the order of their series' columns
#: (:mod:`mbm.tangent.series`): the initial state, then the parameters.
SENSITIVITY_NAMES = ("theta0", "v0", "beta", "gamma", "omega", "drive_amplitude", "drive_frequency", "drive_phase")

#: The estimate is reported as a warning past this many times the tolerance
#: (atol + rtol·|y|): within it the run honours its tolerance as a local error control can.
WARN_FACTOR = 10.0

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


def attach(r, ig, req, windows):
    """Run the tangent pass along a result's windows and add its fields to ``r``.

    Parameters
    ----------
    r : SolveResult
        The run's result (``t``, ``y`` the outputs reached).
    ig : Integrator
        What ran it (model and tolerances).
    req : Request
    windows : (ndarray, ndarray)
        The run's window ends: times (n + 1,) and states (n + 1, 2).

    Adds ``error_estimate`` (the shape of ``y``: an estimate of y_computed − y_true at
    each output), and ``sensitivities`` (len(names), 2, n_out) with
    ``sensitivity_names``, as asked; warns (:class:`AccuracyWarning`) where the
    estimate exceeds WARN_FACTOR times the tolerance.
    """
    m = ig.model
    sc = tuple(float(x) for x in m.params + m.drive)
    params = sorted({SENSITIVITY_NAMES.index(n) for n in req.names} - {0, 1})
    codes = np.array([0, 1] + params, np.int64)
    rows = np.array([SENSITIVITY_NAMES.index(n) if SENSITIVITY_NAMES.index(n) < 2
                     else 2 + params.index(SENSITIVITY_NAMES.index(n)) for n in req.names], np.int64)
    t_out = np.ascontiguousarray(r["t"], dtype=np.float64)
    y_out = np.ascontiguousarray(r["y"][:2], dtype=np.float64)
    err = np.empty((2, t_out.size))
    sens = np.empty((rows.size, 2, t_out.size))
    win_t, win_y = windows
    # An exact flow's windows are exact to round-off: their local error is not measured
    # (over such long windows the reference's own error would be what is measured).
    t_measured = (-np.inf if ig.approximant.exact else np.inf) * (1.0 if win_t[-1] >= win_t[0] else -1.0)
    taken = transport(sc, codes, Track(np.ascontiguousarray(win_t), np.ascontiguousarray(win_y), t_out, y_out),
                      (float(ig.rtol), float(ig.atol), float(t_measured)), Report(err, sens, rows),
                      workspace(REF_DEGREE, codes.size))
    if taken < 0:
        err[:] = np.nan
        sens[:] = np.nan
        warnings.warn("the tangent pass met a non-finite state: error_estimate and sensitivities are NaN",
                      AccuracyWarning, stacklevel=5)
    if req.error_estimate:
        r["error_estimate"] = err
        _warn_past_tolerance(err, y_out, t_out, ig.rtol, ig.atol)
    if req.names:
        r["sensitivities"] = sens
        r["sensitivity_names"] = req.names


def _warn_past_tolerance(err, y, t, rtol, atol):
    # AccuracyWarning where |estimate| > WARN_FACTOR·(atol + rtol·|y|) at some output.
    if err.size == 0:
        return
    ratio = np.abs(err) / (atol + rtol * np.abs(y))
    worst = np.unravel_index(np.nanargmax(ratio), ratio.shape)
    if ratio[worst] > WARN_FACTOR:
        which = ("theta", "theta'")[worst[0]]
        warnings.warn(f"the error estimate of {which} reaches {ratio[worst]:.3g} times the tolerance "
                      f"(atol + rtol*|y|) at t = {t[worst[1]]:.6g} (estimated error {err[worst]:.3g}); "
                      "a tighter rtol/atol reduces it", AccuracyWarning, stacklevel=5)

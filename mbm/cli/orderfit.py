r"""Convergence orders that cannot be read off a reference's own error.

A step-size study measures errors e_i = max |θ_h − θ_ref| at window lengths h_i and
fits the order p of e ≈ C h^p.  Two things bend such a fit without saying so:

* **the reference's floor**: once e_i is of the size of the reference's own error,
  the study measures the reference, not the method.  A point whose error is within
  :data:`FLOOR_FACTOR` times the reference's (measured) error is *at the reference's
  floor* (:func:`at_floor`) and is never fitted;
* **pre-asymptotic points**: at large h the error has not yet reached its C h^p
  regime (near a Taylor series' radius of convergence it grows far faster than h^p).
  The fit keeps the asymptotic range only: the longest run of consecutive points
  (in h) whose local slopes log(e_{i+1}/e_i) / log(h_{i+1}/h_i) agree within
  :func:`slope_tolerance`; among equally long runs, the one at the smallest h.

The order is the least-squares slope of log e against log h over that range, with
its standard error (:func:`fit_order`).  Used by ``mbm study``
(:mod:`mbm.cli.study`), ``examples/step_size_study.py`` and
``examples/convergence_study.py``.
"""

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["FLOOR_FACTOR", "ERR_CEIL", "SLOPE_TOL_ABS", "SLOPE_TOL_REL", "OrderFit",
           "at_floor", "slope_tolerance", "asymptotic_range", "fit_order"]

# A point whose error is within this factor of the reference's error may be mostly
# the reference's error (the rule: 10×); it is shown as at the floor, not fitted.
FLOOR_FACTOR = 10.0
# Errors at or above this are not small corrections (the run has left the solution's
# neighbourhood, e.g. a wrong number of turns), so no C h^p law describes them.
ERR_CEIL = 1e-1
# Local slopes of one asymptotic run differ only through the next term of the error
# expansion: a few per cent of p on the scenes of docs/convergent.md (taylor8: 6.97-7.09
# over τ = 1 .. 1/8 on ex1), while a pre-asymptotic point shifts its slope by whole
# orders (4.7 against 6.0 for taylor8 on the running scene at τ = 1/4, 1/8, 1/16).  Two
# slopes agree when they differ by at most max(SLOPE_TOL_ABS, SLOPE_TOL_REL · |p|).
SLOPE_TOL_ABS = 0.5
SLOPE_TOL_REL = 0.1

_NAN2 = (math.nan, math.nan)


@dataclass(frozen=True)
class OrderFit:
    """A fitted order p of e ≈ C h^p and what it rests on.

    Attributes
    ----------
    order : float
        Least-squares slope of log e against log h over the fitted range; NaN with
        fewer than two usable points.
    stderr : float
        Standard error of that slope (residual scatter over n − 2 degrees of freedom);
        NaN with fewer than three points (two points fix the slope, they do not test it).
    n : int
        Points in the fit.
    h_range : (float, float)
        Smallest and largest h fitted (NaN, NaN without a fit).
    slope_range : (float, float)
        Smallest and largest local slope between consecutive fitted points: how far the
        range is from a straight line, which the standard error (scatter about the
        line) does not show when the slopes drift steadily toward p.
    used : ndarray of bool
        Which of the input points were fitted.
    floor : ndarray of bool
        Which were at the reference's floor (:func:`at_floor`).
    """

    order: float
    stderr: float
    n: int
    h_range: tuple
    slope_range: tuple
    used: np.ndarray
    floor: np.ndarray

    def describe(self):
        """``"7.02 ± 0.03 over 4 points (local slopes 6.98 to 7.05), h in [0.0156, 0.125]"``
        (or why there is no fit)."""
        if not math.isfinite(self.order):
            return "n/a (fewer than two points in the asymptotic range)"
        h = f"h in [{self.h_range[0]:.3g}, {self.h_range[1]:.3g}]"
        if not math.isfinite(self.stderr):
            return f"{self.order:.2f} from 2 points only (no uncertainty), {h}"
        return (f"{self.order:.2f} ± {self.stderr:.2g} over {self.n} points (local slopes "
                f"{self.slope_range[0]:.2f} to {self.slope_range[1]:.2f}), {h}")


def at_floor(err, ref_error, factor=FLOOR_FACTOR):
    """Whether each error is within ``factor`` times the reference's own error.

    Parameters
    ----------
    err : array_like
        Errors against the reference (NaN for failed points: never at the floor).
    ref_error : float
        The reference's error, measured (e.g. against a second, independent reference).
    factor : float, optional
        How close counts as at the floor (:data:`FLOOR_FACTOR`).

    Returns
    -------
    ndarray of bool
    """
    err = np.asarray(err, dtype=float)
    return np.isfinite(err) & (err <= factor * float(ref_error))


def slope_tolerance(p):
    """How far two local slopes of one asymptotic run may differ, around order ``p``.

    Parameters
    ----------
    p : float
        The run's typical slope (its median local slope).

    Returns
    -------
    float
        max(:data:`SLOPE_TOL_ABS`, :data:`SLOPE_TOL_REL` · |p|).
    """
    return max(SLOPE_TOL_ABS, SLOPE_TOL_REL * abs(p))


def _local_slopes(lh, le):
    return np.diff(le) / np.diff(lh)


def asymptotic_range(h, err, min_slope=-math.inf):
    """Indices (into the inputs) of the asymptotic range of a sweep.

    Parameters
    ----------
    h, err : array_like
        Window lengths and errors of the usable points (finite, positive, distinct h).
    min_slope : float, optional
        A local slope below it ends a run (e.g. 1: the error must grow at least
        linearly in h, which a round-off plateau does not); default: none.

    Returns
    -------
    ndarray of int
        The longest run of points consecutive in h whose local slopes span at most
        :func:`slope_tolerance` of their median (max − min), ordered by h; among
        equally long runs the one at the smallest h (the most asymptotic).  Empty when
        no local slope reaches ``min_slope``; the one point itself when only one is given.
    """
    h = np.asarray(h, dtype=float)
    err = np.asarray(err, dtype=float)
    order = np.argsort(h)
    if order.size < 2:
        return order
    s = _local_slopes(np.log(h[order]), np.log(err[order]))
    best = (0, 0)  # [i, j]: points order[i..j], slopes s[i..j-1]
    for i in range(s.size):
        if s[i] < min_slope:
            continue
        j = i + 1
        while j < s.size + 1:
            run = s[i:j]
            if run[-1] < min_slope or np.ptp(run) > slope_tolerance(np.median(run)):
                break
            j += 1
        j -= 1  # s[i:j] is the longest agreeing run from i: points i..j
        if j - i > best[1] - best[0]:
            best = (i, j)
    return order[best[0]:best[1] + 1] if best[1] > best[0] else order[:0]


def fit_order(h, err, ref_error=0.0, ceil=ERR_CEIL, err_min=0.0, min_slope=-math.inf):
    """Order p of e ≈ C h^p over the asymptotic range, off the reference's floor.

    Parameters
    ----------
    h, err : array_like
        Mean window lengths and errors of one sweep (any order; NaN for failures).
    ref_error : float, optional
        The reference's own error: points with err ≤ :data:`FLOOR_FACTOR` · ref_error
        are at its floor and left out (default 0: none).
    ceil : float, optional
        Errors at or above it are left out (:data:`ERR_CEIL`).
    err_min : float, optional
        Errors at or below it are left out too (default 0), for a floor that is not the
        reference's: the method's own round-off, when the reference is far more accurate
        (a run of round-off points has agreeing slopes near 0 and would win the range).
    min_slope : float, optional
        Passed to :func:`asymptotic_range`.

    Returns
    -------
    OrderFit
    """
    h = np.asarray(h, dtype=float)
    err = np.asarray(err, dtype=float)
    floor = at_floor(err, ref_error)
    ok = np.isfinite(h) & (h > 0) & np.isfinite(err) & (err > max(float(err_min), 0.0)) & (err < ceil) & ~floor
    idx = np.flatnonzero(ok)
    # One point per h (a repeated h carries no slope information).
    _, first = np.unique(h[idx], return_index=True)
    idx = idx[np.sort(first)]
    used = np.zeros(h.size, dtype=bool)
    if idx.size < 2:
        return OrderFit(math.nan, math.nan, int(idx.size), _NAN2, _NAN2, used, floor)
    fit = idx[asymptotic_range(h[idx], err[idx], min_slope)]
    if fit.size < 2:
        return OrderFit(math.nan, math.nan, int(fit.size), _NAN2, _NAN2, used, floor)
    used[fit] = True
    x, y = np.log(h[fit]), np.log(err[fit])
    xc = x - x.mean()
    p = float(np.dot(xc, y - y.mean()) / np.dot(xc, xc))
    if fit.size > 2:
        resid = y - y.mean() - p * xc
        se = float(math.sqrt(np.dot(resid, resid) / (fit.size - 2) / np.dot(xc, xc)))
    else:
        se = math.nan
    srt = np.argsort(h[fit])
    s = _local_slopes(x[srt], y[srt])
    return OrderFit(p, se, int(fit.size), (float(h[fit].min()), float(h[fit].max())),
                    (float(s.min()), float(s.max())), used, floor)

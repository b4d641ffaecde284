"""A finished run's regime, period and mean velocity, read from its run record's words.

One reader for every front end (:func:`mbm.solve`, :class:`mbm.Integrator`, the
``solve_ivp`` method, the event runs).  A run that switched reports its regime's
summary (:func:`mbm.regimes.cycle_summary`, :func:`mbm.regimes.strobe_summary`).  A
driven run that integrated to its end without a switch is read by the lock watch (item
S8 of ``docs/theory/regimes.md``): the record keeps block means of its stroboscopic
samples θ(t_s + nT_d), and where the later half of them lies on a line of slope 2πp/q
per drive period (q ≤ LOCK_MAX_Q) within LOCK_BAND, over at least LOCK_MIN_PERIODS drive
periods, the phase is locked to the drive on the step p/q: the run is "phase-locked"
with ⟨θ'⟩ = (p/q)Ω and no switch time.  Its period is qT_d times the smallest multiple
whose samples repeat in the record's ring (up to LOCK_RING_PERIODS drive periods), and
NaN where none repeats: the orbit is chaotic within the step (or its period is longer
than the ring sees).  The switch rule stayed off for such runs because their map
converged too slowly (S5), their period was beyond STROBE_MAX_PERIODS (S7), or there
is no period.
"""

import collections
import fractions
import math

import numpy as np

from ..core.record import WORD
from .common import REGIME_NAMES, REGIME_NONE, REGIME_PHASE_LOCKED
from .cycle import cycle_summary
from .strobe import (LOCK_BAND, LOCK_BLOCK, LOCK_MAX_Q, LOCK_MIN_PERIODS, LOCK_PERIODIC, LOCK_RING_PERIODS,
                     STROBE_RING, strobe_summary)

__all__ = ["RunSummary", "run_summary", "lock_rate", "ring_period"]

#: A finished run's ``regime`` (its name, None: no regime), ``period`` and ``mean_velocity``
#: (NaN where the run does not have one).
RunSummary = collections.namedtuple("RunSummary", ("regime", "period", "mean_velocity"))

_TWO_PI = 2.0 * math.pi
_NONE = RunSummary(REGIME_NAMES[REGIME_NONE], math.nan, math.nan)
_I = {name: WORD[name] for name in ("regime", "lk_nb", "lk_lvl", "str_n")}
_F = {name: WORD[name] for name in ("cyc_T", "cyc_sign", "str_p", "str_q", "drive_freq", "drive_amp", "beta",
                                    "rtol", "atol", "lk_means", "str_ring")}


def lock_rate(means, level):
    """(S8) The step p/q of the lock watch's block means, or None where they show no lock.

    Parameters
    ----------
    means : ndarray
        The block means of θ − θ_first kept (the record's ``lk_means[:lk_nb]``), oldest
        first, each over LOCK_BLOCK·2^``level`` stroboscopic samples.
    level : int
        The record's ``lk_lvl``.

    Returns
    -------
    fractions.Fraction or None
        p/q (q ≤ LOCK_MAX_Q): the later half of the means lies within LOCK_BAND of a line
        of slope 2πp/q per sample over at least LOCK_MIN_PERIODS samples.
    """
    block = LOCK_BLOCK << int(level)
    tail = np.asarray(means, dtype=np.float64)[means.size // 2:]
    n = tail.size
    if n < 2 or n * block < LOCK_MIN_PERIODS:
        return None
    turns = (tail[-1] - tail[0]) / ((n - 1) * block * _TWO_PI)
    if not math.isfinite(turns):
        return None
    rate = fractions.Fraction(turns).limit_denominator(LOCK_MAX_Q)
    line = tail[0] + (_TWO_PI * block * float(rate)) * np.arange(n)
    if not np.max(np.abs(tail - line)) <= LOCK_BAND:
        return None
    return rate


def ring_period(ring, n, rate, scale):
    """(S8) The orbit's period in drive periods from the record's ring of samples, or 0.

    Parameters
    ----------
    ring : ndarray
        The record's ``str_ring``: sample i at 4(i mod STROBE_RING) on (winding count,
        φ, θ', window count).
    n : int
        The next sample's index (``str_n``); samples n − STROBE_RING … n − 1 are kept.
    rate : fractions.Fraction
        The step p/q (:func:`lock_rate`).
    scale : float
        The switch scale (atol + rtol·|θ'|): samples one period apart agree to
        LOCK_PERIODIC of it.

    Returns
    -------
    int
        The smallest multiple m of q, m ≤ LOCK_RING_PERIODS, whose samples m apart all
        gain 2πpm/q and agree in θ', else 0.
    """
    first = max(n - STROBE_RING, 0)
    for m in range(rate.denominator, LOCK_RING_PERIODS + 1, rate.denominator):
        if n - first <= m:
            break
        gain = float(rate * m) * _TWO_PI
        worst = 0.0
        for i in range(first + m, n):
            a, b = 4 * (i % STROBE_RING), 4 * ((i - m) % STROBE_RING)
            dth = (ring[a] - ring[b]) * _TWO_PI + (ring[a + 1] - ring[b + 1]) - gain
            worst = max(worst, abs(dth), abs(ring[a + 2] - ring[b + 2]))
        if worst <= LOCK_PERIODIC * scale:
            return m
    return 0


def run_summary(words, ints=None):
    """The :data:`RunSummary` of a finished run from its record's float64 words.

    Parameters
    ----------
    words : ndarray of float64
        One RUN record's words (:data:`mbm.core.record.WORD` indexes them).
    ints : ndarray of int64, optional
        The same words as int64 (a view the caller may already hold).

    Returns
    -------
    RunSummary
    """
    # Python scalars by .item(): this runs once per call of every front end, whose
    # shortest calls take ~10 µs.
    if ints is None:
        ints = words.view(np.int64)
    regime = ints.item(_I["regime"])
    if regime == REGIME_PHASE_LOCKED:
        period, velocity = strobe_summary(words.item(_F["str_p"]), words.item(_F["str_q"]),
                                          words.item(_F["drive_freq"]))
        return RunSummary(REGIME_NAMES[regime], period, velocity)
    if regime != REGIME_NONE:
        return RunSummary(REGIME_NAMES[regime], *cycle_summary(regime, words.item(_F["cyc_T"]),
                                                               words.item(_F["cyc_sign"])))
    if words.item(_F["drive_amp"]) == 0.0 or ints.item(_I["lk_nb"]) < 2:
        return _NONE
    return _lock_summary(words, ints)


def _lock_summary(words, ints):
    # (S8): a driven run that never switched, read by the lock watch (module docstring).
    freq = words.item(_F["drive_freq"])
    if not (freq > 0.0 and words.item(_F["beta"]) > 0.0):
        return _NONE
    start, nb = _F["lk_means"], ints.item(_I["lk_nb"])
    rate = lock_rate(words[start:start + nb], ints.item(_I["lk_lvl"]))
    if rate is None:
        return _NONE
    ring = words[_F["str_ring"]:_F["str_ring"] + 4 * STROBE_RING]
    n = ints.item(_I["str_n"])
    v_last = ring[4 * ((n - 1) % STROBE_RING) + 2]
    m = ring_period(ring, n, rate, words.item(_F["atol"]) + words.item(_F["rtol"]) * abs(v_last))
    period = m * _TWO_PI / freq if m else math.nan
    return RunSummary(REGIME_NAMES[REGIME_PHASE_LOCKED], period, float(rate) * freq)

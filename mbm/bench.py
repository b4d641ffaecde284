r"""Work-precision benchmark: MBM against scipy, SUNDIALS and compiled peers.

Run ``python -m mbm.bench --help``.  Every solver in the registry
(:func:`solver_registry`) is a function ``run(scene, knob) -> theta`` returning θ
at the scene's 201 output times, plus a sweep of its accuracy knob (``rtol`` for
adaptive solvers, the step ``h`` or window ``τ`` for fixed-step ones), ordered
from cheap to expensive.  For every knob value the harness times the whole call
a user would make (solver construction, integration, output at the 201 times),
takes the median of ``repeats`` runs after one warm-up run, and records the
error ``max |θ − θ_ref|`` over the 201 times.  A work-precision curve is the list
of (error, median time) pairs.  At each target error (1e-3, 1e-6, 1e-9) the table
shows the cheapest *measured* point whose error is at or below the target
(nothing is interpolated) and its ratio to the best MBM entry.

Scenes (ω = 1 throughout; P1-P3 and P6 from the papers, P4-P5 long runs):

====  =====  =====  =====  ======  ==========  =========================================
name  β      γ      θ₀     θ̇₀      t           what
====  =====  =====  =====  ======  ==========  =========================================
P1    0.4    0      0      0.25    [0, 20]     the first paper's damped pendulum
P2    0.1    0.3    30°    0       [0, 80]     the second paper's Example 1
P3    0.1    0.6    90°    0       [0, 80]     the second paper's Example 2 scene
P4    0.01   0.3    1      0       [0, 1e4]    weak damping, long horizon
P5    0.1    1.2    0      0       [0, 1000]   running (γ > ω²): θ grows to ~1.2e4
P6    0      0      0      1.999   [0, 200]    just inside the separatrix (θ̇ = 2)
====  =====  =====  =====  ======  ==========  =========================================

Reference (:func:`scene_reference`): for P6 (β = γ = 0) the exact elliptic flow
:func:`mbm.pendulum_flow`; for the others a degree-28 Taylor integrator in 128-bit
fixed point (mpmath's fixed-point sine and cosine, ~1e-20), because CVODE at
rtol = atol = 1e-13 is itself off by 2e-8 on P5 and 4e-8 on P6.  Each reference is
checked against CVODE at 1e-13 (:func:`mbm.reference`) and the difference is
reported.  Without mpmath the reference falls back to CVODE, checked against the
numba DOP853 below, and targets within :data:`REF_MARGIN` of that difference are
flagged.  References are cached as ``.npz`` files in :func:`default_cache_dir`
(not in the repository).

A full run (all scenes, 5 repeats) took ~30 min on a loaded 2-core machine, most
of it in the Python-RHS solvers on P4 and P5 up to the per-point budget
:data:`MAX_POINT_SECONDS`; ``--scenes``, ``--solvers`` and ``--max-seconds`` narrow
it, ``--json``/``--from-json`` save and re-render results.

The numba peers written here are what a user would write: a fixed-step RK4 that
lands on the output times, and an adaptive Dormand-Prince 8(5,3) (DOP853) with
its 7th-order dense output, with the coefficients of Hairer, Nørsett & Wanner
(the Fortran DOP853; tables as in scipy's ``dop853_coefficients.py``, which has
no public import path, so they are copied below).
"""

import argparse
import contextlib
import dataclasses
import datetime
import functools
import gc
import hashlib
import json
import math
import os
import platform
import shlex
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

from .cli_progress import Progress

__all__ = [
    "Scene",
    "Solver",
    "SCENES",
    "MBM_VARIANTS",
    "timed_runs",
    "TARGETS",
    "solver_registry",
    "scene_reference",
    "default_cache_dir",
    "fixed_point_reference",
    "run_sweep",
    "run_benchmark",
    "write_plots",
    "cheapest_at_target",
    "cold_first_call_seconds",
    "format_report",
    "rk4_run",
    "dop853_run",
    "machine_info",
    "main",
]

# ---------------------------------------------------------------------------
# Tuning constants
# ---------------------------------------------------------------------------

# Output times per scene (the 201 equally spaced times, ends included).
N_OUTPUT = 201

# Target errors of the tables: the three accuracy regimes.
TARGETS = (1e-3, 1e-6, 1e-9)

# Adaptive solvers' knob: rtol from 1e-2 to 1e-12 in half decades (a factor ~3 in
# error between points, so "cheapest point below the target" wastes at most ~3x
# in error); atol = rtol because the error is measured absolutely on θ = O(1).
RTOL_SWEEP = tuple(10.0 ** (-k / 2) for k in range(4, 25))

# MBM fixed windows τ (solve_ivp and mbm.solve), coarse to fine in steps of √2 from
# 2 (a third of the small-oscillation period; past the Taylor radius of a fast
# rotation, where points fail and are recorded as failures) to 2^-9 (order-4
# compositions reach 1e-10 there on P2).
TAU_SWEEP = tuple(2.0 ** (1 - j / 2) for j in range(0, 21))

# Fixed-step RK4 steps h, coarse to fine in steps of √2 from 1 to 2^-12: RK4 with
# error ~ h^4 needs h ~ 5e-3 for 1e-9 on P2.
H_SWEEP = tuple(2.0 ** (-j / 2) for j in range(0, 25))

# --quick (for tests): three knob values per solver, a coarse, middle, fine one.
QUICK_RTOLS = (1e-3, 1e-6, 1e-9)
QUICK_TAUS = (1.0, 0.25, 0.0625)
QUICK_HS = (0.2, 0.05, 0.0125)
QUICK_REPEATS = 3

# Timed runs per point after the warm-up run; the issue asks for medians of >= 5.
DEFAULT_REPEATS = 5

# A sweep stops after the first point whose warm-up run exceeds this many seconds
# (that point is recorded with its error but not timed): later points of a sweep
# are more accurate and cost more, and 5 repeats of a 2 s point already make a
# scene-solver pair cost ~25 s.  Overridden by --max-seconds.
MAX_POINT_SECONDS = 2.0

# A sweep also stops once the error is this small: 100x below the tightest target,
# further points only measure round-off and cost more.
STOP_ERROR = 1e-11

# CVODE tolerance (rtol = atol) of the check of each reference, and of the
# reference itself when mpmath is missing: the 1e-13.  Measured against the
# fixed-point reference it is off by 2e-11 (P2), 7e-11 (P4), 4e-9 (P5 at t <= 200:
# rtol·|θ| with |θ| ~ 1e3) and 4e-8 (P6, next to the separatrix).
REF_TOL = 1e-13

# Fixed-point Taylor reference (mpmath's fixed-point sin/cos, Python integers):
# 2^-128 per operation keeps 2e5 steps of ~1e3 operations below 1e-30; degree 28
# with steps <= 1/16 gives a truncation (h/R)^29 <= 1e-23 per step even on the
# running scene, whose Taylor radius R ~ 0.4 is the smallest.
REF_BITS = 128
REF_DEGREE = 28
REF_MAX_STEP = 1.0 / 16.0

# Tolerance of the independent check of a CVODE reference (numba DOP853 below, used
# only when mpmath is missing); its difference from the reference bounds the larger
# of the two errors.
REF_CHECK_TOL = 1e-13

# With a CVODE reference, a target below REF_MARGIN x the reference discrepancy is
# flagged: errors there are measured against a reference no better than the target.
REF_MARGIN = 10.0

# A fixed-point or exact reference that differs from its CVODE check by more than
# this is a bug, not a tolerance effect (CVODE at 1e-13 is within 1e-7 everywhere).
REF_SANITY = 1e-6

# Step budget of the numba peers and numbalsoda (per run / per output interval):
# large enough for every point of the sweeps, small enough that a stuck
# integration returns instead of spinning.
MAX_STEPS = 50_000_000

# --cold-compile: limit on the subprocess that compiles MBM's kernels from an empty
# numba cache (a few tens of seconds on a loaded 2-core machine).
COLD_COMPILE_TIMEOUT = 600

# Bump when the reference computation changes, to invalidate cached references.
REFERENCE_VERSION = 1

# DOP853 step-size control, as scipy and the Fortran DOP853: safety factor, the
# smallest and largest step ratios, and the error exponent -1/(7 + 1) of the
# 7th-order error estimator.
DOP_SAFETY = 0.9
DOP_MIN_FACTOR = 0.2
DOP_MAX_FACTOR = 10.0
DOP_ERROR_EXPONENT = -1.0 / 8.0


# ---------------------------------------------------------------------------
# Scenes
# ---------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Scene:
    """One initial-value problem θ'' + βθ' + ω² sin θ = γ of the benchmark.

    Parameters
    ----------
    name : str
        Short name (``"P1"`` …).
    beta, gamma, omega : float
        Model parameters.
    theta0, v0 : float
        Initial state θ(0), θ'(0).
    t_end : float
        Horizon; the solution is compared at ``N_OUTPUT`` equally spaced times
        in ``[0, t_end]``.
    title : str
        One-line description for the report.

    Notes
    -----
    ``model``, ``y0`` and ``t_eval`` are built once per scene and shared by every
    run: a timed call measures the solver on ready inputs, not ``np.linspace`` (which
    the numba RK4, building its output times inside, never paid).  Runners must not modify them
    (``test_runners_leave_scene_inputs_unchanged``).
    """

    name: str
    beta: float
    gamma: float
    omega: float
    theta0: float
    v0: float
    t_end: float
    title: str

    @functools.cached_property
    def model(self):
        """The :class:`mbm.Pendulum` of the scene."""
        from .problem import Pendulum

        return Pendulum(self.beta, self.gamma, self.omega)

    @functools.cached_property
    def y0(self):
        """Initial state as a float array of shape (2,)."""
        return np.array([self.theta0, self.v0], dtype=float)

    @property
    def t_span(self):
        """``(0.0, t_end)``."""
        return (0.0, float(self.t_end))

    @functools.cached_property
    def t_eval(self):
        """The ``N_OUTPUT`` output times."""
        return np.linspace(0.0, float(self.t_end), N_OUTPUT)

    @property
    def dt_out(self):
        """Spacing of the output times."""
        return float(self.t_end) / (N_OUTPUT - 1)


SCENES = {
    s.name: s
    for s in (
        Scene("P1", 0.4, 0.0, 1.0, 0.0, 0.25, 20.0, "first paper: beta=0.4, gamma=0, theta0=0, v0=0.25"),
        Scene("P2", 0.1, 0.3, 1.0, math.radians(30.0), 0.0, 80.0, "Example 1: beta=0.1, gamma=0.3, theta0=30 deg"),
        Scene("P3", 0.1, 0.6, 1.0, math.radians(90.0), 0.0, 80.0, "Example 2 scene: beta=0.1, gamma=0.6, theta0=90 deg"),
        Scene("P4", 0.01, 0.3, 1.0, 1.0, 0.0, 1.0e4, "weak damping: beta=0.01, gamma=0.3, theta0=1, t<=1e4"),
        Scene("P5", 0.1, 1.2, 1.0, 0.0, 0.0, 1000.0, "running: beta=0.1, gamma=1.2, t<=1000"),
        Scene("P6", 0.0, 0.0, 1.0, 0.0, 1.999, 200.0, "near separatrix: beta=gamma=0, v0=1.999, t<=200"),
    )
}


# ---------------------------------------------------------------------------
# Numba peers: fixed-step RK4 and adaptive DOP853 with dense output
# ---------------------------------------------------------------------------
# cache=False on purpose: the compile time of these peers is part of what the
# benchmark reports, so each process compiles them afresh.


@njit(cache=False)
def _pend_rhs(beta, gamma, w2, th, v):
    return v, gamma - beta * v - w2 * math.sin(th)


@njit(cache=False)
def rk4_run(beta, gamma, w2, theta0, v0, dt_out, n_out, k):
    """Classical RK4 with step ``dt_out / k``, sampled every ``k`` steps.

    Parameters
    ----------
    beta, gamma, w2 : float
        β, γ and ω².
    theta0, v0 : float
        Initial state at t = 0.
    dt_out : float
        Spacing of the output times.
    n_out : int
        Number of output times (t = 0 included).
    k : int
        Steps per output interval.

    Returns
    -------
    out : ndarray, shape (2, n_out)
        θ and θ' at t = j·dt_out.
    """
    h = dt_out / k
    h2 = 0.5 * h
    h6 = h / 6.0
    out = np.empty((2, n_out))
    th = theta0
    v = v0
    out[0, 0] = th
    out[1, 0] = v
    for j in range(1, n_out):
        for _ in range(k):
            k1t, k1v = _pend_rhs(beta, gamma, w2, th, v)
            k2t, k2v = _pend_rhs(beta, gamma, w2, th + h2 * k1t, v + h2 * k1v)
            k3t, k3v = _pend_rhs(beta, gamma, w2, th + h2 * k2t, v + h2 * k2v)
            k4t, k4v = _pend_rhs(beta, gamma, w2, th + h * k3t, v + h * k3v)
            th += h6 * (k1t + 2.0 * (k2t + k3t) + k4t)
            v += h6 * (k1v + 2.0 * (k2v + k3v) + k4v)
        out[0, j] = th
        out[1, j] = v
    return out


# Dormand-Prince 8(5,3) coefficients: E. Hairer, S. P. Nørsett, G. Wanner, Solving
# Ordinary Differential Equations I (2nd ed., Springer 1993), Sec. II.10, and the
# Fortran code DOP853; transcribed as in scipy/integrate/_ivp/dop853_coefficients.py
# (BSD-3-Clause).  12 stages, a 13th FSAL stage f(t + h, y_new) for the error
# estimate, 3 extra stages for the 7th-order dense output.
_DOP_N_STAGES = 12
_DOP_N_EXT = 16
_DOP_C = np.array([
    0.0, 0.526001519587677318785587544488e-01, 0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510, 0.281649658092772603273242802490,
    0.333333333333333333333333333333, 0.25, 0.307692307692307692307692307692,
    0.651282051282051282051282051282, 0.6, 0.857142857142857142857142857142,
    1.0, 1.0, 0.1, 0.2, 0.777777777777777777777777777778,
])
_DOP_A = np.zeros((_DOP_N_EXT, _DOP_N_EXT))
for (_i, _j), _x in {
    (1, 0): 5.26001519587677318785587544488e-2,
    (2, 0): 1.97250569845378994544595329183e-2, (2, 1): 5.91751709536136983633785987549e-2,
    (3, 0): 2.95875854768068491816892993775e-2, (3, 2): 8.87627564304205475450678981324e-2,
    (4, 0): 2.41365134159266685502369798665e-1, (4, 2): -8.84549479328286085344864962717e-1,
    (4, 3): 9.24834003261792003115737966543e-1,
    (5, 0): 3.7037037037037037037037037037e-2, (5, 3): 1.70828608729473871279604482173e-1,
    (5, 4): 1.25467687566822425016691814123e-1,
    (6, 0): 3.7109375e-2, (6, 3): 1.70252211019544039314978060272e-1,
    (6, 4): 6.02165389804559606850219397283e-2, (6, 5): -1.7578125e-2,
    (7, 0): 3.70920001185047927108779319836e-2, (7, 3): 1.70383925712239993810214054705e-1,
    (7, 4): 1.07262030446373284651809199168e-1, (7, 5): -1.53194377486244017527936158236e-2,
    (7, 6): 8.27378916381402288758473766002e-3,
    (8, 0): 6.24110958716075717114429577812e-1, (8, 3): -3.36089262944694129406857109825,
    (8, 4): -8.68219346841726006818189891453e-1, (8, 5): 2.75920996994467083049415600797e1,
    (8, 6): 2.01540675504778934086186788979e1, (8, 7): -4.34898841810699588477366255144e1,
    (9, 0): 4.77662536438264365890433908527e-1, (9, 3): -2.48811461997166764192642586468,
    (9, 4): -5.90290826836842996371446475743e-1, (9, 5): 2.12300514481811942347288949897e1,
    (9, 6): 1.52792336328824235832596922938e1, (9, 7): -3.32882109689848629194453265587e1,
    (9, 8): -2.03312017085086261358222928593e-2,
    (10, 0): -9.3714243008598732571704021658e-1, (10, 3): 5.18637242884406370830023853209,
    (10, 4): 1.09143734899672957818500254654, (10, 5): -8.14978701074692612513997267357,
    (10, 6): -1.85200656599969598641566180701e1, (10, 7): 2.27394870993505042818970056734e1,
    (10, 8): 2.49360555267965238987089396762, (10, 9): -3.0467644718982195003823669022,
    (11, 0): 2.27331014751653820792359768449, (11, 3): -1.05344954667372501984066689879e1,
    (11, 4): -2.00087205822486249909675718444, (11, 5): -1.79589318631187989172765950534e1,
    (11, 6): 2.79488845294199600508499808837e1, (11, 7): -2.85899827713502369474065508674,
    (11, 8): -8.87285693353062954433549289258, (11, 9): 1.23605671757943030647266201528e1,
    (11, 10): 6.43392746015763530355970484046e-1,
    (12, 0): 5.42937341165687622380535766363e-2, (12, 5): 4.45031289275240888144113950566,
    (12, 6): 1.89151789931450038304281599044, (12, 7): -5.8012039600105847814672114227,
    (12, 8): 3.1116436695781989440891606237e-1, (12, 9): -1.52160949662516078556178806805e-1,
    (12, 10): 2.01365400804030348374776537501e-1, (12, 11): 4.47106157277725905176885569043e-2,
    (13, 0): 5.61675022830479523392909219681e-2, (13, 6): 2.53500210216624811088794765333e-1,
    (13, 7): -2.46239037470802489917441475441e-1, (13, 8): -1.24191423263816360469010140626e-1,
    (13, 9): 1.5329179827876569731206322685e-1, (13, 10): 8.20105229563468988491666602057e-3,
    (13, 11): 7.56789766054569976138603589584e-3, (13, 12): -8.298e-3,
    (14, 0): 3.18346481635021405060768473261e-2, (14, 5): 2.83009096723667755288322961402e-2,
    (14, 6): 5.35419883074385676223797384372e-2, (14, 7): -5.49237485713909884646569340306e-2,
    (14, 10): -1.08347328697249322858509316994e-4, (14, 11): 3.82571090835658412954920192323e-4,
    (14, 12): -3.40465008687404560802977114492e-4, (14, 13): 1.41312443674632500278074618366e-1,
    (15, 0): -4.28896301583791923408573538692e-1, (15, 5): -4.69762141536116384314449447206,
    (15, 6): 7.68342119606259904184240953878, (15, 7): 4.06898981839711007970213554331,
    (15, 8): 3.56727187455281109270669543021e-1, (15, 12): -1.39902416515901462129418009734e-3,
    (15, 13): 2.9475147891527723389556272149, (15, 14): -9.15095847217987001081870187138,
}.items():
    _DOP_A[_i, _j] = _x
_DOP_B = _DOP_A[_DOP_N_STAGES, :_DOP_N_STAGES].copy()
# 5th- and 3rd-order error estimators over the 13 stages (FSAL stage last).
_DOP_E3 = np.zeros(_DOP_N_STAGES + 1)
_DOP_E3[:-1] = _DOP_B
_DOP_E3[0] -= 0.244094488188976377952755905512
_DOP_E3[8] -= 0.733846688281611857341361741547
_DOP_E3[11] -= 0.220588235294117647058823529412e-1
_DOP_E5 = np.zeros(_DOP_N_STAGES + 1)
for _i, _x in {
    0: 0.1312004499419488073250102996e-1, 5: -0.1225156446376204440720569753e1,
    6: -0.4957589496572501915214079952, 7: 0.1664377182454986536961530415e1,
    8: -0.3503288487499736816886487290, 9: 0.3341791187130174790297318841,
    10: 0.8192320648511571246570742613e-1, 11: -0.2235530786388629525884427845e-1,
}.items():
    _DOP_E5[_i] = _x
# Dense output: rows 3..6 of the interpolant (rows 0..2 come from y, f at the ends).
_DOP_D = np.zeros((4, _DOP_N_EXT))
for (_i, _j), _x in {
    (0, 0): -0.84289382761090128651353491142e1, (0, 5): 0.56671495351937776962531783590,
    (0, 6): -0.30689499459498916912797304727e1, (0, 7): 0.23846676565120698287728149680e1,
    (0, 8): 0.21170345824450282767155149946e1, (0, 9): -0.87139158377797299206789907490,
    (0, 10): 0.22404374302607882758541771650e1, (0, 11): 0.63157877876946881815570249290,
    (0, 12): -0.88990336451333310820698117400e-1, (0, 13): 0.18148505520854727256656404962e2,
    (0, 14): -0.91946323924783554000451984436e1, (0, 15): -0.44360363875948939664310572000e1,
    (1, 0): 0.10427508642579134603413151009e2, (1, 5): 0.24228349177525818288430175319e3,
    (1, 6): 0.16520045171727028198505394887e3, (1, 7): -0.37454675472269020279518312152e3,
    (1, 8): -0.22113666853125306036270938578e2, (1, 9): 0.77334326684722638389603898808e1,
    (1, 10): -0.30674084731089398182061213626e2, (1, 11): -0.93321305264302278729567221706e1,
    (1, 12): 0.15697238121770843886131091075e2, (1, 13): -0.31139403219565177677282850411e2,
    (1, 14): -0.93529243588444783865713862664e1, (1, 15): 0.35816841486394083752465898540e2,
    (2, 0): 0.19985053242002433820987653617e2, (2, 5): -0.38703730874935176555105901742e3,
    (2, 6): -0.18917813819516756882830838328e3, (2, 7): 0.52780815920542364900561016686e3,
    (2, 8): -0.11573902539959630126141871134e2, (2, 9): 0.68812326946963000169666922661e1,
    (2, 10): -0.10006050966910838403183860980e1, (2, 11): 0.77771377980534432092869265740,
    (2, 12): -0.27782057523535084065932004339e1, (2, 13): -0.60196695231264120758267380846e2,
    (2, 14): 0.84320405506677161018159903784e2, (2, 15): 0.11992291136182789328035130030e2,
    (3, 0): -0.25693933462703749003312586129e2, (3, 5): -0.15418974869023643374053993627e3,
    (3, 6): -0.23152937917604549567536039109e3, (3, 7): 0.35763911791061412378285349910e3,
    (3, 8): 0.93405324183624310003907691704e2, (3, 9): -0.37458323136451633156875139351e2,
    (3, 10): 0.10409964950896230045147246184e3, (3, 11): 0.29840293426660503123344363579e2,
    (3, 12): -0.43533456590011143754432175058e2, (3, 13): 0.96324553959188282948394950600e2,
    (3, 14): -0.39177261675615439165231486172e2, (3, 15): -0.14972683625798562581422125276e3,
}.items():
    _DOP_D[_i, _j] = _x
del _i, _j, _x


@njit(cache=False)
def _dop_stage(K, s, beta, gamma, w2, th, v, h, A):
    """Stage ``s``: K[s] = f(y + h Σ_{i<s} A[s, i] K[i])."""
    dt = 0.0
    dv = 0.0
    for i in range(s):
        a = A[s, i]
        if a != 0.0:
            dt += a * K[i, 0]
            dv += a * K[i, 1]
    K[s, 0], K[s, 1] = _pend_rhs(beta, gamma, w2, th + h * dt, v + h * dv)


@njit(cache=False)
def dop853_run(beta, gamma, w2, theta0, v0, t_eval, rtol, atol, max_steps):
    """Adaptive DOP853 for the pendulum, output at ``t_eval`` by dense output.

    Step-size control and initial step as in scipy's ``DOP853`` (which follows
    Hairer-Nørsett-Wanner's code): mixed error norm of the 5th- and 3rd-order
    estimators, safety 0.9, step ratio in [0.2, 10].  Output times are reached
    with the 7th-order continuous extension (3 extra stages, only on steps that
    contain an output time), so the step sequence does not depend on them.

    Parameters
    ----------
    beta, gamma, w2 : float
        β, γ and ω².
    theta0, v0 : float
        State at ``t_eval[0]``.
    t_eval : ndarray
        Increasing output times; the integration runs from ``t_eval[0]`` to
        ``t_eval[-1]``.
    rtol, atol : float
        Tolerances (scaled by max(|y|, |y_new|) per component, RMS norm).
    max_steps : int
        Accepted-step budget; past it the remaining outputs are NaN.

    Returns
    -------
    out : ndarray, shape (2, len(t_eval))
        θ and θ' at ``t_eval`` (NaN where not reached).
    """
    A = _DOP_A
    B = _DOP_B
    E3 = _DOP_E3
    E5 = _DOP_E5
    D = _DOP_D
    n_out = t_eval.size
    out = np.full((2, n_out), np.nan)
    K = np.empty((_DOP_N_EXT, 2))
    t = t_eval[0]
    tf = t_eval[-1]
    th = theta0
    v = v0
    out[0, 0] = th
    out[1, 0] = v
    j = 1
    f0, f1 = _pend_rhs(beta, gamma, w2, th, v)
    # Initial step: HNW II.4 (scipy's select_initial_step), error order 7.
    sc0 = atol + abs(th) * rtol
    sc1 = atol + abs(v) * rtol
    d0 = math.sqrt(0.5 * ((th / sc0) ** 2 + (v / sc1) ** 2))
    d1 = math.sqrt(0.5 * ((f0 / sc0) ** 2 + (f1 / sc1) ** 2))
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, tf - t)
    g0, g1 = _pend_rhs(beta, gamma, w2, th + h0 * f0, v + h0 * f1)
    d2 = math.sqrt(0.5 * (((g0 - f0) / sc0) ** 2 + ((g1 - f1) / sc1) ** 2)) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    h = min(100.0 * h0, h1, tf - t)
    steps = 0
    while j < n_out:
        if steps >= max_steps:
            break
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        rejected = False
        while True:
            if h < min_step:
                return out  # step size underflow: leave the rest NaN
            last = t + h >= tf
            if last:
                h = tf - t
            K[0, 0] = f0
            K[0, 1] = f1
            for s in range(1, _DOP_N_STAGES):
                _dop_stage(K, s, beta, gamma, w2, th, v, h, A)
            dt = 0.0
            dv = 0.0
            for i in range(_DOP_N_STAGES):
                dt += B[i] * K[i, 0]
                dv += B[i] * K[i, 1]
            th_new = th + h * dt
            v_new = v + h * dv
            K[_DOP_N_STAGES, 0], K[_DOP_N_STAGES, 1] = _pend_rhs(beta, gamma, w2, th_new, v_new)
            sc0 = atol + max(abs(th), abs(th_new)) * rtol
            sc1 = atol + max(abs(v), abs(v_new)) * rtol
            e50 = 0.0
            e51 = 0.0
            e30 = 0.0
            e31 = 0.0
            for i in range(_DOP_N_STAGES + 1):
                e50 += E5[i] * K[i, 0]
                e51 += E5[i] * K[i, 1]
                e30 += E3[i] * K[i, 0]
                e31 += E3[i] * K[i, 1]
            err5 = (e50 / sc0) ** 2 + (e51 / sc1) ** 2
            err3 = (e30 / sc0) ** 2 + (e31 / sc1) ** 2
            if err5 == 0.0 and err3 == 0.0:
                err = 0.0
            else:
                err = h * err5 / math.sqrt((err5 + 0.01 * err3) * 2.0)
            if err < 1.0:
                if err == 0.0:
                    factor = DOP_MAX_FACTOR
                else:
                    factor = min(DOP_MAX_FACTOR, DOP_SAFETY * err ** DOP_ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                break
            h *= max(DOP_MIN_FACTOR, DOP_SAFETY * err ** DOP_ERROR_EXPONENT)
            rejected = True
        t_new = tf if last else t + h
        if t_eval[j] <= t_new:
            # Continuous extension (only on steps that hold an output time).
            for s in range(_DOP_N_STAGES + 1, _DOP_N_EXT):
                _dop_stage(K, s, beta, gamma, w2, th, v, h, A)
            dy0 = th_new - th
            dy1 = v_new - v
            F = np.empty((7, 2))
            F[0, 0] = dy0
            F[0, 1] = dy1
            F[1, 0] = h * K[0, 0] - dy0
            F[1, 1] = h * K[0, 1] - dy1
            F[2, 0] = 2.0 * dy0 - h * (K[_DOP_N_STAGES, 0] + K[0, 0])
            F[2, 1] = 2.0 * dy1 - h * (K[_DOP_N_STAGES, 1] + K[0, 1])
            for r in range(4):
                a0 = 0.0
                a1 = 0.0
                for i in range(_DOP_N_EXT):
                    a0 += D[r, i] * K[i, 0]
                    a1 += D[r, i] * K[i, 1]
                F[3 + r, 0] = h * a0
                F[3 + r, 1] = h * a1
            while j < n_out and t_eval[j] <= t_new:
                x = (t_eval[j] - t) / h
                y0 = 0.0
                y1 = 0.0
                for m in range(7):
                    y0 += F[6 - m, 0]
                    y1 += F[6 - m, 1]
                    w = x if m % 2 == 0 else 1.0 - x
                    y0 *= w
                    y1 *= w
                out[0, j] = th + y0
                out[1, j] = v + y1
                j += 1
        t = t_new
        th = th_new
        v = v_new
        f0 = K[_DOP_N_STAGES, 0]
        f1 = K[_DOP_N_STAGES, 1]
        h *= factor
        steps += 1
    return out


# First-call (JIT compile) seconds of this module's numba peers, filled by
# _compile_numba_peers: one compile per process, whoever calls first.
_COMPILE_SECONDS = {}


def _compile_numba_peers():
    """Compile the numba peers once per process and record how long it took.

    Returns
    -------
    dict
        ``{"numba RK4": seconds, "numba DOP853": seconds}``.
    """
    if not _COMPILE_SECONDS:
        t0 = time.perf_counter()
        rk4_run(0.1, 0.0, 1.0, 0.1, 0.0, 0.1, 3, 2)
        _COMPILE_SECONDS["numba RK4"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        dop853_run(0.1, 0.0, 1.0, 0.1, 0.0, np.linspace(0.0, 1.0, 3), 1e-6, 1e-6, 100)
        _COMPILE_SECONDS["numba DOP853"] = time.perf_counter() - t0
    return dict(_COMPILE_SECONDS)


# ---------------------------------------------------------------------------
# Solver registry
# ---------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Solver:
    """An entry of the benchmark: a solver, its accuracy knob and its sweep.

    Parameters
    ----------
    name : str
        Row label, e.g. ``"scipy DOP853"``.
    family : {"peer", "mbm", "mbm-compiled"}
        MBM through ``solve_ivp``, compiled MBM, or anything else.  The tables'
        ratios are to the best ``"mbm"`` entry (and, in a second table, the best
        ``"mbm-compiled"`` entry).
    compiled : bool
        Runs without per-step Python (numba, numbalsoda, compiled MBM).
    knob : str
        Name of the accuracy knob (``"rtol"``, ``"h"``, ``"tau"``).
    run : callable
        ``run(scene, knob_value) -> theta``, θ at ``scene.t_eval`` (shape (201,)).
        May raise or return non-finite values: the point is recorded as failed.
    sweep : tuple of float
        Knob values, from cheap/inaccurate to expensive/accurate.
    quick_sweep : tuple of float
        The ``--quick`` sweep.
    note : str
        Footnote for the report (what RHS/Jacobian the solver gets).
    """

    name: str
    family: str
    compiled: bool
    knob: str
    run: object
    sweep: tuple
    quick_sweep: tuple
    note: str = ""


def _python_rhs(scene):
    """Plain-Python RHS (math.sin, list return) and analytic Jacobian for scipy.

    A list is the cheapest honest return (solve_ivp converts it with
    ``np.asarray``); measured ~1.1 µs per call against ~1.2 µs for ``np.array``.
    """
    beta, gamma, w2 = scene.beta, scene.gamma, scene.omega ** 2
    sin, cos = math.sin, math.cos

    def fun(t, y):
        return [y[1], gamma - beta * y[1] - w2 * sin(y[0])]

    def jac(t, y):
        return [[0.0, 1.0], [-w2 * cos(y[0]), -beta]]

    return fun, jac


def _scipy_runner(method, use_jac):
    from scipy.integrate import solve_ivp

    def run(scene, rtol):
        fun, jac = _python_rhs(scene)
        kw = {"jac": jac} if use_jac else {}
        sol = solve_ivp(fun, scene.t_span, scene.y0, method=method, t_eval=scene.t_eval,
                        rtol=rtol, atol=rtol, **kw)
        if not sol.success:
            raise RuntimeError(sol.message)
        return sol.y[0]

    return run


def _cvode_runner(method):
    def run(scene, rtol):
        from sksundae.cvode import CVODE

        beta, gamma, w2 = scene.beta, scene.gamma, scene.omega ** 2
        sin, cos = math.sin, math.cos

        def rhs(t, y, yp):
            yp[0] = y[1]
            yp[1] = gamma - beta * y[1] - w2 * sin(y[0])

        def jac(t, y, yp, jj):
            jj[0, 0] = 0.0
            jj[0, 1] = 1.0
            jj[1, 0] = -w2 * cos(y[0])
            jj[1, 1] = -beta

        solver = CVODE(rhs, method=method, rtol=rtol, atol=rtol, jacfn=jac,
                       max_num_steps=MAX_STEPS)
        # t_eval starts at t0, so SUNDIALS returns exactly the rows of t_eval.
        res = solver.solve(scene.t_eval, scene.y0)
        if not res.success:
            raise RuntimeError(str(res.message))
        return np.asarray(res.y)[:, 0]

    return run


def _k_per_output(scene, h):
    """Steps (windows) per output interval for a target step ``h``: the largest step ≤ h
    that divides the output spacing, so that fixed-step runs land on the output times."""
    return max(1, math.ceil(scene.dt_out / h - 1e-9))


def _rk4(scene, h):
    _compile_numba_peers()
    k = _k_per_output(scene, h)
    return rk4_run(scene.beta, scene.gamma, scene.omega ** 2, scene.theta0, scene.v0,
                   scene.dt_out, N_OUTPUT, k)[0]


def _dop853(scene, rtol):
    _compile_numba_peers()
    return dop853_run(scene.beta, scene.gamma, scene.omega ** 2, scene.theta0, scene.v0,
                      scene.t_eval, rtol, rtol, MAX_STEPS)[0]


def _numbalsoda_entries():
    """numbalsoda's LSODA and DOP853 (a cfunc RHS), or [] with a note when not importable."""
    try:
        import numbalsoda
    except ImportError:
        return [], (
            "numbalsoda is not installed: its compiled LSODA/DOP853 are skipped "
            "(`pip install numbalsoda`, which builds from source and needs gfortran and cmake)."
        )
    from numba import cfunc

    state = {}

    def funcptr():
        # Compiled on first use, not at import: its time goes to the first call.
        if "ptr" not in state:
            @cfunc(numbalsoda.lsoda_sig)
            def rhs(t, u, du, p):
                du[0] = u[1]
                du[1] = p[1] - p[0] * u[1] - p[2] * math.sin(u[0])

            state["cfunc"] = rhs
            state["ptr"] = rhs.address
        return state["ptr"]

    def make(fn):
        def run(scene, rtol):
            data = np.array([scene.beta, scene.gamma, scene.omega ** 2])
            usol, ok = fn(funcptr(), scene.y0, scene.t_eval, data=data, rtol=rtol, atol=rtol,
                          mxstep=MAX_STEPS)
            if not ok:
                raise RuntimeError("numbalsoda reported failure")
            return usol[:, 0]

        return run

    note = "cfunc RHS"
    return [
        Solver("numbalsoda LSODA", "peer", True, "rtol", make(numbalsoda.lsoda), RTOL_SWEEP,
               QUICK_RTOLS, note),
        Solver("numbalsoda DOP853", "peer", True, "rtol", make(numbalsoda.dop853), RTOL_SWEEP,
               QUICK_RTOLS, note),
    ], ""


# MBM entries: (approximant, knob) pairs, each run through solve_ivp(method=mbm.MBM)
# and through the compiled mbm.solve (when the package has it).  Knob "tau": fixed
# windows swept over TAU_SWEEP; knob "rtol": MBM's own window control (atol = rtol)
# swept over RTOL_SWEEP.  Only approximants that converge to the true solution
# belong here with "tau" (salas-torque & co. stop at their model error, ~3e-3 on P2,
# and never reach a target); "auto" lets MBM choose per scene.  To add a variant,
# append a pair; names not registered in this checkout are skipped with a note.
MBM_VARIANTS = [
    ("auto", "rtol"),
    ("taylor", "rtol"),
    ("taylor", "tau"),
    ("split4", "tau"),
    ("split8", "tau"),
]


def _mbm_options(knob, value):
    return {"tau": value} if knob == "tau" else {"rtol": value, "atol": value}


def _mbm_solve_ivp_runner(name, knob, windows_per_step=1):
    def run(scene, value):
        from scipy.integrate import solve_ivp

        from .solver import MBM

        model = scene.model
        sol = solve_ivp(model, scene.t_span, scene.y0, method=MBM, approximant=name, model=model,
                        t_eval=scene.t_eval, windows_per_step=windows_per_step,
                        **_mbm_options(knob, value))
        if not sol.success:
            raise RuntimeError(sol.message)
        return sol.y[0]

    return run


def _mbm_solve_runner(name, knob):
    def run(scene, value):
        import mbm

        res = mbm.solve(scene.model, scene.t_span, scene.y0, t_eval=scene.t_eval,
                        approximant=name, **_mbm_options(knob, value))
        if not res.success:
            raise RuntimeError(res.message)
        return res.y[0]

    return run


def solver_registry():
    """All solvers of the benchmark, and notes on the ones that were skipped.

    Returns
    -------
    solvers : list of Solver
    notes : list of str
        Why entries are missing (numbalsoda not installed, an MBM variant not
        registered, the compiled path not there).
    """
    import mbm

    from . import approximants

    notes = []
    rt, qrt = RTOL_SWEEP, QUICK_RTOLS
    py = "Python RHS (math.sin)"
    solvers = [
        Solver("scipy RK45", "peer", False, "rtol", _scipy_runner("RK45", False), rt, qrt, py),
        Solver("scipy DOP853", "peer", False, "rtol", _scipy_runner("DOP853", False), rt, qrt, py),
        Solver("scipy LSODA", "peer", False, "rtol", _scipy_runner("LSODA", True), rt, qrt,
               py + ", analytic Jacobian"),
        Solver("scipy Radau", "peer", False, "rtol", _scipy_runner("Radau", True), rt, qrt,
               py + ", analytic Jacobian"),
        Solver("CVODE Adams", "peer", False, "rtol", _cvode_runner("Adams"), rt, qrt,
               py + ", analytic Jacobian (Newton iteration), sksundae"),
        Solver("CVODE BDF", "peer", False, "rtol", _cvode_runner("BDF"), rt, qrt,
               py + ", analytic Jacobian, sksundae"),
        Solver("numba RK4", "peer", True, "h", _rk4, H_SWEEP, QUICK_HS,
               "fixed step h dividing the output spacing, written here"),
        Solver("numba DOP853", "peer", True, "rtol", _dop853, rt, qrt,
               "Dormand-Prince 8(5,3) with dense output, written here"),
    ]
    extra, note = _numbalsoda_entries()
    solvers += extra
    if note:
        notes.append(note)
    names = set(approximants.approximant_names()) | {"auto"}
    sweeps = {"tau": (TAU_SWEEP, QUICK_TAUS), "rtol": (RTOL_SWEEP, QUICK_RTOLS)}
    how = {"tau": "fixed window τ", "rtol": "MBM's window control"}
    variants = []
    for n, knob in MBM_VARIANTS:
        if n in names:
            variants.append((n, knob))
        else:
            notes.append(f"MBM variant {n!r} is not a registered approximant here: skipped.")
    paths = [("MBM", "mbm", False, _mbm_solve_ivp_runner, "solve_ivp(method=mbm.MBM")]
    if hasattr(mbm, "solve"):
        paths.append(("mbm.solve", "mbm-compiled", True, _mbm_solve_runner, "mbm.solve("))
    else:
        notes.append("mbm.solve (the compiled path) is not in this checkout: no compiled MBM rows.")
    # solve_ivp with all windows of a step in one compiled call (windows_per_step=None):
    # same windows and answers, Python overhead independent of the number of windows.
    for n, knob in variants:
        if knob == "rtol" and n == "auto":
            solvers.append(Solver(
                f"MBM {n} (rtol, windows_per_step=None)", "mbm", False, knob,
                _mbm_solve_ivp_runner(n, knob, None), *sweeps[knob],
                f"solve_ivp(method=mbm.MBM, approximant={n!r}, windows_per_step=None), {how[knob]}"))
    for prefix, family, compiled, runner, call in paths:
        for n, knob in variants:
            solvers.append(Solver(
                f"{prefix} {n} ({'τ' if knob == 'tau' else 'rtol'})", family, compiled, knob,
                runner(n, knob), *sweeps[knob],
                f"{call}{'' if call.endswith('(') else ', '}approximant={n!r}), {how[knob]}"))
    return solvers, notes

# ---------------------------------------------------------------------------
# References
# ---------------------------------------------------------------------------


def default_cache_dir():
    """Where references are cached: ``$MBM_BENCH_CACHE``, else ``$XDG_CACHE_HOME/mbm-bench``
    (``~/.cache/mbm-bench``)."""
    env = os.environ.get("MBM_BENCH_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "mbm-bench"


def _reference_key(scene):
    payload = repr((REFERENCE_VERSION, dataclasses.astuple(scene)[1:7], N_OUTPUT, REF_TOL,
                    REF_CHECK_TOL, REF_BITS, REF_DEGREE, REF_MAX_STEP))
    return hashlib.sha1(payload.encode()).hexdigest()[:16]


def _fp_step(X, V, cst, degree):
    """One degree-``degree`` Taylor step of θ'' = γ − βθ' − ω² sin θ in fixed point.

    X, V are θ, θ' scaled by 2^REF_BITS; ``cst`` = (βh, γh², ω²h², h) scaled the
    same way.  Scaled coefficients A_k = a_k h^k (all of size (h/R)^k, so nothing
    over- or underflows) follow from s = sin θ, c = cos θ, s' = cθ', c' = −sθ':

        k S_k = Σ_{j=1}^{k} j A_j C_{k−j},   k C_k = −Σ_{j=1}^{k} j A_j S_{k−j},
        (k+1)(k+2) A_{k+2} = γh² δ_{k0} − βh (k+1) A_{k+1} − ω²h² S_k,

    and θ(h) = Σ A_k, θ'(h) = Σ k A_k / h.  Also the step of the tests' reference
    generator ``tests/data/convergent_fixed_point.py``.
    """
    from mpmath.libmp import from_man_exp, mpf_cos_sin, to_fixed

    P = REF_BITS
    bh, gh2, wh2, H = cst
    A = [0] * (degree + 1)
    JA = [0] * (degree + 1)  # j A_j
    A[0] = X
    A[1] = JA[1] = (V * H) >> P
    c0, s0 = mpf_cos_sin(from_man_exp(X, -P), P + 16)
    S = [to_fixed(s0, P)]
    C = [to_fixed(c0, P)]
    A[2] = (gh2 - ((bh * A[1] + wh2 * S[0]) >> P)) // 2
    JA[2] = 2 * A[2]
    for k in range(1, degree - 1):
        ss = 0
        cc = 0
        for j in range(1, k + 1):
            ss += JA[j] * C[k - j]
            cc += JA[j] * S[k - j]
        S.append((ss >> P) // k)
        C.append(-((cc >> P) // k))
        A[k + 2] = (-((bh * (k + 1) * A[k + 1] + wh2 * S[k]) >> P)) // ((k + 1) * (k + 2))
        JA[k + 2] = (k + 2) * A[k + 2]
    return sum(A), (sum(JA) << P) // H


def fixed_point_reference(scene):
    """θ at the scene's output times to ~1e-20: a Taylor integrator in 128-bit fixed point.

    Degree :data:`REF_DEGREE`, steps of at most :data:`REF_MAX_STEP` dividing the
    output spacing exactly (rational arithmetic), the scene's float parameters and
    initial state taken as exact binary numbers.  Needs mpmath (its fixed-point
    sine and cosine).  Costs ~0.5 ms per step: ~1 s for P1-P3, ~10 s for P5,
    ~90 s for P4 (cached by :func:`scene_reference`).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    ndarray, shape (N_OUTPUT,)
    """
    from fractions import Fraction

    one = 1 << REF_BITS

    def fix(x):
        return round(Fraction(x) * one)

    dt_out = Fraction(scene.t_end) / (N_OUTPUT - 1)
    n_sub = math.ceil(dt_out / Fraction(REF_MAX_STEP))
    h = dt_out / n_sub
    b, g, w = Fraction(scene.beta), Fraction(scene.gamma), Fraction(scene.omega)
    cst = (fix(b * h), fix(g * h * h), fix(w * w * h * h), fix(h))
    X, V = fix(scene.theta0), fix(scene.v0)
    out = np.empty(N_OUTPUT)
    out[0] = float(Fraction(X, one))
    for i in range(1, N_OUTPUT):
        for _ in range(n_sub):
            X, V = _fp_step(X, V, cst, REF_DEGREE)
        out[i] = float(Fraction(X, one))
    return out


def scene_reference(scene, cache_dir=None):
    """θ_ref at the scene's output times, its source, and an independent check.

    * β = γ = 0 (P6): the exact elliptic flow :func:`mbm.pendulum_flow`;
    * otherwise, with mpmath: :func:`fixed_point_reference` (~1e-20);
    * without mpmath: CVODE at :data:`REF_TOL`, which is not enough everywhere
      (see ``uncertainty``).

    The check is CVODE (Adams, rtol = atol = :data:`REF_TOL`, via
    :func:`mbm.reference`), or for a CVODE reference the numba DOP853 at
    :data:`REF_CHECK_TOL`.

    Parameters
    ----------
    scene : Scene
    cache_dir : path-like, None or False
        Cache directory (default :func:`default_cache_dir`); ``False`` disables
        the cache.

    Returns
    -------
    dict
        ``theta`` (ndarray (201,)), ``method``, ``check_method`` (str), ``check``
        (max |θ_ref − θ_check|, i.e. mostly the check's own error for an exact or
        fixed-point reference), ``uncertainty`` (the reference's own error scale:
        0 for exact and fixed-point references, ``check`` for CVODE).

    Raises
    ------
    RuntimeError
        If CVODE fails, or an exact/fixed-point reference and its check differ by
        more than :data:`REF_SANITY`.
    """
    if cache_dir is None:
        cache_dir = default_cache_dir()
    path = None
    if cache_dir is not False:
        path = Path(cache_dir) / f"ref_{scene.name}_{_reference_key(scene)}.npz"
        if path.exists():
            with np.load(path) as z:
                return {
                    "theta": z["theta"],
                    "method": str(z["method"]),
                    "check_method": str(z["check_method"]),
                    "check": float(z["check"]),
                    "uncertainty": float(z["uncertainty"]),
                }
    from .approximants.belendez2007 import pendulum_flow
    from .reference import reference

    model, t = scene.model, scene.t_eval
    cvode = reference(model, scene.t_span, scene.y0, t_eval=t, rtol=REF_TOL, atol=REF_TOL)
    if not cvode.success:
        raise RuntimeError(f"CVODE failed on {scene.name}: {cvode.message}")
    cvode_name = f"CVODE Adams rtol=atol={REF_TOL:g}"
    try:
        import mpmath  # noqa: F401
        have_mpmath = True
    except ImportError:
        have_mpmath = False
    if scene.beta == 0.0 and scene.gamma == 0.0:
        theta = np.asarray(pendulum_flow(model, scene.y0, t))[0]
        method, check, check_method, unc = "exact (mbm.pendulum_flow)", cvode.y[0], cvode_name, 0.0
    elif have_mpmath:
        theta = fixed_point_reference(scene)
        method = f"Taylor degree {REF_DEGREE}, {REF_BITS}-bit fixed point (mpmath)"
        check, check_method, unc = cvode.y[0], cvode_name, 0.0
    else:
        theta = cvode.y[0]
        method = cvode_name + " (mpmath missing)"
        _compile_numba_peers()
        check = dop853_run(scene.beta, scene.gamma, scene.omega ** 2, scene.theta0, scene.v0, t,
                           REF_CHECK_TOL, REF_CHECK_TOL, MAX_STEPS)[0]
        check_method = f"numba DOP853 rtol=atol={REF_CHECK_TOL:g}"
        unc = None
    diff = float(np.max(np.abs(np.asarray(check) - theta)))
    if unc is None:
        unc = diff
    elif not diff <= REF_SANITY:
        raise RuntimeError(f"reference of {scene.name} ({method}) and its check ({check_method}) "
                           f"differ by {diff:.2e}")
    out = {"theta": np.asarray(theta, dtype=float), "method": method,
           "check_method": check_method, "check": diff, "uncertainty": unc}
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.stem + ".tmp.npz")
        np.savez(tmp, **out)
        os.replace(tmp, path)
    return out


def _reference_uncertainty(ref):
    """The error scale below which a scene's errors are not resolved (0: exact or ~1e-20)."""
    return ref["uncertainty"]


# ---------------------------------------------------------------------------
# Timing
# ---------------------------------------------------------------------------


def _error(theta, ref_theta):
    theta = np.asarray(theta, dtype=float).reshape(-1)
    if theta.shape != ref_theta.shape or not np.all(np.isfinite(theta)):
        return math.inf
    return float(np.max(np.abs(theta - ref_theta)))


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


@contextlib.contextmanager
def gc_paused():
    """Collect, then keep the garbage collector off for the block (as ``timeit`` does)."""
    gc_was = gc.isenabled()
    gc.collect()
    gc.disable()
    try:
        yield
    finally:
        if gc_was:
            gc.enable()


def timed_runs(fn, repeats):
    """Seconds of ``repeats`` calls of ``fn`` with the garbage collector off (as ``timeit``)."""
    with gc_paused():
        return [_timed(fn)[0] for _ in range(repeats)]


def run_sweep(solver, scene, ref_theta, repeats=DEFAULT_REPEATS, quick=False,
              max_seconds=MAX_POINT_SECONDS, stop_error=STOP_ERROR):
    """Work-precision points of one solver on one scene.

    For each knob value (cheap to expensive): one warm-up run (gives the error),
    then ``repeats`` timed runs with the garbage collector off (as ``timeit``),
    whose median is the point's time.  The sweep stops after a point whose
    warm-up run took more than ``max_seconds`` (recorded, not timed) or whose
    error is at most ``stop_error``.

    Parameters
    ----------
    solver : Solver
    scene : Scene
    ref_theta : ndarray
        Reference θ at ``scene.t_eval``.
    repeats : int
        Timed runs per point (median).
    quick : bool
        Use the solver's ``quick_sweep``.
    max_seconds, stop_error : float
        Stopping rules, see above.

    Returns
    -------
    list of dict
        One per point: ``knob``, ``error`` (inf when the run failed), ``time``
        (median seconds, None when not timed), ``times`` (all timed runs),
        ``status`` (``"ok"``, ``"failed"``, ``"over budget"``), ``message``.
    """
    points = []
    seen = set()
    for knob in (solver.quick_sweep if quick else solver.sweep):
        if solver.knob == "h":
            # Fixed steps are rounded to divide the output spacing: skip duplicates.
            key = _k_per_output(scene, knob)
            if key in seen:
                continue
            seen.add(key)
        point = {"knob": float(knob), "error": math.inf, "time": None, "times": [],
                 "status": "ok", "message": ""}
        try:
            dt, theta = _timed(lambda: solver.run(scene, knob))
            point["error"] = _error(theta, ref_theta)
        except Exception as exc:  # a failed run is a data point, not a crash
            dt = None
            point["status"] = "failed"
            point["message"] = f"{type(exc).__name__}: {exc}"[:200]
        if point["status"] == "ok" and not math.isfinite(point["error"]):
            point["status"] = "failed"
            point["message"] = "non-finite or missing output"
        if dt is not None and dt > max_seconds:
            point["status"] = "over budget"
            point["message"] = f"warm-up run took {dt:.2f} s > {max_seconds:g} s"
            points.append(point)
            break
        if point["status"] == "ok":
            times = timed_runs(lambda: solver.run(scene, knob), repeats)
            point["times"] = times
            point["time"] = statistics.median(times)
        points.append(point)
        if point["error"] <= stop_error:
            break
    return points


def _first_call_seconds(solver, scene):
    """First call minus a warm call of the solver on a scene (JIT compile or cache load)."""
    knob = solver.quick_sweep[0]
    try:
        cold = _timed(lambda: solver.run(scene, knob))[0]
        warm = min(_timed(lambda: solver.run(scene, knob))[0] for _ in range(3))
    except Exception:
        return None
    return max(0.0, cold - warm)


_COLD_SCRIPT = r"""
import json, math, sys, time
t0 = time.perf_counter()
import numpy as np
from scipy.integrate import solve_ivp
import mbm
out = {"import mbm": time.perf_counter() - t0}
model = mbm.Pendulum(0.1, 0.3)
y0 = [math.radians(30.0), 0.0]
t = np.linspace(0.0, 80.0, 201)
calls = [("MBM (solve_ivp), first call",
          lambda: solve_ivp(model, (0.0, 80.0), y0, method=mbm.MBM, model=model, t_eval=t,
                            rtol=1e-6, atol=1e-6))]
if hasattr(mbm, "solve"):
    calls.append(("mbm.solve, first call",
                  lambda: mbm.solve(model, (0.0, 80.0), y0, t_eval=t, rtol=1e-6, atol=1e-6)))
for name, fn in calls:
    t0 = time.perf_counter()
    fn()
    cold = time.perf_counter() - t0
    t0 = time.perf_counter()
    fn()
    out[name] = cold - (time.perf_counter() - t0)
print(json.dumps(out))
"""


def cold_first_call_seconds():
    """MBM's import and first-call seconds in a fresh process with an empty numba cache.

    MBM's kernels are cached on disk (``cache=True``), so in the benchmark process
    their first call is a cache load; this measures the one-off JIT compile a new
    installation pays, in a subprocess whose ``NUMBA_CACHE_DIR`` is a new empty
    directory (P2, ``approximant="auto"``, rtol = 1e-6; first call minus second).

    Returns
    -------
    dict or None
        ``{"import mbm": s, "MBM (solve_ivp), first call": s, "mbm.solve, first call": s}``,
        or None if the subprocess failed.
    """
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, NUMBA_CACHE_DIR=tmp)
        try:
            proc = subprocess.run([sys.executable, "-c", _COLD_SCRIPT], env=env, capture_output=True,
                                  text=True, timeout=COLD_COMPILE_TIMEOUT)
        except subprocess.TimeoutExpired:
            return None
    if proc.returncode != 0:
        return None
    try:
        return json.loads(proc.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return None


def cheapest_at_target(points, target):
    """The cheapest timed point whose error is at or below ``target``.

    Nothing is interpolated: only measured points count.

    Parameters
    ----------
    points : list of dict
        As returned by :func:`run_sweep` (keys ``error``, ``time``, ``status``).
    target : float

    Returns
    -------
    dict or None
        The point, or None when no timed point reaches the target.
    """
    ok = [p for p in points
          if p.get("time") is not None and p.get("status", "ok") == "ok" and p["error"] <= target]
    if not ok:
        return None
    return min(ok, key=lambda p: p["time"])


def machine_info():
    """CPU model, core counts and library versions, for the report.

    Returns
    -------
    dict
    """
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    info = {
        "cpu": cpu,
        "logical cores": os.cpu_count(),
        "usable cores": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
        "platform": platform.platform(),
        "python": platform.python_version(),
    }
    from importlib import metadata

    for dist in ("numpy", "scipy", "numba", "scikit-sundae", "mbm", "numbalsoda", "matplotlib"):
        try:
            info[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            info[dist] = "not installed"
    return info


class _stdout_to_stderr:
    """Point file descriptor 1 at stderr for the duration (one dup2 each way).

    numbalsoda's Fortran DOP853 prints "the problem seems to become stiff" to the
    process's stdout on the running scene; this keeps such lines out of a report
    printed to stdout, without a per-call cost inside the timed runs.
    """

    def __enter__(self):
        sys.stdout.flush()
        try:
            self._saved = os.dup(1)
            os.dup2(2, 1)
        except OSError:
            self._saved = None
        return self

    def __exit__(self, *exc):
        if self._saved is not None:
            sys.stdout.flush()
            os.dup2(self._saved, 1)
            os.close(self._saved)
        return False


def run_benchmark(scenes=None, repeats=DEFAULT_REPEATS, quick=False, max_seconds=MAX_POINT_SECONDS,
                  solver_filter=None, cache_dir=None, cold_compile=False, log=None,
                  show_progress=True):
    """Run every solver's sweep on every scene.

    Parameters
    ----------
    scenes : list of str or None
        Scene names (default all of :data:`SCENES`).
    repeats : int
        Timed runs per point.
    quick : bool
        Short sweeps (for tests).
    max_seconds : float
        Per-point budget of :func:`run_sweep`.
    solver_filter : list of str or None
        Keep solvers whose name contains one of these (case-insensitive).
    cache_dir : path-like, None or False
        Reference cache, see :func:`scene_reference`.
    cold_compile : bool
        Also measure MBM's compile from an empty numba cache
        (:func:`cold_first_call_seconds`, a subprocess).
    log : file-like or None
        Progress lines go here.
    show_progress : bool or file-like
        Draw a progress bar over the (scene, solver) sweeps on stderr when it is a
        terminal (True), never (False), or always on the given stream.

    Returns
    -------
    dict
        ``scenes``, ``solvers`` (name -> family, compiled, knob, note),
        ``references``, ``points`` (scene -> solver -> list of points),
        ``first_call`` (solver -> seconds), ``cold_compile`` (dict or None),
        ``notes``, ``machine``, ``settings``.
    """
    scenes = list(SCENES) if scenes is None else list(scenes)
    for s in scenes:
        if s not in SCENES:
            raise ValueError(f"unknown scene {s!r}; choose from {sorted(SCENES)}")

    solvers, notes = solver_registry()
    if solver_filter:
        keys = [f.lower() for f in solver_filter]
        solvers = [s for s in solvers if any(k in s.name.lower() for k in keys)]
    if show_progress is True or show_progress is False:
        bar = Progress(len(scenes) * len(solvers), "bench", enabled=None if show_progress else False)
    else:
        bar = Progress(len(scenes) * len(solvers), "bench", stream=show_progress, enabled=True)

    def say(msg):
        # Log lines go above the bar when both share a terminal.
        if log is not None:
            bar.message(msg, stream=log)
    # JIT compile times first, before anything else in this process calls the peers.
    compile_s = _compile_numba_peers()
    first_scene = SCENES[scenes[0]]
    first_call = {}
    for s in solvers:
        if s.name in compile_s:
            first_call[s.name] = compile_s[s.name]
        else:
            first_call[s.name] = _first_call_seconds(s, first_scene)
    cold = None
    if cold_compile:
        say("MBM compile from an empty numba cache (subprocess) ...")
        cold = cold_first_call_seconds()
    references = {}
    points = {}
    for name in scenes:
        scene = SCENES[name]
        t0 = time.perf_counter()
        ref = scene_reference(scene, cache_dir)
        references[name] = {k: v for k, v in ref.items() if k != "theta"}
        say(f"{name}: reference {ref['method']} ({time.perf_counter() - t0:.1f} s), "
            f"check {ref['check_method']}: {ref['check']:.1e}")
        points[name] = {}
        for s in solvers:
            t0 = time.perf_counter()
            with _stdout_to_stderr():
                pts = run_sweep(s, scene, ref["theta"], repeats=repeats, quick=quick,
                                max_seconds=max_seconds)
            points[name][s.name] = pts
            best = min((p["error"] for p in pts), default=math.inf)
            say(f"  {s.name:<24} {len(pts):2d} points, best error {best:.1e}, "
                f"{time.perf_counter() - t0:.1f} s")
            bar.update()
    bar.close()
    return {
        "scenes": scenes,
        "solvers": {s.name: {"family": s.family, "compiled": s.compiled, "knob": s.knob,
                             "note": s.note} for s in solvers},
        "references": references,
        "points": points,
        "first_call": first_call,
        "cold_compile": cold,
        "notes": notes,
        "machine": machine_info(),
        "settings": {"repeats": repeats, "quick": quick, "max_seconds": max_seconds,
                     "targets": list(TARGETS), "n_output": N_OUTPUT, "ref_tol": REF_TOL,
                     "date": datetime.datetime.now().isoformat(timespec="seconds")},
    }


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------


def _fmt_ms(seconds):
    ms = seconds * 1e3
    if ms >= 100:
        return f"{ms:.0f}"
    if ms >= 10:
        return f"{ms:.1f}"
    if ms >= 1:
        return f"{ms:.2f}"
    return f"{ms:.3f}"


def _cell(points, target, ref_time):
    best = cheapest_at_target(points, target)
    if best is None:
        if any(p["status"] == "over budget" for p in points):
            return "> budget"
        return "—"
    text = _fmt_ms(best["time"])
    if ref_time is not None:
        r = best["time"] / ref_time
        text += f" ({r:.2g}×)" if r < 10 else f" ({r:.0f}×)"
    return text


def _best_time(points_by_solver, names, target):
    times = [cheapest_at_target(points_by_solver[n], target) for n in names]
    times = [p["time"] for p in times if p is not None]
    return min(times) if times else None


def _target_table(result, target, names, ratio_family):
    scenes = result["scenes"]
    fam = [n for n, s in result["solvers"].items() if s["family"] == ratio_family]
    header = "| solver | " + " | ".join(scenes) + " |"
    lines = [header, "|---|" + "---:|" * len(scenes)]
    ref_times = {sc: _best_time(result["points"][sc], fam, target) for sc in scenes}
    for n in names:
        cells = [_cell(result["points"][sc][n], target, ref_times[sc]) for sc in scenes]
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    flags = []
    for sc in scenes:
        unc = _reference_uncertainty(result["references"][sc])
        if target < REF_MARGIN * unc:
            flags.append(f"{sc} (reference discrepancy {unc:.1e})")
    return lines, flags


def format_report(result, command=None, note=None):
    """The Markdown report: settings, machine, references, one table per target.

    Parameters
    ----------
    result : dict
        From :func:`run_benchmark`.
    command : str or None
        The command line that produced it (shown so that it can be rerun).
    note : str or None
        A line put under the title (e.g. "development run on a loaded machine").

    Returns
    -------
    str
    """
    st, mi = result["settings"], result["machine"]
    out = ["# Work-precision benchmark", ""]
    if note:
        out += [f"> {note}", ""]
    out.append("Generated by `mbm/bench.py`; regenerate with")
    out.append("")
    out.append("```bash")
    out.append(command or ".venv/bin/python -m mbm.bench --out docs/benchmark.md")
    out.append("```")
    out.append("")
    out.append(
        f"Error = max |θ − θ_ref| over {st['n_output']} equally spaced times.  Time = median of "
        f"{st['repeats']} runs (after one warm-up run) of the whole solver call on inputs built once "
        "per scene (model, y0, the 201 output times): solver set-up, integration, output at the 201 "
        "times.  Each cell: the cheapest *measured* point whose "
        "error is at or below the target (nothing interpolated), in ms, and in parentheses its time "
        "divided by the best MBM entry's at that target (> 1: slower than MBM).  "
        "`—`: the sweep never reached the target; `> budget`: the sweep stopped at a point whose "
        f"single run took more than {st['max_seconds']:g} s before reaching it."
        + ("  **Quick run** (3 knob values per solver): not a benchmark." if st["quick"] else "")
    )
    out.append("")
    out.append("## Machine")
    out.append("")
    out.append(f"- CPU: {mi['cpu']}, {mi['logical cores']} logical cores "
               f"({mi['usable cores']} usable by this process)")
    out.append(f"- {mi['platform']}, Python {mi['python']}")
    out.append("- " + ", ".join(f"{k} {mi[k]}" for k in ("numpy", "scipy", "numba", "scikit-sundae",
                                                        "mbm", "numbalsoda")))
    out.append(f"- run {st['date']}")
    out.append("")
    out.append("## Scenes and references")
    out.append("")
    out.append("Max difference: max |θ_ref − θ_check| over the 201 times; with an exact or "
               "fixed-point reference it is the check's own error.")
    out.append("")
    out.append("| scene | problem | reference | independent check | max difference |")
    out.append("|---|---|---|---|---:|")
    for sc in result["scenes"]:
        r = result["references"][sc]
        out.append(f"| {sc} | {SCENES[sc].title} | {r['method']} | {r['check_method']} | "
                   f"{r['check']:.1e} |")
    out.append("")
    names = list(result["solvers"])
    compiled_names = [n for n, s in result["solvers"].items() if s["compiled"]]
    have_compiled_mbm = any(s["family"] == "mbm-compiled" for s in result["solvers"].values())
    for target in st["targets"]:
        out.append(f"## Target error {target:.0e}")
        out.append("")
        out.append("Times in ms; ratio to the best `MBM` (solve_ivp) entry.")
        out.append("")
        lines, flags = _target_table(result, target, names, "mbm")
        out += lines
        out.append("")
        if have_compiled_mbm and compiled_names:
            out.append("Compiled solvers only; ratio to the best compiled MBM entry.")
            out.append("")
            out += _target_table(result, target, compiled_names, "mbm-compiled")[0]
            out.append("")
        if flags:
            out.append(f"Caution: at {target:.0e} the reference is within {REF_MARGIN:g}× of its "
                       "check on " + ", ".join(flags) + ": errors there are not resolved.")
            out.append("")
    out.append("## First-call overhead (JIT compile, numba cache load, imports)")
    out.append("")
    out.append("Seconds; not included in the times above.  Numba peers written here are compiled "
               "afresh in each process (`cache=False`); MBM's kernels are cached on disk by numba, "
               "so their first call is a cache load after the first ever run, and variants sharing "
               "kernels pay once.  Others: first call minus a warm call.")
    out.append("")
    out.append("| solver | first call − warm call (s) |")
    out.append("|---|---:|")
    for n in names:
        v = result["first_call"].get(n)
        out.append(f"| {n} | {'n/a' if v is None else f'{v:.3f}'} |")
    out.append("")
    cold = result.get("cold_compile")
    if cold:
        out.append("From an empty numba cache (a fresh process; what a new installation pays "
                   "once): " + ", ".join(f"{k} {v:.2f} s" for k, v in cold.items()) + ".")
        out.append("")
    out.append("## Solvers")
    out.append("")
    out.append("| solver | knob | notes |")
    out.append("|---|---|---|")
    for n, s in result["solvers"].items():
        knob = {"rtol": "rtol (atol = rtol)", "h": "step h", "tau": "window τ"}[s["knob"]]
        out.append(f"| {n} | {knob} | {s['note']} |")
    out.append("")
    failures = []
    for sc in result["scenes"]:
        for n, pts in result["points"][sc].items():
            msgs = {p["message"] for p in pts if p["status"] == "failed"}
            if msgs:
                failures.append(f"- {sc} {n}: {len([p for p in pts if p['status'] == 'failed'])} "
                                f"failed point(s), e.g. {sorted(msgs)[0]}")
    if result["notes"] or failures:
        out.append("## Notes")
        out.append("")
        out += [f"- {n}" for n in result["notes"]]
        out += failures
        out.append("")
    return "\n".join(out)


def write_plots(result, directory):
    """One PNG per scene: error against median time, log-log, one line per solver.

    Parameters
    ----------
    result : dict
        From :func:`run_benchmark`.
    directory : path-like

    Returns
    -------
    list of Path
        The files written; empty when matplotlib is not importable.
    """
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    files = []
    for sc in result["scenes"]:
        fig, ax = plt.subplots(figsize=(8, 5.5))
        for i, (n, pts) in enumerate(result["points"][sc].items()):
            xs = [p["time"] * 1e3 for p in pts if p["time"] is not None]
            ys = [max(p["error"], 1e-16) for p in pts if p["time"] is not None]
            if not xs:
                continue
            fam = result["solvers"][n]["family"]
            style = "-" if fam == "peer" else ("--" if fam == "mbm" else ":")
            marker = "os^vD<>ph*x+"[i % 12]
            ax.loglog(xs, ys, style, marker=marker, ms=4, lw=1.2 if fam == "peer" else 2, label=n,
                      color=plt.cm.tab20(i % 20))
        for target in result["settings"]["targets"]:
            ax.axhline(target, color="0.6", lw=0.8, ls=":")
        # errors above 10 rad are divergent runs; keep them from squashing the axis
        ax.set_ylim(top=10.0)
        ax.set_xlabel("median time per solve (ms)")
        ax.set_ylabel(r"max $|\theta-\theta_{ref}|$ over 201 times")
        ax.set_title(f"{sc}: {SCENES[sc].title}", fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        path = directory / f"benchmark_{sc}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        files.append(path)
    return files


def _json_default(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, Path):
        return str(x)
    raise TypeError(type(x).__name__)


def main(argv=None):
    """``python -m mbm.bench``: run the benchmark and write the Markdown report.

    Parameters
    ----------
    argv : list of str or None
        Command-line arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status.
    """
    parser = argparse.ArgumentParser(
        prog="python -m mbm.bench",
        description="Work-precision benchmark of MBM against scipy, SUNDIALS and compiled peers.",
    )
    parser.add_argument("--scenes", default=",".join(SCENES),
                        help="comma-separated scene names (default all: %(default)s)")
    parser.add_argument("--repeats", type=int, default=None,
                        help=f"timed runs per point (default {DEFAULT_REPEATS}, --quick {QUICK_REPEATS})")
    parser.add_argument("--quick", action="store_true",
                        help="three knob values per solver, 3 repeats (a smoke run, not a benchmark)")
    parser.add_argument("--out", default=None, help="write the Markdown report here (default: stdout)")
    parser.add_argument("--plot", default=None, metavar="DIR",
                        help="write error-vs-time PNGs per scene here (needs matplotlib)")
    parser.add_argument("--json", default=None, metavar="PATH", help="write all sweep points as JSON")
    parser.add_argument("--solvers", default=None,
                        help="comma-separated substrings: keep solvers whose name contains one")
    parser.add_argument("--max-seconds", type=float, default=MAX_POINT_SECONDS,
                        help="stop a sweep after a point whose single run exceeds this "
                             "(default %(default)s)")
    parser.add_argument("--cache", default=None, metavar="DIR",
                        help=f"reference cache directory (default {default_cache_dir()})")
    parser.add_argument("--no-cache", action="store_true", help="recompute references, store nothing")
    parser.add_argument("--cold-compile", action="store_true",
                        help="also time MBM's JIT compile from an empty numba cache (subprocess)")
    parser.add_argument("--from-json", default=None, metavar="PATH",
                        help="render the report (and plots) from a saved --json file; run nothing")
    parser.add_argument("--note", default=None, help="a line to put under the report's title")
    args = parser.parse_args(argv)
    repeats = args.repeats if args.repeats is not None else (QUICK_REPEATS if args.quick else DEFAULT_REPEATS)
    if repeats < 1:
        parser.error("--repeats must be >= 1")
    if not args.max_seconds > 0:
        parser.error("--max-seconds must be > 0")
    scenes = [s.strip() for s in args.scenes.split(",") if s.strip()]
    unknown = [s for s in scenes if s not in SCENES]
    if unknown or not scenes:
        parser.error(f"unknown scene(s) {unknown}; choose from {','.join(SCENES)}")
    cache = False if args.no_cache else (args.cache or None)
    solver_filter = [s.strip() for s in args.solvers.split(",")] if args.solvers else None
    if args.from_json:
        result = json.loads(Path(args.from_json).read_text())
        command = result.get("command")
    else:
        result = run_benchmark(scenes=scenes, repeats=repeats, quick=args.quick,
                               max_seconds=args.max_seconds, solver_filter=solver_filter,
                               cache_dir=cache, cold_compile=args.cold_compile, log=sys.stderr)
        command = "python -m mbm.bench " + " ".join(
            shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
        result["command"] = command.strip()
    report = format_report(result, command=command, note=args.note)
    if args.plot:
        files = write_plots(result, args.plot)
        if files:
            report += "\n## Plots\n\n" + "\n".join(
                f"![{Path(f).stem}]({os.path.relpath(f, Path(args.out).parent) if args.out else f})"
                for f in files) + "\n"
        else:
            report += "\n(matplotlib is not importable: no plots.)\n"
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(report)
        print(f"wrote {args.out}", file=sys.stderr)
    else:
        print(report)
    if args.json:
        Path(args.json).write_text(json.dumps(result, default=_json_default, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())

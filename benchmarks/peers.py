r"""Peer solvers of the benchmark: scipy, CVODE, numba RK4 and DOP853 written here,
numbalsoda and heyoka.

Every peer is reached through a *runner* ``run(scene, knob) -> theta``: θ at the
scene's output times (shape ``(N_OUTPUT,)``) for one value of its accuracy knob
(``rtol`` = ``atol`` for the adaptive ones, the step ``h`` for RK4).  A runner may
raise or return non-finite values; the harness records the point as failed.

The numba peers written here are what a user would write: a fixed-step RK4 that
lands on the output times, and an adaptive Dormand-Prince 8(5,3) (DOP853) with
its 7th-order dense output, with the coefficients of Hairer, Nørsett & Wanner
(the Fortran DOP853; tables as in scipy's ``dop853_coefficients.py``, which has
no public import path, so they are copied below).

heyoka (:class:`HeyokaPeer`) is the LLVM-compiled adaptive Taylor integrator
(``pip install heyoka``).  Its integrator is built once per tolerance, with β, γ, ω²
as runtime parameters, and reused for every scene by setting ``ta.time``,
``ta.state[:]`` and ``ta.pars[:]``; outputs come from ``ta.propagate_grid``.  The
build (symbolic decomposition and LLVM JIT) is timed apart, as numba's compile is.
numbalsoda and heyoka are optional: without them their entries are missing and the
report says so.
"""

import math
import time

import numpy as np
from numba import njit

__all__ = [
    "MAX_STEPS",
    "rk4_run",
    "dop853_run",
    "compile_numba_peers",
    "python_rhs",
    "scipy_runner",
    "cvode_runner",
    "steps_per_output",
    "rk4_runner",
    "dop853_runner",
    "numbalsoda_runners",
    "heyoka_module",
    "HeyokaPeer",
    "HeyokaBatch",
]

# Step budget of the numba peers and numbalsoda (per run / per output interval):
# large enough for every point of the sweeps, small enough that a stuck
# integration returns instead of spinning.
MAX_STEPS = 50_000_000

# DOP853 step-size control, as scipy and the Fortran DOP853: safety factor, the
# smallest and largest step ratios, and the error exponent -1/(7 + 1) of the
# 7th-order error estimator.
DOP_SAFETY = 0.9
DOP_MIN_FACTOR = 0.2
DOP_MAX_FACTOR = 10.0
DOP_ERROR_EXPONENT = -1.0 / 8.0


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
# compile_numba_peers: one compile per process, whoever calls first.
_COMPILE_SECONDS = {}


def compile_numba_peers():
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


def steps_per_output(scene, h):
    """Steps (windows) per output interval for a target step ``h``: the smallest count
    whose step ``dt_out / k`` is at most ``h``, so that fixed-step runs land on the
    output times."""
    return max(1, math.ceil(scene.dt_out / h - 1e-9))


def rk4_runner(scene, h):
    """The numba RK4 on ``scene`` with a step ≤ ``h`` dividing the output spacing."""
    compile_numba_peers()
    k = steps_per_output(scene, h)
    return rk4_run(scene.beta, scene.gamma, scene.omega ** 2, scene.theta0, scene.v0,
                   scene.dt_out, scene.t_eval.size, k)[0]


def dop853_runner(scene, rtol):
    """The numba DOP853 on ``scene`` at rtol = atol = ``rtol``."""
    compile_numba_peers()
    return dop853_run(scene.beta, scene.gamma, scene.omega ** 2, scene.theta0, scene.v0,
                      scene.t_eval, rtol, rtol, MAX_STEPS)[0]


# ---------------------------------------------------------------------------
# Python-RHS peers: scipy's solve_ivp and SUNDIALS CVODE (scikit-sundae)
# ---------------------------------------------------------------------------


def python_rhs(scene):
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


def scipy_runner(method, use_jac):
    """Runner of ``solve_ivp(method=method)`` on the Python RHS (and Jacobian if ``use_jac``)."""
    from scipy.integrate import solve_ivp

    def run(scene, rtol):
        fun, jac = python_rhs(scene)
        kw = {"jac": jac} if use_jac else {}
        sol = solve_ivp(fun, scene.t_span, scene.y0, method=method, t_eval=scene.t_eval,
                        rtol=rtol, atol=rtol, **kw)
        if not sol.success:
            raise RuntimeError(sol.message)
        return sol.y[0]

    return run


def cvode_runner(method):
    """Runner of scikit-sundae's CVODE (``"Adams"`` or ``"BDF"``) with an analytic Jacobian."""

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




# ---------------------------------------------------------------------------
# numbalsoda (optional): compiled LSODA and DOP853 with a cfunc RHS
# ---------------------------------------------------------------------------


def numbalsoda_runners():
    """numbalsoda's LSODA and DOP853 runners, or ``{}`` and why when it is not importable.

    Returns
    -------
    runners : dict
        ``{"numbalsoda LSODA": run, "numbalsoda DOP853": run}`` (empty without numbalsoda).
    note : str
        Empty, or the reason the runners are missing.
    """
    try:
        import numbalsoda
    except ImportError:
        return {}, (
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

    return {"numbalsoda LSODA": make(numbalsoda.lsoda),
            "numbalsoda DOP853": make(numbalsoda.dop853)}, ""


# ---------------------------------------------------------------------------
# heyoka (optional): adaptive Taylor, LLVM-compiled, scalar and SIMD batch mode
# ---------------------------------------------------------------------------

# Why heyoka may be missing, for the report.
HEYOKA_MISSING = ("heyoka is not installed: its rows are skipped "
                  "(`pip install heyoka`, or `pip install -e '.[bench]'`).")


def heyoka_module():
    """The ``heyoka`` module, or None when it is not importable."""
    try:
        import heyoka
    except ImportError:
        return None
    return heyoka


def _heyoka_system(hy):
    """θ' = v, v' = γ − βv − ω² sin θ with ``par[0] = β``, ``par[1] = γ``, ``par[2] = ω²``."""
    x, v = hy.make_vars("x", "v")
    return [(x, v), (v, hy.par[1] - hy.par[0] * v - hy.par[2] * hy.sin(x))]


class HeyokaPeer:
    """heyoka's scalar ``taylor_adaptive``, built once per tolerance and reused.

    β, γ and ω² are runtime parameters of the integrator, so one integrator per
    tolerance serves every scene: a run sets ``ta.time``, ``ta.state[:]`` and
    ``ta.pars[:]`` and calls ``ta.propagate_grid(t_eval)``.  What the benchmark
    times is that run (heyoka "prepared"); the build is timed apart by
    :meth:`integrator` and recorded in :attr:`build_seconds`.

    Parameters
    ----------
    fp_type : type, optional
        ``float`` (default) or ``numpy.longdouble`` (80-bit on x86-64: the
        reference of :mod:`benchmarks.references`).

    Raises
    ------
    ImportError
        If heyoka is not installed.
    """

    def __init__(self, fp_type=float):
        hy = heyoka_module()
        if hy is None:
            raise ImportError(HEYOKA_MISSING)
        self._hy = hy
        self.fp_type = fp_type
        self._dtype = np.dtype(np.longdouble if fp_type is np.longdouble else float)
        self._integrators = {}
        #: tol -> seconds its integrator took to build (decomposition and JIT).
        self.build_seconds = {}

    def build(self, tol):
        """A new integrator at ``tol`` (not cached); returns it and its build seconds."""
        hy = self._hy
        kw = {} if self.fp_type is float else {"fp_type": self.fp_type}
        t0 = time.perf_counter()
        ta = hy.taylor_adaptive(_heyoka_system(hy), np.zeros(2, dtype=self._dtype),
                                tol=self._dtype.type(tol), pars=np.zeros(3, dtype=self._dtype), **kw)
        return ta, time.perf_counter() - t0

    def integrator(self, tol):
        """The integrator at ``tol``, built on first request (its time in :attr:`build_seconds`)."""
        ta = self._integrators.get(tol)
        if ta is None:
            ta, seconds = self.build(tol)
            self._integrators[tol] = ta
            self.build_seconds[tol] = seconds
        return ta

    def propagate(self, scene, tol, t_eval=None):
        """θ and θ' at ``t_eval`` (default the scene's), shape (len, 2), in the peer's fp type."""
        ta = self.integrator(tol)
        t_eval = scene.t_eval if t_eval is None else t_eval
        ta.time = self._dtype.type(t_eval[0])
        ta.state[0] = scene.theta0
        ta.state[1] = scene.v0
        ta.pars[0] = scene.beta
        ta.pars[1] = scene.gamma
        ta.pars[2] = self._dtype.type(scene.omega) * self._dtype.type(scene.omega)
        if t_eval.dtype != self._dtype:
            t_eval = np.asarray(t_eval, dtype=self._dtype)
        outcome, *_, out = ta.propagate_grid(t_eval)
        if outcome != self._hy.taylor_outcome.time_limit:
            raise RuntimeError(f"heyoka propagate_grid stopped: {outcome}")
        return out

    def run(self, scene, tol):
        """The runner: θ at the scene's output times, tol = ``tol``."""
        return self.propagate(scene, tol)[:, 0]


class HeyokaBatch:
    """heyoka's SIMD batch mode (``taylor_adaptive_batch``) over many scenes.

    One integrator per tolerance with ``batch_size`` lanes (default
    ``heyoka.recommended_simd_size()``), built once; :meth:`theta` runs scenes in
    groups of ``batch_size`` (the last group padded with copies of its last scene),
    each group from the same start time over the same output times.

    Parameters
    ----------
    batch_size : int, optional

    Raises
    ------
    ImportError
        If heyoka is not installed.
    """

    def __init__(self, batch_size=None):
        hy = heyoka_module()
        if hy is None:
            raise ImportError(HEYOKA_MISSING)
        self._hy = hy
        self.batch_size = int(batch_size or hy.recommended_simd_size())
        self._integrators = {}
        #: tol -> seconds its integrator took to build.
        self.build_seconds = {}

    def integrator(self, tol):
        """The batch integrator at ``tol``, built on first request."""
        ta = self._integrators.get(tol)
        if ta is None:
            hy, b = self._hy, self.batch_size
            t0 = time.perf_counter()
            ta = hy.taylor_adaptive_batch(_heyoka_system(hy), np.zeros((2, b)), tol=tol,
                                          pars=np.zeros((3, b)))
            self.build_seconds[tol] = time.perf_counter() - t0
            self._integrators[tol] = ta
        return ta

    def theta(self, beta, gamma, w2, y0, t_eval, tol):
        """θ at ``t_eval`` for every scene; shape (n_scenes, len(t_eval)).

        Parameters
        ----------
        beta, gamma, w2 : array_like, shape (n,) or scalars
            β, γ, ω² per scene (scalars broadcast).
        y0 : array_like, shape (2,) or (n, 2)
            Initial states at ``t_eval[0]``.
        t_eval : ndarray
            Increasing output times, shared by every scene.
        tol : float
        """
        ta = self.integrator(tol)
        b = self.batch_size
        beta, gamma, w2 = np.broadcast_arrays(np.asarray(beta, float), np.asarray(gamma, float),
                                              np.asarray(w2, float))
        n = max(beta.size, np.asarray(y0).reshape(-1, 2).shape[0])
        beta, gamma, w2 = (np.broadcast_to(a.reshape(-1), (n,)) for a in (beta, gamma, w2))
        y0 = np.broadcast_to(np.asarray(y0, float).reshape(-1, 2), (n, 2))
        grid = np.repeat(np.asarray(t_eval, float)[:, None], b, axis=1)
        out = np.empty((n, len(t_eval)))
        pars = np.empty((3, b))
        state = np.empty((2, b))
        limit = self._hy.taylor_outcome.time_limit
        for start in range(0, n, b):
            idx = np.minimum(np.arange(start, start + b), n - 1)  # pad with the last scene
            pars[0], pars[1], pars[2] = beta[idx], gamma[idx], w2[idx]
            state[:] = y0[idx].T
            ta.set_time(np.full(b, t_eval[0]))
            ta.state[:] = state
            ta.pars[:] = pars
            _, res = ta.propagate_grid(grid)
            if any(r[0] != limit for r in ta.propagate_res):
                raise RuntimeError(f"heyoka batch propagate_grid stopped: {ta.propagate_res}")
            k = min(b, n - start)
            out[start:start + k] = res[:, 0, :k].T
        return out

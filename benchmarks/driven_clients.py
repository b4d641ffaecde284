"""Driven right-hand sides as junction code writes them, with ``method=mbm.MBM`` swapped in.

The client forms of issue 52, each a member of θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ)
that ``solve_ivp(fun, ..., method=mbm.MBM)`` identifies by probing
(:mod:`mbm.frontends.probe`):

* ``bound``: ``i_dc + i_ac*np.cos(Om*t + phi)`` in a bound method of a class;
* ``closure``: ``I1*np.sin(omega*t)`` in a closure over a loop variable, with C and R
  scaling, (I − I_c sin θ − θ'/R + I1 sin ωt)/C;
* ``args``: the parameters through ``args=``;
* ``gross``: the Gross form (−θ' − sin θ + i + i_ac cos Ωt)/β_c.

Each is run over [0, T] for T in :data:`SPANS` with :data:`N_PER_UNIT` outputs per unit of
time (``t_eval``) by ``method=mbm.MBM`` and by scipy's RK45 at the client's tolerance
(scipy's defaults rtol = 1e-3, atol = 1e-6, and 1e-6/1e-9), timed as the median of
:data:`REPEATS` calls of each in a row after an untimed one (the probing included), and compared with DOP853 at rtol = atol = 1e-13
(the largest |Δθ|, |Δθ'| over the outputs).  The scenes are not chaotic (DOP853 at 1e-11
agrees with it at 1e-13 to 8e-11 at T = 2000), so the errors measure the methods.

Run ``python -m benchmarks.driven_clients`` (``--spans 200 2000``).
"""

import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp

#: Spans T of the runs.
SPANS = (200.0, 2000.0)
#: Outputs per unit of time (t_eval), as a client's plot or mean-voltage average takes.
N_PER_UNIT = 10
#: Timings: the median of this many calls of each method in a row.
REPEATS = 7
#: The client tolerances (rtol, atol): scipy's defaults and a typical tighter choice.
CLIENT_TOLS = ((1e-3, 1e-6), (1e-6, 1e-9))
#: The reference: DOP853 at this rtol = atol.
REF_TOL = 1e-13
Y0 = [0.1, 0.0]


class Junction:
    """Client form ``bound``."""

    def __init__(self, beta, i_dc, i_ac, Om, phi):
        self.beta, self.i_dc, self.i_ac, self.Om, self.phi = beta, i_dc, i_ac, Om, phi

    def rhs(self, t, y):
        return [y[1], self.i_dc + self.i_ac * np.cos(self.Om * t + self.phi) - self.beta * y[1] - np.sin(y[0])]


def closure(I, C=2.0, R=1.5, Ic=1.2, I1=0.8, omega=0.8):
    """Client form ``closure`` (one loop iteration's closure)."""
    def f(t, y):
        return [y[1], (I - Ic * np.sin(y[0]) - y[1] / R + I1 * np.sin(omega * t)) / C]
    return f


def with_args(t, y, beta, gamma, amp, freq):
    """Client form ``args``."""
    return np.array([y[1], gamma + amp * np.sin(freq * t) - beta * y[1] - np.sin(y[0])])


def gross(t, y, beta_c=2.0, i=0.9, i_ac=0.5, Om=0.6):
    """The Gross form."""
    return [y[1], (-y[1] - np.sin(y[0]) + i + i_ac * np.cos(Om * t)) / beta_c]


def clients():
    """``(name, fun, solve_ivp keywords)`` of each client form."""
    return [
        ("bound", Junction(0.5, 0.4, 0.7, 0.913, 2.5).rhs, {}),
        ("closure", closure(0.5), {}),
        ("args", with_args, {"args": (0.5, 0.3, 0.6, 0.7)}),
        ("gross", gross, {}),
    ]


def _timed(fun, span, t_eval, rtol, atol, kw, repeats):
    """``(MBM seconds, RK45 seconds, MBM's solution, RK45's)``: for each method the median
    of ``repeats`` calls in a row, after one untimed call."""
    import mbm

    out = []
    for method in (mbm.MBM, "RK45"):
        sol = solve_ivp(fun, span, Y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol, **kw)
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            solve_ivp(fun, span, Y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol, **kw)
            times.append(time.perf_counter() - start)
        out += [float(np.median(times)), sol]
    return out[0], out[2], out[1], out[3]


def rows(spans=SPANS, repeats=REPEATS):
    """One dict per client, span and tolerance: ``client, T, rtol, probes`` (MBM's calls of
    fun), ``mbm_s, rk45_s`` (medians of ``repeats``), ``mbm_err, rk45_err`` (vs DOP853)."""
    import mbm

    out = []
    for name, fun, kw in clients():
        solve_ivp(fun, (0.0, 1.0), Y0, method=mbm.MBM, **kw)  # compile outside the timing
        for T in spans:
            span, t_eval = (0.0, T), np.linspace(0.0, T, int(N_PER_UNIT * T) + 1)
            ref = solve_ivp(fun, span, Y0, method="DOP853", t_eval=t_eval, rtol=REF_TOL, atol=REF_TOL, **kw).y
            for rtol, atol in CLIENT_TOLS:
                t_mbm, t_rk, a, b = _timed(fun, span, t_eval, rtol, atol, kw, repeats)
                out.append({"client": name, "T": T, "rtol": rtol, "probes": a.nfev, "mbm_s": t_mbm,
                            "rk45_s": t_rk, "mbm_err": float(np.max(np.abs(a.y - ref))),
                            "rk45_err": float(np.max(np.abs(b.y - ref)))})
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--spans", type=float, nargs="+", default=list(SPANS))
    args = parser.parse_args(argv)
    print(f"{'client':8} {'T':>6} {'rtol':>6} {'probes':>6} {'MBM ms':>8} {'RK45 ms':>8} {'speed-up':>8} "
          f"{'MBM err':>9} {'RK45 err':>9}")
    for r in rows(args.spans):
        print(f"{r['client']:8} {r['T']:6.0f} {r['rtol']:6.0e} {r['probes']:6d} {1e3 * r['mbm_s']:8.2f} "
              f"{1e3 * r['rk45_s']:8.2f} {r['rk45_s'] / r['mbm_s']:8.1f} {r['mbm_err']:9.1e} {r['rk45_err']:9.1e}")


if __name__ == "__main__":
    main()

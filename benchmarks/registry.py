"""What the benchmark measures: the :class:`Solver` record, MBM's entries, all entries.

Every entry is a runner ``run(scene, knob) -> theta`` (θ at the scene's 201 output
times) plus a sweep of its accuracy knob, ordered from cheap to expensive: ``rtol``
(= ``atol``) for adaptive solvers, ``tol`` for heyoka, the step ``h`` or window ``τ``
for fixed-step ones.  MBM is measured through its public entry points only:
``solve_ivp(method=mbm.MBM)`` and :func:`mbm.solve`.
"""

import dataclasses

import mbm

from . import peers

__all__ = [
    "Solver",
    "RTOL_SWEEP",
    "HEYOKA_TOL_SWEEP",
    "TAU_SWEEP",
    "H_SWEEP",
    "QUICK_RTOLS",
    "QUICK_TAUS",
    "QUICK_HS",
    "MBM_VARIANTS",
    "KNOB_LABELS",
    "solver_registry",
]

# Adaptive solvers' knob: rtol from 1e-2 to 1e-12 in half decades (a factor ~3 in
# error between points, so "cheapest point below the target" wastes at most ~3x
# in error); atol = rtol because the error is measured absolutely on θ = O(1).
RTOL_SWEEP = tuple(10.0 ** (-k / 2) for k in range(4, 25))

# heyoka's knob: its one tolerance (relative where |y| > 1, absolute below), from 1e-2
# down to 1e-15 in half decades: on the running scene (|θ| up to 1.2e4) an absolute
# error of 1e-9 needs a relative tolerance near 1e-14.  The sweep stops once the error
# is below the harness's STOP_ERROR, so the extra points cost little elsewhere.
HEYOKA_TOL_SWEEP = tuple(10.0 ** (-k / 2) for k in range(4, 31))

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

# The report's description of each knob.
KNOB_LABELS = {"rtol": "rtol (atol = rtol)", "tol": "tol (heyoka's one tolerance)",
               "h": "step h", "tau": "window τ"}


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
        Runs without per-step Python (numba, numbalsoda, heyoka, compiled MBM).
    knob : str
        Name of the accuracy knob (a key of :data:`KNOB_LABELS`).
    run : callable
        ``run(scene, knob_value) -> theta``, θ at ``scene.t_eval`` (shape (201,)).
        May raise or return non-finite values: the point is recorded as failed.
    sweep : tuple of float
        Knob values, from cheap/inaccurate to expensive/accurate.
    quick_sweep : tuple of float
        The ``--quick`` sweep.
    note : str
        Footnote for the report (what RHS/Jacobian the solver gets).
    prepare : callable or None
        ``prepare(knob_value)``, called untimed before a point's first run: what a
        user does once and reuses (heyoka builds its integrator here).  Its seconds
        are recorded with the point (``"prepare"``), not in the point's time.
    """

    name: str
    family: str
    compiled: bool
    knob: str
    run: object
    sweep: tuple
    quick_sweep: tuple
    note: str = ""
    prepare: object = None


# MBM entries: (approximant, knob) pairs, each run through solve_ivp(method=mbm.MBM)
# and through the compiled mbm.solve.  Knob "tau": fixed windows swept over
# TAU_SWEEP; knob "rtol": MBM's own window control (atol = rtol) swept over
# RTOL_SWEEP.  Only approximants that converge to the true solution belong here
# with "tau" (salas-torque & co. stop at their model error, ~3e-3 on P2, and never
# reach a target); "auto" lets MBM choose per scene.  To add a variant, append a
# pair; names not registered in this checkout are skipped with a note.
MBM_VARIANTS = [
    ("auto", "rtol"),
    ("taylor", "rtol"),
    ("taylor", "tau"),
    ("split4", "tau"),
    ("split8", "tau"),
]


def _mbm_options(knob, value):
    return {"tau": value} if knob == "tau" else {"rtol": value, "atol": value}


def _mbm_solve_ivp_runner(name, knob, windows_per_step="auto"):
    # windows_per_step="auto" is MBM's default: with t_eval and no events, up to
    # mbm.frontends.ivp.WINDOWS_PER_STEP windows a step.
    from scipy.integrate import solve_ivp

    def run(scene, value):
        model = scene.model
        sol = solve_ivp(model, scene.t_span, scene.y0, method=mbm.MBM, approximant=name,
                        model=model, t_eval=scene.t_eval, windows_per_step=windows_per_step,
                        **_mbm_options(knob, value))
        if not sol.success:
            raise RuntimeError(sol.message)
        return sol.y[0]

    return run


def _mbm_solve_runner(name, knob):
    def run(scene, value):
        res = mbm.solve(scene.model, scene.t_span, scene.y0, t_eval=scene.t_eval,
                        approximant=name, **_mbm_options(knob, value))
        if not res.success:
            raise RuntimeError(res.message)
        return res.y[0]

    return run


def _peer_entries():
    """The peers' entries and the names (with reasons) of the optional ones missing."""
    rt, qrt = RTOL_SWEEP, QUICK_RTOLS
    py = "Python RHS (math.sin)"
    solvers = [
        Solver("scipy RK45", "peer", False, "rtol", peers.scipy_runner("RK45", False), rt, qrt, py),
        Solver("scipy DOP853", "peer", False, "rtol", peers.scipy_runner("DOP853", False), rt, qrt,
               py),
        Solver("scipy LSODA", "peer", False, "rtol", peers.scipy_runner("LSODA", True), rt, qrt,
               py + ", analytic Jacobian"),
        Solver("scipy Radau", "peer", False, "rtol", peers.scipy_runner("Radau", True), rt, qrt,
               py + ", analytic Jacobian"),
        Solver("CVODE Adams", "peer", False, "rtol", peers.cvode_runner("Adams"), rt, qrt,
               py + ", analytic Jacobian (Newton iteration), sksundae"),
        Solver("CVODE BDF", "peer", False, "rtol", peers.cvode_runner("BDF"), rt, qrt,
               py + ", analytic Jacobian, sksundae"),
        Solver("numba RK4", "peer", True, "h", peers.rk4_runner, H_SWEEP, QUICK_HS,
               "fixed step h dividing the output spacing, written here"),
        Solver("numba DOP853", "peer", True, "rtol", peers.dop853_runner, rt, qrt,
               "Dormand-Prince 8(5,3) with dense output, written here"),
    ]
    missing = {}
    runners, note = peers.numbalsoda_runners()
    for name, run in runners.items():
        solvers.append(Solver(name, "peer", True, "rtol", run, rt, qrt, "cfunc RHS"))
    if note:
        missing["numbalsoda LSODA"] = missing["numbalsoda DOP853"] = note
    if peers.heyoka_module() is not None:
        hy = peers.HeyokaPeer()
        solvers.append(Solver(
            "heyoka", "peer", True, "tol", hy.run, HEYOKA_TOL_SWEEP, qrt,
            "taylor_adaptive (adaptive order and step, LLVM JIT), β, γ, ω² as "
            "runtime parameters; one integrator per tol built once and reused (ta.time, "
            "ta.state, ta.pars set per run, outputs by propagate_grid); build time apart",
            prepare=hy.integrator))
    else:
        missing["heyoka"] = peers.HEYOKA_MISSING
    return solvers, missing


def solver_registry():
    """All solvers of the benchmark, and notes on the ones that were skipped.

    Returns
    -------
    solvers : list of Solver
    notes : list of str
        Why entries are missing (numbalsoda or heyoka not installed, an MBM variant
        not registered).
    missing : dict
        Row label -> reason, for the optional peers that are not installed (the
        report shows them as rows saying so).
    """
    solvers, missing = _peer_entries()
    notes = sorted(set(missing.values()))
    names = set(mbm.approximant_names()) | {"auto"}
    sweeps = {"tau": (TAU_SWEEP, QUICK_TAUS), "rtol": (RTOL_SWEEP, QUICK_RTOLS)}
    how = {"tau": "fixed window τ", "rtol": "MBM's window control"}
    variants = []
    for n, knob in MBM_VARIANTS:
        if n in names:
            variants.append((n, knob))
        else:
            notes.append(f"MBM variant {n!r} is not a registered approximant here: skipped.")
    paths = [("MBM", "mbm", False, _mbm_solve_ivp_runner, "solve_ivp(method=mbm.MBM"),
             ("mbm.solve", "mbm-compiled", True, _mbm_solve_runner, "mbm.solve(")]
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
    return solvers, notes, missing

"""mbm.compile.jit.kernel: compiled kernels without CPython wrapper.

A kernel called from compiled code runs as an ``@njit`` function; called from Python
it runs a twin (compiled with the wrapper, not cached) and gives the same bits; the
library's own paths never call a kernel from Python (each such call would compile an
uncached twin in every process)."""

import json
import math
import os
import subprocess
import sys
import textwrap

import numba
import numpy as np
import pytest

import mbm
from mbm.approximants import taylor_series
from mbm.core import controller, loop as core_loop
from mbm.compile import jit


def test_kernels_are_compiled_without_wrappers():
    for k in (taylor_series.series_loop, core_loop._store_window, controller._first_window_taylor):
        assert isinstance(k, jit.KernelDispatcher)
        assert k.targetoptions["no_cpython_wrapper"] and k.targetoptions["no_cfunc_wrapper"]
    # the entries Python calls keep theirs
    for entry in (core_loop.RUNNERS[(core_loop.KIND_TAYLOR, core_loop.RS_DAMPED)],
                  core_loop.SIMD_RUNNERS[core_loop.RS_DAMPED]):
        assert not isinstance(entry, jit.KernelDispatcher)


def test_a_kernel_called_from_python_runs_its_twin_with_the_same_bits():
    @jit.kernel
    def hyp(x, y):
        return math.sqrt(x * x + y * y) + math.sin(x) * y

    @numba.njit
    def through(x, y):
        return hyp(x, y)

    xs = np.linspace(-3.0, 3.0, 7)
    for x in xs:
        assert hyp(x, 0.5) == through(x, 0.5)  # the twin and the kernel, bit for bit
    assert jit.TWINS[f"{__name__}.{hyp.py_func.__qualname__}"] == __file__
    assert hyp._twin is not None and not isinstance(hyp._twin, jit.KernelDispatcher)


def test_the_error_model_reaches_the_twin():
    @jit.kernel(error_model="numpy")
    def ratio(x, y):
        return x / y

    assert ratio(1.0, 0.0) == math.inf  # numpy's error model: no ZeroDivisionError
    assert ratio._twin.targetoptions["error_model"] == "numpy"


# The library's paths, one process: every compiled kind through mbm.solve, solve_ivp
# with dense output and events, the batch, events, the junction toolkit's curve.
_PATHS = textwrap.dedent("""
    import json, math, sys
    import numpy as np
    from scipy.integrate import solve_ivp
    import mbm
    from mbm.compile.jit import TWINS
    damped, running = mbm.Pendulum(0.1, 0.3), mbm.Pendulum(0.1, 1.2)
    te = np.linspace(0.0, 20.0, 11)
    for m in (damped, running, mbm.Pendulum(0.0, 0.0), mbm.Pendulum(0.0, 0.2),
              mbm.Pendulum(0.2, 0.1, drive_amplitude=1.2, drive_frequency=0.7)):
        mbm.solve(m, (0.0, 20.0), [0.5, 0.0], rtol=1e-8, atol=1e-8, t_eval=te)
        mbm.solve(m, (0.0, 20.0), [0.5, 0.0], rtol=1e-8, atol=1e-8)
        s = solve_ivp(m, (0.0, 20.0), [0.5, 0.0], method=mbm.MBM, rtol=1e-8, atol=1e-8, dense_output=True)
        s.sol(te)
    for ap in ("split4", "salas-torque", "belendez"):
        m = mbm.Pendulum(0.0, 0.0) if ap == "belendez" else damped
        mbm.solve(m, (0.0, 5.0), [0.5, 0.0], approximant=ap, tau=0.25, t_eval=te[:3])
        solve_ivp(m, (0.0, 5.0), [0.5, 0.0], method=mbm.MBM, approximant=ap, tau=0.25, dense_output=True).sol(1.0)
    mbm.solve(running, (0.0, 50.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=mbm.angle_event(math.pi))
    solve_ivp(running, (0.0, 20.0), [0.0, 0.0], method=mbm.MBM, events=lambda t, y: math.cos(y[0] / 2))
    mbm.solve_batch(0.1, np.linspace(0.1, 1.5, 8), 1.0, [0.0, 0.0], (0.0, 50.0), te, rtol=1e-8, atol=1e-8)
    mbm.solve_batch(0.1, np.linspace(0.1, 1.5, 8), 1.0, [0.0, 0.0], (0.0, 50.0), [], rtol=1e-8, atol=1e-8,
                    events=mbm.angle_event(math.pi, terminal=True))
    print(json.dumps(TWINS))
""")


def test_the_library_calls_no_kernel_from_python():
    proc = subprocess.run([sys.executable, "-c", _PATHS], capture_output=True, text=True,
                          env=dict(os.environ, MBM_COMPILE_NOTICE="0"), timeout=900)
    assert proc.returncode == 0, proc.stderr
    twins = json.loads(proc.stdout.strip().splitlines()[-1])
    package = os.path.dirname(os.path.abspath(mbm.__file__))
    from_library = {k: v for k, v in twins.items() if os.path.abspath(v).startswith(package)}
    assert not from_library, f"kernels called from the library's Python (use numba.njit): {from_library}"

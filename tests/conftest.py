"""Test configuration: hypothesis profiles, and the shared scenes and references.

Hypothesis runs derandomized under CI (reproducible runs).  Scenes come from the one
catalogue, :mod:`mbm.scenes` (the papers' examples and the benchmark's P1–P6 under
the names the tests use); the fixtures below hand them out with a cached reference.
"""

import os

import numpy as np
import pytest
from hypothesis import settings

import mbm
from mbm import scenes as catalogue

settings.register_profile("ci", derandomize=True, deadline=None)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

# CVODE tolerance (rtol = atol) of the shared references: as tight as it goes
# without stalling (good to ~1e-11 on the short scenes, see mbm.reference's tests).
REFERENCE_TOL = 1e-13

# The benchmark's scenes, in table order.
BENCHMARK_SCENES = ("P1", "P2", "P3", "P4", "P5", "P6")


@pytest.fixture(scope="session")
def scene_catalogue():
    """The :mod:`mbm.scenes` module (``get``, ``CATALOGUE``)."""
    return catalogue


@pytest.fixture(scope="session")
def example1():
    """The second paper's Example 1 (P2): β = 0.1, γ = 0.3, θ₀ = 30°, 0 ≤ t ≤ 80."""
    return catalogue.get("ex1")


@pytest.fixture(scope="session")
def example2():
    """The second paper's Example 2 scene (P3): β = 0.1, γ = 0.6, θ₀ = 90°, 0 ≤ t ≤ 80."""
    return catalogue.get("ex2")


@pytest.fixture(params=BENCHMARK_SCENES)
def benchmark_scene(request):
    """Each of the benchmark's scenes P1–P6 in turn."""
    return catalogue.get(request.param)


@pytest.fixture(scope="session")
def scene_reference():
    """``ref(scene, t_eval=None) -> y`` (shape (2, n)): the exact flow where β = γ = 0,
    else CVODE at rtol = atol = 1e-13; cached per scene and output times."""
    cache = {}

    def ref(scene, t_eval=None):
        t = scene.t_eval() if t_eval is None else np.asarray(t_eval, dtype=float)
        key = (scene, t.tobytes())
        if key not in cache:
            if scene.beta == 0.0 and scene.gamma == 0.0:
                y = np.asarray(mbm.pendulum_flow(scene.model, scene.y0, t))
            else:
                sol = mbm.reference(scene.model, scene.t_span, scene.y0, t_eval=t,
                                    rtol=REFERENCE_TOL, atol=REFERENCE_TOL)
                assert sol.success, sol.message
                y = sol.y
            cache[key] = y
        return cache[key]

    return ref


@pytest.fixture
def user_sigint():
    """Python's own SIGINT handler (KeyboardInterrupt in the main thread), as a user's
    session has it, for a test that sends itself Ctrl-C; restored after.  The tests share
    a worker process (pytest-xdist) with others, whose libraries may have replaced it:
    what was there is the fixture's value, for a failure message."""
    import signal
    import threading

    assert threading.current_thread() is threading.main_thread(), "Ctrl-C reaches the main thread only"
    before = signal.getsignal(signal.SIGINT)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield before
    finally:
        signal.signal(signal.SIGINT, before)

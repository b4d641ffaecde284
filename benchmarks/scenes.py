"""The benchmark's scenes: :mod:`mbm.scenes`' P1–P6 with their inputs built once.

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

ω = 1 throughout.  The solution is compared at :data:`N_OUTPUT` equally spaced times.
"""

import dataclasses
import functools

import mbm
from mbm import scenes as catalogue

__all__ = ["BenchScene", "SCENES", "SCENE_NAMES", "N_OUTPUT"]

# Output times per scene: 201 equally spaced times, ends included.
N_OUTPUT = catalogue.N_OUTPUT

# The benchmark's scenes, in table order.
SCENE_NAMES = ("P1", "P2", "P3", "P4", "P5", "P6")


@dataclasses.dataclass(frozen=True)
class BenchScene:
    """A catalogue scene with the inputs every timed run shares, built once.

    Parameters
    ----------
    scene : mbm.scenes.Scene
        The problem (model, initial state, span), starting at t = 0.

    Notes
    -----
    ``model``, ``y0`` and ``t_eval`` are built once per scene and shared by every
    run: a timed call measures the solver on ready inputs, not ``np.linspace`` (which
    the numba RK4, building its output times inside, never paid).  Runners must not
    modify them (``test_runners_leave_scene_inputs_unchanged``).
    """

    scene: catalogue.Scene

    def __post_init__(self):
        if self.scene.t_span[0] != 0.0:
            raise ValueError(f"benchmark scenes start at t = 0, got t_span {self.scene.t_span}")

    @classmethod
    def from_params(cls, name, beta, gamma, omega, theta0, v0, t_end, title=""):
        """A scene outside the catalogue (the I–V ensemble's members, tests)."""
        return cls(catalogue.Scene(name, mbm.Pendulum(beta, gamma, omega), (theta0, v0),
                                   (0.0, t_end), title, "benchmark"))

    name = property(lambda self: self.scene.name, doc="Scene name (``\"P1\"`` …).")
    beta = property(lambda self: self.scene.beta, doc="Damping β.")
    gamma = property(lambda self: self.scene.gamma, doc="Torque γ.")
    omega = property(lambda self: self.scene.omega, doc="Natural frequency ω.")
    theta0 = property(lambda self: self.scene.theta0, doc="Initial angle θ₀.")
    v0 = property(lambda self: self.scene.v0, doc="Initial angular velocity θ̇₀.")
    t_end = property(lambda self: self.scene.t_end, doc="Horizon.")
    t_span = property(lambda self: self.scene.t_span, doc="``(0.0, t_end)``.")
    title = property(lambda self: self.scene.description, doc="One-line description for the report.")

    @property
    def model(self):
        """The :class:`mbm.Pendulum` of the scene."""
        return self.scene.model

    @functools.cached_property
    def y0(self):
        """Initial state as a float array of shape (2,), the same object every time."""
        return self.scene.y0_array

    @functools.cached_property
    def t_eval(self):
        """The :data:`N_OUTPUT` output times, the same array every time."""
        return self.scene.t_eval(N_OUTPUT)

    @property
    def dt_out(self):
        """Spacing of the output times."""
        return float(self.t_end) / (N_OUTPUT - 1)

    def params(self):
        """``(beta, gamma, omega, theta0, v0, t_end)``."""
        return self.scene.params()


SCENES = {name: BenchScene(catalogue.get(name)) for name in SCENE_NAMES}

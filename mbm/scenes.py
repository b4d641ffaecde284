"""Named scenes: the initial-value problems the papers, the tests and the benchmark share.

One catalogue, so that "Example 1" means the same β, γ, θ₀ and horizon in the tests,
the examples, ``mbm study`` and the benchmark.  A :class:`Scene` is a frozen record
(model, initial state, time span, where it comes from); :func:`get` finds one by its
name or by one of its aliases; :meth:`Scene.until` gives the same physical scene over
another horizon (the tests run the running scene to t = 200, the benchmark to 1000).

====================  =====  =====  =====  =====  ========  ===========================================
name (aliases)        β      γ      θ₀     θ̇₀     t         what
====================  =====  =====  =====  =====  ========  ===========================================
P1 (paper1)           0.4    0      0      0.25   [0, 20]   Salas (2021), Figure 1: damped, no torque
P2 (ex1)              0.1    0.3    30°    0      [0, 80]   Salas, Martínez & Ocampo (2022), Example 1
P3 (ex2)              0.1    0.6    90°    0      [0, 80]   the same paper's Example 2 scene
P4 (longweak)         0.01   0.3    1      0      [0, 1e4]  weak damping, long horizon
P5 (running)          0.1    1.2    0      0      [0, 1e3]  running (γ > ω²): θ grows to ~1.2e4
P6 (separatrix)       0      0      0      1.999  [0, 200]  just inside the separatrix (θ̇₀ = 2)
free135 (free)        0      0      135°   0      [0, 40]   Beléndez et al. (2007): large amplitude
undamped-long         0      0      1      0      [0, 1e6]  undamped libration over a long horizon
====================  =====  =====  =====  =====  ========  ===========================================

ω = 1 throughout.  P1–P6 are the scenes of the work-precision benchmark (``python -m
benchmarks`` in a checkout); their output times are :data:`N_OUTPUT` equally spaced
times, ends included (:meth:`Scene.t_eval`).

Examples
--------
>>> from mbm import scenes
>>> ex1 = scenes.get("ex1")
>>> ex1.name, ex1.model, ex1.t_span
('P2', Pendulum(beta=0.1, gamma=0.3, omega=1.0), (0.0, 80.0))
>>> ex1.t_eval().shape
(201,)
>>> scenes.get("running").until(200.0).t_span
(0.0, 200.0)
"""

import dataclasses
import math

import numpy as np

from .model import Pendulum

__all__ = ["Scene", "CATALOGUE", "N_OUTPUT", "get", "names"]

# Output times of a scene by default: 201 equally spaced times, ends included, as the
# benchmark and most accuracy tests measure max |θ − θ_ref| over them.
N_OUTPUT = 201


@dataclasses.dataclass(frozen=True)
class Scene:
    """One initial-value problem θ'' + βθ' + ω² sin θ = γ, y(t₀) = y0, over ``t_span``.

    Parameters
    ----------
    name : str
        Catalogue name (``"P2"``).
    model : Pendulum
        β, γ, ω.
    y0 : tuple of float
        Initial state ``(θ₀, θ̇₀)`` at ``t_span[0]``; stored as a tuple of two floats.
    t_span : tuple of float
        ``(t0, t_end)``; stored as a tuple of two floats.
    description : str, optional
        One line for tables and reports.
    source : str, optional
        Where the scene comes from (paper and equation or figure, or what it tests).
    aliases : tuple of str, optional
        Other names :func:`get` accepts for it (``"ex1"`` for P2).

    Raises
    ------
    TypeError
        If ``model`` is not a :class:`Pendulum`.
    ValueError
        If ``y0`` is not two finite numbers, or ``t_span`` not two distinct finite numbers.

    Notes
    -----
    Frozen and hashable: a scene is a value.  Arrays are built on request
    (:attr:`y0_array`, :meth:`t_eval`) and are new objects each time, so a solver
    writing into them cannot change the scene.
    """

    name: str
    model: Pendulum
    y0: tuple
    t_span: tuple
    description: str = ""
    source: str = ""
    aliases: tuple = ()

    def __post_init__(self):
        if not isinstance(self.model, Pendulum):
            raise TypeError(f"model must be an mbm.Pendulum, got {type(self.model).__name__}")
        y0 = tuple(float(x) for x in self.y0)
        if len(y0) != 2 or not all(math.isfinite(x) for x in y0):
            raise ValueError(f"y0 must be two finite numbers (theta, theta'), got {self.y0!r}")
        span = tuple(float(x) for x in self.t_span)
        if len(span) != 2 or not all(math.isfinite(x) for x in span) or span[0] == span[1]:
            raise ValueError(f"t_span must be two distinct finite numbers, got {self.t_span!r}")
        object.__setattr__(self, "y0", y0)
        object.__setattr__(self, "t_span", span)
        object.__setattr__(self, "aliases", tuple(str(a) for a in self.aliases))

    @property
    def beta(self):
        """Damping β of the model."""
        return self.model.beta

    @property
    def gamma(self):
        """Torque γ of the model."""
        return self.model.gamma

    @property
    def omega(self):
        """Natural frequency ω of the model."""
        return self.model.omega

    @property
    def theta0(self):
        """Initial angle θ₀."""
        return self.y0[0]

    @property
    def v0(self):
        """Initial angular velocity θ̇₀."""
        return self.y0[1]

    @property
    def t_end(self):
        """End of the time span."""
        return self.t_span[1]

    @property
    def y0_array(self):
        """The initial state as a new float array of shape (2,)."""
        return np.array(self.y0, dtype=float)

    def t_eval(self, n=N_OUTPUT):
        """``n`` equally spaced output times over ``t_span``, ends included.

        Parameters
        ----------
        n : int, optional
            Number of times (default :data:`N_OUTPUT`, at least 2).

        Returns
        -------
        ndarray, shape (n,)
            A new array on each call.
        """
        n = int(n)
        if n < 2:
            raise ValueError(f"n must be >= 2, got {n}")
        return np.linspace(self.t_span[0], self.t_span[1], n)

    def until(self, t_end):
        """The same scene over ``(t0, t_end)``.

        Parameters
        ----------
        t_end : float

        Returns
        -------
        Scene
            Same name, model, state and source; the description is kept.
        """
        return dataclasses.replace(self, t_span=(self.t_span[0], float(t_end)))

    def params(self):
        """``(beta, gamma, omega, theta0, v0, t_end)`` as floats.

        The flat form some tables and ``mbm.cli.study.run_study`` take.
        """
        return (self.beta, self.gamma, self.omega, self.theta0, self.v0, self.t_end)


def _scene(name, beta, gamma, theta0, v0, t_end, description, source, *, aliases=()):
    return Scene(name, Pendulum(beta=beta, gamma=gamma, omega=1.0), (theta0, v0), (0.0, t_end),
                 description, source, tuple(aliases))


#: name -> :class:`Scene`, in the order of the table above.
CATALOGUE = {
    s.name: s
    for s in (
        _scene("P1", 0.4, 0.0, 0.0, 0.25, 20.0,
               "first paper: beta=0.4, gamma=0, theta0=0, v0=0.25",
               "Salas (2021), Figure 1 and (3.10)–(3.11): 2ε = 0.4", aliases=("paper1",)),
        _scene("P2", 0.1, 0.3, math.radians(30.0), 0.0, 80.0,
               "Example 1: beta=0.1, gamma=0.3, theta0=30 deg",
               "Salas, Martínez & Ocampo (2022), Example 1, (4.33)", aliases=("ex1",)),
        _scene("P3", 0.1, 0.6, math.radians(90.0), 0.0, 80.0,
               "Example 2 scene: beta=0.1, gamma=0.6, theta0=90 deg",
               "Salas, Martínez & Ocampo (2022), Example 2, (4.37) (its printed constants "
               "belong to θ₀ ≈ 94.6°)", aliases=("ex2",)),
        _scene("P4", 0.01, 0.3, 1.0, 0.0, 1.0e4,
               "weak damping: beta=0.01, gamma=0.3, theta0=1, t<=1e4",
               "benchmark: weak damping over a long horizon", aliases=("longweak",)),
        _scene("P5", 0.1, 1.2, 0.0, 0.0, 1000.0,
               "running: beta=0.1, gamma=1.2, t<=1000",
               "benchmark: running state, γ > ω² (θ grows to ~1.2e4)", aliases=("running",)),
        _scene("P6", 0.0, 0.0, 0.0, 1.999, 200.0,
               "near separatrix: beta=gamma=0, v0=1.999, t<=200",
               "benchmark: just inside the separatrix (θ̇₀ = 2), m = 0.999", aliases=("separatrix",)),
        _scene("free135", 0.0, 0.0, math.radians(135.0), 0.0, 40.0,
               "free pendulum: beta=gamma=0, theta0=135 deg, t<=40",
               "Beléndez et al. (2007): large amplitude (\"practically harmonic below 135°\")",
               aliases=("free",)),
        _scene("undamped-long", 0.0, 0.0, 1.0, 0.0, 1.0e6,
               "undamped: beta=gamma=0, theta0=1 rad from rest, t<=1e6",
               "benchmark extra: the exact elliptic flow over a long horizon"),
    )
}

_BY_ALIAS = {a: s for s in CATALOGUE.values() for a in s.aliases}
if set(_BY_ALIAS) & set(CATALOGUE):  # an alias shadowing a name would make get() ambiguous
    raise RuntimeError("a scene alias repeats a scene name")


def get(name):
    """The catalogue scene called ``name`` (a name or an alias).

    Parameters
    ----------
    name : str
        E.g. ``"P2"`` or its alias ``"ex1"``.

    Returns
    -------
    Scene

    Raises
    ------
    KeyError
        If no scene has that name or alias; the message lists them.
    """
    if name in CATALOGUE:
        return CATALOGUE[name]
    if name in _BY_ALIAS:
        return _BY_ALIAS[name]
    raise KeyError(f"unknown scene {name!r}; choose from {', '.join(names(aliases=True))}")


def names(aliases=False):
    """Scene names in catalogue order, and with ``aliases=True`` their aliases after them.

    Parameters
    ----------
    aliases : bool, optional

    Returns
    -------
    list of str
    """
    out = list(CATALOGUE)
    if aliases:
        out += list(_BY_ALIAS)
    return out

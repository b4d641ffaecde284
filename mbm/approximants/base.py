"""The approximant interface shared by every paper module, and the registry.

An *approximant* maps an anchor state (θ₀, θ̇₀) of a pendulum model to an analytic
formula θ(t), θ'(t), with t measured from the anchor.  Each paper module defines
its approximants as subclasses of :class:`Approximant` with two numba kernels:

``anchor_kernel(beta, gamma, omega, theta0, v0) -> coef``
    float64 scalars in, a float64 1-D array out.  ``coef[0]`` is a status code:
    0 for success, otherwise a code the class maps to a message in
    :attr:`Approximant.status_messages`.  ``coef[1:]`` are whatever the
    formula needs (model parameters included), so evaluation needs nothing else.
``eval_kernel(coef, t) -> (theta, theta_dot)``
    float64 scalars; must return the anchor exactly at ``t == 0.0``.
``eval_array_kernel(coef, t, out_theta, out_v)``
    the same over a contiguous float64 array, calling ``eval_kernel`` in a loop
    (one per module: numba does not cache a kernel that takes another kernel
    as an argument, so the loop cannot be shared).

The solver (window control) sees only these, the anchor state, and
:attr:`Approximant.anchors` (which anchor states the approximant accepts).
"""

import numpy as np

__all__ = [
    "Approximant",
    "Anchored",
    "register",
    "get_approximant",
    "approximant_names",
    "ApproximantDomainError",
    "drive_refusal",
]

_REGISTRY = {}


class ApproximantDomainError(ValueError):
    """An approximant was asked for a scene or an anchor state outside its domain."""


def register(cls):
    """Class decorator: register an :class:`Approximant` subclass under ``cls.name``."""
    if cls.name in _REGISTRY:
        raise RuntimeError(f"approximant name {cls.name!r} registered twice")
    _REGISTRY[cls.name] = cls
    return cls


def approximant_names():
    """Names of all registered approximants, sorted."""
    return sorted(_REGISTRY)


def drive_refusal(name, amplitude):
    """The message of an approximant that cannot integrate an AC drive."""
    return (
        f"approximant {name!r} cannot integrate the AC drive (drive_amplitude={amplitude!r}): "
        "its formula solves the autonomous equation theta'' + beta*theta' + omega**2*sin(theta) "
        "= gamma; use approximant='taylor' (or 'auto', which picks it for a driven model)"
    )


def get_approximant(name):
    """Return an instance of the approximant registered under ``name``.

    Parameters
    ----------
    name : str or Approximant
        A registered name (see :func:`approximant_names`), or an instance, returned as is.

    Raises
    ------
    ValueError
        If ``name`` is not a registered approximant.
    """
    if isinstance(name, Approximant):
        return name
    if not isinstance(name, str) or name not in _REGISTRY:
        raise ValueError(
            f"approximant must be one of {sorted(_REGISTRY)}, got {name!r}"
        )
    return _REGISTRY[name]()


class Approximant:
    """Base class of all approximants: every attribute a solver reads is declared here.

    Subclasses set the class attributes and the kernels (as staticmethods holding
    numba dispatchers); nothing is read with a default elsewhere.

    Attributes
    ----------
    name : str
        Registry name, e.g. ``"salas-torque"``.
    citation : str
        Paper and equation numbers the formula comes from.
    anchors : str
        Which anchor states it accepts: ``"any"``, ``"zero-crossing"`` (θ = d) or
        ``"turning-point"`` (θ' = 0).
    status_messages : dict
        Maps non-zero status codes of ``anchor_kernel`` to error messages.
    anchor_kernel : numba dispatcher
        ``anchor_kernel(beta, gamma, omega, theta0, v0) -> coef`` (see the module docstring).
    eval_kernel : numba dispatcher
        ``eval_kernel(coef, t) -> (theta, theta_dot)``, exact at ``t == 0``.
    eval_array_kernel : numba dispatcher
        ``eval_array_kernel(coef, t, out_theta, out_v)`` over a float64 array.
    error_kernel : numba dispatcher or None
        ``error_kernel(coef, h) -> (err_theta, err_v)``, the local error estimate of the
        window [0, h]; None where the formula has none (then windows need a fixed τ).
    error_order : int or None
        The estimate scales as h^(error_order + 1): the controller's step factor is
        ``err**(-1/(error_order + 1))`` (scipy's ``error_estimator_order``).  None
        exactly when ``error_kernel`` is None.
    measured_order : float or None
        Global order fitted from τ sweeps by the tests (informational; for the
        papers' approximants it refers to their own model equation).
    exact : bool
        True for an exact flow (no truncation error: one window as long as
        ``max_step`` allows).
    compiled_kind : str or None
        Name of the compiled kernel family that runs it (what lets :func:`mbm.solve`,
        :class:`mbm.Integrator` and :func:`mbm.solve_batch` use it); None: no compiled
        kernel, the approximant runs only under ``solve_ivp(method=mbm.MBM)``, its steps
        (windows) driven from Python.
    kind_arg : int
        The kind's integer argument (the Taylor degree, the splitting method id).
    drive_capable : bool
        Whether it integrates the AC drive A sin(Ωt + φ) of a driven model
        (:meth:`drive_anchor`); the others solve the autonomous equation and refuse a
        driven model (:meth:`check_drive`).
    """

    name = None
    citation = ""
    anchors = "any"
    status_messages = {}
    anchor_kernel = None
    eval_kernel = None
    eval_array_kernel = None
    error_kernel = None
    error_order = None
    measured_order = None
    exact = False
    compiled_kind = None
    kind_arg = 0
    drive_capable = False

    def check_model(self, model):
        """Raise :class:`ApproximantDomainError` if the model is outside the approximant's scope.

        Parameters
        ----------
        model : Pendulum
            The equation's parameters.
        """

    def check_drive(self, model):
        """Raise :class:`ApproximantDomainError` if ``model`` is driven and this approximant
        cannot integrate the drive (not :attr:`drive_capable`).

        Parameters
        ----------
        model : Pendulum
            The equation's parameters.
        """
        if model.driven and not self.drive_capable:
            raise ApproximantDomainError(drive_refusal(self.name, model.drive_amplitude))

    def drive_anchor(self, model, t0, theta0, v0):
        """The coefficient vector anchored at (θ₀, θ̇₀) at time ``t0`` of a driven model
        (only a :attr:`drive_capable` approximant has one).

        Parameters
        ----------
        model : Pendulum
            A driven model.
        t0 : float
            The anchor's time (the drive's phase there).
        theta0, v0 : float
            The anchor state.

        Returns
        -------
        ndarray
            The coefficient vector (``coef[0]`` the status).
        """
        raise ApproximantDomainError(drive_refusal(self.name, model.drive_amplitude))

    def anchor_coefficients(self, model, theta0, v0, t0=0.0):
        """The anchor kernel's coefficient vector (``coef[0]`` the status).

        The driven series at time ``t0`` for a driven model (:meth:`drive_anchor`),
        else ``anchor_kernel`` (which does not depend on the time).

        Parameters
        ----------
        model : Pendulum
            The equation's parameters.
        theta0, v0 : float
            The anchor state.
        t0 : float, optional
            The anchor's time (default 0).

        Returns
        -------
        ndarray
        """
        if model.driven:
            return self.drive_anchor(model, t0, theta0, v0)
        return self.anchor_kernel(model.beta, model.gamma, model.omega, theta0, v0)

    def event_center(self, model):
        """The angle d of the zero-crossing event surface θ = d in (3.32), or None.

        Default: the pendulum's stable equilibrium arcsin(γ/ω²) (None when ``|γ| > ω²``).
        Approximants that oscillate about another centre override this.

        Parameters
        ----------
        model : Pendulum
            The equation's parameters.

        Returns
        -------
        float or None
        """
        return model.equilibrium

    def param_names(self):
        """Names of ``coef[1:]`` entries, in order, for :attr:`Anchored.params`."""
        return ()

    def params_from_coef(self, coef):
        """The dictionary exposed as :attr:`Anchored.params`.

        Parameters
        ----------
        coef : ndarray
            A coefficient vector of this approximant.

        Returns
        -------
        dict
        """
        return {k: float(v) for k, v in zip(self.param_names(), coef[1:])}

    def anchor(self, model, theta0, v0, t0=0.0):
        """Anchor the approximant at the state (θ₀, θ̇₀) of ``model``.

        Parameters
        ----------
        model : Pendulum
            The equation's parameters.
        theta0, v0 : float
            Anchor state θ(0), θ'(0).
        t0 : float, optional
            The anchor's time: where the AC drive of a driven model is in its cycle
            (phase Ωt₀ + φ); an undriven model's formula does not depend on it.

        Returns
        -------
        Anchored
            Callable ``(t) -> (theta, theta_dot)`` with ``t`` measured from the anchor.

        Raises
        ------
        ApproximantDomainError
            If the model or the anchor state is outside the approximant's domain, or
            the model is driven and the approximant cannot integrate the drive.
        """
        from ..model import Pendulum

        if not isinstance(model, Pendulum):
            raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")
        self.check_drive(model)
        self.check_model(model)
        theta0 = float(theta0)
        v0 = float(v0)
        t0 = float(t0)
        if not (np.isfinite(theta0) and np.isfinite(v0)):
            raise ValueError(f"anchor state must be finite, got theta0={theta0!r}, v0={v0!r}")
        if not np.isfinite(t0):
            raise ValueError(f"t0 must be finite, got {t0!r}")
        coef = self.anchor_coefficients(model, theta0, v0, t0)
        self.raise_for_status(coef, theta0, v0)
        return Anchored(self, model, theta0, v0, coef, t0)

    def raise_for_status(self, coef, theta0, v0):
        """Raise the error that ``coef[0]`` encodes, if any.

        Parameters
        ----------
        coef : ndarray
            A coefficient vector of this approximant.
        theta0, v0 : float
            The anchor state (named in the message).

        Raises
        ------
        ApproximantDomainError
            If ``coef[0]`` is not 0.
        """
        code = int(coef[0])
        if code != 0:
            msg = self.status_messages.get(code, f"status {code}")
            raise ApproximantDomainError(
                f"approximant {self.name!r} cannot be anchored at theta0={theta0!r}, "
                f"theta'0={v0!r}: {msg}"
            )

    def __repr__(self):
        return f"<approximant {self.name!r}: {self.citation}>"


class Anchored:
    """An approximant anchored at a state: the analytic formula θ(t), θ'(t).

    Built by :meth:`Approximant.anchor`.

    Parameters
    ----------
    approximant : Approximant
        The approximant anchored.
    model : Pendulum
        The equation's parameters.
    theta0, v0 : float
        The anchor state.
    coef : ndarray
        The kernel's coefficient vector.
    t0 : float, optional
        The anchor's time (default 0).

    Attributes
    ----------
    approximant : Approximant
    model : Pendulum
    theta0, v0 : float
        The anchor state.
    coef : ndarray
        The kernel's coefficient vector.
    params : dict
        Named constants of the formula (paper notation).
    t0 : float
        The anchor's time (where a driven model's drive is in its cycle; t is measured
        from it).
    """

    def __init__(self, approximant, model, theta0, v0, coef, t0=0.0):
        self.approximant = approximant
        self.model = model
        self.theta0 = theta0
        self.v0 = v0
        self.coef = coef
        self.t0 = t0
        self.params = approximant.params_from_coef(coef)

    def __call__(self, t):
        """Evaluate at times ``t`` (scalar or array, measured from the anchor).

        Returns
        -------
        theta, theta_dot : float or ndarray
            Same shape as ``t``.
        """
        t_arr = np.asarray(t, dtype=np.float64)
        if t_arr.ndim == 0:
            a, b = self.approximant.eval_kernel(self.coef, float(t_arr))
            return a, b
        flat = np.ascontiguousarray(t_arr.reshape(-1))
        th = np.empty_like(flat)
        v = np.empty_like(flat)
        self.approximant.eval_array_kernel(self.coef, flat, th, v)
        return th.reshape(t_arr.shape), v.reshape(t_arr.shape)

    def __repr__(self):
        return (
            f"<{self.approximant.name} anchored at theta0={self.theta0!r}, "
            f"theta'0={self.v0!r}>"
        )

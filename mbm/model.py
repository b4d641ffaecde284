"""The pendulum family  θ'' + β θ' + ω² sin θ = γ + A sin(Ωt + φ).

This module knows the equation only: no approximant, no window control, no probing
(the probing of plain callables: :mod:`mbm.frontends.probe`).
"""

import math

import numpy as np

from .validate import check_drive, check_rule

__all__ = ["Pendulum"]


class Pendulum:
    """The damped, torque-driven pendulum  θ'' + β θ' + ω² sin θ = γ + A sin(Ωt + φ).

    The state is ``y = [θ, θ']``.  The instance is callable as ``fun(t, y)``
    so that it can be handed to :func:`scipy.integrate.solve_ivp` directly.

    Parameters
    ----------
    beta : float, optional
        Damping coefficient β ≥ 0 (default 0).
    gamma : float, optional
        Constant torque γ, any finite real (default 0).
    omega : float, optional
        Natural frequency ω > 0 (default 1).
    drive_amplitude : float, optional
        Amplitude A of the AC drive A sin(Ωt + φ) added to the torque, any finite real
        (default 0: no drive, the autonomous equation).
    drive_frequency : float, optional
        Its angular frequency Ω ≥ 0, Ω > 0 when A ≠ 0 (default 0).
    drive_phase : float, optional
        Its phase φ, any finite real (default 0).

    Raises
    ------
    ValueError
        If a parameter is not finite, ``beta < 0``, ``omega <= 0``,
        ``drive_frequency < 0``, or ``drive_frequency <= 0`` with
        ``drive_amplitude != 0`` (a drive needs its frequency).
    TypeError
        If a parameter is not a real number (a str, bool, complex or a sequence;
        Python and numpy integers and floats are accepted).

    Notes
    -----
    A driven scene (A ≠ 0) is not autonomous: the time t of the state matters (the
    drive's phase at t is Ωt + φ), only the Taylor family integrates it (``"taylor"``,
    ``"auto"``; the papers' formulas and the exact flow solve the autonomous equation
    and refuse it), and the long-horizon regimes (:doc:`/guide/regimes`) are off.
    With A = 0 the drive's frequency and phase change nothing: every path computes
    exactly what it computes for ``Pendulum(beta, gamma, omega)``.

    Examples
    --------
    >>> from mbm import Pendulum
    >>> p = Pendulum(beta=0.1, gamma=0.3)
    >>> p(0.0, [0.0, 0.0])
    array([0. , 0.3])
    >>> Pendulum(beta=1.0, gamma=0.5, drive_amplitude=1.0, drive_frequency=2.0).driven
    True
    """

    def __init__(self, beta=0.0, gamma=0.0, omega=1.0, drive_amplitude=0.0, drive_frequency=0.0,
                 drive_phase=0.0):
        beta = check_rule("beta", beta)
        gamma = check_rule("gamma", gamma)
        omega = check_rule("omega", omega)
        amp = check_rule("drive_amplitude", drive_amplitude)
        freq = check_rule("drive_frequency", drive_frequency)
        phase = check_rule("drive_phase", drive_phase)
        check_drive(amp, freq)
        self._beta, self._gamma, self._omega = beta, gamma, omega
        self._drive = (amp, freq, phase)
        # Hashed once (the parameters never change): mbm.solve's cache of Integrators
        # hashes the model on every call, and a Python-level hash was ~5% of its fixed cost.
        self._hash = hash((beta, gamma, omega)) if self._drive == (0.0, 0.0, 0.0) else hash(
            (beta, gamma, omega) + self._drive)

    @property
    def beta(self):
        """Damping coefficient β."""
        return self._beta

    @property
    def gamma(self):
        """Constant torque γ."""
        return self._gamma

    @property
    def omega(self):
        """Natural frequency ω."""
        return self._omega

    @property
    def drive_amplitude(self):
        """Amplitude A of the AC drive A sin(Ωt + φ) (0: none)."""
        return self._drive[0]

    @property
    def drive_frequency(self):
        """Angular frequency Ω of the AC drive."""
        return self._drive[1]

    @property
    def drive_phase(self):
        """Phase φ of the AC drive."""
        return self._drive[2]

    @property
    def drive(self):
        """``(drive_amplitude, drive_frequency, drive_phase)`` as floats."""
        return self._drive

    @property
    def driven(self):
        """Whether the torque has an AC part (A ≠ 0): the equation is then not autonomous."""
        return self._drive[0] != 0.0

    def __repr__(self):
        base = f"Pendulum(beta={self._beta!r}, gamma={self._gamma!r}, omega={self._omega!r}"
        if self._drive != (0.0, 0.0, 0.0):
            a, f, ph = self._drive
            base += f", drive_amplitude={a!r}, drive_frequency={f!r}, drive_phase={ph!r}"
        return base + ")"

    def __eq__(self, other):
        if not isinstance(other, Pendulum):
            return NotImplemented
        return ((self._beta, self._gamma, self._omega) + self._drive
                == (other._beta, other._gamma, other._omega) + other._drive)

    def __hash__(self):
        return self._hash

    def __call__(self, t, y):
        """Right-hand side ``[θ', γ + A sin(Ωt + φ) − β θ' − ω² sin θ]``.

        Parameters
        ----------
        t : float
            Time.
        y : array_like, shape (2,) or (2, k)
            State(s) [θ, θ'].

        Returns
        -------
        ndarray
            dy/dt, the shape of ``y``.
        """
        y = np.asarray(y, dtype=float)
        theta, v = y[0], y[1]
        if self._drive[0] != 0.0:
            a, f, ph = self._drive
            return np.array([v, (self._gamma + a * np.sin(f * t + ph)) - self._beta * v
                             - self._omega**2 * np.sin(theta)])
        return np.array([v, self._gamma - self._beta * v - self._omega**2 * np.sin(theta)])

    fun = __call__

    def jac(self, t, y):
        """Jacobian of the right-hand side with respect to ``y`` (the drive does not enter it).

        Parameters
        ----------
        t : float
            Time.
        y : array_like, shape (2,)
            State [θ, θ'].

        Returns
        -------
        ndarray, shape (2, 2)
        """
        theta = float(np.asarray(y, dtype=float)[0])
        return np.array([[0.0, 1.0], [-self._omega**2 * math.cos(theta), -self._beta]])

    def sundials_callbacks(self):
        """Scalar closures ``rhs(t, y, yp)`` and ``jac(t, y, yp, jj)`` for SUNDIALS (scikit-sundae).

        The right-hand side (with the drive γ + A sin(Ωt + φ) where A ≠ 0) and Jacobian
        of :meth:`__call__` and :meth:`jac`, written into the output arrays; ``y`` is
        unpacked with ``tolist()`` because numpy scalars' arithmetic is several times
        slower than float's (these run ~1e5 times a solve).
        """
        beta, gamma, w2 = self._beta, self._gamma, self._omega**2
        sin, cos = math.sin, math.cos
        amp, freq, phase = self._drive

        if amp != 0.0:
            def rhs(t, y, yp):
                th, v = y.tolist()
                yp[0] = v
                yp[1] = (gamma + amp * sin(freq * t + phase)) - beta * v - w2 * sin(th)
        else:
            def rhs(t, y, yp):
                th, v = y.tolist()
                yp[0] = v
                yp[1] = gamma - beta * v - w2 * sin(th)

        def jac(t, y, yp, jj):
            jj[0, 0] = 0.0
            jj[0, 1] = 1.0
            jj[1, 0] = -w2 * cos(y[0])
            jj[1, 1] = -beta

        return rhs, jac

    def energy(self, y):
        """Mechanical energy per unit inertia, ``θ'²/2 + ω² (1 − cos θ) − γ θ``.

        Conserved when β = 0; non-increasing along solutions when γ = 0.  The AC drive
        is not in it: with A ≠ 0 it changes at the rate (A sin(Ωt + φ) − βθ')θ', so it
        is not conserved, not even at β = 0.

        Parameters
        ----------
        y : array_like, shape (2,) or (2, k)
            State(s) [θ, θ'].

        Returns
        -------
        float or ndarray, shape (k,)
        """
        y = np.asarray(y, dtype=float)
        return 0.5 * y[1] ** 2 + self._omega**2 * (1.0 - np.cos(y[0])) - self._gamma * y[0]

    @property
    def equilibrium(self):
        """The stable rest angle ``arcsin(γ/ω²)`` in [−π/2, π/2], or None when ``|γ| > ω²``."""
        s = self._gamma / self._omega**2
        if abs(s) > 1.0:
            return None
        return math.asin(s)

    @property
    def params(self):
        """``(beta, gamma, omega)`` as floats: the autonomous part (the drive: :attr:`drive`)."""
        return (self._beta, self._gamma, self._omega)

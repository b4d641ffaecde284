"""A junction in SI units and the reduced model mbm integrates (RCSJ).

The RCSJ junction biased by a current I:  C dV/dt + V/R + I_c sin φ = I,  with the
Josephson relation V = (Φ₀/2π) dφ/dt.  Dividing by I_c and measuring time in units of
1/ω_p, ω_p = √(2π I_c / (Φ₀ C)) (t' = ω_p t), gives mbm's pendulum

    φ'' + β φ' + sin φ = γ,   β = Φ₀ ω_p / (2π I_c R) = 1/(ω_p R C) = 1/√β_c,   γ = I/I_c,

β_c = 2π I_c R² C / Φ₀ the Stewart–McCumber parameter and ω = 1.  The voltage is
V = (Φ₀ ω_p / 2π) φ', a drive I_ac sin(2π f t + φ₀) becomes A sin(Ω t' + φ₀) with
A = I_ac/I_c and Ω = 2π f / ω_p, and the n-th Shapiro step ⟨φ'⟩ = nΩ sits at
V = n Φ₀ f = n h f / 2e.
"""

import dataclasses
import math

import numpy as np
from scipy import constants

from ..model import Pendulum
from ..validate import check_positive, check_real, check_real_array

__all__ = ["Junction", "FLUX_QUANTUM"]

# Φ₀ = h/2e in webers (CODATA, through scipy.constants).
FLUX_QUANTUM = constants.physical_constants["mag. flux quantum"][0]
# A reduced result converts with a junction whose β agrees with the result's β/ω to
# this (relative): the same model up to round-off in how β was computed.
BETA_RTOL = 1e-9


def _positive(name, value, unit):
    # check_positive's TypeError for what is not a real number; its ValueError reworded
    # with the unit and the value as a plain float.
    try:
        return check_positive(name, value)
    except ValueError:
        raise ValueError(f"{name} must be finite and > 0 (in {unit}), got {float(value)!r}") from None


def _array(name, value):
    # a real number or an array of them, as a float (0-d) or a float ndarray
    arr = check_real_array(name, value)
    return float(arr) if arr.ndim == 0 else arr


def result_scales(junction, beta, omega):
    """Amperes per unit of γ and volts per unit of θ' for a reduced result at (β, ω).

    The result's equation θ'' + βθ' + ω² sin θ = γ (+ A sin Ωt) in the time ωt is the
    junction's model (ω = 1) with β/ω, γ/ω², θ'/ω (and A/ω², Ω/ω): I = γ I_c/ω² and
    V = (Φ₀ω_p/2π) θ'/ω.  The results' ``in_units`` methods use these.

    Parameters
    ----------
    junction : Junction
        The junction the result was computed on.
    beta, omega : float
        The result's β and ω.

    Returns
    -------
    tuple of float
        ``(I_c/ω², (Φ₀ω_p/2π)/ω)``: amperes per unit of γ, volts per unit of θ'.

    Raises
    ------
    TypeError
        If ``junction`` is not an :class:`mbm.Junction`.
    ValueError
        If β/ω is not the junction's β (to :data:`BETA_RTOL`): another junction's result.
    """
    if not isinstance(junction, Junction):
        raise TypeError(f"junction must be an mbm.Junction, got {type(junction).__name__}")
    if not math.isclose(beta / omega, junction.beta, rel_tol=BETA_RTOL):
        raise ValueError(f"junction: its beta = {junction.beta!r} is not the result's "
                         f"beta/omega = {float(beta / omega)!r} (compute the result at junction.beta)")
    return junction.I_c / omega**2, junction.voltage_scale / omega


@dataclasses.dataclass(frozen=True)
class Junction:
    """A Josephson junction in SI units, and its reduced RCSJ model.

    Parameters
    ----------
    I_c : float
        Critical current in amperes (> 0).
    R : float
        Shunt (normal-state) resistance in ohms (> 0).
    C : float
        Capacitance in farads (> 0).
    T : float or None, optional
        Temperature in kelvins (≥ 0), used by :attr:`temperature_reduced` only
        (default None: not given).

    Raises
    ------
    ValueError
        For ``I_c``, ``R`` or ``C`` not finite and > 0, or ``T`` not finite and ≥ 0.
    TypeError
        For a parameter that is not a real number.

    Notes
    -----
    Reduced time t' = ω_p t, β = 1/√β_c, γ = I/I_c, ω = 1, V = (Φ₀ω_p/2π) θ'
    (module docstring :mod:`mbm.junction.units`).

    See Also
    --------
    mbm.IVCurve.in_units, mbm.ShapiroSteps.in_units : a whole result in amperes and volts.

    Examples
    --------
    >>> import mbm
    >>> j = mbm.Junction(I_c=10e-6, R=10.0, C=1e-12)
    >>> round(j.beta_c, 4), round(j.beta, 4)
    (3.0385, 0.5737)
    """

    I_c: float
    R: float
    C: float
    T: float = None

    def __post_init__(self):
        for name, unit in (("I_c", "A"), ("R", "ohm"), ("C", "F")):
            object.__setattr__(self, name, _positive(name, getattr(self, name), unit))
        if self.T is not None:
            try:
                t = check_real("T", self.T)
            except ValueError:
                t = math.nan  # nan or inf: refused below with the plain float
            if not t >= 0.0:
                raise ValueError(f"T must be finite and >= 0 (in K), got {float(self.T)!r}")
            object.__setattr__(self, "T", t)

    @property
    def beta_c(self):
        """The Stewart–McCumber parameter β_c = 2π I_c R² C / Φ₀."""
        return 2.0 * math.pi * self.I_c * self.R * self.R * self.C / FLUX_QUANTUM

    @property
    def beta(self):
        """The model's damping β = 1/√β_c = 1/(ω_p R C) (reduced time ω_p t)."""
        return 1.0 / math.sqrt(self.beta_c)

    @property
    def omega_p(self):
        """The plasma frequency ω_p = √(2π I_c / (Φ₀ C)) in rad/s."""
        return math.sqrt(2.0 * math.pi * self.I_c / (FLUX_QUANTUM * self.C))

    @property
    def time_scale(self):
        """Seconds per unit of reduced time, 1/ω_p."""
        return 1.0 / self.omega_p

    @property
    def voltage_scale(self):
        """Volts per unit of θ', Φ₀ ω_p / 2π (also I_c R · β)."""
        return FLUX_QUANTUM * self.omega_p / (2.0 * math.pi)

    @property
    def E_J(self):
        """The Josephson energy Φ₀ I_c / 2π in joules."""
        return FLUX_QUANTUM * self.I_c / (2.0 * math.pi)

    @property
    def temperature_reduced(self):
        """k_B T / E_J, the thermal energy in units of E_J (None without ``T``)."""
        return None if self.T is None else constants.k * self.T / self.E_J

    def gamma(self, current):
        """The reduced bias γ = I/I_c.

        Parameters
        ----------
        current : float or array_like
            Current in amperes.

        Returns
        -------
        float or ndarray
        """
        return _array("current", current) / self.I_c

    def current(self, gamma):
        """The current I = γ I_c in amperes.

        Parameters
        ----------
        gamma : float or array_like
            Reduced bias.

        Returns
        -------
        float or ndarray
        """
        return _array("gamma", gamma) * self.I_c

    def voltage(self, theta_dot):
        """The voltage V = (Φ₀ ω_p / 2π) θ' in volts (⟨θ'⟩ gives the dc voltage).

        Parameters
        ----------
        theta_dot : float or array_like
            Reduced velocity θ' (e.g. :attr:`mbm.IVCurve.mean_velocity`).

        Returns
        -------
        float or ndarray
        """
        return _array("theta_dot", theta_dot) * self.voltage_scale

    def theta_dot(self, voltage):
        """The reduced velocity θ' = 2π V / (Φ₀ ω_p).

        Parameters
        ----------
        voltage : float or array_like
            Voltage in volts.

        Returns
        -------
        float or ndarray
        """
        return _array("voltage", voltage) / self.voltage_scale

    def differential_resistance(self, dvoltage_dgamma):
        """The differential resistance dV/dI = (Φ₀ ω_p / 2π I_c) d⟨θ'⟩/dγ = β R d⟨θ'⟩/dγ in ohms.

        Parameters
        ----------
        dvoltage_dgamma : float or array_like
            Reduced differential resistance (e.g. :attr:`mbm.IVCurve.dvoltage_dgamma`;
            NaN stays NaN).  R on the ohmic branch, where ⟨θ'⟩ → γ/β.

        Returns
        -------
        float or ndarray
        """
        return _array("dvoltage_dgamma", dvoltage_dgamma) * (self.voltage_scale / self.I_c)

    def Omega(self, frequency_hz):
        """The reduced drive frequency Ω = 2π f / ω_p.

        Parameters
        ----------
        frequency_hz : float or array_like
            Drive frequency f in hertz.

        Returns
        -------
        float or ndarray
        """
        return 2.0 * math.pi * _array("frequency_hz", frequency_hz) / self.omega_p

    def frequency(self, Omega):
        """The drive frequency f = Ω ω_p / 2π in hertz.

        Parameters
        ----------
        Omega : float or array_like
            Reduced angular frequency Ω.

        Returns
        -------
        float or ndarray
        """
        return _array("Omega", Omega) * self.omega_p / (2.0 * math.pi)

    def shapiro_voltage(self, n, frequency_hz):
        """The voltage of Shapiro step n under a drive at f: V = n h f / 2e = n Φ₀ f.

        Parameters
        ----------
        n : float or array_like
            Step order (p/q for a fractional step).
        frequency_hz : float or array_like
            Drive frequency f in hertz.

        Returns
        -------
        float or ndarray
        """
        return _array("n", n) * FLUX_QUANTUM * _array("frequency_hz", frequency_hz)

    def model(self, bias_current, *, drive_current=0.0, drive_frequency_hz=0.0, drive_phase=0.0):
        """The reduced model :class:`mbm.Pendulum` at a bias current (and drive).

        Parameters
        ----------
        bias_current : float
            dc bias I in amperes (γ = I/I_c).
        drive_current : float, optional
            Amplitude I_ac of a drive I_ac sin(2π f t + φ) in amperes (A = I_ac/I_c;
            default 0: none).
        drive_frequency_hz : float, optional
            Its frequency f in hertz (Ω = 2π f / ω_p; > 0 with a drive).
        drive_phase : float, optional
            Its phase φ in radians.

        Returns
        -------
        Pendulum
            β, γ, ω = 1 and the drive, in reduced time t' = ω_p t.
        """
        gamma = check_real("bias_current", bias_current) / self.I_c
        amplitude = check_real("drive_current", drive_current) / self.I_c
        frequency = 2.0 * math.pi * check_real("drive_frequency_hz", drive_frequency_hz) / self.omega_p
        return Pendulum(self.beta, gamma, 1.0, drive_amplitude=amplitude, drive_frequency=frequency,
                        drive_phase=check_real("drive_phase", drive_phase))

"""The result of :func:`mbm.iv_curve` (:class:`IVCurve`) and its form in physical units
(:class:`IVCurveSI`); the sweep and its measurements are in :mod:`mbm.junction.iv`."""

import dataclasses
import math

import numpy as np

# Two successive blocks whose averages agree to this (absolute, in units of ω): converged
# (a driven point's ⟨θ'⟩, mbm.junction.iv; the default of IVCurve.velocity_tol).
DRIVE_VELOCITY_TOL = 1e-9


@dataclasses.dataclass(frozen=True)
class IVCurve:
    """An I–V curve: the mean velocity at each bias point, in the order visited.

    A dataclass built by :func:`iv_curve`: each parameter is an attribute.

    Parameters
    ----------
    gamma : ndarray
        Bias points, in the order visited.
    mean_velocity : ndarray
        ⟨θ'⟩ at each point (the dc voltage): 0 when locked, ±2π/T_c when running.
    regime : ndarray of str
        ``"locked"`` or ``"running"`` at each point, or (driven) ``"phase-locked"`` on
        a Shapiro step p/q (``mean_velocity`` = (p/q)Ω), the zero-voltage step p = 0
        included: the label of :func:`mbm.solve`.  The zero-voltage step is on the
        locked side of the switching and retrapping currents, every other step on the
        running side.
    period : ndarray
        T_c of the running cycle, q·2π/Ω on a Shapiro step (NaN where locked and at
        driven points off the steps).
    start_state : ndarray, shape (n, 2)
        The state each point started from (the previous point's settled state).
    switching_current : float
        The first locked → running transition located by bisection (NaN if none): the
        midpoint of ``switching_bracket``.
    retrapping_current : float
        The first running → locked transition located by bisection (NaN if none): the
        midpoint of ``retrapping_bracket``.
    beta, omega, current_tol : float
        The junction and the bisection tolerance.
    drive_amplitude, drive_frequency, drive_phase : float
        The AC drive A sin(Ωt + φ) added to each bias point (A = 0: none).  With a
        drive, ``mean_velocity`` is measured over whole drive periods (module
        docstring).
    switching_bracket, retrapping_bracket : tuple of float
        ``(lo, hi)``, lo ≤ current ≤ hi, hi − lo ≤ ``current_tol``: the bias points
        bisection found on either side of the transition ((nan, nan) if none).  The
        switching bracket lies within [−ω², ω²]: a zero-voltage state needs
        abs(γ) = ω² abs(⟨sin θ⟩) ≤ ω² (with or without a drive, whose mean is 0), so the
        switching current never exceeds ω².
    converged : ndarray of bool
        Whether each point settled: True at every undriven point (one that does not
        settle raises) and at a driven point that reached the phase-locked regime or
        whose last two blocks agreed to ``velocity_tol``; False where the blocks never
        agreed within :data:`~mbm.junction.iv.DRIVE_MAX_BLOCKS` (a long transient, quasi-periodic or
        chaotic motion: ``mean_velocity`` is then the average over the blocks measured,
        not settled to ``velocity_tol``).  None on a curve built without it.
    velocity_tol : float
        The agreement of two successive blocks asked of a driven point (absolute, in
        units of ω).
    switching_settled, retrapping_settled : bool
        Whether every probe of the bisection behind ``switching_bracket`` (resp.
        ``retrapping_bracket``) kept one voltage state over the blocks it was measured
        on: True without a drive and without a bracket.  False where a driven probe
        slipped in some blocks and not in others (a transient, or the intermittent
        slips beside a step's edge): the probe counts in the voltage state of its last
        block, and the bracket may then be off by more than ``current_tol``.  (A probe
        whose ⟨θ'⟩ did not settle to ``velocity_tol`` but slipped in every block, or in
        none, is in that state: the bisection needs the state, not the voltage.)
    dvoltage_dgamma : ndarray or None
        The differential resistance d⟨θ'⟩/dγ at each point in reduced units (module
        docstring; :meth:`mbm.Junction.differential_resistance` gives ohms): from the
        period's sensitivity on a running cycle, 0 at a locked point and on a Shapiro
        step (phase-locked), NaN at a driven point off the steps.  None unless
        :func:`iv_curve` was asked for it (``differential=True``).
    """

    gamma: np.ndarray
    mean_velocity: np.ndarray
    regime: np.ndarray
    period: np.ndarray
    start_state: np.ndarray
    switching_current: float
    retrapping_current: float
    beta: float
    omega: float
    current_tol: float
    drive_amplitude: float = 0.0
    drive_frequency: float = 0.0
    drive_phase: float = 0.0
    switching_bracket: tuple = (math.nan, math.nan)
    retrapping_bracket: tuple = (math.nan, math.nan)
    converged: np.ndarray = None
    velocity_tol: float = DRIVE_VELOCITY_TOL
    switching_settled: bool = True
    retrapping_settled: bool = True
    dvoltage_dgamma: np.ndarray = None

    def in_units(self, junction):
        """The curve in amperes, volts and ohms, for the junction it models.

        Parameters
        ----------
        junction : mbm.Junction
            The junction: its β must be the curve's ``beta`` (``beta / omega`` where
            ``omega`` ≠ 1: :func:`mbm.junction.units.result_scales`).

        Returns
        -------
        IVCurveSI

        Raises
        ------
        TypeError
            If ``junction`` is not an :class:`mbm.Junction`.
        ValueError
            If the curve was computed at another β than the junction's.

        Examples
        --------
        >>> import mbm
        >>> j = mbm.Junction(I_c=10e-6, R=10.0, C=1e-12)
        >>> si = mbm.iv_curve(j.beta, j.gamma([14e-6]), theta_dot0=3.0).in_units(j)
        >>> f"{si.current[0] * 1e6:.1f} µA, {si.voltage[0] * 1e6:.0f} µV"
        '14.0 µA, 138 µV'
        """
        from .units import result_scales

        amps, volts = result_scales(junction, self.beta, self.omega)
        slope = self.dvoltage_dgamma
        return IVCurveSI(
            current=self.gamma * amps, voltage=self.mean_velocity * volts,
            switching_current=float(self.switching_current) * amps,
            retrapping_current=float(self.retrapping_current) * amps,
            switching_bracket=tuple(float(g) * amps for g in self.switching_bracket),
            retrapping_bracket=tuple(float(g) * amps for g in self.retrapping_bracket),
            differential_resistance=None if slope is None else slope * (volts / amps),
            drive_current=float(self.drive_amplitude) * amps,
            drive_frequency_hz=junction.frequency(self.drive_frequency / self.omega),
            junction=junction)

    def branches(self):
        """Index arrays of the up (γ increasing) and down (γ decreasing) parts of the sweep."""
        d = np.diff(self.gamma)
        step = np.concatenate(([d[0] if d.size else 0.0], d))
        return np.flatnonzero(step >= 0.0), np.flatnonzero(step < 0.0)

    def to_csv(self, path):
        """Write gamma, mean_velocity, regime, period, converged as CSV (the currents in a header comment),
        and dvoltage_dgamma where the curve has it.

        Parameters
        ----------
        path : str or path-like
            The file to write.
        """
        with open(path, "w") as f:
            drive = (f", drive_amplitude={self.drive_amplitude!r}, drive_frequency={self.drive_frequency!r}, "
                     f"drive_phase={self.drive_phase!r}" if self.drive_amplitude != 0.0 else "")
            f.write(f"# beta={self.beta!r}, omega={self.omega!r}, switching_current={self.switching_current!r}, "
                    f"retrapping_current={self.retrapping_current!r}, current_tol={self.current_tol!r}{drive}, "
                    f"switching_bracket={tuple(map(float, self.switching_bracket))!r}, "
                    f"retrapping_bracket={tuple(map(float, self.retrapping_bracket))!r}, "
                    f"switching_settled={bool(self.switching_settled)!r}, "
                    f"retrapping_settled={bool(self.retrapping_settled)!r}\n")
            slope = self.dvoltage_dgamma is not None
            f.write("gamma,mean_velocity,regime,period,converged" + (",dvoltage_dgamma" if slope else "") + "\n")
            settled = [""] * self.gamma.size if self.converged is None else [str(bool(c)) for c in self.converged]
            extra = [f",{float(x)!r}" for x in self.dvoltage_dgamma] if slope else [""] * self.gamma.size
            for g, v, r, p, c, x in zip(self.gamma, self.mean_velocity, self.regime, self.period, settled, extra):
                f.write(f"{float(g)!r},{float(v)!r},{r},{float(p)!r},{c}{x}\n")

    def plot(self, ax=None):
        """Draw the curve (voltage ⟨θ'⟩ across, bias γ up), up and down branches marked.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (default a new figure).

        Returns
        -------
        matplotlib.axes.Axes
        """
        if ax is None:
            import matplotlib.pyplot as plt

            ax = plt.subplots(figsize=(7, 5))[1]
        up, down = self.branches()
        ax.plot(self.mean_velocity[up], self.gamma[up], "b.-", ms=3, lw=0.8, label="bias up")
        if down.size:
            ax.plot(self.mean_velocity[down], self.gamma[down], "r.-", ms=3, lw=0.8, label="bias down")
        for cur, name, style in ((self.switching_current, "switching", "k--"),
                                 (self.retrapping_current, "retrapping", "g--")):
            if math.isfinite(cur):
                ax.axhline(cur, color=style[0], ls="--", lw=0.7, label=f"{name} {cur:.5g}")
        ax.set_xlabel(r"voltage $\langle\theta'\rangle$")
        ax.set_ylabel(r"bias current $\gamma$")
        title = rf"RCSJ I–V, $\beta$ = {self.beta:g}"
        if self.drive_amplitude != 0.0:
            title += rf", drive $A$ = {self.drive_amplitude:g}, $\Omega$ = {self.drive_frequency:g}"
        ax.set_title(title)
        ax.legend(fontsize=8, loc="lower right")
        return ax


@dataclasses.dataclass(frozen=True)
class IVCurveSI:
    """An I–V curve in amperes, volts and ohms: what :meth:`IVCurve.in_units` returns.

    Parameters
    ----------
    current : ndarray
        The bias current I = γ I_c at each point (A), in the order visited.
    voltage : ndarray
        The dc voltage V = (Φ₀ω_p/2π)⟨θ'⟩ at each point (V).
    switching_current, retrapping_current : float
        I_s and I_r (A; NaN where the curve has none).
    switching_bracket, retrapping_bracket : tuple of float
        Their bisection brackets ``(lo, hi)`` (A).
    differential_resistance : ndarray or None
        dV/dI at each point (Ω), None unless the curve has ``dvoltage_dgamma``.
    drive_current, drive_frequency_hz : float
        The AC drive's amplitude I_ac (A) and frequency f (Hz); 0 without a drive.
    junction : mbm.Junction
        The junction converted with.
    """

    current: np.ndarray
    voltage: np.ndarray
    switching_current: float
    retrapping_current: float
    switching_bracket: tuple
    retrapping_bracket: tuple
    differential_resistance: np.ndarray
    drive_current: float
    drive_frequency_hz: float
    junction: object

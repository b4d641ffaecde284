"""Thermal noise: Langevin junctions, escape times, switching- and retrapping-current histograms.

θ'' + βθ' + ω² sin θ = γ(t) + A sin(Ωt + φ) + ξ(t), ⟨ξ(t)ξ(t')⟩ = 2βT δ(t − t'),
integrated by the symmetric splitting O(h/2) D(h) O(h/2) of an exact Ornstein–Uhlenbeck
step O and a high-order Taylor flow D (:mod:`mbm.noise.flow`, :mod:`mbm.noise.kernels`),
with a counter-based generator per scene (:mod:`mbm.noise.rng`).  The deterministic
path of mbm is untouched.  docs/guide/noise.md has the theory and the checks.
"""

from .api import (
    EscapeTimes,
    SwitchingHistogram,
    barrier_action,
    bhl_rate,
    escape_times,
    kramers_rate,
    switching_currents,
    well,
)
from .grids import switching_grid
from .retrap import RetrappingHistogram, retrapping_currents

__all__ = ["EscapeTimes", "RetrappingHistogram", "SwitchingHistogram", "barrier_action", "bhl_rate", "escape_times", "kramers_rate",
           "retrapping_currents", "switching_currents", "switching_grid", "well"]

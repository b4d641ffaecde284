"""What every long-horizon regime shares: the regime codes and names, the switch's safety.

``regime`` of a run record is one of the REGIME_* codes (REGIME_NONE: the run did not
switch), and REGIME_NAMES gives the name a result reports.  SWITCH_SAFETY is the share
of the tolerance every regime's switch rule allows (L5, R2, C4, S5).
"""

import collections

#: A run's tolerances: ``rtol``, ``atol`` (the switch rules' scale).
Tolerance = collections.namedtuple("Tolerance", ("rtol", "atol"))

# (L5): the remainder bound must be this fraction of the tolerance, so the switch adds
# at most a tenth of one window's allowed error to the outputs after it.
SWITCH_SAFETY = 0.1

# The run record's ``regimes`` field: which regimes a run may switch to.
REGIMES_OFF = 0  # none: every window is the approximant's
REGIMES_ALL = 1  # every regime its set reaches (the default)
# Only the stored-period regimes (running cycle, libration): the windows the compiled
# events (mbm.events.compiled) locate crossings on, besides the approximant's own.
REGIMES_PERIODIC = 2

REGIME_NONE = 0
REGIME_LOCKED = 1
REGIME_RUNNING = 2
REGIME_LIBRATION = 3
REGIME_PHASE_LOCKED = 4
#: The name of each regime (``regime`` of a result).
REGIME_NAMES = {REGIME_NONE: None, REGIME_LOCKED: "locked", REGIME_RUNNING: "running",
                REGIME_LIBRATION: "libration", REGIME_PHASE_LOCKED: "phase-locked"}

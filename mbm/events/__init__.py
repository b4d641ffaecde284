"""Events: where a run crosses an angle, a velocity or a drive section, or where g = 0.

=====================  ==========================================================
:mod:`.compiled`       the event specs (:class:`mbm.Event`, ``angle_event``, ...) and
                       their runs on the compiled paths (solve, solve_batch)
:mod:`.functions`      your own ``numba.njit`` g(t, θ, θ') watched on the windows
:mod:`.njit`           events inside your own numba code (``solve_njit_events``)
:mod:`.points`         the seed paper's event points θ = d, θ' = 0 (``successive``)
=====================  ==========================================================

The compiled watch of a window and the lanes' event tables live in :mod:`mbm.core`
(``event_watch``, ``event_batch``).
"""

"""The entry points a user calls, each over the one compiled loop of :mod:`mbm.core`.

=====================  ==========================================================
:mod:`.solve`          :func:`mbm.solve`, :class:`mbm.Integrator`, :func:`mbm.solve_njit`
:mod:`.batch`          :func:`mbm.solve_batch`: many scenes on threads, no GIL
:mod:`.ivp`            :class:`mbm.MBM`: the ``scipy.integrate.solve_ivp`` method
:mod:`.dense`          the dense output of stored windows (``sol(t)``)
:mod:`.probe`          :func:`mbm.identify_model`: which pendulum a plain ``fun(t, y)`` is
:mod:`.reference`      :func:`mbm.reference`: tight independent solutions (CVODE)
=====================  ==========================================================
"""

"""Error bars and sensitivities of a run, from the tangent map along its windows.

``error_estimate=True`` and ``sensitivities=(names)`` on :func:`mbm.solve` and
:meth:`mbm.Integrator.solve`: :mod:`mbm.tangent.transport` (the pass),
:mod:`mbm.tangent.series` (the variational recurrence), :mod:`mbm.tangent.api` (the
options and the result's fields).
"""

from .api import SENSITIVITY_NAMES, AccuracyWarning, attach, coefficient_width, request

__all__ = ["SENSITIVITY_NAMES", "AccuracyWarning", "attach", "coefficient_width", "request"]

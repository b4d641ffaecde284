"""Josephson-junction tools on the RCSJ model, and parameter sweeps.

=====================  ============================================================================
:mod:`.units`          :class:`mbm.Junction`: SI units (I_c, R, C) ↔ the reduced model
:mod:`.fits`           :func:`mbm.beta_from_retrapping`, :func:`mbm.fit_iv`: β from a measurement
:mod:`.iv`             :func:`mbm.iv_curve`: the I–V curve, with hysteresis
:mod:`.shapiro`        :func:`mbm.shapiro_steps`: a driven junction's steps
:mod:`.sweeps`         :func:`mbm.sweep`: grids of scenes as xarray Datasets on Dask
:mod:`.progress`       the progress bar of long runs (tqdm)
=====================  ============================================================================
"""

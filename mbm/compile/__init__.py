"""Compile-time machinery: numba's settings, its cache, the helper that compiles ahead.

=====================  ==========================================================
:mod:`.jit`            the kernels' numba options and the ``@kernel`` decorator
:mod:`.cache`          the on-disk cache kept in step with the sources; the notice
:mod:`.cache_lock`     numba's cache index written under a file lock (two processes)
:mod:`.gc`             the garbage collector relaxed while numba compiles
:mod:`.warm`           the compile helper and its generated manifest (manifest.pkl)
=====================  ==========================================================

Nothing here changes an answer: only when and where kernels are compiled.
"""

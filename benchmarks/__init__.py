"""The work-precision benchmark of mbm, run from a checkout: ``python -m benchmarks``.

Kept outside the ``mbm`` package (as scipy, diffrax and numbalsoda keep theirs): it
holds peer solvers, reference integrators and report rendering that a user of mbm
does not need, and it calls mbm only through its public API.

Modules, by concern:

* :mod:`benchmarks.scenes`: the benchmark's scenes P1–P6 (from :mod:`mbm.scenes`) with
  their inputs built once;
* :mod:`benchmarks.peers`: the peer solvers (scipy, CVODE, a numba RK4 and DOP853
  written here, numbalsoda, heyoka);
* :mod:`benchmarks.registry`: what is measured: the :class:`~benchmarks.registry.Solver`
  record, MBM's entries and the list of all entries;
* :mod:`benchmarks.references`: the references the errors are measured against
  (a 128-bit fixed-point Taylor integrator, heyoka in long double, the exact flow);
* :mod:`benchmarks.harness`: timing (medians with the garbage collector paused,
  compile and JIT time apart) and the sweeps;
* :mod:`benchmarks.report`: Markdown, JSON, plots, and the blocks the README quotes;
* :mod:`benchmarks.extras`: the targets the tables do not cover (undamped t = 10⁶,
  an I–V ensemble, the fixed costs of a short run).

``python -m benchmarks --help`` lists the options; ``python -m benchmarks extras
--help`` those of the extras; ``python -m benchmarks readme`` copies the generated
blocks the README quotes from ``docs/`` into ``README.md``.
"""

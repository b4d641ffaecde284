"""benchmarks.best_of: a positive time and the run's window count."""

from benchmarks import best_of

import mbm
from benchmarks.scenes import SCENES


def test_best_of_small(capsys):
    us, windows = best_of.best_of("P1", 1e-4, batches=2, calls=3)
    s = SCENES["P1"]
    assert us > 0.0
    assert windows == mbm.solve(s.model, s.t_span, s.y0, rtol=1e-4, atol=1e-4).n_windows
    best_of.main(["--scene", "P1", "--batches", "1", "--calls", "2"])
    assert "P1 rtol 1e-06:" in capsys.readouterr().out

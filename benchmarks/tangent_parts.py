"""Where an ``error_estimate=True`` call's time goes, on a prepared :class:`mbm.Integrator`.

    python -m benchmarks.tangent_parts [--calls 20]

Per scene (benchmark scenes P1, P5; rtol = atol = 1e-6): the plain run, the run with its
windows' coefficients stored (the pass switched off), the whole call, and the tangent pass
alone (:func:`mbm.tangent.transport.transport` on the run's stored windows) at 2, 201 and
2001 outputs, so that the pass's cost per output and per window can be read off.  Best of
5 batches of ``--calls`` calls, one process; heyoka's figures at matched error are in
``python -m benchmarks.tangent``.
"""

import argparse

import numpy as np

import mbm
import mbm.frontends.solve as _solve
import mbm.tangent.api as _api
from mbm.tangent.reference import REF_DEGREE
from mbm.tangent.transport import carry_arrays, transport

from .best_of import best_us
from .scenes import SCENES


def _pass_us(ig, span, y0, te, calls):
    # The pass alone on the windows of one stored run: (µs, windows).
    got = {}
    orig = _solve._tangent.attach
    _solve._tangent.attach = lambda r, ig_, req, windows: got.update(r=r, req=req, windows=windows)
    try:
        ig.solve(span, y0, t_eval=te, error_estimate=True)
    finally:
        _solve._tangent.attach = orig
    r, req, (win_t, win_y, win_c) = got["r"], got["req"], got["windows"]
    sc, codes, rows, n_order, kt = _api._setup(ig, req.names, True)
    t_out, y_out = r["t"], np.ascontiguousarray(r["y"][:2])
    err, sens = np.empty((2, t_out.size)), np.empty((rows.size, 2, t_out.size))
    t_taylor = r["t_regime"] if r["t_regime"] == r["t_regime"] else np.inf
    ctl = ((ig.rtol, ig.atol), np.inf, t_taylor, n_order, kt, r["period"])
    track, report = (win_t, win_y, win_c, t_out, y_out), (err, sens, rows)
    nt = max(REF_DEGREE, int(n_order) + 2)
    ws = _api.workspace(nt, codes.size)
    carry = carry_arrays(rows.size, codes.size, nt, r["period"])

    def run():
        carry[2][0] = -1
        while transport(sc, codes, track, ctl, report, ws, carry) == 1:
            pass

    return best_us(run, 5, calls), win_t.size - 1


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=20)
    args = parser.parse_args(argv)
    print("| scene | outputs | windows | plain µs | stored run µs | error_estimate µs | pass alone µs |")
    print("|---|---|---|---|---|---|---|")
    for name in ("P1", "P5"):
        s = SCENES[name]
        ig = mbm.Integrator(s.model, rtol=1e-6, atol=1e-6)
        for n_out in (2, 201, 2001):
            te = np.linspace(*s.t_span, n_out)
            plain = best_us(lambda: ig.solve(s.t_span, s.y0, t_eval=te), 5, args.calls)
            est = best_us(lambda: ig.solve(s.t_span, s.y0, t_eval=te, error_estimate=True), 5, args.calls)
            orig = _solve._tangent.attach
            _solve._tangent.attach = lambda *a: None
            try:
                stored = best_us(lambda: ig.solve(s.t_span, s.y0, t_eval=te, error_estimate=True), 5, args.calls)
            finally:
                _solve._tangent.attach = orig
            alone, nw = _pass_us(ig, s.t_span, s.y0, te, args.calls)
            print(f"| {name} | {n_out} | {nw} | {plain:.1f} | {stored:.1f} | {est:.1f} | {alone:.1f} |")


if __name__ == "__main__":
    main()

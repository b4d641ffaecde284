"""The run record (mbm.core.record): its named groups, its size where it is documented,
and the one initialiser every path uses."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

import mbm
from mbm.core import controller, loop, record, window

ROOT = Path(__file__).resolve().parents[2]

# The layout, group by group: a change of the record is a change of this table (and of
# the size quoted in the README).
LAYOUT = {
    "model": ("beta", "gamma", "omega", "drive_amp", "drive_freq", "drive_phase"),
    "state": ("t", "theta", "v", "t_bound"),
    "winding": ("phi", "wind"),
    "control": ("kind", "karg", "controller", "h_abs", "max_step", "max_dtheta", "rtol", "atol", "error_order"),
    "progress": ("max_windows", "call_windows", "n_windows", "j", "status"),
    "switch": ("regimes", "regime", "t_regime"),
    "cycle": ("sec_n", "sec_sign", "sec_t", "sec_v", "sec_T", "sec_dv", "sec_vmax", "cyc_theta", "cyc_v",
              "cyc_T", "cyc_t", "cyc_sign", "cyc_k", "cyc_wind", "cyc_Tlo"),
    "strobe": ("str_t0", "str_n", "str_k", "str_phi", "str_v", "str_p", "str_m", "str_d1t", "str_d1v",
               "str_d2t", "str_d2v", "str_d3t", "str_d3v", "str_ta", "str_psi", "str_tau1", "str_tau2",
               "str_rho", "str_nw", "str_q", "str_ring", "str_qtau1", "str_qtau2", "str_qrho", "str_qb",
               "lk_k0", "lk_phi0", "lk_acc", "lk_cnt", "lk_lvl", "lk_nb", "lk_means"),
    "damped": ("dmp_beta", "dmp_gamma", "dmp_omega", "dmp_d", "dmp_wl2", "dmp_g0", "dmp_g1", "dmp_sd", "dmp_q2",
               "dmp_sec_off", "dmp_sec_acc"),
}
SIZE = 1696


def test_layout_is_the_named_groups():
    assert record.RUN.names == tuple(LAYOUT)
    for group, fields in LAYOUT.items():
        assert record.RUN.fields[group][0].names == fields
    assert record.RUN.itemsize == SIZE
    assert set(record.GROUP) == {f for fields in LAYOUT.values() for f in fields}


def test_documented_size_is_the_record_size():
    page = (ROOT / "docs" / "guide" / "sweeps.md").read_text()
    quoted = re.search(r"`mbm\.core\.record\.RUN\.itemsize`, is (\d+) bytes", page)
    assert quoted and int(quoted.group(1)) == record.RUN.itemsize


def test_words_and_flat_view_address_the_same_fields():
    p = record.new_run(record.RunModel(0.1, 0.2, 1.5, 0.3, 0.7, 0.2), record.RunState(3.0, 0.4, -0.5, 9.0),
                       record.RunControl(window.KIND_TAYLOR, 24, controller.CONTROLLER_ADAPTIVE, -1.0, 2.5, math.inf,
                                         1e-7, 1e-8, 24), 1000)
    words = p.view(np.float64)
    ints = p.view(np.int64)
    f = record.flat(p)[0]
    for name, group in record.GROUP.items():
        value = p[0][group][name]
        assert np.array_equal(f[name], value, equal_nan=True)
        if np.ndim(value) == 0:
            w = record.WORD[name]
            got = ints[w] if np.issubdtype(np.asarray(value).dtype, np.integer) else words[w]
            assert got == value or (math.isnan(got) and math.isnan(value)), name
    assert record.WORD["v"] == record.WORD["theta"] + 1


def test_new_run_is_the_fresh_record():
    p = record.new_run(record.RunModel(0.1, 0.2, 1.5), record.RunState(3.0, 0.4, -0.5, 9.0),
                       record.RunControl(window.KIND_SPLIT, 4, controller.CONTROLLER_FIXED, 0.1, math.inf, 0.5, 1e-6,
                                         1e-9, 4), 77, call_windows=5, regimes=0)
    r = record.flat(p)[0]
    assert (r["beta"], r["gamma"], r["omega"]) == (0.1, 0.2, 1.5)
    assert (r["t"], r["theta"], r["v"], r["t_bound"]) == (3.0, 0.4, -0.5, 9.0)
    assert (r["phi"], r["wind"]) == (0.4, 0.0)
    assert (r["kind"], r["karg"], r["controller"], r["h_abs"]) == (window.KIND_SPLIT, 4, controller.CONTROLLER_FIXED, 0.1)
    assert (r["max_dtheta"], r["rtol"], r["atol"], r["error_order"]) == (0.5, 1e-6, 1e-9, 4)
    assert (r["max_windows"], r["call_windows"], r["n_windows"], r["j"], r["status"]) == (77, 5, 0, 0, 0)
    assert r["regimes"] == 0 and r["regime"] == mbm.regimes.REGIME_NONE and math.isnan(r["t_regime"])
    assert math.isnan(r["cyc_T"]) and r["str_q"] == 1.0 and r["sec_n"] == 0
    assert np.all(np.isnan(r["str_qtau1"])) and np.all(np.isinf(r["str_qb"])) and not np.any(r["str_ring"])
    assert (r["drive_amp"], r["drive_freq"], r["drive_phase"]) == (0.0, 0.0, 0.0)


def test_batch_records_are_new_run_records_bit_for_bit():
    # init_runs (solve_batch's) and new_run (every other path's) write the same words
    beta, gamma, omega = np.array([0.1, 0.0]), np.array([1.2, 0.0]), np.array([1.0, 2.0])
    y0 = np.array([[0.5, 0.0], [1.0, -0.25]])
    plan = np.array([[window.KIND_TAYLOR, window.KIND_EXACT], [24, 0], [controller.CONTROLLER_ADAPTIVE, controller.CONTROLLER_FIXED],
                     [24, 0]], dtype=np.int64)
    h = np.array([-1.0, 5.0])
    model = np.stack([beta, gamma, omega, np.zeros(2), np.zeros(2), np.zeros(2)])
    p = np.empty(2, dtype=record.RUN)
    record.init_runs(p, model, y0, plan, h, (0.0, 5.0, math.inf, 1e-8, 1e-9, 1000))
    for i in range(2):
        want = record.new_run(record.RunModel(beta[i], gamma[i], omega[i]), record.RunState(0.0, *y0[i], 5.0),
                              record.RunControl(plan[0, i], plan[1, i], plan[2, i], h[i], math.inf, math.inf, 1e-8,
                                                1e-9, plan[3, i]), 1000)
        assert p[i:i + 1].tobytes() == want.tobytes()


def test_solve_njit_and_batch_build_records_with_the_initialiser():
    # no path spells the record out field by field: solve_njit and solve_batch call the
    # compiled initialiser (and solve_njit's run equals mbm.solve's, tests/frontends/test_fast.py)
    src = (ROOT / "mbm" / "frontends" / "solve.py").read_text()
    njit_src = src[src.index("def solve_njit("):]
    batch_src = (ROOT / "mbm" / "frontends" / "batch.py").read_text()
    assert "record.init_run(" in njit_src and "record.init_runs(" in batch_src
    assert "np.zeros(1, dtype=record.RUN)" not in njit_src and 'p["' not in batch_src


def test_a_fresh_record_has_no_damped_constants():
    p = record.new_run(record.RunModel(0.1, 0.2, 1.5), record.RunState(0.0, 0.4, -0.5, 9.0),
                       record.RunControl(window.KIND_TAYLOR, 24, controller.CONTROLLER_ADAPTIVE, -1.0, math.inf,
                                         math.inf, 1e-8, 1e-8, 24), 1000)
    d = p[0]["damped"]
    assert math.isnan(d["dmp_beta"]) and math.isnan(d["dmp_gamma"]) and math.isnan(d["dmp_omega"])


# A damped scene (RS_DAMPED) that locks, and one whose return map is watched (running).
_DAMPED_SCENES = [(0.5, 0.3, 1.2, 0.8, 0.0, 60.0), (0.2, 1.3, 1.0, 0.0, 0.0, 30.0)]


def _damped_buffer(beta, gamma, omega):
    p = record.new_run(record.RunModel(beta, gamma, omega), record.RunState(0.0, 0.0, 0.0, 0.0),
                       record.RunControl(window.KIND_TAYLOR, 24, controller.CONTROLLER_ADAPTIVE, -1.0, math.inf,
                                         math.inf, 1e-9, 1e-9, 24), 10**6)
    assert loop.set_of(p[0]) == loop.RS_DAMPED
    buf = np.empty((2, record.RUN.itemsize // 8))
    buf[0] = p.view(np.float64)
    return buf


def _entry_run(buf, theta0, t1, t_eval):
    entry = loop.entry_for(window.KIND_TAYLOR, loop.RS_DAMPED, 24)
    out = np.empty((2, t_eval.size))
    no_t, no_y, no_coef = np.empty(0), np.empty((0, 2)), np.empty((0, 0))
    entry(buf, True, (0.0, theta0, 0.0, t1, -1.0), (t_eval, out, no_t, no_y, no_coef, np.zeros(1, dtype=np.int64)))
    return out, buf[1].copy()


@pytest.mark.parametrize("beta,gamma,omega,theta0,_,t1", _DAMPED_SCENES)
def test_damped_constants_are_formed_once_and_kept_in_the_template(beta, gamma, omega, theta0, _, t1):
    buf = _damped_buffer(beta, gamma, omega)
    t_eval = np.linspace(0.0, t1, 41)
    out1, run1 = _entry_run(buf, theta0, t1, t_eval)
    d = buf[0].view(record.RUN)[0]["damped"]
    # the run's model's constants, as the locked test (L1, L4, L7) and the section (R1) form them
    want = mbm.regimes.locked._lock_setup.py_func(beta, gamma, omega, abs(gamma) < omega**2, True)[:6]
    assert (d["dmp_beta"], d["dmp_gamma"], d["dmp_omega"]) == (beta, gamma, omega)
    assert (d["dmp_d"], d["dmp_wl2"], d["dmp_g0"], d["dmp_g1"], d["dmp_sd"], d["dmp_q2"]) == want
    assert d["dmp_sec_off"] == mbm.regimes.section_offset(gamma, omega)
    assert d["dmp_sec_acc"] == gamma - omega * omega * math.sin(d["dmp_sec_off"])
    # the next run from the template takes them as formed: the same run, bit for bit
    out2, run2 = _entry_run(buf, theta0, t1, t_eval)
    assert out1.tobytes() == out2.tobytes() and run1.tobytes() == run2.tobytes()


def test_damped_constants_of_another_model_are_formed_again():
    # a template whose model words change after a run (a swept γ) runs as a new record would
    (beta, gamma, omega, theta0, _, t1), (_, gamma2, _, _, _, _) = _DAMPED_SCENES[0], _DAMPED_SCENES[1]
    t_eval = np.linspace(0.0, t1, 41)
    buf = _damped_buffer(beta, gamma, omega)
    _entry_run(buf, theta0, t1, t_eval)
    buf[0, record.WORD["gamma"]] = gamma2
    got, run = _entry_run(buf, theta0, t1, t_eval)
    want, run_new = _entry_run(_damped_buffer(beta, gamma2, omega), theta0, t1, t_eval)
    assert got.tobytes() == want.tobytes() and run.tobytes() == run_new.tobytes()
    assert buf[0, record.WORD["dmp_gamma"]] == gamma2

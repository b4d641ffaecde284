"""The scene catalogue, mbm.scenes: one set of named scenes for tests, examples, CLI and benchmark."""

import dataclasses
import doctest
import math

import numpy as np
import pytest

import mbm
import mbm.scenes
from mbm.cli import study as cli_study
from mbm.scenes import CATALOGUE, Scene, get, names


def test_benchmark_scenes_as_defined():
    # P1-P6 as the benchmark has always defined them (omega = 1 throughout).
    want = {
        "P1": (0.4, 0.0, 1.0, 0.0, 0.25, 20.0),
        "P2": (0.1, 0.3, 1.0, math.radians(30.0), 0.0, 80.0),
        "P3": (0.1, 0.6, 1.0, math.radians(90.0), 0.0, 80.0),
        "P4": (0.01, 0.3, 1.0, 1.0, 0.0, 1.0e4),
        "P5": (0.1, 1.2, 1.0, 0.0, 0.0, 1000.0),
        "P6": (0.0, 0.0, 1.0, 0.0, 1.999, 200.0),
    }
    for name, params in want.items():
        sc = get(name)
        assert sc.name == name and sc.params() == params and sc.t_span == (0.0, params[-1])
        assert sc.description and sc.source


def test_aliases_are_the_same_scenes():
    # The names the tests, the papers' examples and `mbm study` use.
    for alias, name in (("ex1", "P2"), ("ex2", "P3"), ("paper1", "P1"), ("running", "P5"),
                        ("separatrix", "P6"), ("longweak", "P4"), ("free", "free135")):
        assert get(alias) is CATALOGUE[name]
    assert "Example 1" in get("ex1").source and "Example 2" in get("ex2").source
    assert names()[:6] == ["P1", "P2", "P3", "P4", "P5", "P6"]
    assert set(names(aliases=True)) > set(names())


def test_unknown_scene_lists_the_names():
    with pytest.raises(KeyError, match="P1.*ex1"):
        get("mars")


def test_scene_is_a_frozen_value():
    sc = get("ex1")
    with pytest.raises(dataclasses.FrozenInstanceError):
        sc.y0 = (0.0, 0.0)
    assert hash(sc) == hash(dataclasses.replace(sc)) and sc == dataclasses.replace(sc)
    assert sc.y0 == (math.radians(30.0), 0.0) and isinstance(sc.y0, tuple)
    assert (sc.beta, sc.gamma, sc.omega, sc.theta0, sc.v0, sc.t_end) == sc.params()
    assert sc.model == mbm.Pendulum(0.1, 0.3)


def test_inputs_are_normalised_and_checked():
    sc = Scene("x", mbm.Pendulum(), [1, 0], [0, 5], aliases=["y"])
    assert sc.y0 == (1.0, 0.0) and sc.t_span == (0.0, 5.0) and sc.aliases == ("y",)
    with pytest.raises(TypeError, match="Pendulum"):
        Scene("x", (0.1, 0.0, 1.0), (0.0, 0.0), (0.0, 1.0))
    for y0 in ((0.0,), (0.0, math.nan), (1.0, 2.0, 3.0)):
        with pytest.raises(ValueError, match="y0"):
            Scene("x", mbm.Pendulum(), y0, (0.0, 1.0))
    for span in ((0.0, 0.0), (0.0, math.inf), (1.0,)):
        with pytest.raises(ValueError, match="t_span"):
            Scene("x", mbm.Pendulum(), (0.0, 0.0), span)


def test_output_times_and_other_horizons():
    sc = get("P1")
    t = sc.t_eval()
    np.testing.assert_array_equal(t, np.linspace(0.0, 20.0, mbm.scenes.N_OUTPUT))
    assert sc.t_eval() is not t  # a new array each time: a solver writing into it changes nothing
    t[:] = 0.0
    assert sc.t_eval()[-1] == 20.0 and sc.t_eval(5).tolist() == [0.0, 5.0, 10.0, 15.0, 20.0]
    with pytest.raises(ValueError):
        sc.t_eval(1)
    y = sc.y0_array
    y[0] = 9.0
    assert sc.y0 == (0.0, 0.25)
    short = get("running").until(200.0)
    assert short.t_span == (0.0, 200.0) and short.model == get("P5").model and short.name == "P5"
    assert get("P5").t_end == 1000.0  # the catalogue is unchanged


def test_cli_study_scenes_come_from_the_catalogue():
    assert cli_study.SCENES["ex1"] == get("ex1").params()
    assert cli_study.SCENES["running"] == get("running").until(200.0).params()
    assert cli_study.SCENES["free"] == (0.0, 0.0, 1.0, math.radians(135.0), 0.0, 40.0)


def test_run_study_accepts_a_scene():
    study = cli_study.run_study(get("paper1").until(5.0), ["taylor8"], taus=[0.5, 0.25],
                                show_progress=False)
    assert study["scene"] == (0.4, 0.0, 1.0, 0.0, 0.25, 5.0) and len(study["rows"]) == 2


def test_module_examples():
    failures, tried = doctest.testmod(mbm.scenes)
    assert tried > 0 and failures == 0


def test_benchmark_scenes_solve(benchmark_scene, scene_reference):
    # Every benchmark scene, over its first 20 time units, by mbm.solve at rtol 1e-9
    # against the shared reference (exact flow or CVODE at 1e-13).
    sc = benchmark_scene.until(20.0)
    t = sc.t_eval(41)
    sol = mbm.solve(sc.model, sc.t_span, sc.y0, rtol=1e-9, atol=1e-9, t_eval=t)
    assert sol.success
    assert np.max(np.abs(sol.y[0] - scene_reference(sc, t)[0])) < 1e-6


def test_shared_fixtures(example1, example2, scene_catalogue):
    assert example1 is scene_catalogue.get("P2") and example2 is scene_catalogue.get("P3")

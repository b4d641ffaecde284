"""The junction toolkit's messages in a user's words (issue 53, item 6)."""

import re

import pytest

import mbm
from mbm.validate import keywords_named


@pytest.mark.parametrize("call", [
    lambda: mbm.iv_curve(0.0, [0.1, 0.2]),
    lambda: mbm.shapiro_steps(0.0, (0.0, 1.0), amplitude=0.5, frequency=0.5),
    lambda: mbm.iv_curve(-0.1, [0.1]),
])
def test_one_beta_rule_wording(call):
    # The toolkit needs beta > 0 where Pendulum takes beta >= 0: the same words, the reason said.
    with pytest.raises(ValueError, match=re.escape("beta must be > 0 (damping: an I–V curve needs a damped "
                                                   "junction), got")):
        call()
    with pytest.raises(ValueError, match=re.escape("beta must be >= 0 (damping), got -0.1")):
        mbm.Pendulum(-0.1)


def test_positional_misuse_names_the_keywords():
    with pytest.raises(TypeError) as exc:
        mbm.shapiro_steps(0.5, (0, 1.5), 0.8, 0.5)
    msg = str(exc.value)
    assert "takes 2 positional argument(s) (beta, gamma_range) but 4 were given" in msg
    assert "amplitude=..., frequency=..." in msg
    with pytest.raises(TypeError, match=r"sweep\(\) takes 0 positional argument\(s\) \(none\) but 1 were given; "
                                        r"pass the others by keyword \(beta=\.\.\., \.\.\.\)"):
        mbm.sweep(0.1)
    with pytest.raises(TypeError, match=r"iv_curve\(\) takes 2 .*\(omega=\.\.\., current_tol=\.\.\., \.\.\.\)"):
        mbm.iv_curve(0.5, [0.1], 1.0, 1e-3)


def test_keywords_named_keeps_the_signature_and_the_call():
    def f(a, *, b=1, c=2):
        """doc"""
        return a + b + c

    g = keywords_named(f)
    assert g(1, c=5) == 7 and g.__doc__ == "doc" and g.__name__ == "f"
    import inspect
    assert str(inspect.signature(g)) == "(a, *, b=1, c=2)"
    with pytest.raises(TypeError, match="f\\(\\) takes 1 positional"):
        g(1, 2)
    # A keyword it does not take is Python's own error, unchanged.
    with pytest.raises(TypeError, match="unexpected keyword argument 'd'"):
        g(1, d=3)


def test_implausible_bias_warns():
    # gamma up to 50: a bias in µA by mistake; the warning names the reduced bias and the converter.
    with pytest.warns(RuntimeWarning, match=r"iv_curve: \|gamma\| reaches 50, 50 times the critical current "
                                            r"omega\*\*2 = 1: gamma is the reduced bias I/I_c .*mbm\.Junction"):
        with pytest.raises(TypeError, match="progress must be True or False"):
            # (the warning comes before the run; a bad progress stops it there)
            mbm.iv_curve(0.5, [10.0, 50.0], progress="yes")
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(TypeError, match="progress must be True or False"):
            mbm.iv_curve(0.5, [0.0, 2.0, 9.0], progress="yes")

"""A mistyped keyword argument names the closest one the function takes (issue 28), as the command line
names the closest flag."""

import inspect

import pytest

import geotex


@pytest.fixture(scope="module")
def cube():
    return geotex.generate("cube", level=0)


@pytest.mark.parametrize("call, typo, suggestion", [
    (lambda m, **k: geotex.denoise(m, **k), "sigmaa", "sigma"),            # through the method dispatcher
    (lambda m, **k: geotex.denoise(m, method="mrf", **k), "optimiser", "optimizer"),
    (lambda m, **k: geotex.smooth(m, **k), "lamda", "lambda_"),             # the keyword's trailing underscore aside
    (lambda m, **k: geotex.smooth(m, **k), "setps", "steps"),               # two letters swapped
    (lambda m, **k: geotex.add_noise(m, **k), "sigma_", "sigma"),
    (lambda m, **k: geotex.smooth(m, **k), "thread", "threads"),            # the call arguments too
])
def test_a_mistyped_keyword_names_the_closest_one(cube, call, typo, suggestion):
    with pytest.raises(TypeError) as e:
        call(cube, **{typo: 1})
    assert f"unexpected keyword argument '{typo}' (did you mean '{suggestion}'?)" in str(e.value)
    assert e.value.__cause__ is None and e.value.__suppress_context__  # one message, not a chained traceback


def test_a_keyword_far_from_every_name_gets_no_guess(cube):
    with pytest.raises(TypeError) as e:
        geotex.smooth(cube, zzzzzzzz=1)
    assert "unexpected keyword argument 'zzzzzzzz'" in str(e.value) and "did you mean" not in str(e.value)


def test_other_binding_errors_are_unchanged(cube):
    with pytest.raises(TypeError, match="too many positional arguments"):
        geotex.smooth(cube, None, 1, 2)


def test_every_suggestion_is_a_keyword_the_function_takes(cube):
    params = inspect.signature(geotex.denoise_auto).parameters
    with pytest.raises(TypeError) as e:
        geotex.denoise_auto(cube, label_angel=30)
    suggested = str(e.value).split("did you mean '")[1].split("'")[0]
    assert suggested in params

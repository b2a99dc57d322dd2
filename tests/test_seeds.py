"""workbench.seeds.check_seed, the one rule of a Monte-Carlo seed: what it accepts, what it
returns, and the fix each refusal names."""

import numpy as np
import pytest

from workbench.seeds import check_seed


def test_integers_and_generators_pass_and_draw_the_same_samples():
    assert check_seed(3) == 3 and type(check_seed(np.int64(3))) is int
    gen = np.random.default_rng(5)
    assert check_seed(gen) is gen
    # an int seed and a Generator made from it give one stream
    a = np.random.default_rng(check_seed(7)).normal(size=4)
    b = check_seed(np.random.default_rng(7)).normal(size=4)
    np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    ("seed", "match"),
    [
        (1.5, r"got 1.5 — pass an integer, e.g. seed=0"),
        (3.0, r"got 3.0 — pass seed=3"),
        (-1, r"seed must be an integer >= 0 or a numpy.random.Generator; got -1"),
        (True, r"got True"),
        ("abc", r"got 'abc'"),
        (None, r"got None"),
    ],
)
def test_anything_else_is_refused_naming_the_fix(seed, match):
    with pytest.raises(ValueError, match=match):
        check_seed(seed)


def test_where_every_call_must_draw_the_same_a_generator_is_refused():
    with pytest.raises(ValueError, match=r"rng must be an integer >= 0 here \(the same draw on every call\)"):
        check_seed(np.random.default_rng(0), "rng", generator=False)
    assert check_seed(4, generator=False) == 4

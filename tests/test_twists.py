"""Plücker conversions (Eqs. 2.21–2.30) and the seeded samplers."""

import numpy as np
import pytest

from workbench import (
    canonical_twists,
    plucker_from_twists,
    sample_twists_6dfc,
    sample_twists_thesis,
    translation_twists,
    twists_from_plucker,
)
from workbench.twists import fibonacci_sphere


def test_plucker_roundtrip(rng):
    e = rng.standard_normal((50, 3))
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    q = rng.standard_normal((50, 3))
    m = np.cross(q, e)
    h = rng.uniform(-2, 2, 50)
    xi = twists_from_plucker(e, m, h)
    np.testing.assert_allclose(np.linalg.norm(xi[:, 3:], axis=1), 1.0)
    e2, m2, h2, tr = plucker_from_twists(xi)
    assert not tr.any()
    np.testing.assert_allclose(e2, e, atol=1e-14)
    np.testing.assert_allclose(m2, m, atol=1e-13)
    np.testing.assert_allclose(h2, h, atol=1e-13)
    # scaling a twist changes neither the axis nor the pitch
    e3, m3, h3, _ = plucker_from_twists(3.7 * xi)
    np.testing.assert_allclose(h3, h, atol=1e-13)
    np.testing.assert_allclose(m3, m, atol=1e-13)


def test_velocity_of_axis_points_is_along_axis(rng):
    # a point q on the screw axis moves with v(q) = h e (Eqs. 2.24–2.27)
    e = np.array([[0.0, 0.6, 0.8]])
    q = np.array([[0.3, -0.1, 0.2]])
    xi = twists_from_plucker(e, np.cross(q, e), [0.5])[0]
    v_q = xi[:3] + np.cross(xi[3:], q[0])
    np.testing.assert_allclose(v_q, 0.5 * e[0], atol=1e-15)


def test_translations():
    xi = translation_twists([[0, 0, 2.0]])
    np.testing.assert_allclose(xi, [[0, 0, 1, 0, 0, 0]])
    e, m, h, tr = plucker_from_twists(xi)
    assert tr.all() and np.isinf(h).all()
    np.testing.assert_allclose(e, [[0, 0, 1.0]])


def test_plucker_rejects_inconsistent_moment():
    with pytest.raises(ValueError, match="e·m = 0"):
        twists_from_plucker([1.0, 0, 0], [1.0, 0, 0], 0.0)
    with pytest.raises(ValueError, match="zero row"):
        plucker_from_twists(np.zeros((1, 6)))


def test_fibonacci_sphere_is_unit_and_balanced():
    e = fibonacci_sphere(1000)
    np.testing.assert_allclose(np.linalg.norm(e, axis=1), 1.0, rtol=1e-14)
    assert np.abs(e.mean(axis=0)).max() < 2e-3


def test_thesis_sampler():
    ls = 0.04
    xi = sample_twists_thesis(200, ls, seed=1)
    assert xi.shape == (400, 6)
    e, m, h, tr = plucker_from_twists(xi)
    assert (~tr[:200]).all() and tr[200:].all()
    assert (np.abs(h[:200]) <= ls).all() and np.abs(h[:200]).max() > 0.9 * ls  # h ~ U[-1, 1] l_s
    # |m| = |q x e| <= |q| <= 0.25 l_s
    assert np.linalg.norm(m[:200], axis=1).max() <= 0.25 * ls + 1e-15
    np.testing.assert_allclose(e[:200], fibonacci_sphere(200), atol=1e-14)
    np.testing.assert_array_equal(xi, sample_twists_thesis(200, ls, seed=1))
    assert not np.array_equal(xi, sample_twists_thesis(200, ls, seed=2))
    assert sample_twists_thesis(10, ls, translations=False).shape == (10, 6)


def test_6dfc_sampler():
    xi = sample_twists_6dfc(30, 20, 0.1, seed=np.random.default_rng(3))
    assert xi.shape == (50, 6)
    e, m, h, tr = plucker_from_twists(xi)
    assert (~tr[:30]).all() and tr[30:].all()
    np.testing.assert_allclose(h[:30], 0.0, atol=1e-14)  # pure rotations
    assert np.linalg.norm(m[:30], axis=1).max() <= 0.025 + 1e-15
    with pytest.raises(ValueError, match="length_scale must be a positive length"):
        sample_twists_6dfc(3, 3, -1.0)


def test_canonical():
    np.testing.assert_array_equal(canonical_twists(), np.eye(6))


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: sample_twists_thesis(2.5, 0.01), r"n must be an integer >= 1 .*got 2.5"),
        (lambda: sample_twists_thesis("10", 0.01), r"n must be an integer >= 1 .*got '10'"),
        (lambda: sample_twists_thesis(True, 0.01), r"n must be an integer >= 1 .*got True"),
        (lambda: sample_twists_thesis(0, 0.01), r"n must be an integer >= 1 .*got 0"),
        (
            lambda: sample_twists_thesis(10, "0.01"),
            r"length_scale must be a positive length \[m\] \(a number\)",
        ),
        (lambda: sample_twists_6dfc(4.0, 2, 0.01), r"k1 must be an integer >= 0 .*got 4.0"),
        (lambda: sample_twists_6dfc(4, "2", 0.01), r"k2 must be an integer >= 0 .*got '2'"),
    ],
)
def test_samplers_refuse_counts_that_are_not_integers(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_numpy_integer_counts_are_counts():
    np.testing.assert_array_equal(
        sample_twists_thesis(np.int64(5), 0.01, 3), sample_twists_thesis(5, 0.01, 3)
    )

"""The author's twist grid ("thesis-code" protocol): its documented structure
and bad input.  The grid downsampling is tested in test_downsample.py."""

import naive
import numpy as np
import pytest

from workbench.twists import plucker_from_twists
from workbench.twists_author import AUTHOR_LEVELS, author_sphere, sample_twists_author

SIDES = np.array([0.012, 0.020, 0.0037])  # a contact's axis-aligned box [m]


def test_author_sphere_has_the_six_axes_and_is_spread():
    w = author_sphere(25)
    assert w.shape == (25, 3)
    np.testing.assert_allclose(np.linalg.norm(w, axis=1), 1.0)
    for a in np.vstack([np.eye(3), -np.eye(3)]):
        assert np.isclose(w @ a, 1.0).sum() == 1
    d = np.linalg.norm(w[:, None] - w[None], axis=2) + 10 * np.eye(25)
    assert d.min() > 0.3  # no two directions closer than ~17° (25 points: mean spacing ~41°)


def test_level0_grid_has_the_documented_structure():
    xi = sample_twists_author(SIDES, 0)
    lv = AUTHOR_LEVELS[0]
    n_d = 2 * 2 * len(lv.coeffs) + 1  # ±c·min, ±c·max and 0, all distinct for these sides
    n_axes = lv.n_axes * n_d**2 + lv.n_through
    n_pitch = 2 * len(lv.pitch_factors) + 1
    assert len(xi) == (n_axes + 36) * n_pitch == 48_483
    e, m, h, trans = plucker_from_twists(xi)
    assert trans.sum() == 36 * n_pitch  # the near-translations
    rot = ~trans
    # pitches {0, ±0.25 mean(L)}
    np.testing.assert_allclose(np.unique(np.round(h[rot] / SIDES.mean(), 12)), [-0.25, 0.0, 0.25])
    # axis points: q = e × m is the point of the axis nearest o; on the author's grid it is
    # the offset p ⊥ e itself, with its two grid coordinates at most 1.0 × the longest side
    q = np.cross(e[rot], m[rot])
    assert np.abs(np.einsum("ij,ij->i", q, e[rot])).max() < 1e-15
    k = np.argmax(np.abs(e[rot]), axis=1)
    others = np.abs(q).copy()
    others[np.arange(len(k)), k] = 0.0
    assert others.max() == pytest.approx(SIDES.max(), rel=1e-12)
    # axes through o: n_through plus the offset grid's (0, 0) per direction, per pitch;
    # the translations are along the ± axes and the face diagonals
    assert (np.linalg.norm(q, axis=1) < 1e-12).sum() == (lv.n_through + lv.n_axes) * n_pitch
    dirs = np.unique(np.round(e[trans], 12), axis=0)
    assert len(dirs) == 12 and set(np.round(np.abs(dirs).sum(axis=1) ** 2, 9)) == {1.0, 2.0}


def test_levels_and_bad_input():
    assert len(sample_twists_author(SIDES, -1)) == 10 + 36  # the parametric example's level
    with pytest.raises(ValueError, match="fine_level"):
        sample_twists_author(SIDES, 7)
    with pytest.raises(ValueError, match="box sides"):
        sample_twists_author([0.0, 0.0, 0.0])


def test_sides_in_millimetres_are_refused():
    with pytest.raises(ValueError, match="millimetres"):
        sample_twists_author([39.0, 19.0, 4.9])
    assert len(sample_twists_author([39.0, 19.0, 4.9], allow_scale=True)) == 48_483


@pytest.mark.parametrize("level", sorted(AUTHOR_LEVELS))
def test_the_compiled_grid_is_the_numpy_grid_bit_for_bit(level):
    """_kernels._author_grid against the NumPy expressions (naive.author_grid), every level, on
    boxes with three distinct sides, a flat one, a line and a cube: equal to the last bit."""
    rng = np.random.default_rng(level + 10)
    boxes = [rng.uniform(0.002, 0.06, 3), np.array([0.02, 0.04, 0.0]), np.array([0.0, 0.03, 0.0])]
    for L in [*boxes, np.full(3, 0.01)]:
        got = sample_twists_author(L, level)
        want = naive.author_grid(L, level)
        assert got.shape == want.shape
        np.testing.assert_array_equal(got, want)

"""workbench.limit_surface.linearize: inner vertices on the model, outer half-spaces around it,
the gap shrinking with M."""

import numpy as np
import pytest
from scipy.optimize import linprog

from workbench import fit_ellipsoid


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
@pytest.mark.parametrize("which", ["ellipsoid", "quartic"])
def test_inner_vertices_lie_on_the_model_and_outer_contains_it(which, s4_data, s4_quartic):
    model = fit_ellipsoid(s4_data[1]) if which == "ellipsoid" else s4_quartic
    inner = model.linearize(500, "inner")
    assert np.abs(model.value(inner.vertices) - 1).max() <= 1e-12
    outer = model.linearize(500, "outer", directions="sphere", seed=4)
    probe = model.linearize(3000, "inner", directions="sphere", seed=99).vertices
    assert outer.contains(probe, tol=1e-12).all()


def _support_ratio(model, M, dirs):
    inner = model.linearize(M, "inner", seed=5)
    outer = model.linearize(M, "outer", seed=5)
    ratios = []
    for u in dirs:
        res = linprog(-u, A_ub=outer.A, b_ub=outer.b, bounds=[(None, None)] * 6, method="highs")
        assert res.status == 0
        ratios.append(-res.fun / (inner.vertices @ u).max())
    return float(np.mean(ratios))


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_outer_inner_gap_shrinks_with_M(s4_data):
    model = fit_ellipsoid(s4_data[1])
    dirs = np.random.default_rng(6).standard_normal((30, 6)) * model.scale
    gaps = [_support_ratio(model, M, dirs) for M in (50, 200, 1000)]
    assert all(g >= 1.0 for g in gaps)
    assert gaps[0] > gaps[1] > gaps[2]


def test_sample_directions_lie_on_the_cube_or_the_sphere_and_cover_every_face():
    from workbench.limit_surface.linearize import sample_directions

    cube = sample_directions(6000, 6, "cube", seed=3)
    assert cube.shape == (6000, 6) and np.allclose(np.abs(cube).max(axis=1), 1.0, rtol=0, atol=0)
    # uniform over the 12 faces: each face holds 1/12 of 6000 = 500 points (binomial sd ~ 21)
    face = np.argmax(np.abs(cube), axis=1) * 2 + (cube[np.arange(6000), np.argmax(np.abs(cube), axis=1)] > 0)
    assert np.abs(np.bincount(face, minlength=12) - 500).max() < 5 * 21
    sphere = sample_directions(4000, 6, "sphere", seed=3)
    assert np.allclose(np.linalg.norm(sphere, axis=1), 1.0, rtol=1e-14)
    # isotropic: the second moment of a uniform unit 6-vector is I/6
    assert np.abs(sphere.T @ sphere / 4000 - np.eye(6) / 6).max() < 0.02
    assert np.array_equal(sample_directions(10, 6, seed=1), sample_directions(10, 6, seed=1))
    for bad, match in (((0, 6), "M must be"), ((5, 6, "ball"), "directions must be")):
        with pytest.raises(ValueError, match=match):
            sample_directions(*bad)

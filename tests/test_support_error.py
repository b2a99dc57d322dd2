"""The sampler-independent limit-surface error: exact cases and a
brute-force check of every step on a small contact.  The thesis-code wrench sets are
tested in test_thesis_code.py."""

import numpy as np
import pytest
from naive import fw_loop, fw_vectorized, random_profile

from workbench import ContactProfile, fit_ellipsoid, fit_quartic, frictional_wrenches
from workbench.limit_surface.support_error import SharedWrenches, support_error, uniform_normals
from workbench.twists import sample_twists_thesis


def _ellipsoid_support(A_n: np.ndarray, scale: np.ndarray, factor: float = 1.0):
    """Exact support points of {x̂ᵀ A_n x̂ <= factor²} for twists: the point with
    normalised outward normal d = −s ⊙ ξ is factor · A⁻¹d / sqrt(dᵀA⁻¹d)."""
    Ainv = np.linalg.inv(A_n)

    def wrenches_of(xi):
        d = -xi * scale
        y = d @ Ainv
        return factor * y / np.sqrt(np.einsum("ij,ij->i", y, d))[:, None] * scale

    return wrenches_of


@pytest.fixture
def ellipsoid_case(rng):
    G = rng.standard_normal((6, 6))
    A_n = G @ G.T + 6 * np.eye(6)
    scale = np.array([2.0, 3.0, 5.0, 0.02, 0.03, 0.01])  # forces [N], torques [N m]
    x = rng.standard_normal((400, 6))
    x /= np.sqrt(np.einsum("ij,jk,ik->i", x, A_n, x))[:, None]  # exactly on x̂ᵀ A_n x̂ = 1
    return A_n, scale, x * scale, scale * np.sqrt(np.diag(np.linalg.inv(A_n)))  # ..., exact w_max


def test_zero_for_an_exact_ellipsoid(ellipsoid_case):
    A_n, scale, W, wm = ellipsoid_case
    model = fit_ellipsoid(W, "lsq", w_max=wm)  # exact data: the fit is the ellipsoid itself
    err = support_error(model, _ellipsoid_support(A_n, scale), 3000, seed=3)
    assert err.dim == 6 and err.n_directions == 3000
    assert err.radial_max < 1e-9 and err.eq318_mean < 1e-9


def test_a_ten_percent_larger_set_is_a_ten_percent_radial_miss(ellipsoid_case):
    A_n, scale, W, wm = ellipsoid_case
    model = fit_ellipsoid(W, "lsq", w_max=wm)
    err = support_error(model, _ellipsoid_support(A_n, scale, factor=1.1), 500)
    np.testing.assert_allclose([err.radial_mean, err.radial_max], 0.1, rtol=1e-9)
    np.testing.assert_allclose(err.eq318_mean, 0.21, rtol=1e-9)  # |1.1² − 1|


def test_matches_a_brute_force_check_on_a_small_contact(rng):
    c, n, a, p = random_profile(rng, 40)
    prof = ContactProfile(c, n, a, p)
    xi = sample_twists_thesis(200, prof, seed=1)
    W = frictional_wrenches(prof, xi, 0.7)
    for model in (fit_ellipsoid(W, "lsq"), fit_quartic(W, twists=xi)):
        got = support_error(model, lambda t: frictional_wrenches(prof, t, 0.7), 60, seed=5)
        # brute force: the same directions, an explicit element loop for each wrench,
        # the model value by its own formula, and the support property checked
        d = uniform_normals(model, 60, seed=5)
        np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1.0)
        s = model.scale
        x_exact = np.array([fw_loop(c, n, a, p, -dk / s, 0.7) for dk in d]) / s
        others = fw_vectorized(c, n, a, p, rng.standard_normal((3000, 6)), 0.7) / s
        h = np.einsum("ij,ij->i", x_exact, d)  # support value in direction d
        assert (others @ d.T <= h[None, :] + 1e-9 * np.abs(h).max()).all()
        if model.degree == 2:
            f = np.einsum("ni,ij,nj->n", x_exact, model.A_e, x_exact)
        else:
            f = model.value(x_exact * s)
        r = np.abs(f ** (1 / model.degree) - 1)
        assert got.radial_mean == pytest.approx(r.mean(), rel=1e-9)
        assert got.radial_max == pytest.approx(r.max(), rel=1e-9)
        assert got.eq318_mean == pytest.approx(np.abs(f - 1).mean(), rel=1e-9)


def test_planar_contact_draws_normals_in_its_three_dimensions(rng):
    c = np.c_[rng.uniform(-0.01, 0.01, (50, 2)), np.zeros(50)]
    prof = ContactProfile(c, np.tile([0.0, 0, 1], (50, 1)), np.full(50, 1e-5), rng.uniform(1, 2, 50))
    xi = sample_twists_thesis(150, prof, seed=2)
    model = fit_ellipsoid(frictional_wrenches(prof, xi), "lsq")
    assert model.dim == 3
    d = uniform_normals(model, 100)
    assert np.abs(d[:, [2, 3, 4]]).max() < 1e-9  # f_z, τ_x, τ_y: not in a planar set
    err = support_error(model, lambda t: frictional_wrenches(prof, t), 500)
    assert err.dim == 3 and 0 < err.radial_mean < 0.1


def test_careless_input_is_refused(ellipsoid_case):
    A_n, scale, W, wm = ellipsoid_case
    model = fit_ellipsoid(W, "lsq", w_max=wm)
    with pytest.raises(ValueError, match="positive integer"):
        support_error(model, _ellipsoid_support(A_n, scale), 0)
    with pytest.raises(ValueError, match=r"\(K, 6\)"):
        support_error(model, lambda t: t[:, :3], 10)
    with pytest.raises(ValueError, match="positive integer"):
        support_error(model, _ellipsoid_support(A_n, scale), True)
    # the wrenches of another μ (here half): refused, not scored as a 50 % miss
    with pytest.raises(ValueError, match="w_max"):
        support_error(model, _ellipsoid_support(A_n, scale, factor=0.5), 500)


def test_shared_wrenches_computes_each_support_twist_set_once():
    """The models of one contact ask the support error's twists again: the second ask is the
    first's wrenches (the same bits, a fresh array); larger sets are computed every time."""
    rng = np.random.default_rng(3)
    prof = ContactProfile(
        0.01 * rng.normal(size=(40, 3)),
        np.tile([0.0, 0.0, 1.0], (40, 1)),
        np.full(40, 1e-4),
        rng.uniform(0.5, 1.5, 40),
    )
    calls = []

    def fn(xi):
        calls.append(len(xi))
        return frictional_wrenches(prof, xi, 0.5)

    shared = SharedWrenches(fn, 100)
    xi = rng.normal(size=(112, 6))
    first, second = shared(xi), shared(xi.copy())
    assert calls == [112] and shared.hits == 1
    assert np.array_equal(first, second) and first is not second
    first[:] = 0.0  # a caller's change does not reach the kept set
    assert np.array_equal(shared(xi), frictional_wrenches(prof, xi, 0.5))
    big = rng.normal(size=(113, 6))  # beyond the support error's 100 + 12 twists: not kept
    shared(big), shared(big)
    assert calls == [112, 113, 113] and shared.hits == 2

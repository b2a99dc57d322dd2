"""workbench.limit_surface.quartic: the SOS-convex quartic (Eqs. 3.13–3.17), its certificates,
gradients and Hessians, twists as normals, the reduced Gram fit and the solver fallback."""

import naive
import numpy as np
import pytest

from workbench import fit_ellipsoid, fit_quartic, frictional_wrenches, sample_twists_thesis
from workbench.limit_surface import is_sos_convex
from workbench.limit_surface import quartic as quart_mod
from workbench.limit_surface.quartic import _square_norm_squared
from workbench.limit_surface.sos import exponents


def test_sos_convexity_certificates():
    assert is_sos_convex(_square_norm_squared(6), 6)  # (xᵀx)² is SOS-convex
    expo = exponents(3, 4)
    nonconvex = np.zeros(len(expo))
    nonconvex[(expo == [4, 0, 0]).all(axis=1)] = 1.0
    nonconvex[(expo == [0, 4, 0]).all(axis=1)] = -1.0  # x1⁴ - x2⁴
    assert not is_sos_convex(nonconvex, 3)
    cross = np.where((expo == [2, 2, 0]).all(axis=1), 1.0, 0.0)  # x1² x2²: not convex
    assert not is_sos_convex(cross, 3)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_quartic_beats_ellipsoid_and_is_convex(s4_data, s4_quartic):
    _, train, test = s4_data
    q = s4_quartic
    e = fit_ellipsoid(train)
    assert q.fitting_error(test) < e.fitting_error(test)
    assert q.fitting_error(test) <= 0.02
    # Hessian PSD at 10,000 random points of the subspace (the model is homogeneous:
    # directions suffice, magnitudes only scale the Hessian)
    assert q.min_hessian_eigenvalue(10_000, seed=3) >= -1e-12
    assert q.info["certificate_delta"] >= 0
    # the fast quadratic-form Hessian against the slow per-monomial reference
    y = np.random.default_rng(4).standard_normal((50, q.dim))
    slow = np.einsum("njkl,l->njk", naive.monomial_hessians(y, exponents(q.dim, 4)), q.A_q)
    np.testing.assert_allclose(q.hessian_subspace(y), slow, rtol=1e-10, atol=1e-10 * np.abs(slow).max())


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_quartic_gradient_matches_finite_differences(s4_data, s4_quartic):
    q = s4_quartic
    w = s4_data[2][:4]
    h = 1e-6 * q.scale
    fd = np.array(
        [(q.value(w + np.diag(h)[j]) - q.value(w - np.diag(h)[j])) / (2 * h[j]) for j in range(6)]
    ).T
    np.testing.assert_allclose(q.gradient(w), fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


@pytest.mark.parametrize("r", [6, 3, 1])
def test_gradients_and_values_match_the_per_monomial_reference(r, rng):
    """The kernels behind values and gradients (one pass per block of points) against the
    gradient of Σ a_κ y^κ term by term and against the sum itself (and Euler's 4 f = y·∇f), on
    random coefficients (any quartic: convexity plays no part) and points of every sign and
    of magnitudes 1e-3 to 1e3; more points than a kernel block, and not a multiple of it."""
    from workbench.limit_surface._kernels import BLOCK

    expo = exponents(r, 4)
    a = rng.standard_normal(len(expo))
    q = quart_mod.QuarticLS(np.ones(6), np.ones(6), _subspace(r), {}, A_q=a, gram=np.eye(r * r))
    n = 2 * BLOCK + 37
    y = rng.standard_normal((n, r)) * 10.0 ** rng.uniform(-3, 3, (n, 1))
    terms = naive.monomial_gradients(y, expo) * a  # (n, r, L)
    # rounding bound of a sum: a few ulps of the sum of the terms' magnitudes
    bound = 1e-14 * np.abs(terms).sum(axis=2)
    np.testing.assert_array_less(np.abs(q._grad_sub(y) - terms.sum(axis=2)), bound + 1e-300)
    values = np.prod(y[:, None, :] ** expo[None], axis=2) * a  # (n, L)
    f = 0.25 * np.einsum("ij,ij->i", y, q._grad_sub(y))
    np.testing.assert_array_less(np.abs(f - values.sum(axis=1)), 1e-13 * np.abs(values).sum(axis=1))
    # the values' own kernel (the nested sum over sorted index tuples) against the same sum
    np.testing.assert_array_less(
        np.abs(q._values_sub(y) - values.sum(axis=1)), 1e-14 * np.abs(values).sum(axis=1) + 1e-300
    )
    x = np.zeros((n, 6))
    x[:, :r] = y  # nothing in the complement: the model's value is the kernel's
    np.testing.assert_array_equal(q._value_n(x), q._values_sub(y))


def _subspace(r):
    """The Subspace of the first r coordinate axes of 6D (the rest its complement)."""
    from workbench.limit_surface.normalize import Subspace

    eye = np.eye(6)
    return Subspace(basis=eye[:, :r], complement=eye[:, r:], std=np.ones(6))


def test_quartic_with_a_thin_direction_is_recovered_without_fallback(rng):
    """A known SOS-convex quartic whose level set is 100x thinner along one axis
    (as on near-planar FEM contacts): Clarabel solves it (whitened monomials) and
    recovers it on held-out points."""
    s = np.array([1.0, 0.8, 0.6, 0.3, 0.1, 0.01])

    def f(w):
        z = w / s
        return (z**4).sum(axis=1) + ((z**2).sum(axis=1)) ** 2

    def on_surface(n):
        u = rng.standard_normal((n, 6))
        return u * f(u)[:, None] ** -0.25

    W = on_surface(400)
    model = fit_quartic(W, w_max=np.abs(W).max(axis=0), fallback_solver=None)
    assert model.info["fallback"] is None and model.dim == 6
    W_test = on_surface(2000)
    assert np.abs(model.value(W_test) - 1).max() < 1e-4
    assert model.min_hessian_eigenvalue(2000) >= -1e-12


def _known_quartic():
    s = np.array([1.0, 0.8, 0.6, 0.3, 0.1, 0.05])

    def f(w):
        z = w / s
        return (z**4).sum(axis=1) + ((z**2).sum(axis=1)) ** 2

    def grad(w):
        z = w / s
        return (4 * z**3 + 4 * (z**2).sum(axis=1, keepdims=True) * z) / s

    return f, grad


def test_normal_rows_are_satisfied_by_the_true_quartic(rng):
    """The gradient rows are linear in the coefficients: the true quartic's
    coefficients (interpolated exactly from values) satisfy them to round-off."""
    f, grad = _known_quartic()
    expo = exponents(6, 4)
    u = rng.standard_normal((300, 6))
    z = u * f(u)[:, None] ** -0.25  # on f = 1
    a_true = np.linalg.lstsq(quart_mod.monomials(z, expo), f(z), rcond=None)[0]
    A, b = quart_mod._normal_rows(z, grad(z), expo, 1.0)
    assert A.shape == (6 * 300, 126)
    np.testing.assert_allclose(A @ a_true, b, atol=1e-9 * np.abs(b).max())
    # Euler: z·∇f = 4 on the surface, so the target is the true gradient itself
    np.testing.assert_allclose(b.reshape(6, -1).T * 4, grad(z), rtol=1e-12)


def test_quartic_with_normals_recovers_a_known_quartic_from_few_wrenches(rng):
    f, grad = _known_quartic()
    u = rng.standard_normal((130, 6))  # just above the 126 coefficients
    W = u * f(u)[:, None] ** -0.25
    twists = -grad(W)  # friction wrench minimises w·ξ: ξ is the inward normal
    model = fit_quartic(W, twists=twists, w_max=np.abs(W).max(axis=0), fallback_solver=None)
    v = rng.standard_normal((2000, 6))
    W_test = v * f(v)[:, None] ** -0.25
    assert np.abs(model.value(W_test) - 1).max() < 1e-4
    g = model.gradient(W)
    cos = np.einsum("ij,ij->i", g, -twists) / np.linalg.norm(g, axis=1) / np.linalg.norm(twists, axis=1)
    assert cos.min() > 1 - 1e-8
    assert model.info["normal_weight"] == pytest.approx(0.5 * np.sqrt(126 / 130))


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_normals_fix_the_quartic_at_small_k(s4_data):
    """K = 200 on S4: Eq. 3.17 on values alone overfits the 126 coefficients;
    the sampling twists as normals bring the quartic below the ellipsoid."""
    prof, _, test = s4_data
    xi = sample_twists_thesis(100, prof, seed=7)
    W = frictional_wrenches(prof, xi)
    values = fit_quartic(W).fitting_error(test)
    hermite = fit_quartic(W, twists=xi)
    ellipsoid = fit_ellipsoid(W, "sdp").fitting_error(test)
    assert hermite.fitting_error(test) < min(values, ellipsoid)
    assert hermite.min_hessian_eigenvalue(10_000, seed=3) >= -1e-12
    with pytest.raises(ValueError, match="not a friction twist"):
        fit_quartic(W, twists=-xi)  # sign flipped: w·ξ > 0
    with pytest.raises(ValueError, match="wrenches' shape"):
        fit_quartic(W, twists=xi[:-1])
    with pytest.raises(ValueError, match="normal_weight"):
        fit_quartic(W, twists=xi, normal_weight=-1.0)
    assert fit_quartic(W, twists=xi, normal_weight=0.0).fitting_error(test) == pytest.approx(values, rel=1e-6)


def test_reduced_gram_fit_is_the_full_gram_fit(rng):
    """The quartic fit with the swap-invariant Gram matrix (21 × 21 and 15 × 15 blocks)
    against Eq. 3.16 with the full 36 × 36 M, built here independently: the same
    optimal residual (to the solver's tolerance) and the same coefficients."""
    import cvxpy as cp

    from workbench.limit_surface.sos import monomials, sos_convexity_maps

    r = 6
    expo = exponents(r, 4)
    # points near a skewed, rotated ellipsoid: a fit the convexity constraint shapes
    z = rng.standard_normal((300, r)) * [1.0, 0.7, 1.3, 0.5, 1.1, 0.9]
    z /= np.linalg.norm(z, axis=1, keepdims=True) ** rng.uniform(0.8, 1.2, (300, 1))
    Q, Rm = np.linalg.qr(monomials(z, expo))
    c_val = Q.T @ np.ones(len(z))
    ok, a_red, M_red, _ = quart_mod._solve(r, "CLARABEL", Rm, c_val, warm_start=False)
    assert ok
    V1, V2 = sos_convexity_maps(r)
    a = cp.Variable(len(expo))
    M = cp.Variable((r * r, r * r), PSD=True)
    full = cp.Problem(cp.Minimize(cp.norm(Rm @ a - c_val, 2)), [V1 @ cp.vec(M, order="F") == V2 @ a])
    full.solve(solver="CLARABEL")
    res_red = np.linalg.norm(Rm @ a_red - c_val)
    assert res_red == pytest.approx(full.value, rel=1e-6)
    np.testing.assert_allclose(a_red, a.value, atol=1e-4 * np.abs(a.value).max())
    # the reduced M certifies a_red as the full one would: PSD and V1 vec(M) = V2 a
    assert np.linalg.eigvalsh(M_red).min() >= -1e-7 * np.abs(M_red).max()
    assert np.abs(V1 @ M_red.ravel(order="F") - V2 @ a_red).max() <= 1e-6 * np.abs(a_red).max()


@pytest.mark.parametrize("r", [1, 2, 3, 4, 5, 6])
def test_symmetric_block_is_fixed_by_the_coefficients_and_the_antisymmetric_block(r, rng):
    """The fit's elimination (``_reduced_maps``): for any coefficients a and antisymmetric
    block A, ``svec S = P a + Q svec A`` gives the Gram matrix M = T_sᵀ S T_s + T_aᵀ A T_a
    of Eq. 3.16, ``V1 vec(M) = V2 a`` (checked with the maps of :mod:`.sos`, not the solver's
    rows) — the equalities the solver no longer sees hold by construction."""
    from workbench.limit_surface.sos import sos_convexity_maps, swap_blocks

    V1, V2 = sos_convexity_maps(r)
    P, Q = quart_mod._reduced_maps(r)
    T_s, T_a = swap_blocks(r)
    a = rng.standard_normal(V2.shape[1])
    s_A = rng.standard_normal(len(T_a) * (len(T_a) + 1) // 2)
    s_S = P @ a + (Q @ s_A if len(T_a) else 0.0)
    M = T_s.T @ quart_mod._unsvec(s_S, len(T_s)) @ T_s
    if len(T_a):
        M = M + T_a.T @ quart_mod._unsvec(s_A, len(T_a)) @ T_a
    scale = np.abs(a).max() + np.abs(s_A).max(initial=0)
    assert np.abs(V1 @ M.ravel(order="F") - V2 @ a).max() <= 1e-12 * scale
    # and the symmetric block is the only one: another S with the same (a, A) breaks Eq. 3.16
    bump = np.zeros(len(s_S))
    bump[0] = 1.0
    M2 = M + T_s.T @ quart_mod._unsvec(bump, len(T_s)) @ T_s
    assert np.abs(V1 @ M2.ravel(order="F") - V2 @ a).max() > 0.1


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_a_clarabel_failure_falls_back_to_scs(s4_data, monkeypatch):
    """Clarabel is called directly; its errors are a recorded fallback, as cvxpy's were."""
    from dataclasses import replace

    from workbench import config

    monkeypatch.setattr(config, "DEFAULTS", replace(config.DEFAULTS, quartic_kkt_method="no-such-method"))
    q = fit_quartic(s4_data[1], solver="CLARABEL")
    assert q.info["solver"] == "SCS" and "CLARABEL" in q.info["fallback"]
    assert q.fitting_error(s4_data[2]) <= 0.02  # SCS's fit is a fit


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_repeated_wrenches_are_reported_underdetermined_and_careless_weights_refused(s4_data, caplog):
    """100 distinct wrenches given twice pass the 126-row count but fix only ~100
    coefficients: the fit says so (logged, info["underdetermined"]) instead of returning an
    overfit as if the data determined it; the S4 fit itself is determined.  A normal weight
    without twists is refused, and too few wrenches point to the regularised objective."""
    W = s4_data[1]
    assert fit_quartic(W).info["underdetermined"] is None
    with caplog.at_level("WARNING"):
        q = fit_quartic(np.vstack([W[:100], W[:100]]))
    assert "determine about" in q.info["underdetermined"] and "of the 126" in caplog.text
    determined = int(q.info["underdetermined"].split("about ")[1].split()[0])
    assert 90 <= determined <= 100  # the 100 distinct wrenches' rows, at most
    with pytest.raises(ValueError, match="no twists were given"):
        fit_quartic(W, normal_weight=1.0)
    with pytest.raises(ValueError, match="fit_author_objective"):
        fit_quartic(W[:100])


def test_a_fit_that_misses_its_own_wrenches_says_so(caplog):
    """A rank-4 wrench set with 3e-7 noise in its two other directions: points off the kept
    subspace by about TOL.flat_axis are charged the dropped directions' term, and the fit misses
    its own wrenches (a new-user trial: values up to 65, status optimal).  The fit now records
    its training error and warns; the noise-free set records ~0 and no warning."""
    import logging

    rng = np.random.default_rng(0)
    s4 = np.array([1.0, 0.1, 3.0, 0.03])
    U = rng.standard_normal((600, 4)) * s4
    U /= (((U / s4) ** 4).sum(1) + ((U / s4) ** 2).sum(1) ** 2)[:, None] ** 0.25
    Q = np.linalg.qr(rng.standard_normal((6, 4)))[0]
    null = np.linalg.svd(Q, full_matrices=True)[0][:, 4:]
    W = U @ Q.T + 3e-7 * rng.standard_normal((600, 2)) @ null.T
    with caplog.at_level(logging.WARNING, logger=quart_mod.__name__):
        q = fit_quartic(W)
    assert q.info["train_error"] > 0.1 and "misses its own training wrenches" in q.info["warning"]
    assert "misses its own training wrenches" in caplog.text
    clean = fit_quartic(U @ Q.T)
    assert clean.dim == 4 and clean.info["train_error"] < 1e-6 and "warning" not in clean.info

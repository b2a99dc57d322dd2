"""6D limit-surface models: ellipsoid (LSQ/SDP), SOS-convex quartic, linearisation,
contact-wrench model, 6DFC and the cache."""

import naive
import numpy as np
import pytest
from scipy.optimize import linprog

from workbench import (
    ContactProfile,
    fit_ellipsoid,
    fit_quartic,
    frictional_wrenches,
    mesh_profile,
    sample_twists_thesis,
)
from workbench.limit_surface import (
    LimitSurfaceCache,
    ModelSpec,
    SamplerSpec,
    is_sos_convex,
)
from workbench.limit_surface import ellipsoid as ell_mod
from workbench.limit_surface import quartic as quart_mod
from workbench.limit_surface.quartic import _square_norm_squared
from workbench.limit_surface.sos import exponents
from workbench.pressure import power_law
from workbench.sources.surface_catalog import S4


@pytest.fixture(scope="module")
def s4_data():
    prof = mesh_profile(S4, 800).normalized()
    train = frictional_wrenches(prof, sample_twists_thesis(300, prof, seed=1))
    test = frictional_wrenches(prof, sample_twists_thesis(2000, prof, seed=2))
    return prof, train, test


@pytest.fixture(scope="module")
def s4_quartic(s4_data):
    return fit_quartic(s4_data[1])


# ---------------------------------------------------------------- ellipsoid
def _rotated_ellipsoid_points(rng, n):
    scales = np.array([12.0, 3.0, 7.0, 0.02, 0.005, 0.04])  # N and N·m: mixed units
    R = np.linalg.qr(rng.standard_normal((6, 6)))[0]
    semi = rng.uniform(0.3, 1.0, 6)
    u = rng.standard_normal((n, 6))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    pts = ((u * semi) @ R.T) * scales  # on the ellipsoid by construction
    A_true = np.linalg.inv(np.diag(scales) @ R @ np.diag(semi**2) @ R.T @ np.diag(scales))
    return pts, A_true


def test_lsq_recovers_a_known_rotated_ellipsoid(rng):
    pts, A_true = _rotated_ellipsoid_points(rng, 400)
    model = fit_ellipsoid(pts, "lsq")
    fresh, _ = _rotated_ellipsoid_points(np.random.default_rng(12345), 1)  # same construction seed
    assert np.abs(model.value(pts) - 1).max() <= 1e-6
    np.testing.assert_allclose(model.A_raw, A_true, rtol=1e-6, atol=1e-9 * np.abs(A_true).max())
    assert model.info["fallback"] is None and model.dim == 6
    assert np.abs(model.value(fresh) - np.einsum("ni,ij,nj->n", fresh, A_true, fresh)).max() <= 1e-6


def test_sdp_close_to_exact_on_exact_data(rng):
    pts, _ = _rotated_ellipsoid_points(rng, 400)
    model = fit_ellipsoid(pts, "sdp")
    assert model.info["fallback"] is None
    assert np.abs(model.value(pts) - 1).max() <= 1e-4  # the -α log det term biases only slightly


def test_ellipsoid_models_are_pd_and_fit_surface_wrenches(s4_data):
    _, train, test = s4_data
    for method in ("lsq", "sdp"):
        m = fit_ellipsoid(train, method)
        assert np.linalg.eigvalsh(m.A_e).min() > 0
        assert m.fitting_error(test) <= 0.04  # thesis §3.6
        # gradient is the derivative of value
        w = test[:5]
        h = 1e-7 * m.scale
        fd = np.array(
            [(m.value(w + np.diag(h)[j]) - m.value(w - np.diag(h)[j])) / (2 * h[j]) for j in range(6)]
        ).T
        np.testing.assert_allclose(m.gradient(w), fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


# ---------------------------------------------------------------- quartic
def test_sos_convexity_certificates():
    assert is_sos_convex(_square_norm_squared(6), 6)  # (xᵀx)² is SOS-convex
    expo = exponents(3, 4)
    nonconvex = np.zeros(len(expo))
    nonconvex[(expo == [4, 0, 0]).all(axis=1)] = 1.0
    nonconvex[(expo == [0, 4, 0]).all(axis=1)] = -1.0  # x1⁴ - x2⁴
    assert not is_sos_convex(nonconvex, 3)
    cross = np.where((expo == [2, 2, 0]).all(axis=1), 1.0, 0.0)  # x1² x2²: not convex
    assert not is_sos_convex(cross, 3)


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


def test_radial_error_is_the_geometric_distance(s4_data, s4_quartic):
    # points at radius rho times the surface: radial error |rho - 1| for both degrees,
    # Eq. (3.18) |rho^d - 1|
    e = fit_ellipsoid(s4_data[1])
    for model in (e, s4_quartic):
        on = model.linearize(200, "inner", directions="sphere").vertices
        for rho in (0.9, 1.05):
            assert model.fitting_error(rho * on, "radial") == pytest.approx(abs(rho - 1), rel=1e-9)
            assert model.fitting_error(rho * on) == pytest.approx(abs(rho**model.degree - 1), rel=1e-9)
    with pytest.raises(ValueError, match="kind must be"):
        e.fitting_error(on, "nope")


def test_quartic_gradient_matches_finite_differences(s4_data, s4_quartic):
    q = s4_quartic
    w = s4_data[2][:4]
    h = 1e-6 * q.scale
    fd = np.array(
        [(q.value(w + np.diag(h)[j]) - q.value(w - np.diag(h)[j])) / (2 * h[j]) for j in range(6)]
    ).T
    np.testing.assert_allclose(q.gradient(w), fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


# ------------------------------------------------------------- planar contacts
def _disc(n_r=14, n_t=40, R=0.01):
    r = (np.arange(n_r) + 0.5) / n_r * R
    t = (np.arange(n_t) + 0.5) / n_t * 2 * np.pi
    rr, tt = np.meshgrid(r, t, indexing="ij")
    c = np.column_stack([(rr * np.cos(tt)).ravel(), (rr * np.sin(tt)).ravel(), np.zeros(rr.size)])
    a = (rr * (R / n_r) * (2 * np.pi / n_t)).ravel()
    return c, a, rr.ravel(), R


def _rect(nx=30, ny=12, lx=0.03, ly=0.012):
    x = ((np.arange(nx) + 0.5) / nx - 0.5) * lx
    y = ((np.arange(ny) + 0.5) / ny - 0.5) * ly
    xx, yy = np.meshgrid(x, y, indexing="ij")
    c = np.column_stack([xx.ravel(), yy.ravel(), np.zeros(xx.size)])
    r = np.hypot(xx, yy).ravel()
    return c, np.full(xx.size, lx * ly / (nx * ny)), r, r.max() * 1.0001


@pytest.mark.parametrize("shape", ["disc", "rect"])
@pytest.mark.parametrize("k", [np.inf, 2.0])
def test_planar_contacts_reduce_to_3d(shape, k):
    c, a, r, rmax = _disc() if shape == "disc" else _rect()
    p = 1e5 * power_law(r, rmax, k)
    prof = ContactProfile(c, np.tile([0, 0, 1.0], (len(c), 1)), a, p)
    mu = 0.6
    cache = LimitSurfaceCache()
    held_out = frictional_wrenches(prof, sample_twists_thesis(1000, prof, seed=9), mu)
    for spec in (ModelSpec("ellipsoid", "lsq"), ModelSpec("ellipsoid", "sdp"), ModelSpec("quartic")):
        m = cache.get(prof, mu, sampler=SamplerSpec(n=200), spec=spec)
        assert m.dim == 3, spec  # fitted in 3D, not 6D
        assert m.info["fallback"] is None, m.info
        # §2.3.5.3: f_x,max = f_y,max = μF, τ_z,max = μ Σ p a |r|
        np.testing.assert_allclose(m.w_max[:2], mu * prof.F, rtol=1e-3)
        r_o = np.linalg.norm(prof.centers - prof.pressure_center, axis=1)
        np.testing.assert_allclose(m.w_max[5], mu * (prof.forces * r_o).sum(), rtol=1e-3)
        np.testing.assert_allclose(m.w_max[2:5], 0.0, atol=1e-9 * mu * prof.F)
        # held-out fitting error (Eq. 3.18) within the thesis's 6D bounds
        assert m.fitting_error(held_out) <= (0.02 if spec.model == "quartic" else 0.04)


# ------------------------------------------------------------ linearisation
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


def test_outer_inner_gap_shrinks_with_M(s4_data):
    model = fit_ellipsoid(s4_data[1])
    dirs = np.random.default_rng(6).standard_normal((30, 6)) * model.scale
    gaps = [_support_ratio(model, M, dirs) for M in (50, 200, 1000)]
    assert all(g >= 1.0 for g in gaps)
    assert gaps[0] > gaps[1] > gaps[2]


# ------------------------------------------------------------------- cache
def test_cache_hits_rescale_and_skip_unneeded_work(tmp_path):
    prof = mesh_profile(S4, 300).with_pressures(np.full(len(mesh_profile(S4, 300)), 2e4))
    cache = LimitSurfaceCache(tmp_path)
    q_builds = quart_mod.BUILD_COUNT["quartic"]
    m1 = cache.get(prof, 0.5, sampler=SamplerSpec(n=150))
    assert cache.stats["sampling"] == 1 and cache.stats["solves"] == 1
    # same profile pair, 3x the force: no sampling, no solve, wrenches scale by 3
    m2 = cache.get(prof.with_pressures(prof.pressures * 3), 0.5, sampler=SamplerSpec(n=150))
    assert cache.stats["sampling"] == 1 and cache.stats["solves"] == 1 and cache.stats["hits"] == 1
    np.testing.assert_allclose(m2.w_max, 3 * m1.w_max, rtol=1e-12)
    w = m1.linearize(20).vertices
    np.testing.assert_allclose(m2.value(3 * w), m1.value(w), rtol=1e-12)
    # the ellipsoid never built the quartic problem
    assert quart_mod.BUILD_COUNT["quartic"] == q_builds
    # a different mu or sampler is a different key
    cache.get(prof, 0.4, sampler=SamplerSpec(n=150))
    assert cache.stats["solves"] == 2
    # persisted: a fresh cache on the same directory loads instead of solving
    fresh = LimitSurfaceCache(tmp_path)
    m3 = fresh.get(prof, 0.5, sampler=SamplerSpec(n=150))
    assert fresh.stats["disk_hits"] == 1 and fresh.stats["solves"] == 0
    np.testing.assert_allclose(m3.value(w), m1.value(w), rtol=1e-12)


# --------------------------------------------------------------- bad input
def test_bad_inputs():
    rng = np.random.default_rng(0)
    W = rng.standard_normal((30, 6))
    with pytest.raises(ValueError, match="21 unknowns but only 15 wrenches"):
        fit_ellipsoid(W[:15])
    with pytest.raises(ValueError, match="126 coefficients but only 30 wrenches"):
        fit_quartic(W)
    bad = W.copy()
    bad[3, 2] = np.nan
    with pytest.raises(ValueError, match="row 3 has NaN"):
        fit_ellipsoid(bad)
    with pytest.raises(ValueError, match="all zero"):
        fit_ellipsoid(np.zeros((30, 6)))
    with pytest.raises(ValueError, match=r"shape \(K, 6\)"):
        fit_ellipsoid(W[:, :5])
    with pytest.raises(ValueError, match="method must be"):
        fit_ellipsoid(W, "nope")
    with pytest.raises(ValueError, match="belongs to method='sdp'"):  # never silently ignored
        fit_ellipsoid(W, "lsq", alpha=1.0)


def test_an_unknown_solver_is_refused_and_a_failing_one_falls_back_or_raises(s4_data, monkeypatch):
    train = s4_data[1]
    # an unknown name is a mistake, not a solver failure: refused before any fit (it was
    # silently solved by the fallback), with or without the conic solve it would select
    for call in (
        lambda: fit_ellipsoid(train, "sdp", solver="NOT_A_SOLVER", alpha=1e-6 * len(train)),
        lambda: fit_ellipsoid(train, "sdp", solver="NOT_A_SOLVER"),
        lambda: fit_quartic(train, solver="NOT_A_SOLVER"),
    ):
        with pytest.raises(ValueError, match=r"solver must name a conic solver .*got 'NOT_A_SOLVER'"):
            call()
    with pytest.raises(ValueError, match=r"fallback_solver must name .*\['CLARABEL', 'SCS'.*got 'ECOS_X'"):
        fit_quartic(train, fallback_solver="ECOS_X")
    # without α the PD least-squares A is the SDP's optimum: no conic solve, and info
    # names the solver that ran (not the one asked for)
    direct = fit_ellipsoid(train, "sdp", solver="SCS")
    assert direct.info["fallback"] is None and direct.info["solver"] == "numpy.linalg.lstsq"
    # a solver that fails: the fallback answers (recorded), or RuntimeError without one
    monkeypatch.setattr(quart_mod, "_solve_clarabel", lambda r, Rm, c: (False, None, None, "NumericalError"))
    with pytest.raises(RuntimeError, match="CLARABEL: NumericalError"):
        fit_quartic(train, fallback_solver=None)
    q = fit_quartic(train)  # documented fallback to SCS
    assert q.info["solver"] == "SCS" and q.info["fallback"] == "CLARABEL: NumericalError; solved with SCS"


def test_sdp_problem_built_once_per_dimension(s4_data):
    train = s4_data[1]
    a = 1e-6 * len(train)  # with the log-det term: a conic solve every time
    fit_ellipsoid(train, "sdp", alpha=a)
    before = ell_mod.BUILD_COUNT["sdp"]
    fit_ellipsoid(train[::2], "sdp", alpha=a)
    fit_ellipsoid(train[1::2], "sdp", alpha=a)
    assert ell_mod.BUILD_COUNT["sdp"] == before


def test_psd_least_squares_is_least_squares_when_that_is_definite(s4_data):
    """α = 0: the constraint A ⪰ 0 is inactive at a PD least-squares optimum, so "sdp"
    returns it exactly; with α = 1e-6·K (Eq. 3.12) the conic solve lands within 1e-3."""
    train = s4_data[1]
    lsq = fit_ellipsoid(train, "lsq")
    np.testing.assert_array_equal(fit_ellipsoid(train, "sdp").A_e, lsq.A_e)
    pen = fit_ellipsoid(train, "sdp", alpha=1e-6 * len(train))
    B = lsq.subspace.basis
    a, b = B.T @ pen.A_e @ B, B.T @ lsq.A_e @ B
    assert np.abs(a - b).max() < 1e-3 * np.abs(b).max()


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


# ------------------------------------------------- quartic with twist normals
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


def test_normals_fix_the_quartic_at_small_k(s4_data):
    """K = 200 on S4: Eq. (3.17) on values alone overfits the 126 coefficients;
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


def test_mu_zero_is_named_when_a_limit_surface_is_asked_for(rng):
    from workbench.limit_surface.thesis_code import thesis_code_sample

    prof = ContactProfile(*naive.random_profile(rng, 40))
    with pytest.raises(ValueError, match="mu = 0 has no friction wrench"):
        LimitSurfaceCache().get(prof, 0.0)
    with pytest.raises(ValueError, match="mu = 0 has no friction wrench"):
        thesis_code_sample(prof, 0.0)
    # the wrenches themselves are fine at mu = 0 (all zero), only a fit is meaningless
    assert not frictional_wrenches(prof, np.eye(6), 0.0).any()


# ------------------------------------------------- swap-invariant Gram matrix
def test_swap_blocks_split_the_products_orthonormally():
    from workbench.limit_surface.sos import swap_blocks

    for n in (1, 3, 6):
        T_s, T_a = swap_blocks(n)
        assert T_s.shape == (n * (n + 1) // 2, n * n) and T_a.shape == (n * (n - 1) // 2, n * n)
        T = np.vstack([T_s, T_a])
        np.testing.assert_allclose(T @ T.T, np.eye(n * n), atol=1e-15)  # a complete orthonormal basis
        swap = np.arange(n * n).reshape(n, n).T.ravel()  # x_i z_j -> x_j z_i
        np.testing.assert_array_equal(T_s[:, swap], T_s)
        np.testing.assert_array_equal(T_a[:, swap], -T_a)


def test_hessian_biform_is_symmetric_in_its_arguments(rng):
    """zᵀ∇²f(x) z = xᵀ∇²f(z) x for any quartic: the fact the reduced Gram basis rests on
    (checked on the slow per-monomial Hessians of tests/naive.py)."""
    expo = exponents(6, 4)
    a = rng.standard_normal(len(expo))
    x, z = rng.standard_normal((2, 20, 6))
    H = [np.einsum("njkl,l->njk", naive.monomial_hessians(p, expo), a) for p in (x, z)]
    zHz = np.einsum("nj,njk,nk->n", z, H[0], z)
    xHx = np.einsum("nj,njk,nk->n", x, H[1], x)
    np.testing.assert_allclose(zHz, xHx, rtol=1e-11, atol=1e-11 * np.abs(zHz).max())


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


def test_a_clarabel_failure_falls_back_to_scs(s4_data, monkeypatch):
    """Clarabel is called directly; its errors are a recorded fallback, as cvxpy's were."""
    from dataclasses import replace

    from workbench import config

    monkeypatch.setattr(config, "DEFAULTS", replace(config.DEFAULTS, quartic_kkt_method="no-such-method"))
    q = fit_quartic(s4_data[1])
    assert q.info["solver"] == "SCS" and "CLARABEL" in q.info["fallback"]
    assert q.fitting_error(s4_data[2]) <= 0.02  # SCS's fit is a fit

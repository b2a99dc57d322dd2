"""workbench.limit_surface.ellipsoid: LSQ and SDP ellipsoids (Eqs. 3.11–3.12) on exact and sampled
wrenches, bad input, solver fallbacks, the SDP problem built once."""

import numpy as np
import pytest

from workbench import fit_ellipsoid, fit_quartic
from workbench.limit_surface import ellipsoid as ell_mod


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


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
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


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_an_unknown_solver_is_refused_and_a_failing_one_falls_back_or_raises(s4_data, monkeypatch):
    from workbench.limit_surface import quartic as quart_mod

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
        fit_quartic(train, solver="CLARABEL", fallback_solver=None)
    q = fit_quartic(train, solver="clarabel")  # documented fallback to SCS
    assert q.info["solver"] == "SCS" and q.info["fallback"] == "CLARABEL: NumericalError; solved with SCS"


def test_sdp_problem_built_once_per_dimension(s4_data):
    train = s4_data[1]
    a = 1e-6 * len(train)  # with the log-det term: a conic solve every time
    fit_ellipsoid(train, "sdp", alpha=a)
    before = ell_mod.BUILD_COUNT["sdp"]
    fit_ellipsoid(train[::2], "sdp", alpha=a)
    fit_ellipsoid(train[1::2], "sdp", alpha=a)
    assert ell_mod.BUILD_COUNT["sdp"] == before


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
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


def _saddle_wrenches(seed: int, neg: float, noise: float, n: int = 300) -> np.ndarray:
    """(2n, 6) raw wrenches, ± pairs, near ``Σ_{i<5} u_i² − neg u_5² = 1`` (radial noise of relative
    size ``noise``) in mixed units: a hyperboloid, so the least-squares A is indefinite and the
    PSD constraint is active."""
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n, 5))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    t = rng.uniform(-1.0, 1.0, n)
    pts = np.column_stack([u * np.sqrt(1.0 + neg * t**2)[:, None], t])
    pts *= (1.0 + noise * rng.standard_normal(n))[:, None] * np.array([12.0, 3.0, 7.0, 0.02, 0.005, 0.04])
    return np.vstack([pts, -pts])


def _psd_lsq_kkt(model, W):
    """(objective, optimality residuals) of Eq. 3.11 with A ⪰ 0 at the model's A, derived here:
    f(A) = Σ_k (y_kᵀ A y_k − 1)² on the model's normalised subspace coordinates y; at the optimum
    over the PSD cone the gradient G = 2 Σ_k (y_kᵀ A y_k − 1) y_k y_kᵀ is PSD and tr(G A) = 0.
    Returns (f, λ_min(G) / ‖G‖, tr(G A) / (‖G‖ ‖A‖))."""
    B = model.subspace.basis
    y = (W / model.scale) @ B
    A = B.T @ model.A_e @ B
    res = np.einsum("ni,ij,nj->n", y, A, y) - 1.0
    G = 2.0 * (y * res[:, None]).T @ y
    norm = np.linalg.norm(G)
    return float(res @ res), np.linalg.eigvalsh(G)[0] / norm, np.trace(G @ A) / (norm * np.linalg.norm(A))


@pytest.mark.parametrize("neg, noise", [(0.05, 0.05), (0.2, 0.0), (0.5, 0.05)])
def test_psd_least_squares_on_an_indefinite_sample_by_the_interior_point(neg, noise):
    """An indefinite least-squares A: the SDP's own interior point (the default) meets the
    optimality conditions of Eq. 3.11 with A ⪰ 0 derived independently (_psd_lsq_kkt), at an
    objective no higher than Clarabel's, on the cone's boundary and strictly inside it."""
    W = _saddle_wrenches(0, neg, noise)
    assert fit_ellipsoid(W, "lsq").info["fallback"].startswith("indefinite least-squares A")
    ipm = fit_ellipsoid(W, "sdp")
    assert (ipm.info["solver"], ipm.info["fallback"]) == ("IPM", None)
    f_ipm, g_min, comp = _psd_lsq_kkt(ipm, W)
    assert g_min >= -1e-9 and abs(comp) <= 1e-9
    clarabel = fit_ellipsoid(W, "sdp", solver="clarabel")
    assert (clarabel.info["solver"], clarabel.info["fallback"]) == ("CLARABEL", None)
    assert f_ipm <= _psd_lsq_kkt(clarabel, W)[0] * (1 + 1e-8)
    B = ipm.subspace.basis
    lam = np.linalg.eigvalsh(B.T @ ipm.A_e @ B)
    assert 0 < lam[0] <= 1e-6 * lam[-1]


def test_the_interior_point_where_clarabel_returns_a_singular_a(monkeypatch):
    """A sample on which Clarabel's iterate lands on the cone's boundary (A singular): its small
    eigenvalues are raised to the floor (recorded), which keeps the optimum — the projected least
    squares it fell back to before missed the optimality conditions (λ_min(G) = −0.13 ‖G‖) at a
    1.2 % higher objective.  The interior point meets them.  Its own failure falls back to
    Clarabel, recorded; Eq. 3.12's log-det term is Clarabel's by default and refused to a named
    IPM; solver names are read in any case, here and in config."""
    from workbench import config
    from workbench.limit_surface import sos_ipm

    W = _saddle_wrenches(0, 0.2, 0.05)
    clarabel = fit_ellipsoid(W, "sdp", solver="CLARABEL")
    assert clarabel.info["solver"] == "CLARABEL"
    assert clarabel.info["fallback"].startswith("SDP's A singular (the optimum on the cone's boundary)")
    f_c, g_c, comp_c = _psd_lsq_kkt(clarabel, W)
    ipm = fit_ellipsoid(W, "sdp")
    f_i, g_i, comp = _psd_lsq_kkt(ipm, W)
    assert g_i >= -1e-9 and abs(comp) <= 1e-9
    assert g_c >= -1e-6 and abs(comp_c) <= 1e-6 and abs(f_c / f_i - 1) <= 1e-7
    projected = fit_ellipsoid(W, "lsq")  # what the singular answer became before
    f_p, g_p, _ = _psd_lsq_kkt(projected, W)
    assert g_p < -0.1 and f_p > 1.01 * f_i
    failed = sos_ipm.SosFitResult(False, None, None, None, "no convergence in 2 iterations", 2)
    monkeypatch.setattr(sos_ipm, "solve", lambda Rm, c, blocks: failed)
    fell = fit_ellipsoid(W, "sdp")
    assert fell.info["solver"] == "CLARABEL"
    assert fell.info["fallback"].startswith(
        "IPM: no convergence in 2 iterations; fell back to CLARABEL; SDP's A singular"
    )
    np.testing.assert_array_equal(fell.A_e, clarabel.A_e)
    monkeypatch.undo()
    assert fit_ellipsoid(W, "sdp", alpha=1e-6 * len(W)).info["solver"] == "CLARABEL"
    with pytest.raises(ValueError, match=r"'IPM'\) solves Eq. 3.11 with A ⪰ 0 only.*solver='CLARABEL'"):
        fit_ellipsoid(W, "sdp", solver="ipm", alpha=1e-6 * len(W))
    with config.override(ellipsoid_solver="clarabel"):
        assert config.DEFAULTS.ellipsoid_solver == "CLARABEL"
        assert fit_ellipsoid(W, "sdp").info["solver"] == "CLARABEL"
    with pytest.raises(ValueError, match=r"solver must name a conic solver .*got 'bogus'"):
        fit_ellipsoid(W, "lsq", solver="bogus")  # checked whichever method, never ignored

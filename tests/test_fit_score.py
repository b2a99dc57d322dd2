"""Fit-and-score of the named 6DLS models (workbench.limit_surface.fit_score): exact
ellipsoidal wrench sets are fitted with ~0 error by every model, the scores agree with
slow NumPy loops, and the names are validated."""

import numpy as np
import pytest

from workbench import fit_quartic
from workbench.limit_surface.fit_score import (
    MODELS,
    Scoring,
    check_model,
    convexity,
    fit_and_score,
    fit_model,
    min_wrenches,
)


def _ellipsoid(rng, n: int, A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """n raw wrenches exactly on {wᵀ A w = 1} (n, 6) and their friction twists −A w (n, 6)
    (maximum dissipation: the twist opposes the outward normal 2 A w)."""
    C = np.linalg.inv(np.linalg.cholesky(A)).T  # Cᵀ A C = I
    u = rng.standard_normal((n, 6))
    W = (u / np.linalg.norm(u, axis=1, keepdims=True)) @ C.T
    return W, -W @ A


def _support_points(A: np.ndarray):
    """Exact support map of {wᵀ A w <= 1}: the point minimising ξ·w is −A⁻¹ξ / sqrt(ξᵀA⁻¹ξ)."""
    Ainv = np.linalg.inv(A)

    def wrenches_of(xi):
        y = xi @ Ainv
        return -y / np.sqrt(np.einsum("ij,ij->i", y, xi))[:, None]

    return wrenches_of


@pytest.fixture
def case(rng):
    G = rng.standard_normal((6, 6))
    S = np.diag(1.0 / np.array([2.0, 3.0, 5.0, 0.02, 0.03, 0.01]))  # forces [N], torques [N m]
    A = S @ (G @ G.T + 6 * np.eye(6)) @ S
    W, xi = _ellipsoid(rng, 300, A)
    W_test, _ = _ellipsoid(rng, 2000, A)
    wm = np.sqrt(np.diag(np.linalg.inv(A)))  # exact maxima: support values in ±e_i
    return A, W, xi, W_test, wm


def test_unknowns_are_the_coefficient_counts():
    assert min_wrenches("ellipsoid_lsq") == min_wrenches("ellipsoid_sdp") == 6 * 7 // 2
    assert min_wrenches("quartic_values") == min_wrenches("quartic_normals") == 126  # C(9, 5)


@pytest.mark.parametrize("model", sorted(MODELS))
def test_an_exact_ellipsoid_is_fitted_with_zero_error(case, model):
    A, W, xi, W_test, wm = case
    scoring = Scoring(W_test, wrenches_of=_support_points(A), support_directions=500)
    fs = fit_and_score(model, W, w_max=wm, twists=xi, scoring=scoring)
    # (wᵀ A w)² is an SOS-convex quartic, so every model contains the exact surface; the
    # ellipsoids are linear least squares (round-off), the quartics a conic solve (~1e-7)
    tol = 1e-9 if model.startswith("ellipsoid") else 1e-5
    assert fs.train_error < tol and fs.test_error < tol and fs.test_radial < tol
    assert fs.support.radial_max < tol and fs.support.n_directions == 500
    assert fs.fit_s > 0 and fs.fallback is None
    assert fs.model.degree == (2 if model.startswith("ellipsoid") else 4)


def test_scores_match_a_slow_numpy_loop(case, rng):
    """A model of a 10 % larger ellipsoid scored against the exact one: Eq. 3.18, the
    radial error and the support error recomputed point by point."""
    A, W, xi, W_test, wm = case
    A_big = A / 1.1**2
    W_big, _ = _ellipsoid(rng, 300, A_big)
    fs = fit_and_score(
        "ellipsoid_lsq",
        W_big,
        w_max=wm * 1.1,
        scoring=Scoring(W_test, wrenches_of=_support_points(A), support_directions=300, support_seed=7),
    )
    f = [float(w @ A_big @ w) for w in W_test]  # the fit is A_big itself (exact data)
    assert fs.test_error == pytest.approx(np.mean([abs(v - 1) for v in f]), rel=1e-7)
    assert fs.test_error == pytest.approx(1 - 1 / 1.21, rel=1e-7)  # every point at f = 1/1.1²
    assert fs.test_radial == pytest.approx(np.mean([abs(np.sqrt(v) - 1) for v in f]), rel=1e-7)
    # support error: uniform normals d (seed 7) of the normalised space, twists −d ⊘ scale,
    # the exact points there, their radial distance to the model
    scale = fs.model.scale
    u = np.random.default_rng(7).standard_normal((300, 6))
    radial = []
    for d in u / np.linalg.norm(u, axis=1, keepdims=True):
        w = _support_points(A)((-d / scale)[None])[0]
        radial.append(abs(np.sqrt(w @ A_big @ w) - 1))
    assert fs.support.radial_mean == pytest.approx(np.mean(radial), rel=1e-7)
    assert fs.support.radial_mean == pytest.approx(1 - 1 / 1.1, rel=1e-7)


def test_the_names_select_the_fitters(case):
    _, W, xi, _, wm = case
    values = fit_model("quartic_values", W, w_max=wm)
    normals = fit_model("quartic_normals", W, w_max=wm, twists=xi)
    np.testing.assert_allclose(values.A_q, fit_quartic(W, w_max=wm).A_q, atol=1e-12)
    np.testing.assert_allclose(normals.A_q, fit_quartic(W, twists=xi, w_max=wm).A_q, atol=1e-12)
    assert fit_model("ellipsoid_lsq", W, w_max=wm).info["method"] == "lsq"
    assert fit_model("ellipsoid_sdp", W, w_max=wm).info["method"] == "sdp"


def test_convexity_is_the_eigenvalue_ratio(case):
    A, W, _, _, wm = case
    fs = fit_and_score("ellipsoid_sdp", W, w_max=wm)
    S = np.diag(fs.model.scale)
    lam = np.linalg.eigvalsh(S @ A @ S)  # A_e of the exact ellipsoid in normalised coordinates
    assert convexity(fs.model) == pytest.approx(lam.min() / lam.max(), rel=1e-6)
    quartic = fit_model("quartic_values", W, w_max=wm)
    assert convexity(quartic, 2000) >= -1e-12  # certified SOS-convex


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"model": "quartic"}, "ambiguous"),
        ({"model": "sphere"}, "model must be one of"),
        ({"model": "quartic_normals"}, "pass twists"),
        ({"model": "ellipsoid_lsq", "alpha": 1.0}, "belongs to 'ellipsoid_sdp'"),
        ({"model": "ellipsoid_lsq", "repeats": 0}, "repeats must be an integer"),
        ({"model": "ellipsoid_lsq", "twists": np.ones((3, 6))}, "twists must have the wrenches' shape"),
        ({"model": "ellipsoid_lsq", "test": np.ones((3, 5))}, r"test must have shape \(K, 6\)"),
        ({"model": "ellipsoid_lsq", "wrenches_of": 3}, "wrenches_of must map"),
        ({"model": "ellipsoid_lsq", "wrenches_of": abs, "support_seed": -1}, "support_seed"),
        ({"model": "quartic_values", "solver": "NOPE"}, r"one of \['CLARABEL', 'SCS'.*got 'NOPE'"),
        ({"model": "ellipsoid_lsq", "solver": "NOPE"}, r"solver must name a conic solver .*got 'NOPE'"),
        ({"model": "ellipsoid_sdp", "solver": "OSQP"}, r"semidefinite support.*got 'OSQP'"),
    ],
)
def test_bad_input_is_refused(case, kwargs, match):
    _, W, _, _, wm = case
    args = {"w_max": wm, **kwargs}
    scored = {k: args.pop(k) for k in ("test", "wrenches_of", "support_seed") if k in args}
    with pytest.raises(ValueError, match=match):
        fit_and_score(args.pop("model"), W, scoring=Scoring(**scored), **args)


def test_a_solver_failure_falls_back_and_is_logged(case, monkeypatch, caplog):
    from workbench.limit_surface import quartic

    _, W, _, _, wm = case
    monkeypatch.setattr(quartic, "_solve_clarabel", lambda r, Rm, c: (False, None, None, "NumericalError"))
    with caplog.at_level("WARNING", logger="workbench.limit_surface.quartic"):
        fs = fit_and_score("quartic_values", W, w_max=wm, solver="CLARABEL")
    assert fs.fallback == "CLARABEL: NumericalError; solved with SCS" and fs.model.info["solver"] == "SCS"
    assert [r.levelname for r in caplog.records] == ["WARNING"]
    assert "CLARABEL: NumericalError; solved with SCS" in caplog.records[0].getMessage()
    assert fs.train_error < 1e-3  # SCS's answer on the exact ellipsoid


def test_an_sdp_failure_falls_back_to_least_squares_and_is_logged(case, monkeypatch, caplog):
    import cvxpy as cp

    def fail(*args, **kwargs):
        raise cp.error.SolverError("forced")

    _, W, _, _, wm = case
    monkeypatch.setattr(cp.Problem, "solve", fail)
    with caplog.at_level("WARNING", logger="workbench.limit_surface.ellipsoid"):
        fs = fit_and_score("ellipsoid_sdp", W, w_max=wm, alpha=1e-3)  # alpha > 0: the SDP runs
    assert fs.fallback.startswith("SDP with CLARABEL failed (SolverError: forced); used least squares")
    assert len(caplog.records) == 1 and "SolverError: forced" in caplog.records[0].getMessage()
    np.testing.assert_allclose(fs.model.A_e, fit_model("ellipsoid_lsq", W, w_max=wm).A_e, rtol=1e-12)


def test_check_model_returns_the_name():
    assert [check_model(m) for m in MODELS] == list(MODELS)

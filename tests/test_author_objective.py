"""The author's fitting objective (limit_surface/author_objective.py): exact recovery,
optimality against an independent evaluation of the objective, the twists' sign, the
regularised quartic below 126 wrenches, careless input."""

import numpy as np
import pytest

from workbench import fit_quartic
from workbench.limit_surface.author_objective import fit_author_objective


@pytest.fixture
def ellipsoid_data(rng):
    """Wrenches exactly on x̂ᵀ A x̂ = 1 and their friction twists: the outward normal is
    A x̂ and friction opposes motion, so ξ = −A x̂.  A is scaled so that diag(A⁻¹) = 1:
    the surface's exact w_max is 1 in every component (x̂ = w, as normalised data)."""
    G = rng.standard_normal((6, 6))
    A = G @ G.T + 6 * np.eye(6)
    d = np.sqrt(np.diag(np.linalg.inv(A)))
    A = A * d[:, None] * d[None, :]
    x = rng.standard_normal((300, 6))
    x /= np.sqrt(np.einsum("ij,jk,ik->i", x, A, x))[:, None]
    return A, x, -(x @ A)


def _objective(model, W, xi, weights):
    """Independent NumPy value of λ‖a‖ + ω_w Σ|f − 1| + ω_t Σ min_{s>=0} ‖g − s n‖ for an
    ellipsoid (g = A x̂); the inner minimum is sqrt(|g|² − max(g·n, 0)²) for unit n."""
    lam, ww, tw = weights
    A = model.A_e  # w_max = 1, full rank: the normalised coordinates are the raw ones
    f = np.einsum("ij,jk,ik->i", W, A, W)
    g = W @ A
    n = -xi / np.linalg.norm(xi, axis=1, keepdims=True)
    gn = np.maximum(np.einsum("ij,ij->i", g, n), 0.0)
    twist = np.sqrt(np.maximum(np.einsum("ij,ij->i", g, g) - gn**2, 0.0))
    return lam * np.linalg.norm(A) + ww * np.abs(f - 1).sum() + tw * twist.sum()


def test_exact_ellipsoid_is_recovered_without_the_regulariser(ellipsoid_data):
    A, W, xi = ellipsoid_data
    model = fit_author_objective(W, xi, "ellipsoid", w_max=np.ones(6), weights=(0, 10, 1))
    assert model.info["method"] == "author" and model.dim == 6
    np.testing.assert_allclose(model.A_e, A, rtol=1e-5, atol=1e-5 * np.abs(A).max())
    assert model.info["train_twist_residual_mean"] < 1e-5


def test_the_regularised_fit_minimises_the_stated_objective(ellipsoid_data, rng):
    A, W, xi = ellipsoid_data
    weights = (1.0, 10.0, 1.0)
    model = fit_author_objective(W, xi, "ellipsoid", w_max=np.ones(6), weights=weights)
    best = _objective(model, W, xi, weights)
    # the solver's own terms agree with the independent evaluation
    solver_terms = 10 * model.info["train_value_l1_mean"] * len(W) + model.info[
        "train_twist_residual_mean"
    ] * len(W)
    assert solver_terms + np.linalg.norm(model.A_e) == pytest.approx(best, rel=1e-5)
    # and no feasible point nearby (PSD perturbations, the truth itself) does better
    from dataclasses import replace

    for _ in range(20):
        D = rng.standard_normal((6, 6)) * 1e-3 * np.abs(A).max()
        cand = replace(model, A_e=model.A_e + D @ D.T * rng.choice([-1, 1]) * 0.5 + 1e-4 * (D + D.T))
        if np.linalg.eigvalsh(cand.A_e).min() > 0:
            assert _objective(cand, W, xi, weights) >= best * (1 - 1e-6)
    assert _objective(replace(model, A_e=A), W, xi, weights) >= best * (1 - 1e-6)
    # an L1 penalty is exact: with consistent data and ω_w = 10 the residuals vanish
    # despite the regulariser (a squared penalty would shrink A inside the data)
    assert model.fitting_error(W) < 1e-6


def test_the_twists_sign_is_checked(ellipsoid_data):
    """Twists of the right sign (friction opposes motion, w·ξ <= 0) fit with ~0 residual;
    the author's +ξ convention would fit a wrong surface (a trial measured a quartic 0.13
    off) and is refused."""
    A, W, xi = ellipsoid_data
    good = fit_author_objective(W, xi, "ellipsoid", w_max=np.ones(6), weights=(0, 10, 1))
    assert good.info["train_twist_residual_mean"] < 1e-5
    with pytest.raises(ValueError, match="not a friction twist"):
        fit_author_objective(W, -xi, "ellipsoid", w_max=np.ones(6))


def test_exact_quartic_is_recovered(ellipsoid_data, rng):
    """(x̂ᵀAx̂)² is SOS-convex with the same level set and normals as the ellipsoid; a
    homogeneous quartic equal to 1 on that quadric is it, so the fit is exact."""
    A, W, xi = ellipsoid_data
    model = fit_author_objective(W, xi, "quartic", w_max=np.ones(6), weights=(0, 10, 1))
    x = rng.standard_normal((500, 6))
    x /= np.sqrt(np.einsum("ij,jk,ik->i", x, A, x))[:, None]
    np.testing.assert_allclose(model.value(x), 1.0, atol=1e-4)
    assert model.min_hessian_eigenvalue() >= -1e-9  # certified convex


def test_regularised_quartic_fits_below_126_wrenches(ellipsoid_data, rng):
    A, W, xi = ellipsoid_data
    with pytest.raises(ValueError, match="126 coefficients"):
        fit_quartic(W[:80], w_max=np.ones(6))
    model = fit_author_objective(W[:80], xi[:80], "quartic", w_max=np.ones(6))
    x = rng.standard_normal((2000, 6))
    x /= np.sqrt(np.einsum("ij,jk,ik->i", x, A, x))[:, None]
    # 80 points and their normals pin the surface down away from them too (measured
    # 5e-10); without the twists the same 80 values leave it ~10 % off
    assert model.fitting_error(x) < 1e-6
    assert model.min_hessian_eigenvalue() >= -1e-9
    values_only = fit_author_objective(W[:80], xi[:80], "quartic", w_max=np.ones(6), weights=(1, 10, 0))
    assert values_only.fitting_error(x) > 0.01


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"model": "cubic"}, "model must be one of"),
        # the rule of config.DEFAULTS.author_fit_weights (the same for the config field)
        ({"weights": (1, 0, 1)}, r"weights \(λ, wrench weight, .* omega_w > 0; got \(1, 0, 1\)"),
        ({"weights": (1, 10)}, r"a tuple of 3 finite numbers"),
        ({"weights": (-1, 10, 1)}, r"finite numbers >= 0 .*got \(-1, 10, 1\)"),
        ({"weights": (True, 10, 1)}, r"got \(True, 10, 1\)"),
        ({"twists": "transposed"}, "twists must have the wrenches' shape"),
        ({"twists": "nan"}, "twist 3 is NaN/inf or zero"),
        ({"twists": "zero"}, "twist 3 is NaN/inf or zero"),
        ({"n": 5}, "5 wrenches span 5 dimensions: too few"),
        ({"w_max": 0.5}, "exceed the given w_max in component"),
    ],
)
def test_careless_input_is_refused(ellipsoid_data, kwargs, match):
    A, W, xi = ellipsoid_data
    n = kwargs.pop("n", 30)
    W, twists = W[:n], xi[:n].copy()
    how = kwargs.pop("twists", None)
    if how == "transposed":
        twists = twists.T
    elif how in ("nan", "zero"):
        twists[3] = np.nan if how == "nan" else 0.0
    kwargs["w_max"] = kwargs.get("w_max", 1.0) * np.ones(6)  # torques in N·mm would look like this
    with pytest.raises(ValueError, match=match):
        fit_author_objective(W, twists, **{"model": "ellipsoid", **kwargs})


@pytest.mark.parametrize("model", ["ellipsoid", "quartic"])
@pytest.mark.parametrize("weights", [(1.0, 10.0, 1.0), (1.0, 10.0, 0.0)])
def test_direct_clarabel_program_is_the_cvxpy_program(ellipsoid_data, rng, model, weights):
    """The program given to Clarabel by hand (svec variables, epigraph rows, Eq. 3.16's
    equalities) against cvxpy's statement of the same objective (its own cone forms,
    atoms and Gram blocks) on noisy data, where every term is active: the same optimal
    objective, evaluated here from each solution's coefficients (the L1 fits' minimisers
    need not be unique — with values only, two of 150 quartic values differed by 2e-4 at
    the same objective — so the coefficients are not compared)."""
    from workbench.limit_surface import author_objective as ao

    A, W, xi = ellipsoid_data
    W = W[:150] * (1 + 0.03 * rng.standard_normal((150, 1)))  # off the surface
    xi = xi[:150] + 0.1 * np.abs(xi).mean() * rng.standard_normal((150, 6))  # normals off too
    xi[np.einsum("ij,ij->i", W, xi) > 0] *= -1  # still friction twists
    wm, scale, sub, y, n = ao._problem(W, xi, None)

    def objective(sol):
        lam, ww, tw = weights
        coef = sol["A"] if model == "ellipsoid" else sol["a"]
        twist = np.linalg.norm(sol["g"] - sol["s"][:, None] * n, axis=1).sum() if tw else 0.0
        return lam * np.linalg.norm(coef) + ww * np.abs(sol["f"] - 1).sum() + tw * twist

    direct = ao._solve_clarabel(model, y, n, weights)
    ref = ao._solve_cvxpy(model, y, n, weights, "CLARABEL")
    assert direct["status"] == ref["status"] == "optimal"
    assert objective(direct) == pytest.approx(objective(ref), rel=1e-6)
    # the public function solves this program: the objective of the model it returns (the
    # quartic's certificate moves it off the optimum by its δ) is the direct solution's, and
    # its recorded terms add up to it
    info = fit_author_objective(W, xi, model, weights=weights).info
    lam, ww, tw = weights
    assert info["solver"] == "CLARABEL" and "warning" not in info
    assert info["objective"] == pytest.approx(objective(direct), rel=1e-6)
    terms = ww * info["train_value_l1_mean"] + tw * info["train_twist_residual_mean"]
    assert lam * info["regulariser"] + len(W) * terms == pytest.approx(info["objective"], rel=1e-12)


def test_a_fit_that_collapses_toward_zero_is_reported(ellipsoid_data, rng, caplog):
    """A large twist weight against the value weight buys a lower objective with a surface far
    outside every training wrench (the twist term rewards a small gradient): reported, not
    silent; and ω_w = 0 is refused by the config as by the fit."""
    from workbench import config

    A, W, xi = ellipsoid_data
    W = W[:150] * (1 + 0.03 * rng.standard_normal((150, 1)))
    xi = xi[:150] + 0.1 * np.abs(xi).mean() * rng.standard_normal((150, 6))
    xi[np.einsum("ij,ij->i", W, xi) > 0] *= -1
    with caplog.at_level("WARNING"):
        model = fit_author_objective(W, xi, "quartic", weights=(0.1, 1.0, 5.0))
    assert np.median(model.value(W)) < config.DEFAULTS.author_fit_collapse_below
    assert "collapsed toward f = 0" in model.info["warning"] and "collapsed" in caplog.text
    with pytest.raises(ValueError, match="omega_w > 0"):
        config.configure(author_fit_weights=(1.0, 0.0, 1.0))

"""The author's fitting objective for both 6DLS models (issue 12).

The thesis text fits limit surfaces by least squares on values (Eq. 3.11 with
Eq. 3.13 for the ellipsoid, Eq. 3.17 for the quartic).  The author's code
(``fitellipsoid6d.m``, ``fit4thorderpoly6d.m``, weights from ``exampleFEM.m``)
minimises instead, over normalised training wrenches ``x̂_k`` and their unit
normalised twists ``n_k``::

    λ ‖a‖ + ω_w Σ_k |f(x̂_k) − 1| + ω_t Σ_k ‖g(x̂_k) − s_k n_k‖,   s_k >= 0

with ``λ = 1``, ``ω_w = 10``, ``ω_t = 1``; ``‖a‖`` the Frobenius norm of
``A`` (ellipsoid) or the 2-norm of the 126 monomial coefficients (quartic);
``g = A x̂`` for the ellipsoid (half its gradient) and ``∇f`` for the quartic;
``A ⪰ 0`` or SOS-convexity (Eq. 3.15-3.16).  The L1 value residuals make it a
median-type fit of Eq. (3.18) itself, the twist terms ask the surface's normal
to point along the twist (maximum dissipation), and the regulariser keeps the
quartic determined with fewer wrenches than its 126 coefficients — the
thesis-code training sets often have (``results/fem-fitting``).

Reproduced as a *method*, here as one cvxpy problem per fit (the problem's size
depends on the number of training wrenches, so it is not cached).  Conventions:
the twists are scaled into normalised coordinates (``ξ ⊙ scale``) and unit
normalised as in ``normalizewrenchtwist.m``; our friction wrench opposes motion,
so the outward normal is ``−ξ`` (the author's sign convention has ``+ξ``; the
same geometry).  The fit runs in the normalised coordinates themselves when the
wrenches span all six dimensions (the regulariser is not rotation invariant for
the quartic, so no PCA rotation is applied) and in the PCA subspace otherwise.
The quartic's coefficients are certified convex like :func:`fit_quartic`'s.
"""

from __future__ import annotations

import time
import warnings
from typing import Any

import numpy as np

from .. import config
from .ellipsoid import EllipsoidLS, _embed
from .normalize import Subspace, check_twists, prepare
from .quartic import QuarticLS, _gram, _solver_options, _sos_convexity, certify
from .sos import exponents, monomials

MODELS = ("ellipsoid", "quartic")


def _gradient_design(y: np.ndarray, expo: np.ndarray) -> list[np.ndarray]:
    """r matrices (K, L): column κ of the j-th is ``∂_j y^{d_κ}`` at the K points."""
    out = []
    for j in range(y.shape[1]):
        d = expo[:, j]
        lowered = expo.copy()
        lowered[:, j] = np.maximum(d - 1, 0)
        out.append(monomials(y, lowered) * d)
    return out


def _check_weights(weights: Any) -> tuple[float, float, float]:
    try:
        lam, ww, tw = (float(v) for v in weights)
    except (TypeError, ValueError):
        raise ValueError(
            "weights must be three numbers (λ, wrench weight, twist weight), e.g. (1, 10, 1); "
            f"got {weights!r}"
        ) from None
    if not all(np.isfinite(v) and v >= 0 for v in (lam, ww, tw)) or ww == 0:
        raise ValueError(
            f"weights (λ, wrench weight, twist weight) must be finite, >= 0, with a positive wrench "
            f"weight; got {(lam, ww, tw)}"
        )
    return lam, ww, tw


def fit_author_objective(
    wrenches: Any,
    twists: Any,
    model: str = "ellipsoid",
    *,
    w_max: Any = None,
    weights: Any = None,
    solver: str = "CLARABEL",
) -> EllipsoidLS | QuarticLS:
    """Fit ``model`` ("ellipsoid" or "quartic") to raw wrenches (K, 6) and the
    twists (K, 6) ``[v; ω]`` they were computed from, with the author's objective
    (module docstring).

    w_max : optional exact (6,) maxima; default the sampled maxima.
    weights : (λ, ω_w, ω_t); default ``config.DEFAULTS.author_fit_weights`` = (1, 10, 1).
        ω_t = 0 fits values only (still L1 and regularised).
    Returns the same model classes as :func:`fit_ellipsoid` / :func:`fit_quartic`;
    ``info["method"] == "author"``, with the solver status and the objective's terms.
    Raises ``ValueError`` on malformed input, ``RuntimeError`` if the solver fails.
    """
    import cvxpy as cp

    t0 = time.perf_counter()
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}; got {model!r}")
    lam, ww, tw = _check_weights(config.DEFAULTS.author_fit_weights if weights is None else weights)
    W, wm, scale, x, sub = prepare(wrenches, w_max)
    xi = check_twists(W, twists, nonzero=True)  # every term of the objective needs a direction
    if sub.dim == 6:  # fit in the normalised coordinates themselves, as the author's code
        sub = Subspace(np.eye(6), np.zeros((6, 0)), sub.std)
    B, r = sub.basis, sub.dim
    y = x @ B
    n = -(xi * scale) @ B  # outward normals in the fit's coordinates (friction opposes motion)
    norm = np.linalg.norm(n, axis=1)
    keep = norm > 0  # a twist with no component in the subspace says nothing about the normal
    n[keep] /= norm[keep, None]
    K = len(y)

    s = cp.Variable(K, nonneg=True)  # free scale of each normal (the code's s_k >= eps)
    if model == "ellipsoid":
        A = cp.Variable((r, r), PSD=True)
        Y = cp.Constant(y)
        f = cp.sum(cp.multiply(Y @ A, Y), axis=1)
        g = Y @ A
        reg = cp.norm(A, "fro")
        cons = []
        L = r * (r + 1) // 2
    else:
        expo = exponents(r, 4)
        L = len(expo)
        a = cp.Variable(L)
        # SOS-convexity as fit_quartic states it: the swap-invariant Gram blocks (21 and 15
        # at r = 6 instead of one 36 x 36 cone; M enters only this constraint, so the
        # optimum is the same)
        blocks, sos_convex = _sos_convexity(r, a)
        f = monomials(y, expo) @ a
        g = cp.vstack([D @ a for D in _gradient_design(y, expo)]).T
        reg = cp.norm(a, 2)
        cons = [sos_convex]
    value_l1 = cp.sum(cp.abs(f - 1.0))
    twist_sum = cp.sum(cp.norm(g - cp.multiply(s[:, None], cp.Constant(n)), 2, axis=1))
    prob = cp.Problem(cp.Minimize(lam * reg + ww * value_l1 + (tw * twist_sum if tw > 0 else 0)), cons)
    try:
        with warnings.catch_warnings():  # "may be inaccurate": the status is recorded in info
            warnings.simplefilter("ignore", UserWarning)
            # the quartic with fit_quartic's Clarabel settings (KKT method, one thread); the
            # ellipsoid's small problem solved faster with Clarabel's defaults (measured)
            prob.solve(solver=solver, **(_solver_options(solver) if model == "quartic" else {}))
    except (cp.error.SolverError, ValueError) as exc:
        raise RuntimeError(f"author-objective {model} fit failed with {solver}: {exc}") from exc
    if prob.status not in ("optimal", "optimal_inaccurate"):
        raise RuntimeError(f"author-objective {model} fit: solver status {prob.status}")
    info = {
        "model": model,
        "method": "author",
        "solver": solver,
        "status": prob.status,
        "fallback": None if prob.status == "optimal" else "solved to reduced accuracy",
        "weights": (lam, ww, tw),
        "train_value_l1_mean": float(value_l1.value) / K,
        "train_twist_residual_mean": float(twist_sum.value) / K if tw > 0 else None,
        "dim": r,
        "n_wrenches": K,
        "n_coefficients": L,
    }
    if model == "ellipsoid":
        A_r = 0.5 * (A.value + A.value.T)
        lam_min = float(np.linalg.eigvalsh(A_r).min())
        if lam_min <= 0:  # a boundary optimum (a flat direction): lift it to PD, record it
            # shift the spectrum to 1e-12 (relative) above zero: positive definite, a round-off change
            A_r = A_r + (1e-12 * float(np.abs(A_r).max()) - lam_min) * np.eye(r)
            info["fallback"] = f"A had eigenvalue {lam_min:.2e}; lifted to positive definite"
        info["fit_time_s"] = time.perf_counter() - t0
        return EllipsoidLS(wm, scale, sub, info, A_e=_embed(A_r, sub))
    M = _gram(blocks)
    coeffs, delta = certify(np.asarray(a.value), M, r)
    info.update(certificate_delta=delta, whitening=np.ones(r), normal_weight=None)
    info["fit_time_s"] = time.perf_counter() - t0
    return QuarticLS(wm, scale, sub, info, A_q=coeffs, gram=M)


__all__ = ["MODELS", "fit_author_objective"]

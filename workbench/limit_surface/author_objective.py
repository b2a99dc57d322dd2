"""The author's fitting objective for both 6DLS models.

The thesis text fits limit surfaces by least squares on values (Eq. 3.11 with
Eq. 3.13 for the ellipsoid, Eq. 3.17 for the quartic).  The author's code
(``fitellipsoid6d.m``, ``fit4thorderpoly6d.m``, weights from ``exampleFEM.m``)
minimises instead, over normalised training wrenches ``x̂_k`` and their unit
normalised twists ``n_k``::

    λ ‖a‖ + ω_w Σ_k |f(x̂_k) − 1| + ω_t Σ_k ‖g(x̂_k) − s_k n_k‖,   s_k >= 0

with ``λ = 1``, ``ω_w = 10``, ``ω_t = 1``; ``‖a‖`` the Frobenius norm of
``A`` (ellipsoid) or the 2-norm of the 126 monomial coefficients (quartic);
``g = A x̂`` for the ellipsoid (half its gradient) and ``∇f`` for the quartic;
``A ⪰ 0`` or SOS-convexity (Eqs. 3.15–3.16).  The L1 value residuals make it a
median-type fit of Eq. 3.18 itself, the twist terms ask the surface's normal
to point along the twist (maximum dissipation), and the regulariser keeps the
quartic determined with fewer wrenches than its 126 coefficients — the
thesis-code training sets often have (``results/fem-fitting``).

Reproduced as a *method*, one conic program per fit, given to Clarabel directly (its size
depends on the number of training wrenches, so nothing is cached; another solver goes
through cvxpy).  Conventions:
the twists are scaled into normalised coordinates (``ξ ⊙ scale``) and unit
normalised as in ``normalizewrenchtwist.m``; our friction wrench opposes motion,
so the outward normal is ``−ξ`` (the author's sign convention has ``+ξ``; the
same geometry).  The fit runs in the normalised coordinates themselves when the
wrenches span all six dimensions (the regulariser is not rotation invariant for
the quartic, so no PCA rotation is applied) and in the PCA subspace otherwise.
The quartic's coefficients are certified convex like :func:`fit_quartic`'s.
"""

from __future__ import annotations

import logging
import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from .. import config
from .ellipsoid import EllipsoidLS, _embed
from .normalize import Subspace, check_twists, prepare
from .quartic import (
    QuarticLS,
    _clarabel_data,
    _clarabel_settings,
    _gram,
    _solver_options,
    _sos_convexity,
    _unsvec,
    certify,
)
from .sdp_solver import check_sdp_solver
from .sos import exponents, monomials, swap_blocks
from .sos import svec_index as _svec_index

MODELS = ("ellipsoid", "quartic")
log = logging.getLogger(__name__)


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
    """(λ, ω_w, ω_t) by the rule of ``config.DEFAULTS.author_fit_weights`` (one rule for both)."""
    return config.check_value("author_fit_weights", weights, "weights (λ, wrench weight, twist weight)")


def _problem(wrenches: Any, twists: Any, w_max: Any):
    """The fit's data: (w_max (6,), scale (6,), subspace, y (K, r) normalised wrenches in the
    fit's coordinates, n (K, r) unit outward normals there) — module docstring."""
    W, wm, scale, x, sub = prepare(wrenches, w_max)
    xi = check_twists(W, twists, nonzero=True)  # every term of the objective needs a direction
    if sub.dim == 6:  # fit in the normalised coordinates themselves, as the author's code
        sub = Subspace(np.eye(6), np.zeros((6, 0)), sub.std)
    B = sub.basis
    y = x @ B
    n = -(xi * scale) @ B  # outward normals in the fit's coordinates (friction opposes motion)
    norm = np.linalg.norm(n, axis=1)
    keep = norm > 0  # a twist with no component in the subspace says nothing about the normal
    n[keep] /= norm[keep, None]
    return wm, scale, sub, y, n


def _ellipsoid_maps(y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Value map Φ (K, m) and half-gradient maps G (K, r, m) of ``f = yᵀ A y`` and
    ``g = A y`` in Clarabel's svec of A (m = r(r+1)/2; off-diagonal entries times √2, so
    ``‖svec A‖ = ‖A‖_F``, the author's regulariser)."""
    K, r = y.shape
    i, j = _svec_index(r)
    off = i != j
    Phi = np.where(off, np.sqrt(2.0), 1.0) * y[:, i] * y[:, j]
    G = np.zeros((K, r, len(i)))
    cols = np.arange(len(i))
    w = np.where(off, 1.0 / np.sqrt(2.0), 1.0)
    G[:, i, cols] += w * y[:, j]  # (A y)_i gets A_ij y_j ...
    G[:, j[off], cols[off]] += w[off] * y[:, i[off]]  # ... and (A y)_j gets A_ij y_i
    return Phi, G


def _solve_clarabel(model: str, y: np.ndarray, n: np.ndarray, weights: tuple) -> dict:
    """The author's objective straight in Clarabel (cvxpy would compile it anew for every fit,
    its size changing with every training set, on top of cvxpy's slow import):
    ``min λ t + ω_w Σ u + ω_t Σ v`` over ``[c, (svec S, svec A), t, u, s, v]`` with
    ``‖c‖ <= t``, ``|Φ c − 1| <= u``, ``s >= 0``, ``‖G_k c − s_k n_k‖ <= v_k`` (the twist
    terms only when ω_t > 0) and ``c`` PSD (ellipsoid: c = svec A) or SOS-convex (quartic:
    Eq. 3.16 with the Gram blocks S, A PSD, :func:`.quartic._clarabel_data`).  Returns the
    values f (K,), gradients g (K, r) and twist scales s (K,) at the solution, the status,
    and ``A`` (ellipsoid) or the coefficients ``a`` and Gram matrix ``M`` (quartic)."""
    import clarabel

    lam, ww, tw = weights
    lay = _Layout.of(model, y, tw > 0)
    blocks, rhs, cones = [], [], []
    _value_rows(lay, blocks, rhs, cones)
    _norm_rows(lay, blocks, rhs, cones)
    if lay.twist:
        _twist_cones(lay, n, blocks, rhs, cones)
    _convexity_rows(lay, blocks, rhs, cones)
    K = lay.K
    q = np.zeros(lay.n_x)
    q[lay.o_t] = lam
    q[lay.o_u : lay.o_u + K] = ww
    q[lay.o_v : lay.o_v + lay.nK] = tw
    if model == "quartic":  # fit_quartic's KKT settings; the ellipsoid's defaults (measured)
        settings = _clarabel_settings()
    else:
        settings = clarabel.DefaultSettings()
        settings.verbose = False
    A = sp.vstack(blocks).tocsc()
    try:
        sol = clarabel.DefaultSolver(
            sp.csc_matrix((lay.n_x, lay.n_x)), q, A, np.concatenate(rhs), cones, settings
        ).solve()
    except Exception as exc:  # noqa: BLE001 - Clarabel's errors (e.g. a failed factorisation)
        raise RuntimeError(f"author-objective {model} fit failed with CLARABEL: {exc}") from exc
    status = str(sol.status)
    if status not in ("Solved", "AlmostSolved"):
        raise RuntimeError(f"author-objective {model} fit: solver status {status}")
    return _clarabel_solution(
        lay, np.asarray(sol.x), "optimal" if status == "Solved" else "optimal_inaccurate"
    )


@dataclass(frozen=True)
class _Layout:
    """The maps and the column layout of :func:`_solve_clarabel`'s program: variables
    ``[c, (svec S, svec A), t, u, s, v]``."""

    model: str
    K: int  # training wrenches
    r: int  # fit dimension
    Phi: np.ndarray  # (K, nc) value map
    G: np.ndarray  # (K, r, nc) (half-)gradient maps
    nc: int  # coefficients c
    n_gram: int  # the quartic's svec S and svec A (0: ellipsoid)
    Z: Any  # the quartic's Eq. 3.16 rows (:func:`.quartic._clarabel_data`), None for the ellipsoid
    nS: int  # svec S entries
    nA: int  # svec A entries
    twist: bool  # the twist terms are in (ω_t > 0)

    @classmethod
    def of(cls, model: str, y: np.ndarray, twist: bool) -> _Layout:
        K, r = y.shape
        if model == "ellipsoid":
            Phi, G = _ellipsoid_maps(y)
            return cls(model, K, r, Phi, G, Phi.shape[1], 0, None, 0, 0, twist)
        expo = exponents(r, 4)
        Phi = monomials(y, expo)
        G = np.stack(_gradient_design(y, expo), axis=1)  # (K, r, L)
        # Eq. 3.16 as equalities over both Gram blocks (fit_quartic's elimination of the
        # symmetric block made this program's KKT system denser and its fit slower:
        # docs/decisions.md)
        Z, nc, nS, nA = _clarabel_data(r)
        return cls(model, K, r, Phi, G, nc, nS + nA, Z, nS, nA, twist)

    @property
    def nK(self) -> int:
        """Twist scales s and slacks v: K each with the twist terms, else none."""
        return self.K if self.twist else 0

    # column offsets: c, the quartic's svec S and svec A, t, u, s, v
    @property
    def o_t(self) -> int:
        return self.nc + self.n_gram

    @property
    def o_u(self) -> int:
        return self.o_t + 1

    @property
    def o_s(self) -> int:
        return self.o_u + self.K

    @property
    def o_v(self) -> int:
        return self.o_s + self.nK

    @property
    def n_x(self) -> int:
        return self.o_v + self.nK


def _value_rows(lay: _Layout, blocks: list, rhs: list, cones: list) -> None:
    """L1 value rows: Φ c − u <= 1 and −Φ c − u <= −1; and s >= 0 (one nonnegative cone)."""
    import clarabel

    K, n_x, nc = lay.K, lay.n_x, lay.nc
    ik = np.arange(K)
    E_u = sp.csc_matrix((-np.ones(K), (ik, lay.o_u + ik)), shape=(K, n_x))
    F = sp.hstack([sp.csc_matrix(lay.Phi), sp.csc_matrix((K, n_x - nc))])
    blocks += [F + E_u, -F + E_u]
    rhs += [np.ones(K), -np.ones(K)]
    if lay.twist:
        blocks.append(sp.csc_matrix((-np.ones(K), (ik, lay.o_s + ik)), shape=(K, n_x)))
        rhs.append(np.zeros(K))
    cones.append(clarabel.NonnegativeConeT(sum(len(b) for b in rhs)))


def _norm_rows(lay: _Layout, blocks: list, rhs: list, cones: list) -> None:
    """‖c‖ <= t: the slack (t, c)."""
    import clarabel

    n_x, nc = lay.n_x, lay.nc
    blocks.append(
        sp.vstack(
            [
                sp.csc_matrix(([-1.0], ([0], [lay.o_t])), shape=(1, n_x)),
                sp.hstack([-sp.identity(nc), sp.csc_matrix((nc, n_x - nc))]),
            ]
        )
    )
    rhs.append(np.zeros(nc + 1))
    cones.append(clarabel.SecondOrderConeT(nc + 1))


def _twist_cones(lay: _Layout, n: np.ndarray, blocks: list, rhs: list, cones: list) -> None:
    """Per wrench the slack (v_k, G_k c − s_k n_k) in a second-order cone: rows k (r + 1) ..
    k (r + 1) + r."""
    import clarabel

    K, r, G = lay.K, lay.r, lay.G
    ik = np.arange(K)
    rows = np.arange(K)[:, None] * (r + 1) + 1 + np.arange(r)[None, :]  # (K, r)
    g_k, g_r, g_c = np.nonzero(G)
    parts = [
        (-np.ones(K), ik * (r + 1), lay.o_v + ik),
        (-G[g_k, g_r, g_c], rows[g_k, g_r], g_c),
        (n.ravel(), rows.ravel(), np.repeat(lay.o_s + ik, r)),
    ]
    data, ri, ci = (np.concatenate(z) for z in zip(*parts, strict=True))
    blocks.append(sp.csc_matrix((data, (ri, ci)), shape=(K * (r + 1), lay.n_x)))
    rhs.append(np.zeros(K * (r + 1)))
    cones += [clarabel.SecondOrderConeT(r + 1)] * K


def _convexity_rows(lay: _Layout, blocks: list, rhs: list, cones: list) -> None:
    """The ellipsoid's c in a PSD triangle, or the quartic's Eq. 3.16, ``Z [a; τ; svec S;
    svec A] = 0`` without its (empty) τ column, with S, A in PSD triangles."""
    import clarabel

    n_x, nc, n_gram, r = lay.n_x, lay.nc, lay.n_gram, lay.r
    if lay.model == "ellipsoid":
        blocks.append(sp.hstack([-sp.identity(nc), sp.csc_matrix((nc, n_x - nc))]))
        rhs.append(np.zeros(nc))
        cones.append(clarabel.PSDTriangleConeT(r))
        return
    Z = lay.Z
    blocks.append(sp.hstack([Z[:, :nc], Z[:, nc + 1 :], sp.csc_matrix((Z.shape[0], n_x - nc - n_gram))]))
    rhs.append(np.zeros(Z.shape[0]))
    cones.append(clarabel.ZeroConeT(Z.shape[0]))
    blocks.append(
        sp.hstack(
            [
                sp.csc_matrix((n_gram, nc)),
                -sp.identity(n_gram),
                sp.csc_matrix((n_gram, n_x - nc - n_gram)),
            ]
        )
    )
    rhs.append(np.zeros(n_gram))
    cones += [clarabel.PSDTriangleConeT(len(T)) for T in swap_blocks(r) if len(T)]


def _clarabel_solution(lay: _Layout, xs: np.ndarray, status: str) -> dict:
    """:func:`_solve_clarabel`'s answer from the solver's ``xs`` (n_x,)."""
    nc, nS, nA, r = lay.nc, lay.nS, lay.nA, lay.r
    c = xs[:nc]
    out = {"status": status, "f": lay.Phi @ c}
    out["g"] = np.einsum("krm,m->kr", lay.G, c)
    out["s"] = xs[lay.o_s : lay.o_s + lay.nK] if lay.twist else None
    if lay.model == "ellipsoid":
        out["A"] = _unsvec(c, r)
        return out
    s_S, s_A = xs[nc : nc + nS], xs[nc + nS : nc + nS + nA]
    T_s, T_a = swap_blocks(r)
    M = T_s.T @ _unsvec(s_S, len(T_s)) @ T_s
    if nA:
        M += T_a.T @ _unsvec(s_A, len(T_a)) @ T_a
    out.update(a=c, M=M)
    return out


def _solve_cvxpy(model: str, y: np.ndarray, n: np.ndarray, weights: tuple, solver: str) -> dict:
    """The same program through cvxpy, for the other conic solvers (and, in the tests, an
    independent statement of it: the full Eq. 3.16 equalities, cvxpy's own cone forms)."""
    import cvxpy as cp

    lam, ww, tw = weights
    K, r = y.shape
    s = cp.Variable(K, nonneg=True)  # free scale of each normal (the code's s_k >= eps)
    if model == "ellipsoid":
        A = cp.Variable((r, r), PSD=True)
        Y = cp.Constant(y)
        f = cp.sum(cp.multiply(Y @ A, Y), axis=1)
        g = Y @ A
        reg = cp.norm(A, "fro")
        cons = []
    else:
        expo = exponents(r, 4)
        a = cp.Variable(len(expo))
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
            prob.solve(solver=solver, **(_solver_options(solver) if model == "quartic" else {}))
    except (cp.error.SolverError, ValueError) as exc:
        raise RuntimeError(f"author-objective {model} fit failed with {solver}: {exc}") from exc
    if prob.status not in ("optimal", "optimal_inaccurate"):
        raise RuntimeError(f"author-objective {model} fit: solver status {prob.status}")
    out = {"status": prob.status, "f": np.asarray(f.value), "g": np.asarray(g.value)}
    out["s"] = np.asarray(s.value) if tw > 0 else None
    if model == "ellipsoid":
        out["A"] = 0.5 * (A.value + A.value.T)
    else:
        out.update(a=np.asarray(a.value), M=_gram(blocks))
    return out


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
    solver : "CLARABEL" (called directly, no cvxpy) or another cvxpy conic solver with SDP
        support ("SCS").
    Returns the same model classes as :func:`fit_ellipsoid` / :func:`fit_quartic`;
    ``info["method"] == "author"``, with the solver status and the objective's terms of the
    returned model (:func:`_terms`: ``train_value_l1_mean``, ``train_twist_residual_mean``,
    ``regulariser``, ``objective``), and ``info["warning"]`` if it collapsed toward f ≡ 0.
    ω_w must be > 0 (without it the zero function is optimal).
    Raises ``ValueError`` on malformed input, ``RuntimeError`` if the solver fails.
    """
    t0 = time.perf_counter()
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}; got {model!r}")
    check_sdp_solver(solver)
    lam, ww, tw = _check_weights(config.DEFAULTS.author_fit_weights if weights is None else weights)
    wm, scale, sub, y, n = _problem(wrenches, twists, w_max)
    K, r = y.shape
    if solver.upper() == "CLARABEL":
        sol = _solve_clarabel(model, y, n, (lam, ww, tw))
    else:
        sol = _solve_cvxpy(model, y, n, (lam, ww, tw), solver)
    info = {
        "model": model,
        "method": "author",
        "solver": solver,
        "status": sol["status"],
        "fallback": None if sol["status"] == "optimal" else "solved to reduced accuracy",
        "weights": (lam, ww, tw),
        "dim": r,
        "n_wrenches": K,
        "n_coefficients": r * (r + 1) // 2 if model == "ellipsoid" else len(exponents(r, 4)),
    }
    if model == "ellipsoid":
        A_r = sol["A"]
        lam_min = float(np.linalg.eigvalsh(A_r).min())
        if lam_min <= 0:  # a boundary optimum (a flat direction): lift it to PD, record it
            # shift the spectrum to 1e-12 (relative) above zero: positive definite, a round-off change
            A_r = A_r + (1e-12 * float(np.abs(A_r).max()) - lam_min) * np.eye(r)
            info["fallback"] = f"A had eigenvalue {lam_min:.2e}; lifted to positive definite"
        coef, f, g = A_r, np.einsum("ij,jk,ik->i", y, A_r, y), y @ A_r
    else:
        coef, delta = certify(sol["a"], sol["M"], r)
        info.update(certificate_delta=delta, whitening=np.ones(r), normal_weight=None)
        expo = exponents(r, 4)
        f = monomials(y, expo) @ coef
        g = np.column_stack([D @ coef for D in _gradient_design(y, expo)])
    info.update(_terms(coef, f, g, n, (lam, ww, tw)))
    _check_collapse(info, f)
    info["fit_time_s"] = time.perf_counter() - t0
    if model == "ellipsoid":
        return EllipsoidLS(wm, scale, sub, info, A_e=_embed(A_r, sub))
    return QuarticLS(wm, scale, sub, info, A_q=coef, gram=sol["M"])


def _terms(coef: np.ndarray, f: np.ndarray, g: np.ndarray, n: np.ndarray, weights: tuple) -> dict:
    """The objective's terms for the returned model (after the ellipsoid's lift or the quartic's
    certificate, which move it off the solver's optimum by round-off or by ``certificate_delta``):
    coefficients ``coef``, values f (K,) and (half-)gradients g (K, r) at the training wrenches,
    unit normals n (K, r) (zero rows: no direction).  The twist term is its minimum over the
    free scale, ``min_{s >= 0} ‖g − s n‖ = sqrt(|g|² − max(g·n, 0)²)``, also when ω_t = 0."""
    lam, ww, tw = weights
    gn = np.maximum(np.einsum("ij,ij->i", g, n), 0.0)
    twist = np.sqrt(np.maximum(np.einsum("ij,ij->i", g, g) - gn**2, 0.0))
    value = np.abs(f - 1.0)
    reg = float(np.linalg.norm(coef))
    return {
        "train_value_l1_mean": float(value.mean()),
        "train_twist_residual_mean": float(twist.mean()),
        "regulariser": reg,  # ‖A‖_F or ‖a‖₂
        "objective": lam * reg + ww * float(value.sum()) + tw * float(twist.sum()),
    }


def _check_collapse(info: dict, f: np.ndarray) -> None:
    """Warn (log and ``info["warning"]``) when the fit shrank toward f ≡ 0: the twist term
    rewards a small gradient, so a large ω_t (or λ) against ω_w can buy a lower objective with
    a surface far outside every training wrench (a trial: ‖a‖ = 3e-8 at weights (0.1, 1, 5)),
    which every resistance test would then call inside."""
    median = float(np.median(f))
    floor = config.DEFAULTS.author_fit_collapse_below
    if median < floor:
        info["warning"] = (
            f"the fit collapsed toward f = 0: median value {median:.3g} on its training wrenches "
            f"(below config.DEFAULTS.author_fit_collapse_below = {floor:g}); raise the wrench weight "
            f"ω_w or lower ω_t and λ (weights {info['weights']})"
        )
        log.warning("author-objective %s fit: %s", info["model"], info["warning"])


__all__ = ["MODELS", "fit_author_objective"]

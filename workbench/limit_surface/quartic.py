"""SOS-convex homogeneous quartic 6D limit surface (thesis §3.3.5, Eqs. 3.14–3.17).

``min_a Σ (f(x̂_k) - 1)²  s.t.  V1 vec(M) = V2 a,  M ⪰ 0`` in the PCA
subspace of dimension r (126 coefficients and a 36×36 Gram matrix for r = 6,
taken swap-invariant: 21×21 and 15×15 blocks, :mod:`.sos`).  The K-term objective
is compressed by QR to ``‖R a - c‖²`` so the conic problem depends only on r.
Clarabel gets it directly (its fixed rows cached per r); another solver (SCS,
the fallback) through a cvxpy problem with Parameters, built once per r and
re-solved (``BUILD_COUNT`` counts builds: cvxpy's compile is the expensive step).  Dropped
directions enter as ``‖Cᵀx̂‖⁴ / flat⁴`` so the 6D function stays convex and
homogeneous of degree 4.
"""

from __future__ import annotations

import logging
import time
import warnings
from dataclasses import dataclass
from functools import cached_property, lru_cache
from math import factorial
from typing import Any

import numpy as np
import scipy.sparse as sp

from .. import config
from ..blas_threads import on_one_blas_thread, one_blas_thread
from ..kernel_launch import launch
from ._kernels import _cubic_gradients, _quartic_values
from .base import LimitSurfaceModel
from .normalize import check_twists, prepare
from .sdp_solver import IPM, check_fit_solver
from .sos import exponents, monomials, sos_convexity_maps, swap_blocks
from .sos import svec_index as _svec_index

log = logging.getLogger(__name__)

#: incremented whenever a cvxpy quartic problem is built (tests count it)
BUILD_COUNT = {"quartic": 0, "sos_check": 0}


@dataclass(frozen=True)
class QuarticLS(LimitSurfaceModel):
    """Coefficients ``A_q`` (L,) of the quartic in the subspace coordinates
    ``y = Bᵀ x̂`` (Eq. 3.17); ``gram`` is the certifying M of g(z) = f(z * info["whitening"])."""

    A_q: np.ndarray = None  # type: ignore[assignment]
    gram: np.ndarray = None  # type: ignore[assignment]
    degree: int = 4

    @property
    def _expo(self) -> np.ndarray:
        return exponents(self.dim, 4)

    @cached_property
    def _grad_map(self) -> np.ndarray:
        """(L3, r) coefficients of ∇f in the cubic monomials: ∂_j x^d = d_j x^(d - e_j)."""
        e3 = exponents(self.dim, 3)
        index = {tuple(e): i for i, e in enumerate(e3)}
        G = np.zeros((len(e3), self.dim))
        for a, d in zip(self.A_q, self._expo, strict=True):
            for j in np.flatnonzero(d):
                e = d.copy()
                e[j] -= 1
                G[index[tuple(e)], j] += a * d[j]
        return G

    def _grad_sub(self, y: np.ndarray) -> np.ndarray:
        """(N, r) gradients at subspace points y (N, r) (the kernel; the slow NumPy reference
        ``monomials(y, exponents(r, 3)) @ _grad_map`` is in tests/test_quartic.py)."""
        yt = np.ascontiguousarray(np.asarray(y, dtype=np.float64).T)
        out = np.empty_like(yt)
        factors = _cubic_factors(self.dim)
        launch(
            _cubic_gradients,
            yt.shape[1] * factors.shape[0] * self.dim,
            *(yt, factors, np.ascontiguousarray(self._grad_map), out),
        )
        return out.T

    def _values_sub(self, y: np.ndarray) -> np.ndarray:
        """(N,) values at subspace points y (N, r) (the kernel; the slow NumPy reference
        ``monomials(y, exponents(r, 4)) @ A_q`` is in tests/test_quartic.py)."""
        yt = np.ascontiguousarray(np.asarray(y, dtype=np.float64).T)
        out = np.empty(yt.shape[1])
        coef = np.ascontiguousarray(self.A_q, dtype=np.float64)
        launch(_quartic_values, yt.shape[1] * coef.size, yt, coef, out)
        return out

    def _value_n(self, x: np.ndarray) -> np.ndarray:
        v = self._values_sub(x @ self.subspace.basis)
        if self.subspace.complement.shape[1]:
            v = v + (np.sum((x @ self.subspace.complement) ** 2, axis=1) / config.TOL.flat_axis**2) ** 2
        return v

    def _gradient_n(self, x: np.ndarray) -> np.ndarray:
        B, C = self.subspace.basis, self.subspace.complement
        g = self._grad_sub(x @ B) @ B.T
        if C.shape[1]:
            cx = x @ C
            g = g + (4.0 * np.sum(cx**2, axis=1, keepdims=True) / config.TOL.flat_axis**4) * (cx @ C.T)
        return g

    @cached_property
    def _hess_map(self) -> np.ndarray:
        """(L2, r, r): ∇²f(y) = Σ_q m_q(y) C_q over the quadratic monomials m_q,
        from ∂_j∂_k x^d = d_j (d_k - δ_jk) x^(d - e_j - e_k)."""
        r = self.dim
        e2 = exponents(r, 2)
        index = {tuple(e): i for i, e in enumerate(e2)}
        C = np.zeros((len(e2), r, r))
        unit = np.eye(r, dtype=np.int64)
        for a, d in zip(self.A_q, self._expo, strict=True):
            for j in range(r):
                for k in range(r):
                    coef = d[j] * (d[k] - (j == k))
                    if coef > 0:
                        C[index[tuple(d - unit[j] - unit[k])], j, k] += a * coef
        return C

    def hessian_subspace(self, y: np.ndarray) -> np.ndarray:
        """(N, r, r) Hessian of the fitted quartic at subspace points y : (N, r)."""
        r = self.dim
        return (monomials(y, exponents(r, 2)) @ self._hess_map.reshape(-1, r * r)).reshape(-1, r, r)

    def min_hessian_eigenvalue(self, n_points: int = 10_000, seed: int = 0) -> float:
        """Smallest Hessian eigenvalue over random directions of the subspace,
        relative to the largest |eigenvalue| (>= -1e-12 means convex there)."""
        from ..seeds import check_seed

        y = np.random.default_rng(check_seed(seed)).standard_normal((n_points, self.dim))
        lam = np.linalg.eigvalsh(self.hessian_subspace(y))
        return float(lam.min() / np.abs(lam).max())


@lru_cache(maxsize=16)
def _cubic_factors(r: int) -> np.ndarray:
    """(L3, 3) int: the coordinates whose product is each cubic monomial of
    :func:`.sos.exponents` ``(r, 3)``, in its order (x_0² x_2 -> [0, 0, 2])."""
    out = np.array([np.repeat(np.arange(r), e) for e in exponents(r, 3)], dtype=np.int64)
    out.flags.writeable = False
    return out


@lru_cache(maxsize=16)
def _quartic_problem(r: int):
    """cvxpy problem of Eq. 3.17 in r dims with Parameters (R, c)."""
    import cvxpy as cp

    BUILD_COUNT["quartic"] += 1
    L = sos_convexity_maps(r)[1].shape[1]
    a = cp.Variable(L)
    blocks, sos_convex = _sos_convexity(r, a)
    R = cp.Parameter((L, L))
    c = cp.Parameter(L)
    # ‖R a - c‖ has the minimiser of Σ (f - 1)² and, as one second-order cone,
    # solves faster in Clarabel than the squared form (docs/decisions.md)
    prob = cp.Problem(cp.Minimize(cp.norm(R @ a - c, 2)), [sos_convex])
    return prob, a, blocks, R, c


def _sos_convexity(r: int, a):
    """cvxpy form of Eqs. 3.15–3.16 for the coefficients ``a`` (a cvxpy Variable (L,)): the
    PSD blocks ``[(X, T), ...]`` and the constraint ``V1 vec(M) = V2 a`` with the Gram
    matrix in its swap-invariant form ``M = T_sᵀ S T_s + T_aᵀ A T_a`` (sos.py's notes: no
    SOS-convex quartic is lost); ``vec(Tᵀ X T) = (Tᵀ ⊗ Tᵀ) vec X``, column-major."""
    import cvxpy as cp

    blocks = [(cp.Variable((len(T), len(T)), PSD=True), T) for T in swap_blocks(r) if len(T)]
    lhs = sum(rows @ cp.vec(X, order="F") for (X, _), rows in zip(blocks, _block_rows(r), strict=True))
    return blocks, lhs == sos_convexity_maps(r)[1] @ a


@lru_cache(maxsize=16)
def _block_rows(r: int) -> list[sp.csr_matrix]:
    """Per non-empty swap block T (:func:`.sos.swap_blocks`), ``V1 (Tᵀ ⊗ Tᵀ)``: the rows of
    Eq. 3.16 in the block's column-major ``vec X`` (``vec(Tᵀ X T) = (Tᵀ ⊗ Tᵀ) vec X``),
    shared by the cvxpy problem and Clarabel's rows."""
    V1 = sos_convexity_maps(r)[0]
    return [V1 @ sp.kron(sp.csr_matrix(T.T), sp.csr_matrix(T.T)) for T in swap_blocks(r) if len(T)]


def _gram(blocks) -> np.ndarray:
    """The full Gram matrix ``M = Σ Tᵀ X T`` (n², n²) of the solved blocks."""
    return sum(T.T @ np.asarray(X.value) @ T for X, T in blocks)


@lru_cache(maxsize=16)
def _square_norm_squared(n: int) -> np.ndarray:
    """Coefficients of ``(xᵀx)² = Σ x_i⁴ + 2 Σ_{i<j} x_i² x_j²`` (SOS-convex)."""
    expo = exponents(n, 4)
    even = (expo % 2 == 0).all(axis=1)
    half = expo // 2
    # multinomial coefficient 2! / Π (e_j/2)!
    coef = np.array([2.0 / np.prod([factorial(int(h)) for h in row]) for row in half])
    out = np.where(even, coef, 0.0)
    out.flags.writeable = False  # cached: shared by every caller
    return out


def certify(a: np.ndarray, M: np.ndarray, n: int) -> tuple[np.ndarray, float]:
    """Make ``a`` provably convex given an approximate certificate ``M``.

    With ``λ_min(M) = -ε`` and equality residual ``e = V1 vec(M) - V2 a``,
    ``zᵀ∇²f z >= -(ε + ‖e‖₁) |x|²|z|²`` (every monomial ``|x^α z^β| <= |x|²|z|²``),
    while ``zᵀ∇²(xᵀx)² z >= 4 |x|²|z|²``; so ``f + δ (xᵀx)²`` with
    ``δ = (ε + ‖e‖₁) / 4`` (plus a rounding margin) is convex.  Returns
    ``(a + δ g, δ)``.
    """
    V1, V2 = sos_convexity_maps(n)
    eps = max(0.0, -float(np.linalg.eigvalsh(0.5 * (M + M.T)).min()))
    resid = float(np.abs(V1 @ M.ravel(order="F") - V2 @ a).sum())
    if eps == 0.0 and resid == 0.0:
        return a, 0.0
    # a 1e-6 relative margin (plus the coefficients' round-off): the shifted quartic is strictly SOS-convex
    delta = 0.25 * (eps + resid) * (1 + 1e-6) + 1e-15 * float(np.abs(a).max())
    return a + delta * _square_norm_squared(n), delta


def is_sos_convex(coeffs: Any, n: int, solver: str = "CLARABEL") -> bool:
    """Whether the quartic with ``coeffs`` (L,) in n variables (monomial order of
    :func:`exponents`) admits ``M ⪰ 0`` with ``V1 vec(M) = V2 a`` (Eqs. 3.15–3.16)."""
    import cvxpy as cp

    BUILD_COUNT["sos_check"] += 1
    V1, V2 = sos_convexity_maps(n)
    a = np.asarray(coeffs, dtype=np.float64)
    if a.shape != (V2.shape[1],):
        raise ValueError(f"coeffs must have shape ({V2.shape[1]},) for n = {n}; got {a.shape}")
    M = cp.Variable((n * n, n * n), PSD=True)
    prob = cp.Problem(cp.Minimize(0), [V1 @ cp.vec(M, order="F") == V2 @ a])
    prob.solve(solver=solver, **_solver_options(solver))
    return prob.status in ("optimal", "optimal_inaccurate")


def _solver_options(solver: str) -> dict:
    """cvxpy solve() options of the SOS programs: Clarabel's KKT factorisation, its threads
    and its iterative refinement (``config.DEFAULTS.quartic_kkt_*``, read at call time);
    CVXOPT's robust (LDL) KKT solver, without which it fails every quartic fit (its default
    Cholesky needs full-rank equality constraints, which the SOS program's are not)."""
    from .. import config

    if solver.upper() == "CVXOPT":
        return {"kktsolver": "robust"}
    if solver.upper() != "CLARABEL":
        return {}
    d = config.DEFAULTS
    return {
        "direct_solve_method": d.quartic_kkt_method,
        "max_threads": d.quartic_kkt_threads,
        "iterative_refinement_enable": d.quartic_kkt_refinement > 0,
        "iterative_refinement_max_iter": max(d.quartic_kkt_refinement, 1),
    }


def _clarabel_settings() -> Any:
    """Clarabel's settings of the SOS programs (:func:`_solver_options`), quiet."""
    import clarabel

    settings = clarabel.DefaultSettings()
    settings.verbose = False
    for key, value in _solver_options("CLARABEL").items():
        setattr(settings, key, value)
    return settings


@lru_cache(maxsize=16)
def _clarabel_data(r: int) -> tuple[sp.csc_matrix, int, int, int]:
    """Eq. 3.16 in the svec variables of the two PSD blocks: ``Z [a; τ; svec S; svec A] = 0``
    (441 rows at r = 6; the τ column empty) with ``M = Σ Tᵀ X T`` (:func:`.sos.swap_blocks`)
    and Clarabel's svec (the upper triangle by columns, off-diagonal entries times √2).
    Returns (Z, L, n_S, n_A); :func:`_reduced_maps` solves it for ``svec S``."""
    V2 = sos_convexity_maps(r)[1]
    L = V2.shape[1]
    cols = [-V2, sp.csc_matrix((V2.shape[0], 1))]
    sizes = [0, 0]
    for b, (T, rows) in enumerate(zip([T for T in swap_blocks(r) if len(T)], _block_rows(r), strict=True)):
        n = len(T)
        i, j = _svec_index(n)
        w = np.where(i == j, 1.0, 1.0 / np.sqrt(2.0))  # svec entry -> X_ij = X_ji
        k = np.arange(len(i))
        unsvec = sp.csc_matrix(
            (np.r_[w, w[i != j]], (np.r_[i + j * n, (j + i * n)[i != j]], np.r_[k, k[i != j]])),
            shape=(n * n, len(i)),
        )
        cols.append(rows @ unsvec)
        sizes[b] = len(i)
    zero = sp.hstack(cols).tocsc()
    zero.eliminate_zeros()
    return zero, L, sizes[0], sizes[1]


@lru_cache(maxsize=16)
def _reduced_maps(r: int) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """``(P, Q)`` with ``svec S = P a + Q svec A`` the only solution of Eq. 3.16
    (:func:`_clarabel_data`): the symmetric block's map ``B_S`` is injective and its range holds
    those of ``V2`` and of the antisymmetric block's ``B_A`` (checked here for the r asked;
    true for r = 1..6, tests/test_quartic.py), so ``S`` is a linear function of ``(a, A)`` and
    the fit needs no equality rows: at r = 6, 247 variables and 478 cone rows instead of 478
    and 919 (441 equalities of rank 231), a smaller program with the same optimum to the solver's
    tolerance (docs/decisions.md).  P and Q hold small
    constants (12, 6, 4, 2√2, 2, √2); entries below 1e-12 are round-off of exact zeros."""
    zero, L, nS, nA = _clarabel_data(r)
    Z = zero.toarray()
    B_S, V2, B_A = Z[:, L + 1 : L + 1 + nS], -Z[:, :L], Z[:, L + 1 + nS :]
    rhs = np.hstack([V2, -B_A])
    # one BLAS thread: a threaded LAPACK sums in another order, and these last bits would make a
    # fit depend on whether this process had computed the maps with more threads (measured:
    # serial and Dask rows apart by 1e-11)
    with one_blas_thread():
        sol = np.linalg.lstsq(B_S, rhs, rcond=None)[0]
    resid = float(np.abs(B_S @ sol - rhs).max())
    if np.linalg.matrix_rank(B_S) != nS or resid > 1e-10:
        raise RuntimeError(
            f"the swap-invariant Gram form in {r} dims does not fix S from (a, A) "
            f"(rank {np.linalg.matrix_rank(B_S)} of {nS}, residual {resid:.1e})"
        )
    sol[np.abs(sol) < 1e-12] = 0.0
    return sp.csc_matrix(sol[:, :L]), sp.csc_matrix(sol[:, L:])


def _unsvec(v: np.ndarray, n: int) -> np.ndarray:
    """The symmetric (n, n) matrix of Clarabel's svec ``v`` (off-diagonals times √2)."""
    i, j = _svec_index(n)
    X = np.zeros((n, n))
    X[i, j] = np.where(i == j, v, v / np.sqrt(2.0))
    X[j, i] = X[i, j]
    return X


@lru_cache(maxsize=16)
def _clarabel_fixed(r: int) -> tuple[sp.csc_matrix, int, int, int]:
    """The rows of the fit that do not depend on the data: the PSD triangles
    ``svec S = P a + Q svec A`` and ``svec A`` itself over ``x = [a (L), τ, svec A]``
    (Clarabel's ``A x + s = b`` with ``b = 0``).  Returns (rows, L, n_S, n_A)."""
    _, L, nS, nA = _clarabel_data(r)
    P, Q = _reduced_maps(r)
    rows = sp.hstack([-P, sp.csc_matrix((nS, 1))] + ([-Q] if nA else []))
    if nA:
        rows = sp.vstack([rows, sp.hstack([sp.csc_matrix((nA, L + 1)), -sp.identity(nA)])])
    return rows.tocsc(), L, nS, nA


def _solve_clarabel(r: int, Rm: np.ndarray, c_val: np.ndarray):
    """Eq. 3.17 straight in Clarabel (no cvxpy: nothing to compile per process): ``min τ`` over
    ``x = [a, τ, svec A]`` with ``(τ, R a − c)`` in a second-order cone and the two swap-invariant
    Gram blocks ``S(a, A)`` (:func:`_reduced_maps`) and ``A`` in PSD triangles.  Returns
    (ok, a, M, status)."""
    import clarabel

    psd, L, nS, nA = _clarabel_fixed(r)
    n_x = L + 1 + nA
    # (τ, R a − c) = b − A x  with  A = [[0, −1, 0], [−R, 0, 0]], b = [0; −c]
    soc = sp.bmat([[None, sp.csc_matrix(-np.ones((1, 1)))], [sp.csc_matrix(-Rm), None]])
    if nA:
        soc = sp.hstack([soc, sp.csc_matrix((L + 1, nA))])
    A = sp.vstack([soc, psd]).tocsc()
    b = np.concatenate([[0.0], -c_val, np.zeros(nS + nA)])
    cones = [clarabel.SecondOrderConeT(L + 1)]
    cones += [clarabel.PSDTriangleConeT(len(T)) for T in swap_blocks(r) if len(T)]
    q = np.zeros(n_x)
    q[L] = 1.0  # min τ
    try:
        sol = clarabel.DefaultSolver(sp.csc_matrix((n_x, n_x)), q, A, b, cones, _clarabel_settings()).solve()
    except Exception as exc:  # noqa: BLE001 - Clarabel's errors (e.g. a failed factorisation): fall back
        return False, None, None, f"{type(exc).__name__}: {exc}"
    status = str(sol.status)
    if status not in ("Solved", "AlmostSolved"):
        return False, None, None, status
    x = np.asarray(sol.x)
    a, s_A = x[:L], x[L + 1 :]
    P, Q = _reduced_maps(r)
    s_S = P @ a + (Q @ s_A if nA else 0.0)
    (T_s, T_a) = swap_blocks(r)
    M = T_s.T @ _unsvec(s_S, len(T_s)) @ T_s
    if nA:
        M += T_a.T @ _unsvec(s_A, len(T_a)) @ T_a
    return True, a, M, "optimal" if status == "Solved" else "optimal_inaccurate"


def _fallback_for(solver: str, fallback_solver: str | None) -> str | None:
    """The checked fallback: "auto" is Clarabel after the IPM or SCS and SCS after any other
    solver; a fallback that is the solver itself is refused (it would only fail again)."""
    if fallback_solver is None:
        return None
    if isinstance(fallback_solver, str) and fallback_solver.lower() == "auto":
        return "CLARABEL" if solver in (IPM, "SCS") else "SCS"
    out = check_fit_solver(fallback_solver, "fallback_solver")
    if out == solver:
        other = "CLARABEL" if solver != "CLARABEL" else "SCS"
        raise ValueError(
            f"fallback_solver is the solver itself ({out!r}): it is tried only after that solver "
            f"failed, and would fail again; pass another (e.g. fallback_solver={other!r}), 'auto' "
            "or None (no fallback)"
        )
    return out


@lru_cache(maxsize=16)
def _ipm_program(r: int):
    """The interior point's fixed maps in r dimensions (:class:`.sos_ipm.SosProgram`)."""
    from .sos_ipm import SosProgram

    T_s, T_a = swap_blocks(r)
    return SosProgram(*_reduced_maps(r), len(T_s), len(T_a), _square_norm_squared(r))


def _solve_ipm(r: int, Rm: np.ndarray, c_val: np.ndarray):
    """Eq. 3.17 by :func:`.sos_ipm.solve` on one BLAS thread (a threaded LAPACK sums in another
    order, and on a shared machine waits for its threads); returns (ok, a, M, status)."""
    from . import sos_ipm

    T_s, T_a = swap_blocks(r)
    with one_blas_thread():
        res = sos_ipm.solve(Rm, c_val, _ipm_program(r))
    if not res.ok:
        return False, None, None, res.status
    M = T_s.T @ res.grams[0] @ T_s
    if len(T_a):
        M += T_a.T @ res.grams[1] @ T_a
    return True, res.a, M, res.status


def _solve(r: int, solver: str, Rm: np.ndarray, c_val: np.ndarray, warm_start: bool = True):
    """Solve Eq. 3.17: Clarabel directly (:func:`_solve_clarabel`; ``warm_start`` does
    not apply), any other cvxpy solver through the cached cvxpy problem; returns
    (ok, a, M, status)."""
    if solver.upper() == "CLARABEL":
        return _solve_clarabel(r, Rm, c_val)
    if solver.upper() == IPM:
        return _solve_ipm(r, Rm, c_val)
    import cvxpy as cp

    prob, a, blocks, R, c = _quartic_problem(r)
    R.value = Rm
    c.value = c_val
    try:
        with warnings.catch_warnings():  # "may be inaccurate": the status is recorded in info
            warnings.simplefilter("ignore", UserWarning)
            prob.solve(solver=solver, warm_start=warm_start, **_solver_options(solver))
    except (cp.error.SolverError, ValueError) as exc:
        return False, None, None, f"{type(exc).__name__}: {exc}"
    if prob.status not in ("optimal", "optimal_inaccurate") or a.value is None:
        return False, None, None, str(prob.status)
    return True, np.array(a.value), _gram(blocks), prob.status


def _normal_rows(
    z: np.ndarray, n_z: np.ndarray, expo: np.ndarray, beta: float
) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares rows ``(β/4)(∇g(z_k) - 4 n_k / (n_k·z_k)) = 0`` for the
    quartic g with exponents ``expo`` (L, r).

    z : (K, r) wrenches on the surface, n_z : (K, r) outward normals there (the
    negated twists, maximum dissipation §2.3.4).  For a homogeneous quartic with
    ``g(z) = 1``, Euler's ``z·∇g = 4`` fixes the normal's length, so the target
    gradient is linear data and the rows are linear in the coefficients.  Rows
    whose normal is (nearly) tangent to the ray — zero wrenches, e.g. a
    translation along a planar contact's normal — carry no information and are
    dropped; the caller has checked the twists' sign (:func:`.normalize.check_twists`).
    Returns (A (K' r, L), b (K' r,)).
    """
    nz = np.einsum("ij,ij->i", n_z, z)
    # a normal tangent to the ray to round-off carries no information (docstring)
    tol = 1e-9 * np.linalg.norm(n_z, axis=1) * np.linalg.norm(z, axis=1)
    keep = nz > tol
    z, n_z, nz = z[keep], n_z[keep], nz[keep]
    target = 4.0 * n_z / nz[:, None]
    A, b = [], []
    for j in range(z.shape[1]):
        d = expo[:, j]
        lowered = expo.copy()
        lowered[:, j] = np.maximum(d - 1, 0)  # ∂_j z^d = d_j z^(d - e_j); d_j = 0 rows vanish
        A.append(monomials(z, lowered) * (0.25 * beta * d))
        b.append(0.25 * beta * target[:, j])
    return np.vstack(A), np.concatenate(b)


@on_one_blas_thread  # small matrices: a threaded BLAS waits for the cores others hold
def fit_quartic(
    wrenches: Any,
    *,
    twists: Any = None,
    normal_weight: float | None = None,
    w_max: Any = None,
    solver: str | None = None,
    fallback_solver: str | None = "auto",
    warm_start: bool = False,
) -> QuarticLS:
    """Fit an SOS-convex quartic 6DLS to raw frictional wrenches (K, 6), Eq. 3.17.

    twists : optional (K, 6) twists ``[v; ω]`` the wrenches were sampled with.
        By maximum dissipation ``-twist`` is the outward normal of the limit
        surface at its wrench, so each twist adds r linear gradient rows
        (:func:`_normal_rows`) to the value rows of Eq. 3.17 — Hermite
        instead of Lagrange fitting.  The thesis text (Eq. 3.17) fits values
        only; the author's code (``fit4thorderpoly6d.m``) does fit gradients to
        twists, differently: L1 norms of the value residuals (weight 10) and of
        ``∇f − s_k ξ_k`` with a free scale ``s_k > 0`` per twist (weight 1), plus
        ``‖A_q‖`` (weight 1).  Here Euler's relation fixes the gradient's length,
        so the rows stay linear least squares.  It matters for K near the 126
        coefficients, where the values-only quartic overfits (held-out error
        above the ellipsoid's).
    normal_weight : β of those rows; default ``config.DEFAULTS.quartic_normal_weight *
        sqrt(L / K)`` (a fixed total weight that fades against the K value rows).
        0 fits values only.
    w_max : optional exact (6,) maxima; default the sampled maxima.
    solver : "IPM" (:mod:`.sos_ipm`: an interior point shaped for this program, the same
        optimum to Clarabel's tolerances, several times faster a fit: results/benchmarks/
        limit_surface.json), "CLARABEL" (called directly) or another cvxpy conic solver with SDP
        support ("SCS"); any case.  None (the default): ``config.DEFAULTS.quartic_solver``, read
        at the call.
    fallback_solver : tried when ``solver`` fails (Clarabel's interior point
        occasionally stops with a numerical error when K is close to the 126
        unknowns); recorded in ``info["fallback"]`` and logged as a warning.  "auto" (the
        default): Clarabel after the IPM or SCS, SCS after any other solver; ``None`` disables
        it; the solver itself is refused.  Both names are checked (:func:`~.sdp_solver.check_fit_solver`)
        and recorded in upper case.
    warm_start : let cvxpy reuse the previous fit of the same problem size in this
        process (SCS starts from it).  Off by default: with it, a fit depends on what the
        process fitted before — measured on a bottle contact (fem-fitting, K = 130),
        Clarabel failed (SCS fallback, held-out error 0.00819) after one earlier grasp's
        fits and succeeded (0.00823) in a fresh process — so a row's numbers would
        depend on the order rows ran in, serially or on Dask workers.
    Either way the coefficients are made provably convex by :func:`certify`.
    Raises ``ValueError`` with fewer wrenches than coefficients and
    ``RuntimeError`` if every solver fails.
    """
    t0 = time.perf_counter()
    solver = check_fit_solver(config.DEFAULTS.quartic_solver if solver is None else solver)
    fallback_solver = _fallback_for(solver, fallback_solver)
    W, wm, scale, x, sub = prepare(wrenches, w_max)
    r = sub.dim
    L = exponents(r, 4).shape[0]
    _check_fit_size(len(W), r, L, twists, normal_weight)
    # fit in whitened coordinates z = y / s (s: RMS of the wrenches along each PCA
    # direction): thin contacts have directions ~100x thinner than others, whose
    # quartic monomials (~1e-8) made R ill-conditioned and Clarabel fail. A diagonal
    # change of variables maps SOS-convex quartics to SOS-convex quartics and leaves
    # the objective unchanged, so this is the same fit, only well-posed.
    expo = exponents(r, 4)
    s = sub.std[:r]
    z = (x @ sub.basis) / s
    A_fit, b_fit = monomials(z, expo), np.ones(len(W))
    beta = 0.0
    if twists is not None:
        beta, rows = _twist_rows(W, twists, normal_weight, z, (scale, sub, s), expo)
        if rows is not None:
            A_fit, b_fit = np.vstack([A_fit, rows[0]]), np.concatenate([b_fit, rows[1]])
    # R of [A | b] holds R of A and Qᵀb in its last column: Q is never formed (~40 % of the QR's time)
    Rb = np.linalg.qr(np.column_stack([A_fit, b_fit]), mode="r")
    Rm, c_val = Rb[:L, :L], Rb[:L, L]
    diag = np.abs(np.diag(Rm))
    determined = int(np.sum(diag > config.TOL.quartic_rank_rtol * diag.max()))
    a_val, M_val, name, status, fallback = _solve_with_fallback(
        r, (solver, fallback_solver), Rm, c_val, warm_start
    )
    if fallback:
        log.warning("quartic fit (%d wrenches, dim %d): %s", len(W), r, fallback)
    underdetermined = None
    if determined < L:  # repeated, dependent or outlying wrenches: the fit is not the data's
        underdetermined = (
            f"the {len(W)} wrenches determine about {determined} of the {L} coefficients (repeated or "
            "dependent wrenches, or a few far larger than the rest: their quartic monomials swamp the "
            "others'); the rest are set by the convexity constraint alone — sample more distinct "
            "wrenches, or check for outliers"
        )
        log.warning("quartic fit: %s", underdetermined)
    g, delta = certify(a_val, M_val, r)  # rigorously convex in z
    coeffs = g / np.prod(s**expo, axis=1)  # f(y) = g(y / s)
    info = {
        "model": "quartic",
        "solver": name,
        "status": status,
        "fallback": fallback,
        "certificate_delta": delta,  # weight of (zᵀz)² added to make convexity rigorous
        "whitening": s,  # the certificate ``gram`` is for g(z), z = y / whitening
        "dim": r,
        "n_wrenches": len(W),
        "normal_weight": float(beta),  # 0: values only (Eq. 3.17 as in the thesis)
        "underdetermined": underdetermined,  # None, or why the data do not fix the fit
        "fit_time_s": time.perf_counter() - t0,
    }
    model = QuarticLS(wm, scale, sub, info, A_q=coeffs, gram=M_val)
    _check_training_error(model, W, r, info)
    info["fit_time_s"] = time.perf_counter() - t0  # the check included
    return model


def _check_training_error(model: QuarticLS, W: np.ndarray, r: int, info: dict) -> None:
    """Record the fit's Eq. 3.18 error over its own training wrenches W (K, 6) in
    ``info["train_error"]``, and say so (logged, ``info["warning"]``) when it is above
    ``TOL.quartic_train_error_warn``: the solver's status is "optimal" either way."""
    train = model.fitting_error(W)
    info["train_error"] = train
    limit = config.TOL.quartic_train_error_warn
    if train > limit:
        info["warning"] = (
            f"the fit misses its own training wrenches (mean Eq. 3.18 error {train:.3g} > "
            f"TOL.quartic_train_error_warn = {limit:g}): they do not lie on one convex surface in the "
            f"{r} dimensions kept — is one of them noise (an extent ~1e-6 of the largest)? check the "
            "wrenches' singular values, or fit fewer dimensions"
        )
        log.warning("quartic fit: %s", info["warning"])


def _check_fit_size(K: int, r: int, L: int, twists: Any, normal_weight: float | None) -> None:
    """ValueError unless the ``K`` wrenches are at least the ``L`` coefficients of a quartic in
    ``r`` dimensions, and ``normal_weight`` comes with ``twists``."""
    if K < L:
        raise ValueError(
            f"a quartic in {r} dimensions has {L} coefficients but only {K} wrenches were given "
            f"— sample at least {L} (the thesis uses 100-1,000; > 200 to beat the ellipsoid), or fit "
            "fewer with their twists by the author's regularised objective (fit_author_objective)"
        )
    if twists is None and normal_weight:
        raise ValueError(
            f"normal_weight={normal_weight} weights the twists' gradient rows, but no twists were given: "
            "pass twists= (the ones the wrenches were computed from) or leave normal_weight out"
        )


def _twist_rows(
    W: np.ndarray, twists: Any, normal_weight: float | None, z: np.ndarray, frame: tuple, expo: np.ndarray
) -> tuple[float, tuple[np.ndarray, np.ndarray] | None]:
    """β and the gradient rows (:func:`_normal_rows`) of the ``twists`` (K, 6) of the wrenches
    ``W`` (K, 6) at their whitened points ``z`` (K, r); ``frame`` = (scale (6,), subspace,
    whitening s (r,)).  The rows are None when β = 0."""
    scale, sub, s = frame
    xi = check_twists(W, twists, friction_sign=False)
    w0 = config.DEFAULTS.quartic_normal_weight
    L = len(expo)
    beta = w0 * np.sqrt(L / len(W)) if normal_weight is None else normal_weight
    if not np.isfinite(beta) or beta < 0:
        raise ValueError(f"normal_weight must be finite and >= 0; got {beta}")
    if not beta > 0:
        return beta, None
    check_twists(W, xi)  # the rows take -ξ as the outward normal: friction must oppose ξ
    # power w·ξ = z·(s ⊙ Bᵀ(scale ⊙ ξ)); friction minimises it, so the outward normal is -that
    return beta, _normal_rows(z, -((xi * scale) @ sub.basis) * s, expo, float(beta))


def _solve_with_fallback(
    r: int, solvers: tuple[str, str | None], Rm: np.ndarray, c_val: np.ndarray, warm_start: bool
) -> tuple[np.ndarray, np.ndarray, str, str, str | None]:
    """:func:`_solve` by ``solvers`` = (solver, fallback solver or None) in turn: (a, M, the
    solver that solved it, its status, the failures before it or None); RuntimeError if all fail."""
    solver, fallback_solver = solvers
    failures = []
    for name in [solver] + ([fallback_solver] if fallback_solver else []):
        ok, a_val, M_val, status = _solve(r, name, Rm, c_val, warm_start)
        if ok:
            break
        failures.append(f"{name}: {status}")
    else:
        raise RuntimeError(
            "quartic fit failed (" + "; ".join(failures) + "); try another solver (solver= or "
            "fallback_solver= 'IPM', 'CLARABEL' or 'SCS'), more distinct wrenches, or fit_ellipsoid"
        )
    fallback = f"{'; '.join(failures)}; solved with {name}" if failures else None
    return a_val, M_val, name, status, fallback

"""A primal-dual interior point shaped for the SOS-convex quartic fit (Eq. 3.17).

The fit, after :func:`.quartic._reduced_maps`, is a small conic least-squares problem of fixed
structure::

    min_x  ½‖R a − c‖²   over  x = [a (L), α (n_A(n_A+1)/2)]
    s.t.   X_S = smat(P a + Q α) ⪰ 0   (n_S × n_S, the swap-symmetric Gram block)
           X_A = smat(α) ⪰ 0           (n_A × n_A, the antisymmetric block)

with ``svec`` Clarabel's (upper triangle by columns, off-diagonals times √2) — at r = 6, L = 126
and blocks of 21 × 21 and 15 × 15.  There is no equality row and no constant term, so a strictly
feasible point is known in closed form (the quartic ``(zᵀz)²``, whose Hessian biform has the
Gram ``4 I + 8 vec(I) vec(I)ᵀ``): the iterates stay primal feasible and only the dual residual
and the gap are driven to zero.  Each iteration solves the Schur system of the HKM direction
(Helmberg, Rendl, Vanderbei and Wolkowicz 1996; Kojima, Shindoh and Hara 1997; Monteiro 1997),
``(H + Σ_b G_bᵀ (Z_b ⊛ X_b⁻¹) G_b) Δx = rhs``, one dense Cholesky of the (246-square at r = 6)
matrix, with Mehrotra's predictor-corrector.  A general solver spends its time on the sparse
KKT system of the same problem (247 variables, 478 cone rows); here the structure is used as it
is: the Schur matrix is formed with one sparse-dense product per block.

``solve`` returns the optimum of the same convex program as Clarabel's (unique in ``a`` when R has
full rank), to the tolerances of :data:`~workbench.config.TOL` (``sos_ipm_*``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dpotrf as _potrf
from scipy.linalg.lapack import dpotrs as _potrs

from .. import config
from ._kernels import _svec_kron
from .sos import svec_index as _svec_index


def svec_to_vec(n: int) -> sp.csr_matrix:
    """(n², n(n+1)/2) sparse map from Clarabel's svec of a symmetric (n, n) matrix (upper
    triangle by columns, off-diagonals times √2) to its row-major ``ravel()``."""
    i, j = _svec_index(n)
    k = np.arange(len(i))
    off = i != j
    vals = np.where(off, 1.0 / np.sqrt(2.0), 1.0)
    return sp.csr_matrix(
        (np.r_[vals, vals[off]], (np.r_[i * n + j, (j * n + i)[off]], np.r_[k, k[off]])),
        shape=(n * n, len(i)),
    )


@dataclass(frozen=True)
class SosFitResult:
    """What :func:`solve` found: ``a`` (L,), ``alpha`` (svec of the antisymmetric block), ``grams``
    the blocks ``[X_S (n_S, n_S), X_A (n_A, n_A)]`` (strictly positive definite), ``status``
    ("optimal" or why not) and the ``iterations`` taken; on failure the arrays are None."""

    ok: bool
    a: np.ndarray | None
    alpha: np.ndarray | None
    grams: list[np.ndarray] | None
    status: str
    iterations: int


def _inv_factors(As: list[np.ndarray]) -> list[np.ndarray]:
    """``L⁻¹`` of each ``A = L Lᵀ ≻ 0``: ``A + t D ⪰ 0`` iff ``I + t L⁻¹ D L⁻ᵀ ⪰ 0``."""
    return [np.linalg.inv(np.linalg.cholesky(A)) for A in As]


def _max_step(Li: list[np.ndarray], Ds: list[np.ndarray]) -> float:
    """Largest t with ``A + t D ⪰ 0`` for every pair (``Li`` from :func:`_inv_factors`; inf when
    every D ⪰ 0): one over minus the smallest eigenvalue of ``L⁻¹ D L⁻ᵀ``, pairs of one size
    in one batched call."""
    lam = np.inf
    for n in {len(D) for D in Ds}:
        C = np.stack([F @ D @ F.T for F, D in zip(Li, Ds, strict=True) if len(D) == n])
        lam = min(lam, float(np.linalg.eigvalsh(C)[:, 0].min()))
    return np.inf if lam >= 0 else -1.0 / lam


class _Svec:
    """The svec layout of an (n, n) block (m = n(n+1)/2 entries, ``i``, ``j`` the row and column
    of each): for symmetric Z, Y, ``kron(Z, Y)`` (m, m) is the matrix of
    ``U ↦ svec(½(Z U Y + Y U Z))`` on svec vectors (upper triangle by columns, off-diagonals times
    √2), with entries
    ``½ w_p u_q (Z_ik Y_lj + Z_il Y_kj + Y_ik Z_lj + Y_il Z_kj)`` for ``p = (i, j)``, ``q = (k, l)``
    (w_p = 1 or √2, u_q = ½ or 1/√2 on and off the diagonal)."""

    def __init__(self, n: int) -> None:
        i, j = _svec_index(n)
        self.n, self.m = n, len(i)
        self.i, self.j = i, j
        self.to_vec = svec_to_vec(n)
        self.from_vec = self.to_vec.T.tocsr()

    def kron(self, Z: np.ndarray, Y: np.ndarray) -> np.ndarray:
        out = np.empty((self.m, self.m))
        _svec_kron(Z, Y, self.i, self.j, out)
        return out

    def smat(self, v: np.ndarray) -> np.ndarray:
        return (self.to_vec @ v).reshape(self.n, self.n)

    def svec(self, U: np.ndarray) -> np.ndarray:
        return self.from_vec @ U.ravel()


class SosProgram:
    """The fixed part of the fit, built once per subspace dimension: the PSD blocks as linear maps
    of x, ``svec X_S = G x`` with ``G = [P Q]`` (a few entries per row) and ``svec X_A = α`` (the
    last n_A(n_A+1)/2 entries of x), and the start (:func:`_start`; read-only).  The HKM Schur matrix of a
    block is ``Gᵀ (Z ⊛ X⁻¹) G``, ``⊛`` the svec Kronecker product (:class:`_Svec`)."""

    def __init__(self, P: sp.spmatrix, Q: sp.spmatrix, n_S: int, n_A: int, a0: np.ndarray) -> None:
        """P, Q : :func:`.quartic._reduced_maps`; n_S, n_A : the blocks' sizes; a0 (L,) : the
        coefficients of ``(zᵀz)²`` (the strictly feasible start, :func:`_start`)."""
        self.L = P.shape[1]
        self.G = (sp.hstack([P, Q]) if n_A else sp.csr_matrix(P)).tocsr()
        self.GT = self.G.T.tocsr()
        self.sv = [_Svec(n_S)] + ([_Svec(n_A)] if n_A else [])
        self.n_x = self.G.shape[1]
        self.degree = float(n_S + n_A)  # the barrier parameter: Σ block sizes
        # X_b.ravel() = V_b x: one sparse product per block
        maps = [self.G] + (
            [sp.hstack([sp.csr_matrix((self.sv[1].m, self.L)), sp.identity(self.sv[1].m)])] if n_A else []
        )
        self.V = [(sv.to_vec @ g).tocsr() for sv, g in zip(self.sv, maps, strict=True)]
        self.VT = [V.T.tocsr() for V in self.V]
        self.start = _start(self, a0)
        for a in [self.start[0], *self.start[1]]:
            a.flags.writeable = False

    def mats(self, x: np.ndarray) -> list[np.ndarray]:
        return [(V @ x).reshape(sv.n, sv.n) for V, sv in zip(self.V, self.sv, strict=True)]

    def adjoint(self, Us: list[np.ndarray]) -> np.ndarray:
        """``Σ_b G_bᵀ svec U_b``: the x-gradient of ``Σ_b tr(U_b X_b(x))``."""
        return sum(VT @ U.ravel() for VT, U in zip(self.VT, Us, strict=True))

    def schur(self, Zs: list[np.ndarray], Xi: list[np.ndarray]) -> np.ndarray:
        """``Σ_b G_bᵀ (Z_b ⊛ X_b⁻¹) G_b`` (n_x, n_x)."""
        K = self.sv[0].kron(Zs[0], Xi[0])
        M = self.GT @ (self.GT @ K).T  # K symmetric: (Gᵀ K)ᵀ = K G
        if len(self.sv) > 1:
            M[self.L :, self.L :] += self.sv[1].kron(Zs[1], Xi[1])
        return M


def _start(blocks: SosProgram, a0: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
    """A strictly feasible x (the quartic ``(zᵀz)²`` with ``A = 4 I``) and centred duals ``Z = X⁻¹``."""
    x = np.zeros(blocks.n_x)
    x[: len(a0)] = a0
    if len(blocks.sv) > 1:
        x[len(a0) :] = blocks.sv[1].svec(4.0 * np.eye(blocks.sv[1].n))
    Xs = blocks.mats(x)
    return x, [np.linalg.inv(X) for X in Xs]


def solve(Rm: np.ndarray, c: np.ndarray, blocks: SosProgram) -> SosFitResult:
    """Minimise ``½‖Rm a − c‖²`` over SOS-convex quartics (module notes).

    Rm : (L, L) upper triangular R of the fit's QR, c : (L,) its right-hand side;
    blocks : the program of the subspace dimension (:class:`SosProgram`).
    Stops when the duality gap is below ``TOL.sos_ipm_gap`` of the objective (of ``½‖c‖²``, the
    objective at a = 0, times the same tolerance for a fit through its data) and the dual
    residual below ``TOL.sos_ipm_residual`` of ``1 + max|Rᵀc|``; at most ``TOL.sos_ipm_max_iter``
    iterations.
    """
    tol = config.TOL
    L = Rm.shape[1]
    H = np.zeros((blocks.n_x, blocks.n_x))
    H[:L, :L] = Rm.T @ Rm
    g = np.zeros(blocks.n_x)
    g[:L] = -Rm.T @ c
    x, Zs = blocks.start[0].copy(), [Z.copy() for Z in blocks.start[1]]
    try:
        return _iterate(blocks, (H, g, Rm, c), x, Zs, tol)
    except np.linalg.LinAlgError as exc:  # an iterate lost definiteness to round-off
        return SosFitResult(False, None, None, None, f"numerical failure ({exc})", -1)


def _iterate(blocks: SosProgram, data: tuple, x: np.ndarray, Zs: list[np.ndarray], tol) -> SosFitResult:
    """:func:`solve`'s iterations from (x, Z); ``data`` = (H, g, Rm, c)."""
    H, g, Rm, c = data
    L = Rm.shape[1]
    scale = 1.0 + float(np.abs(g).max())
    # the gap is relative to the objective, down to tol × the objective at a = 0 (½‖c‖², the
    # data's own scale): a fit that nearly interpolates its wrenches (K near the coefficients)
    # has a small objective, and a gap absolute in it stopped 0.6 % above the optimum
    floor = tol.sos_ipm_gap * 0.5 * float(c @ c)
    for it in range(tol.sos_ipm_max_iter):
        Xs = blocks.mats(x)
        factors = _inv_factors(Xs + Zs)  # L⁻¹ of X and Z: the inverses and the step lengths
        Xi = [F.T @ F for F in factors[: len(Xs)]]
        gap = sum(float(np.sum(X * Z)) for X, Z in zip(Xs, Zs, strict=True))
        r_d = H @ x + g - blocks.adjoint(Zs)
        obj = 0.5 * float(np.sum((Rm @ x[:L] - c) ** 2))
        if gap <= tol.sos_ipm_gap * max(obj, floor) and np.abs(r_d).max() <= tol.sos_ipm_residual * scale:
            return SosFitResult(True, x[:L], x[L:], Xs, "optimal", it)
        cho = _cholesky(H + blocks.schur(Zs, Xi))
        x, Zs = _step(blocks, (x, Zs, Xs, Xi, factors), cho, r_d, gap, tol.sos_ipm_step)
    return SosFitResult(
        False, None, None, None, f"no convergence in {tol.sos_ipm_max_iter} iterations", tol.sos_ipm_max_iter
    )


def _step(blocks: SosProgram, state: tuple, cho: tuple, r_d: np.ndarray, gap: float, frac: float) -> tuple:
    """Mehrotra's predictor-corrector step of the HKM direction from ``state`` = (x, Z, X, X⁻¹):
    ``ΔZ = σμX⁻¹ − Z − sym(X⁻¹ ΔX Z) − sym(X⁻¹ ΔX_aff ΔZ_aff)``, ΔX = X(Δx), substituted in the
    dual residual (the Schur system ``cho``); both take ``frac`` of the step to the boundary."""
    x, Zs, Xs, Xi, factors = state

    def direction(sigma_mu: float, corr: list[np.ndarray] | None) -> tuple:
        base = [sigma_mu * Y - Z for Y, Z in zip(Xi, Zs, strict=True)]
        if corr is not None:
            base = [b - k for b, k in zip(base, corr, strict=True)]
        dx = _cho_solve(cho, -r_d + blocks.adjoint(base))
        dX = blocks.mats(dx)
        dZ = [b - _sym(Y @ D @ Z) for b, Y, D, Z in zip(base, Xi, dX, Zs, strict=True)]
        return dx, dX, dZ

    def longest(dX: list, dZ: list) -> float:
        return _max_step(factors, dX + dZ)

    dx, dX, dZ = direction(0.0, None)
    t_aff = min(1.0, longest(dX, dZ))
    gap_aff = sum(
        float(np.sum((X + t_aff * D) * (Z + t_aff * E))) for X, D, Z, E in zip(Xs, dX, Zs, dZ, strict=True)
    )
    sigma = (gap_aff / gap) ** 3
    corr = [_sym(Y @ D @ E) for Y, D, E in zip(Xi, dX, dZ, strict=True)]
    dx, dX, dZ = direction(sigma * gap / blocks.degree, corr)
    t = min(1.0, frac * longest(dX, dZ))
    return x + t * dx, [Z + t * E for Z, E in zip(Zs, dZ, strict=True)]


def _cholesky(M: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """``(M, U)``: the upper Cholesky factor U of M (LAPACK potrf), or near the optimum, where the
    Schur matrix's conditioning is lost to round-off, of ``M + δ I`` with ``δ`` the smallest of
    ``TOL.sos_ipm_regularisation × 100^k × max diag M`` (k = 0..3) that factors (Clarabel's
    static regularisation); :func:`_cho_solve` then refines against M itself."""
    U, info = _potrf(M, lower=False, clean=False, overwrite_a=False)
    if info == 0:
        return M, U
    scale = float(np.abs(np.diag(M)).max())
    for k in range(4):
        delta = config.TOL.sos_ipm_regularisation * 100.0**k * scale
        U, info = _potrf(M + delta * np.eye(len(M)), lower=False, clean=False, overwrite_a=True)
        if info == 0:
            return M, U
    raise np.linalg.LinAlgError(f"the Schur matrix is not positive definite (potrf info {info})")


def _cho_solve(F: tuple[np.ndarray, np.ndarray], b: np.ndarray, refine: int = 2) -> np.ndarray:
    """``M⁻¹ b`` from :func:`_cholesky`'s ``(M, U)``, with ``refine`` steps of iterative
    refinement (they cost a matrix-vector product each; a regularised U needs them)."""
    M, U = F
    x, info = _potrs(U, b, lower=False)
    for _ in range(refine):
        dx, info = _potrs(U, b - M @ x, lower=False)
        x = x + dx
    if info != 0:
        raise np.linalg.LinAlgError(f"potrs info {info}")
    return x


def _sym(A: np.ndarray) -> np.ndarray:
    return 0.5 * (A + A.T)


__all__ = ["SosFitResult", "SosProgram", "solve", "svec_to_vec"]

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

The SDP ellipsoid (Eq. 3.11 with ``A ⪰ 0``, :mod:`.ellipsoid`) is the same program with one block:
``a`` the unique entries of A, ``P`` the scaled permutation ``svec A = P a`` and no antisymmetric
block, started at ``A = I`` (:func:`.ellipsoid._ipm_program`).

``solve`` returns the optimum of the same convex program as Clarabel's (unique in ``a`` when R has
full rank), to the tolerances of :data:`~workbench.config.TOL` (``sos_ipm_*``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dpotrf as _potrf

from .. import config
from ._kernels import _gram_mats, _hkm_state, _hkm_step, _schur
from .sos import svec_index as _svec_index


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


class SosProgram:
    """The fixed part of the fit, built once per subspace dimension: the PSD blocks as linear maps
    of x, ``svec X_S = G x`` with ``G = [P Q]`` (a few entries per row) and ``svec X_A = α`` (the
    last n_A(n_A+1)/2 entries of x), laid out for the kernels (``layout``: G's CSR and CSC arrays,
    then each block's svec rows and columns, :func:`._kernels._gram_mats`), and the start
    (:func:`_start`).  Read-only."""

    def __init__(self, P: sp.spmatrix, Q: sp.spmatrix, n_S: int, n_A: int, a0: np.ndarray) -> None:
        """P, Q : :func:`.quartic._reduced_maps`; n_S, n_A : the blocks' sizes; a0 (L,) : the
        coefficients of ``(zᵀz)²`` (the strictly feasible start, :func:`_start`)."""
        self.L = P.shape[1]
        self.G = (sp.hstack([P, Q]) if n_A else sp.csr_matrix(P)).tocsr()
        Gc = self.G.tocsc()
        self.n_S, self.n_A = n_S, n_A
        self.layout = (
            self.G.indptr.astype(np.int64),
            self.G.indices.astype(np.int64),
            self.G.data.copy(),
            Gc.indptr.astype(np.int64),
            Gc.indices.astype(np.int64),
            Gc.data.copy(),
            *_svec_index(n_S),
            *_svec_index(n_A),
        )
        self.n_x = self.G.shape[1]
        self.degree = float(n_S + n_A)  # the barrier parameter: Σ block sizes
        self.start = _start(self, a0)
        for arr in [*self.layout, self.start[0], *self.start[1]]:
            arr.flags.writeable = False


def _start(blocks: SosProgram, a0: np.ndarray) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """A strictly feasible x (the quartic ``(zᵀz)²`` with ``A = 4 I``) and centred duals ``Z = X⁻¹``
    (``(Z_S, Z_A)``, Z_A (0, 0) without an antisymmetric block)."""
    x = np.zeros(blocks.n_x)
    x[: len(a0)] = a0
    iA, jA = blocks.layout[8:]
    x[len(a0) :] = np.where(iA == jA, 4.0, 0.0)  # svec(4 I)
    XS, XA = _gram_mats(x, blocks.layout, blocks.n_S, blocks.n_A, blocks.L)
    return x, (np.linalg.inv(XS), np.linalg.inv(XA) if blocks.n_A else np.zeros((0, 0)))


def solve(Rm: np.ndarray, c: np.ndarray, blocks: SosProgram) -> SosFitResult:
    """Minimise ``½‖Rm a − c‖²`` over SOS-convex quartics (module notes).

    Rm : (L, L) upper triangular R of the fit's QR, c : (L,) its right-hand side;
    blocks : the program of the subspace dimension (:class:`SosProgram`).
    Stops when the duality gap is below ``TOL.sos_ipm_gap`` of the objective or below
    ``TOL.sos_ipm_gap_floor × ½‖c‖²`` (½‖c‖²: the objective at a = 0; the floor decides a fit
    through its data) and the dual
    residual below ``TOL.sos_ipm_residual`` of ``1 + max|Rᵀc|``; at most ``TOL.sos_ipm_max_iter``
    iterations.  Where round-off stalls the gap above the floor (it halves no more in three
    iterations), or the iterations run out or lose definiteness, an iterate within Clarabel's own
    accuracy (``sos_ipm_gap`` of the objective, or of ``sos_ipm_gap × ½‖c‖²``) is returned with
    status "optimal_inaccurate".  Each iteration is two compiled kernels (``_kernels._hkm_state``: the blocks,
    residuals and Schur matrix; ``_kernels._hkm_step``: Mehrotra's predictor-corrector step)
    around one LAPACK Cholesky of the Schur matrix (:func:`_cholesky`).
    """
    tol = config.TOL
    Rm = np.ascontiguousarray(Rm, dtype=float)
    c = np.ascontiguousarray(c, dtype=float)
    L = Rm.shape[1]
    H = np.zeros((blocks.n_x, blocks.n_x))
    H[:L, :L] = Rm.T @ Rm
    g = np.zeros(blocks.n_x)
    g[:L] = -Rm.T @ c
    x, Zs = blocks.start[0].copy(), tuple(Z.copy() for Z in blocks.start[1])
    scale = 1.0 + float(np.abs(g).max())
    # the gap is relative to the objective, down to a floor × the objective at a = 0 (½‖c‖², the
    # data's own scale): a fit that nearly interpolates its wrenches (K near the coefficients)
    # has an objective ~0, and its coefficients are fixed only by a gap far below Clarabel's
    half_cc = 0.5 * float(c @ c)
    floor = tol.sos_ipm_gap_floor * half_cc
    data, consts = (H, g, Rm, c), (blocks.degree, tol.sos_ipm_step)
    loose, gaps = None, []
    try:
        for it in range(tol.sos_ipm_max_iter):
            Xs, F, Xi, gap, r_d, obj, S = _hkm_state(x, Zs, data, blocks.layout)
            grams = list(Xs[: 1 + (blocks.n_A > 0)])
            if np.abs(r_d).max() <= tol.sos_ipm_residual * scale:
                if gap <= max(tol.sos_ipm_gap * obj, floor):
                    return SosFitResult(True, x[:L].copy(), x[L:].copy(), grams, "optimal", it)
                if gap <= tol.sos_ipm_gap * max(obj, tol.sos_ipm_gap * half_cc):  # Clarabel's accuracy
                    loose = SosFitResult(True, x[:L].copy(), x[L:].copy(), grams, "optimal_inaccurate", it)
                    if len(gaps) >= 3 and gap > 0.5 * gaps[-3]:  # round-off stalls it above the floor
                        return loose
            gaps.append(gap)
            MU = _cholesky(S, (Zs, Xi, H, blocks.layout))
            x, Zs = _hkm_step(x, Zs, (Xs, F, Xi, r_d, gap), MU, blocks.layout, consts)
    except np.linalg.LinAlgError as exc:  # an iterate lost definiteness to round-off
        return loose or SosFitResult(False, None, None, None, f"numerical failure ({exc})", -1)
    return loose or SosFitResult(
        False, None, None, None, f"no convergence in {tol.sos_ipm_max_iter} iterations", tol.sos_ipm_max_iter
    )


def _cholesky(S: np.ndarray, schur_args: tuple, refine: int = 2) -> tuple[np.ndarray, np.ndarray, int]:
    """``(M, U, steps)`` for the step (:func:`._kernels._hkm_direction`): the upper Cholesky factor
    ``U = Lᵀ`` of the Schur matrix M from LAPACK's lower potrf (the faster of OpenBLAS's two),
    factored in place in ``S.T`` (M's upper triangle, :func:`._kernels._schur`, seen as the lower
    triangle of a column-major matrix), and no refinement (M, not read then, is S).  Near the
    optimum, where the Schur matrix's conditioning is lost to round-off, M is formed again in full
    from ``schur_args`` (``_schur``'s, the factorisation having overwritten S) and U is the factor
    of ``M + δ I`` with ``δ`` the smallest of ``TOL.sos_ipm_regularisation × 100^k × max diag M``
    (k = 0..3) that factors (Clarabel's static regularisation), with ``refine`` steps of
    iterative refinement against M itself for the step's solves."""
    L, info = _potrf(S.T, lower=True, clean=False, overwrite_a=True)
    if info == 0:
        return S, L.T, 0
    M = _schur(*schur_args, True)
    scale = float(np.abs(np.diag(M)).max())
    for k in range(4):
        delta = config.TOL.sos_ipm_regularisation * 100.0**k * scale
        L, info = _potrf((M + delta * np.eye(len(M))).T, lower=True, clean=False, overwrite_a=True)
        if info == 0:
            return M, L.T, refine
    raise np.linalg.LinAlgError(f"the Schur matrix is not positive definite (potrf info {info})")


__all__ = ["SosFitResult", "SosProgram", "solve"]

"""Sparse factorisation of a symmetric positive definite stiffness matrix, nested-dissection ordered.

SuperLU's default column ordering (COLAMD) fills the factor of a closed thin-walled
tube badly: the shell is a 2D surface closed in θ.  METIS's nested dissection (``pymetis``)
is the ordering made for such meshes: several times fewer non-zeros, a factor and solves an
order of magnitude faster, the same residual (docs/decisions.md).  The matrix is symmetric
positive definite, so SuperLU keeps that ordering (no pivoting: ``diag_pivot_thresh = 0``,
symmetric mode).

SuperLU solves several right-hand sides one after another, reading the whole factor
for each, so a column's solve is bound by memory bandwidth
(``results/benchmarks/wall_stiffness.json``).  A wall's contact
solve asks for dozens of columns at once, so ``factor_spd(..., blocked=True)`` also
keeps row-major copies of L and U and solves many columns together in
:mod:`workbench.fem._kernels` (each entry read once for all of them), from
``config.DEFAULTS.blocked_solve_min_rhs`` columns on.

Newton's method factors a new tangent of the same sparsity pattern at every iteration.
:class:`Refactor` does the symbolic analysis once per pattern and Dirichlet set and then
only the numeric Cholesky factorisation, by CHOLMOD's supernodal ``L Lᵀ`` (``cvxopt.cholmod``,
BLAS-3 on dense blocks of the factor), several times faster than SuperLU in the same order on
a wall's tangent (``results/benchmarks/newton.json``).  A tangent that is not positive
definite (a wall past a limit point) is factored by SuperLU instead; each such fallback is
logged and counted.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SPDFactor:
    """``K = P L U Pᵀ`` with ``perm`` the nested-dissection order; :meth:`solve` solves ``K x = b``.

    rows : None, or CSR copies ``(L, U)`` of the factor (``blocked=True`` in
    :func:`factor_spd`) for solving many right-hand sides together."""

    lu: spla.SuperLU
    perm: np.ndarray  # (n,) new position -> original index
    shape: tuple[int, int]
    rows: tuple[sp.csr_matrix, sp.csr_matrix] | None = None

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``K⁻¹ b`` for b (n,) or (n, k): with ``rows`` and at least
        ``config.DEFAULTS.blocked_solve_min_rhs`` columns (read now) in the blocked
        kernels, else by SuperLU (the same solution to rounding)."""
        from workbench.config import DEFAULTS

        b = np.asarray(b, dtype=float)
        if self.rows is not None and b.ndim == 2 and b.shape[1] >= DEFAULTS.blocked_solve_min_rhs:
            from ._kernels import _lower_unit_rows, _upper_rows

            L, U = self.rows
            x = np.ascontiguousarray(b[self.perm])
            _lower_unit_rows(L.indptr, L.indices, L.data, x)
            _upper_rows(U.indptr, U.indices, U.data, x)
        else:
            x = self.lu.solve(b[self.perm])
        out = np.empty_like(x)
        out[self.perm] = x
        return out


def nested_dissection(K: sp.spmatrix) -> np.ndarray:
    """METIS's nested-dissection order (n,) of the graph of a sparse symmetric ``K`` (n, n):
    position -> original index, the fill-reducing order :func:`factor_spd` eliminates in."""
    import pymetis

    K = sp.csr_matrix(K)
    if K.shape[0] != K.shape[1]:
        raise ValueError(f"K must be square; got {K.shape}")
    graph = K.copy()
    graph.setdiag(0)
    graph.eliminate_zeros()
    graph.sort_indices()
    perm, _ = pymetis.nested_dissection(pymetis.CSRAdjacency(graph.indptr, graph.indices))
    return np.asarray(perm, dtype=np.int64)


def csr_slots(rows: np.ndarray, cols: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The CSR pattern of an (n, n) matrix assembled from entries at ``rows``, ``cols`` (k,):
    ``(slot, indices, indptr)``, entry i summing into ``data[slot[i]]`` (duplicates share a slot),
    so each assembly with the same pattern is ``np.bincount(slot, values)`` into the fixed
    ``indices`` / ``indptr`` instead of a COO -> CSR conversion."""
    entry, slot = np.unique(np.asarray(rows, dtype=np.int64) * n + cols, return_inverse=True)
    return slot, entry % n, np.r_[0, np.cumsum(np.bincount(entry // n, minlength=n))]


def restrict_order(perm: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """An elimination order of the sub-matrix ``K[keep][:, keep]`` from one ``perm`` (n,) of
    ``K``: the kept indices in the order ``perm`` eliminates them, as positions (m,) into
    ``keep`` (m,) sorted int.  The sub-matrix's graph is an induced subgraph, so its fill in
    this order is contained in the fill of ``K`` in ``perm``: one ordering serves every
    Dirichlet set of a mesh (:func:`workbench.fem.wall_nonlinear.squeeze_nonlinear` orders once
    per grasp instead of once per Newton step)."""
    rank = np.empty(perm.size, dtype=np.int64)
    rank[perm] = np.arange(perm.size)
    return np.argsort(rank[keep], kind="stable")


class Refactor:
    """Cholesky factorisations of ``K[keep][:, keep]`` for a sequence of sparse symmetric ``K``
    (n, n) csr sharing one pattern (a Newton loop's tangents), CHOLMOD's symbolic analysis done
    once here, offered the elimination order ``order`` (m,) (positions into ``keep`` (m,) sorted
    int; e.g. :func:`restrict_order`) — CHOLMOD's default also tries AMD and METIS and keeps the
    order that fills least (:meth:`solve` applies whichever it kept).  :meth:`factor` then
    :meth:`solve` ``K_kk x = b``; a changing Dirichlet set needs no new analysis:
    ``factor(K, pinned)`` replaces those rows and columns by the identity's, keeping the pattern.
    Holds the current numeric factor: one user at a time.

    ``fallbacks`` counts the matrices that were not positive definite and went to SuperLU
    (:func:`factor_spd`, the same order; pivots on the diagonal, as before this class)."""

    def __init__(self, pattern: sp.csr_matrix, keep: np.ndarray, order: np.ndarray):
        from cvxopt import cholmod, matrix, spmatrix

        n = pattern.shape[0]
        keep = np.asarray(keep, dtype=np.int64)
        if keep.ndim != 1 or (keep.size and (np.any(np.diff(keep) <= 0) or keep[0] < 0 or keep[-1] >= n)):
            raise ValueError(f"keep must be sorted unique indices into 0..{n - 1}; got {keep}")
        m = keep.size
        self.keep, self.order, self.fallbacks = keep, np.asarray(order, dtype=np.int64), 0
        if self.order.shape != (m,):
            raise ValueError(
                f"order must be an elimination order of the {m} kept indices; got {self.order.shape}"
            )
        csr = sp.csr_matrix(pattern)
        if not csr.has_sorted_indices:
            raise ValueError("pattern's column indices must be sorted within rows (K.sort_indices())")
        loc = np.full(n, -1, dtype=np.int64)
        loc[keep] = np.arange(m)
        r = loc[np.repeat(np.arange(n), np.diff(csr.indptr))]
        c = loc[csr.indices]
        # the kept upper triangle in CSR order is the lower triangle in column-major order, CHOLMOD's
        # storage order (K symmetric; keep sorted keeps the order): no sort needed
        self._sel = np.flatnonzero((r >= 0) & (c >= r))
        self._row, self._col = c[self._sel], r[self._sel]  # lower-triangle (row >= col) coordinates
        self._diag = self._row == self._col
        self._indptr, self._indices = csr.indptr.copy(), csr.indices.copy()
        self._A = spmatrix(1.0, matrix(self._row), matrix(self._col), (m, m))
        self._F = cholmod.symbolic(self._A, p=matrix(self.order), uplo="L")
        self._lu: SPDFactor | None = None  # SuperLU's factor after a fallback

    def factor(self, K: sp.csr_matrix, pinned: np.ndarray | None = None) -> Refactor:
        """Factor ``K[keep][:, keep]`` (K (n, n) csr with the pattern given at construction), the
        rows and columns where ``pinned`` (m,) bool is true replaced by the identity's: then
        :meth:`solve` returns ``b`` there, and the other rows no longer see those unknowns — for
        Dirichlet values ``x_p``, pass ``b = x_p`` on the pinned rows and ``b_f − K_fp x_p`` on
        the others.  Returns self, for ``.factor(K).solve(b)``."""
        from cvxopt import cholmod, matrix

        if not (np.array_equal(K.indptr, self._indptr) and np.array_equal(K.indices, self._indices)):
            raise ValueError(
                "K's sparsity pattern differs from the one this Refactor was built for; build another"
            )
        v = K.data[self._sel]
        if pinned is not None:
            pinned = np.asarray(pinned, dtype=bool)
            if pinned.shape != self.keep.shape:
                raise ValueError(
                    f"pinned must be a ({self.keep.size},) bool mask of the kept dofs; got {pinned.shape}"
                )
            out = pinned[self._row] | pinned[self._col]
            v[out] = 0.0
            v[out & self._diag] = 1.0
        self._A.V = matrix(v)
        try:
            cholmod.numeric(self._A, self._F)
            self._lu = None
        except ArithmeticError as exc:  # not positive definite: LU with diagonal pivots
            self.fallbacks += 1
            log.info("Refactor: the matrix is not positive definite (CHOLMOD: %s); SuperLU instead", exc)
            m = self.keep.size
            low = sp.csc_matrix((v, (self._row, self._col)), shape=(m, m))
            self._lu = factor_spd(low + sp.tril(low, -1).T, perm=self.order)
        return self

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``x`` (m,) or (m, k) with ``K_kk x = b`` for the matrix of the last :meth:`factor`."""
        from cvxopt import cholmod, matrix

        if self._lu is not None:
            return self._lu.solve(b)
        b = np.asarray(b, dtype=float)
        X = matrix(np.asfortranarray(b if b.ndim == 2 else b[:, None]))
        cholmod.solve(self._F, X)
        x = np.array(X)
        return x if b.ndim == 2 else x[:, 0]


def cholesky(K: sp.spmatrix, perm: np.ndarray | None = None) -> Refactor:
    """One CHOLMOD Cholesky factorisation of a sparse symmetric positive definite ``K`` (n, n) in
    the elimination order ``perm`` (n,) (default :func:`nested_dissection`): ``.solve(b)`` for
    one or a few right-hand sides (many columns at once: :func:`factor_spd` with ``blocked``).
    Not positive definite: SuperLU in the same order, logged and counted in ``.fallbacks``
    (:class:`Refactor`).  Used by the full-mesh contact reference (one factor per active set),
    where it is faster than SuperLU (docs/decisions.md)."""
    K = sp.csr_matrix(K)
    if K.shape[0] != K.shape[1]:
        raise ValueError(f"K must be square; got {K.shape}")
    if not K.has_sorted_indices:
        K = K.sorted_indices()  # a sorted copy: the caller's matrix is left as it was
    perm = nested_dissection(K) if perm is None else np.asarray(perm, dtype=np.int64)
    return Refactor(K, np.arange(K.shape[0]), perm).factor(K)


def schur_compliance(K: sp.spmatrix, rows: np.ndarray) -> np.ndarray:
    """``(K⁻¹)[rows][:, rows]`` (m, m) of a sparse symmetric positive definite ``K`` (n, n): the
    compliance of the dofs ``rows`` (m,) with every other dof free, as the inverse of the Schur
    complement ``S = K_rr − K_ri K_ii⁻¹ K_ir``.

    The other dofs are eliminated first (METIS's nested dissection of ``K_ii``), ``rows`` last, so
    the trailing (m, m) block of the Cholesky factor (CHOLMOD, this order kept exactly) is
    ``S = L₂₂ L₂₂ᵀ`` and ``S⁻¹`` is two dense triangular solves — instead of m sparse solves
    through the whole factor, several times faster on fem-validation's Hertz blocks
    (docs/decisions.md).  Not positive definite: SuperLU's solves of the m columns instead,
    logged."""
    from cvxopt import cholmod, matrix, spmatrix

    K = sp.csr_matrix(K)
    n = K.shape[0]
    rows = np.asarray(rows, dtype=np.int64)
    if K.shape != (n, n) or rows.ndim != 1 or np.unique(rows).size != rows.size:
        raise ValueError(f"K must be square and rows unique indices; got K {K.shape}, rows {rows.shape}")
    if rows.size and (rows.min() < 0 or rows.max() >= n):
        raise ValueError(f"rows must index 0..{n - 1}; got {rows.min()}..{rows.max()}")
    m = rows.size
    inner = np.setdiff1d(np.arange(n), rows)
    order = np.concatenate([inner[nested_dissection(K[inner][:, inner])], rows]) if inner.size else rows
    low = sp.tril(K[order][:, order]).tocoo()
    A = spmatrix(matrix(low.data), matrix(low.row.astype(np.int64)), matrix(low.col.astype(np.int64)), (n, n))
    saved = dict(cholmod.options)
    # the order given, exactly: the rows' block must stay last (by default CHOLMOD also tries AMD and
    # METIS and keeps whichever fills least, then postorders the elimination tree)
    cholmod.options.update(nmethods=1, postorder=False)
    try:
        F = cholmod.symbolic(A, p=matrix(np.arange(n, dtype=np.int64)), uplo="L")
        cholmod.numeric(A, F)
    except ArithmeticError as exc:
        log.info("schur_compliance: K is not positive definite (CHOLMOD: %s); SuperLU solves instead", exc)
        lu = factor_spd(K)
        C = np.empty((m, m))
        for start in range(0, m, 512):
            cols = np.arange(start, min(start + 512, m))
            rhs = np.zeros((n, cols.size))
            rhs[rows[cols], np.arange(cols.size)] = 1.0
            C[:, cols] = lu.solve(rhs)[rows]
        return 0.5 * (C + C.T)
    finally:
        cholmod.options.clear()
        cholmod.options.update(saved)
    colptr, rowind, val = (np.asarray(v).ravel() for v in cholmod.getfactor(F).CCS)
    first = n - m
    L22 = np.zeros((m, m))
    for j in range(first, n):  # the trailing columns: rows >= first only (lower triangle)
        lo, hi = colptr[j], colptr[j + 1]
        L22[rowind[lo:hi] - first, j - first] = val[lo:hi]
    C = sla.cho_solve((L22, True), np.eye(m))
    return 0.5 * (C + C.T)  # symmetric up to round-off


def factor_spd(K: sp.spmatrix, *, blocked: bool = False, perm: np.ndarray | None = None) -> SPDFactor:
    """Factorise a sparse symmetric positive definite ``K`` (n, n) in nested-dissection order.

    blocked : also keep CSR copies of L and U (as much memory again as the factor) for
    solves of many right-hand sides at once (module docstring).  perm : an elimination
    order (n,) to use instead of computing :func:`nested_dissection` (e.g. one restricted
    from a larger matrix by :func:`restrict_order`)."""
    K = sp.csr_matrix(K)
    if K.shape[0] != K.shape[1]:
        raise ValueError(f"K must be square; got {K.shape}")
    if perm is None:
        perm = nested_dissection(K)
    else:
        perm = np.asarray(perm, dtype=np.int64)
        if perm.shape != (K.shape[0],) or not np.array_equal(np.sort(perm), np.arange(K.shape[0])):
            raise ValueError(
                f"perm must be a permutation of 0..{K.shape[0] - 1} (an elimination order of K); "
                f"got shape {perm.shape}"
            )
    Kp = K[perm][:, perm].tocsc()
    lu = spla.splu(Kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    rows = None
    if blocked:
        n = K.shape[0]
        if not (np.array_equal(lu.perm_r, np.arange(n)) and np.array_equal(lu.perm_c, np.arange(n))):
            # not expected without pivoting and with the natural column order; then SuperLU solves
            log.warning("factor_spd: SuperLU permuted the matrix; blocked solves off")
        else:
            rows = (lu.L.tocsr(), lu.U.tocsr())
            for M in rows:
                M.sort_indices()
    return SPDFactor(lu, perm, K.shape, rows)


__all__ = [
    "Refactor",
    "SPDFactor",
    "cholesky",
    "factor_spd",
    "nested_dissection",
    "restrict_order",
    "schur_compliance",
]

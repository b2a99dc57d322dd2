"""Sparse factorisation of a symmetric positive definite stiffness matrix, nested-dissection ordered.

SuperLU's default column ordering (COLAMD) fills the factor of a closed thin-walled
tube badly: the shell is a 2D surface closed in θ, and on the shampoo bottle's wall
(40,608 free dofs) it gave 131 M non-zeros in L + U, 31 s to factor and 0.19 s per
solve.  METIS's nested dissection (``pymetis``) is the ordering made for such
meshes: 22 M non-zeros, 1.6 s to factor and 0.01 s per solve on the same matrix,
same residual.  The matrix is symmetric positive definite, so SuperLU keeps that
ordering (no pivoting: ``diag_pivot_thresh = 0``, symmetric mode).

SuperLU solves several right-hand sides one after another, reading the whole factor
for each: ~11 ms a column on a wall, bound by memory bandwidth (25 GB/s of the factor
against 33 GB/s copy, ``results/benchmarks/wall_stiffness.json``).  A wall's contact
solve asks for dozens of columns at once, so ``factor_spd(..., blocked=True)`` also
keeps row-major copies of L and U and solves many columns together in
:mod:`workbench.fem._kernels` (each entry read once for all of them): 2.4× faster per column at
48 columns (``config.DEFAULTS.blocked_solve_min_rhs``).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
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


__all__ = ["SPDFactor", "factor_spd", "nested_dissection", "restrict_order"]

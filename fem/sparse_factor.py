"""Sparse factorisation of a symmetric positive definite stiffness matrix, nested-dissection ordered.

SuperLU's default column ordering (COLAMD) fills the factor of a closed thin-walled
tube badly: the shell is a 2D surface closed in θ, and on the shampoo bottle's wall
(40,608 free dofs) it gave 131 M non-zeros in L + U, 31 s to factor and 0.19 s per
solve.  METIS's nested dissection (``pymetis``) is the ordering made for such
meshes: 22 M non-zeros, 1.6 s to factor and 0.01 s per solve on the same matrix,
same residual.  The matrix is symmetric positive definite, so SuperLU keeps that
ordering (no pivoting: ``diag_pivot_thresh = 0``, symmetric mode).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


@dataclass(frozen=True)
class SPDFactor:
    """``K = P L U Pᵀ`` with ``perm`` the nested-dissection order; :meth:`solve` solves ``K x = b``."""

    lu: spla.SuperLU
    perm: np.ndarray  # (n,) new position -> original index
    shape: tuple[int, int]

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``K⁻¹ b`` for b (n,) or (n, k)."""
        x = self.lu.solve(np.asarray(b, dtype=float)[self.perm])
        out = np.empty_like(x)
        out[self.perm] = x
        return out


def factor_spd(K: sp.spmatrix) -> SPDFactor:
    """Factorise a sparse symmetric positive definite ``K`` (n, n) in nested-dissection order."""
    import pymetis

    K = sp.csr_matrix(K)
    if K.shape[0] != K.shape[1]:
        raise ValueError(f"K must be square; got {K.shape}")
    graph = K.copy()
    graph.setdiag(0)
    graph.eliminate_zeros()
    graph.sort_indices()
    perm, _ = pymetis.nested_dissection(pymetis.CSRAdjacency(graph.indptr, graph.indices))
    perm = np.asarray(perm, dtype=np.int64)
    Kp = K[perm][:, perm].tocsc()
    lu = spla.splu(Kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    return SPDFactor(lu, perm, K.shape)


__all__ = ["SPDFactor", "factor_spd"]

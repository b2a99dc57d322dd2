"""Polynomial bookkeeping for the SOS-convex quartic (thesis Eqs. 3.14–3.16).

For a homogeneous quartic ``f(x) = Σ_κ a_κ x^{d_κ}`` in ``n`` variables and the
auxiliary ``z``, SOS-convexity asks for ``M ⪰ 0`` (n² × n²) with
``zᵀ ∇²f(x) z = yᵀ M y``, ``y = x ⊗ z`` (Eqs. 3.14–3.15).  Both sides are
polynomials in monomials ``x^α z^β`` with ``|α| = |β| = 2``; matching their
coefficients gives ``V1 vec(M) = V2 a`` (Eq. 3.16).  For n = 6: 126
monomials, 441 equations, V1 441 × 1296, V2 441 × 126 — as in the thesis.

The Hessian biform of a quartic is symmetric in its two arguments,
``zᵀ∇²f(x) z = xᵀ∇²f(z) x`` (both are ``12 Σ c_jklm x_j x_k z_l z_m`` for the
symmetric coefficient tensor ``c``), so swapping ``x`` and ``z`` maps any Gram
matrix ``M`` to another one, and their mean is one that the swap leaves unchanged:
block diagonal in the basis of symmetric ``(x_i z_j + x_j z_i)/√2`` and
antisymmetric ``(x_i z_j − x_j z_i)/√2`` products (:func:`swap_blocks`).  Asking
for ``M`` in that form loses no SOS-convex quartic and splits the 36 × 36 PSD
cone into 21 × 21 and 15 × 15 (n = 6).
"""

from __future__ import annotations

from functools import lru_cache
from itertools import combinations_with_replacement

import numpy as np
import scipy.sparse as sp


@lru_cache(maxsize=16)
def exponents(n: int, degree: int) -> np.ndarray:
    """(L, n) int exponents of all monomials of total ``degree`` in n variables
    (graded lexicographic order); L = C(n + degree - 1, degree)."""
    rows = []
    for combo in combinations_with_replacement(range(n), degree):
        e = np.zeros(n, dtype=np.int64)
        for j in combo:
            e[j] += 1
        rows.append(e)
    out = np.array(rows, dtype=np.int64)
    out.flags.writeable = False
    return out


@lru_cache(maxsize=16)
def sos_convexity_maps(n: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Sparse ``V1`` (E × n⁴) and ``V2`` (E × L) of Eq. 3.16, E = C(n+1, 2)².

    ``vec(M)`` is column-major: entry ``(p, q)`` of M sits at ``p + q n²`` with
    ``p = i n + j`` indexing ``y_p = x_i z_j``.
    """
    quad = exponents(n, 2)
    row_of = {(tuple(a), tuple(b)): k for k, (a, b) in enumerate((a, b) for a in quad for b in quad)}
    unit = np.eye(n, dtype=np.int64)
    N = n * n
    # RHS: y_p y_q = x_i z_j x_k z_l  ->  x^(e_i+e_k) z^(e_j+e_l)
    r1, c1 = [], []
    for i in range(n):
        for j in range(n):
            for k in range(n):
                for l in range(n):
                    p, q = i * n + j, k * n + l
                    r1.append(row_of[(tuple(unit[i] + unit[k]), tuple(unit[j] + unit[l]))])
                    c1.append(p + q * N)
    V1 = sp.csr_matrix((np.ones(len(r1)), (r1, c1)), shape=(len(row_of), N * N))
    # LHS: z^T ∇²f z = Σ_jk z_j z_k ∂_j∂_k f; ∂_j∂_k x^d = d_j (d_k - δ_jk) x^(d - e_j - e_k)
    quart = exponents(n, 4)
    r2, c2, v2 = [], [], []
    for kappa, d in enumerate(quart):
        for j in range(n):
            for k in range(n):
                coef = d[j] * (d[k] - (j == k))
                if coef <= 0:
                    continue
                alpha = d - unit[j] - unit[k]
                r2.append(row_of[(tuple(alpha), tuple(unit[j] + unit[k]))])
                c2.append(kappa)
                v2.append(float(coef))
    V2 = sp.csr_matrix((v2, (r2, c2)), shape=(len(row_of), len(quart)))
    return V1, V2


@lru_cache(maxsize=16)
def swap_blocks(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Orthonormal ``T_s`` (n(n+1)/2, n²) and ``T_a`` (n(n−1)/2, n²): rows span the
    products ``y_p = x_i z_j`` (``p = i n + j``) that the swap ``x ↔ z`` keeps
    (symmetric) and negates (antisymmetric).  A swap-invariant Gram matrix is
    ``M = T_sᵀ S T_s + T_aᵀ A T_a`` with ``S, A ⪰ 0`` (module notes)."""
    sym, anti = [], []
    r = 1.0 / np.sqrt(2.0)
    for i in range(n):
        for j in range(i, n):
            v = np.zeros(n * n)
            if i == j:
                v[i * n + i] = 1.0
                sym.append(v)
                continue
            v[i * n + j], v[j * n + i] = r, r
            sym.append(v)
            w = np.zeros(n * n)
            w[i * n + j], w[j * n + i] = r, -r
            anti.append(w)
    T_s = np.array(sym)
    T_a = np.array(anti).reshape(-1, n * n)
    for T in (T_s, T_a):
        T.flags.writeable = False
    return T_s, T_a


@lru_cache(maxsize=16)
def svec_index(n: int) -> tuple[np.ndarray, np.ndarray]:
    """(row, column) of each entry of Clarabel's svec of an (n, n) symmetric matrix: the
    upper triangle (row <= column) column by column (shared by the quartic's solvers)."""
    i, j = np.triu_indices(n)
    order = np.lexsort((i, j))  # by column, then row
    return i[order], j[order]


def _powers(x: np.ndarray, degree: int) -> np.ndarray:
    """(n, degree + 1, N) powers x_j^k by repeated products; rows are contiguous
    so the gathers below copy whole rows."""
    xt = np.ascontiguousarray(x.T)
    out = np.empty((x.shape[1], degree + 1, x.shape[0]))
    out[:, 0] = 1.0
    for k in range(1, degree + 1):
        out[:, k] = out[:, k - 1] * xt
    return out


def monomials(x: np.ndarray, expo: np.ndarray) -> np.ndarray:
    """(N, L) values ``x^{d_κ}`` for points x : (N, n) and exponents (L, n)."""
    powers = _powers(x, int(expo.max()))
    out = powers[0][expo[:, 0]]  # (L, N)
    for j in range(1, x.shape[1]):
        out *= powers[j][expo[:, j]]
    return out.T

"""Private ``@njit`` kernels of the limit surfaces: math only, no validation (``quartic.py``
checks and lays out the arrays).  Flags come from ``config``."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..config import NUMBA_FLAGS, NUMBA_FLAGS_PARALLEL

#: points per parallel block: long enough for the inner loops to vectorise, short enough for
#: the block's rows to stay in L1
BLOCK = 128


@njit(**NUMBA_FLAGS_PARALLEL)
def _cubic_gradients(yt, factors, G, out):
    """``out[:, i] = Σ_q y_i^{e_q} G_q``: the gradient (r,) of a homogeneous quartic at each
    point, points by columns yt (r, N), from its cubic monomials — ``factors`` (L3, 3): the
    three coordinates whose product is monomial q — and the coefficient map G (L3, r)
    (``QuarticLS._grad_map``); out (r, N).  Blocks of points along the inner loops
    (they vectorise) instead of an (N, L3) monomial matrix streamed through memory."""
    r, n = yt.shape
    n_blocks = (n + BLOCK - 1) // BLOCK
    for b in prange(n_blocks):
        lo = b * BLOCK
        hi = min(n, lo + BLOCK)
        m = np.empty(hi - lo)
        for j in range(r):
            for k in range(lo, hi):
                out[j, k] = 0.0
        for q in range(factors.shape[0]):
            f0, f1, f2 = factors[q, 0], factors[q, 1], factors[q, 2]
            for k in range(lo, hi):
                m[k - lo] = yt[f0, k] * yt[f1, k] * yt[f2, k]
            for j in range(r):
                g = G[q, j]
                if g != 0.0:
                    for k in range(lo, hi):
                        out[j, k] += m[k - lo] * g


@njit(**NUMBA_FLAGS_PARALLEL)
def _quartic_values(yt, coef, out):  # noqa: C901 - Numba kernel: the nested sum is one fused loop nest per block
    """``out[k] = Σ_q coef_q y_k^{e_q}``: a homogeneous quartic at each point, points by
    columns yt (r, N), its coefficients coef (L,) in :func:`.sos.exponents` order — the sorted
    index tuples i <= j <= k <= l — evaluated as the nested sum
    ``Σ_i y_i Σ_{j>=i} y_j Σ_{k>=j} y_k Σ_{l>=k} c_ijkl y_l`` (at r = 6: 209 multiply-adds a
    point against ~400 through the gradient and Euler's relation); out (N,)."""
    r, n = yt.shape
    n_blocks = (n + BLOCK - 1) // BLOCK
    for b in prange(n_blocks):
        lo = b * BLOCK
        hi = min(n, lo + BLOCK)
        m = hi - lo
        s1 = np.empty(m)
        s2 = np.empty(m)
        s3 = np.empty(m)
        for t in range(m):
            out[lo + t] = 0.0
        q = 0
        for i in range(r):
            s1[:] = 0.0
            for j in range(i, r):
                s2[:] = 0.0
                for k in range(j, r):
                    s3[:] = 0.0
                    for ll in range(k, r):
                        c = coef[q]
                        q += 1
                        for t in range(m):
                            s3[t] += c * yt[ll, lo + t]
                    for t in range(m):
                        s2[t] += yt[k, lo + t] * s3[t]
                for t in range(m):
                    s1[t] += yt[j, lo + t] * s2[t]
            for t in range(m):
                out[lo + t] += yt[i, lo + t] * s1[t]


@njit(**NUMBA_FLAGS)
def _svec_kron(Z, Y, i, j, out):
    """``out`` (m, m): the svec Kronecker product of symmetric Z, Y (n, n) — the matrix of
    ``U ↦ svec(½(Z U Y + Y U Z))`` on svec vectors (the upper triangle by columns, off-diagonals
    times √2; entry p is (i[p], j[p])) — ``½ w_p u_q (Z_ik Y_lj + Z_il Y_kj + Y_ik Z_lj + Y_il Z_kj)``
    for p = (i, j), q = (k, l), w = 1 | √2 and u = ½ | 1/√2 on | off the diagonal.  Row by row
    from rows of Z and Y (Y_lj = Y_jl: both symmetric); the inner loop runs down a column of the
    triangle (k = 0..l: contiguous, it vectorises)."""
    m, n = i.shape[0], Z.shape[0]
    r2 = np.sqrt(2.0)
    h = 1.0 / r2  # u off the diagonal
    for p in range(m):
        a, b = i[p], j[p]
        za, zb, ya, yb = Z[a], Z[b], Y[a], Y[b]
        s = 0.5 if a == b else 0.5 * r2
        q = 0
        for l in range(n):
            c1, c2, c3, c4 = s * yb[l], s * za[l], s * zb[l], s * ya[l]
            for k in range(l):
                out[p, q + k] = (za[k] * c1 + yb[k] * c2 + ya[k] * c3 + zb[k] * c4) * h
            out[p, q + l] = 0.5 * (za[l] * c1 + yb[l] * c2 + ya[l] * c3 + zb[l] * c4)
            q += l + 1

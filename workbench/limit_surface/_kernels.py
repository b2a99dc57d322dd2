"""Private ``@njit`` kernels of the limit surfaces: math only, no validation (``quartic.py``
checks and lays out the arrays).  Flags come from ``config``."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..config import NUMBA_FLAGS_IEEE, NUMBA_FLAGS_PARALLEL

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


@njit(**NUMBA_FLAGS_IEEE)
def _svec_kron(Z, Y, i, j, out):
    """``out`` (m, m): the svec Kronecker product of symmetric Z, Y (n, n) — the matrix of
    ``U ↦ svec(½(Z U Y + Y U Z))`` on svec vectors (the upper triangle by columns, off-diagonals
    times √2; entry p is (i[p], j[p])) — ``½ w_p u_q (Z_ik Y_lj + Z_il Y_kj + Y_ik Z_lj + Y_il Z_kj)``
    for p = (i, j), q = (k, l), w = 1 | √2 and u = ½ | 1/√2 on | off the diagonal (Y_lj = Y_jl:
    both symmetric).  Each row of Z and Y is first spread over the svec entries (``ZI[a, q] =
    Z[a, i[q]]``, ``ZJ[a, q] = Z[a, j[q]]``, the same for Y), so that a row of ``out`` is one
    contiguous loop over all q (it vectorises) rather than a short loop per column."""
    m, n = i.shape[0], Z.shape[0]
    r2 = np.sqrt(2.0)
    h = 1.0 / r2  # u off the diagonal
    ZI, ZJ = np.empty((n, m)), np.empty((n, m))
    YI, YJ = np.empty((n, m)), np.empty((n, m))
    u = np.empty(m)
    for a in range(n):
        for q in range(m):
            ZI[a, q], ZJ[a, q] = Z[a, i[q]], Z[a, j[q]]
            YI[a, q], YJ[a, q] = Y[a, i[q]], Y[a, j[q]]
    for q in range(m):
        u[q] = 0.5 if i[q] == j[q] else h
    for p in range(m):
        a, b = i[p], j[p]
        s = 0.5 if a == b else 0.5 * r2
        zia, zja, yia, yja = ZI[a], ZJ[a], YI[a], YJ[a]
        zib, zjb, yib, yjb = ZI[b], ZJ[b], YI[b], YJ[b]
        row = out[p]
        for q in range(m):
            c1, c2, c3, c4 = s * yjb[q], s * zja[q], s * zjb[q], s * yja[q]
            row[q] = (zia[q] * c1 + yib[q] * c2 + yia[q] * c3 + zib[q] * c4) * u[q]


# --- the quartic fit's interior point (sos_ipm.py): one iteration's dense algebra -------------
# IEEE flags: with fastmath, a process that compiled these kernels and one that loaded them from
# the cache rounded differently (config.NUMBA_FLAGS_IEEE), and the fit amplifies round-off


@njit(**NUMBA_FLAGS_IEEE)
def _smat(v, i, j, n):
    """The symmetric (n, n) matrix of the svec vector v (entry p at (i[p], j[p]), off-diagonals
    times √2)."""
    X = np.empty((n, n))
    h = 1.0 / np.sqrt(2.0)
    for p in range(i.shape[0]):
        a, b = i[p], j[p]
        if a == b:
            X[a, a] = v[p]
        else:
            X[a, b] = v[p] * h
            X[b, a] = v[p] * h
    return X


@njit(**NUMBA_FLAGS_IEEE)
def _add_svec(U, i, j, out, off):
    """``out[off + p] += svec(½(U + Uᵀ))[p]``: the adjoint of :func:`_smat`."""
    h = 1.0 / np.sqrt(2.0)
    for p in range(i.shape[0]):
        a, b = i[p], j[p]
        if a == b:
            out[off + p] += U[a, a]
        else:
            out[off + p] += (U[a, b] + U[b, a]) * h


@njit(**NUMBA_FLAGS_IEEE)
def _csr_matvec(ptr, idx, val, x):
    """``G x`` for G in CSR arrays (rows = len(ptr) - 1)."""
    m = ptr.shape[0] - 1
    y = np.zeros(m)
    for q in range(m):
        s = 0.0
        for t in range(ptr[q], ptr[q + 1]):
            s += val[t] * x[idx[t]]
        y[q] = s
    return y


@njit(**NUMBA_FLAGS_IEEE)
def _gram_mats(x, lay, nS, nA, L):
    """The Gram blocks of x: ``X_S = smat(G x)`` (nS, nS) and ``X_A = smat(x[L:])`` (nA, nA);
    ``lay`` = (G's CSR ptr, idx, val, its CSC ptr, idx, val, i_S, j_S, i_A, j_A): the program's
    layout (``sos_ipm.SosProgram.layout``)."""
    XS = _smat(_csr_matvec(lay[0], lay[1], lay[2], x), lay[6], lay[7], nS)
    XA = _smat(x[L:], lay[8], lay[9], nA)
    return XS, XA


@njit(**NUMBA_FLAGS_IEEE)
def _adjoint(US, UA, lay, n_x, L):
    """``Gᵀ svec(U_S) + [0; svec(U_A)]`` (n_x,): the x-gradient of ``tr(U_S X_S) + tr(U_A X_A)``."""
    ptr, idx, val = lay[0], lay[1], lay[2]
    vS = np.zeros(ptr.shape[0] - 1)
    _add_svec(US, lay[6], lay[7], vS, 0)
    out = np.zeros(n_x)
    for q in range(vS.shape[0]):
        for t in range(ptr[q], ptr[q + 1]):
            out[idx[t]] += val[t] * vS[q]
    _add_svec(UA, lay[8], lay[9], out, L)
    return out


@njit(**NUMBA_FLAGS_IEEE)
def _tril_inverse(C):
    """The inverse of a lower-triangular (n, n) C by forward substitution, column by column."""
    n = C.shape[0]
    F = np.zeros((n, n))
    for j in range(n):
        F[j, j] = 1.0 / C[j, j]
        for i in range(j + 1, n):
            s = 0.0
            for k in range(j, i):
                s += C[i, k] * F[k, j]
            F[i, j] = -s / C[i, i]
    return F


@njit(**NUMBA_FLAGS_IEEE)
def _inv_factor(A):
    """``L⁻¹`` (n, n) of ``A = L Lᵀ ≻ 0`` (LinAlgError when A is not positive definite); (0, 0)
    for an empty block."""
    if A.shape[0] == 0:
        return np.zeros((0, 0))
    return _tril_inverse(np.ascontiguousarray(np.linalg.cholesky(A)))


@njit(**NUMBA_FLAGS_IEEE)
def _sym_triple(A, B, C):
    """``½(A B C + (A B C)ᵀ)`` for square A, B, C."""
    if A.shape[0] == 0:
        return np.zeros((0, 0))
    T = A @ B @ C
    return 0.5 * (T + T.T)


@njit(**NUMBA_FLAGS_IEEE)
def _schur(Zs, Xi, H, lay, full):
    """The Schur matrix ``M = H + Σ_b G_bᵀ (Z_b ⊛ X_b⁻¹) G_b`` (n_x, n_x) of the HKM direction
    at the duals ``Zs = (Z_S, Z_A)`` and ``Xi = (X_S⁻¹, X_A⁻¹)``, the layout ``lay``
    (:func:`_gram_mats`).  ``full``: M itself, row-major; else only its upper triangle, row-major,
    the strict lower triangle unset — ``S.T`` is then that triangle as the lower one of a
    column-major matrix, which LAPACK's lower potrf factors in place (the entries are M's to the
    bit: the same sums in the same order)."""
    ZS, ZA = Zs
    XiS, XiA = Xi
    # M = H + Gᵀ K G with K = Z_S ⊛ X_S⁻¹ (symmetric) and G sparse (~2 entries a row and a column):
    # W = (Gᵀ K)ᵀ = K G by rows of K, then each row a of M adds the rows q of W that column a of G
    # holds — every inner loop runs along a contiguous row
    ptr, idx, val = lay[0], lay[1], lay[2]
    n_x, mS, mA = H.shape[0], ptr.shape[0] - 1, lay[8].shape[0]
    K = np.empty((mS, mS))
    _svec_kron(ZS, XiS, lay[6], lay[7], K)
    Wt = np.zeros((n_x, mS))
    for q in range(mS):
        for t in range(ptr[q], ptr[q + 1]):
            b, v = idx[t], val[t]
            for p in range(mS):
                Wt[b, p] += v * K[q, p]
    W = np.ascontiguousarray(Wt.T)
    KA = np.empty((mA, mA))
    if mA > 0:
        _svec_kron(ZA, XiA, lay[8], lay[9], KA)
    return _schur_full(H, W, KA, lay) if full else _schur_upper(H, W, KA, lay)


@njit(**NUMBA_FLAGS_IEEE)
def _schur_full(H, W, KA, lay):
    """``M = H + Gᵀ W + [0 0; 0 KA]`` row-major (:func:`_schur`; G's CSC arrays in ``lay``)."""
    cptr, cidx, cval = lay[3], lay[4], lay[5]
    n_x, mA = H.shape[0], KA.shape[0]
    M = H.copy()
    for a in range(n_x):
        for t in range(cptr[a], cptr[a + 1]):
            q, v = cidx[t], cval[t]
            for b in range(n_x):
                M[a, b] += v * W[q, b]
    if mA > 0:
        M[n_x - mA :, n_x - mA :] += KA
    return M


@njit(**NUMBA_FLAGS_IEEE)
def _schur_upper(H, W, KA, lay):
    """The upper triangle of :func:`_schur_full`'s M (the same sums in the same order), row-major;
    the strict lower triangle unset."""
    cptr, cidx, cval = lay[3], lay[4], lay[5]
    n_x, mA = H.shape[0], KA.shape[0]
    L = n_x - mA
    S = np.empty((n_x, n_x))
    for a in range(n_x):
        m = n_x - a
        row, h = S[a, a:], H[a, a:]
        for k in range(m):  # on views from the diagonal: loops from 0 vectorise (no negative-index checks)
            row[k] = h[k]
        for t in range(cptr[a], cptr[a + 1]):
            v, w = cval[t], W[cidx[t], a:]
            for k in range(m):
                row[k] += v * w[k]
        if a >= L:
            ka = KA[a - L, a - L :]
            for k in range(m):
                row[k] += ka[k]
    return S


@njit(**NUMBA_FLAGS_IEEE)
def _hkm_state(x, Zs, data, lay):
    """One iteration's state of the HKM interior point (sos_ipm.py) at (x, Z = (Z_S, Z_A)) for
    ``data`` = (H, g, Rm, c) and the layout ``lay`` (:func:`_gram_mats`): the Gram blocks
    (X_S, X_A), the inverse Cholesky factors ``L⁻¹`` of (X_S, X_A, Z_S, Z_A), ``X⁻¹ = Fᵀ F`` of
    both blocks, the gap ``Σ tr(X Z)``, the dual residual ``H x + g − Σ G_bᵀ svec Z_b`` (n_x,),
    the objective ``½‖Rm x[:L] − c‖²`` and the Schur matrix's upper triangle S
    (:func:`_schur`)."""
    H, g, Rm, c = data
    ZS, ZA = Zs
    L, n_x = Rm.shape[1], x.shape[0]
    nS, nA = ZS.shape[0], ZA.shape[0]
    XS, XA = _gram_mats(x, lay, nS, nA, L)
    FXS, FZS = _inv_factor(XS), _inv_factor(ZS)
    FXA, FZA = _inv_factor(XA), _inv_factor(ZA)
    XiS = FXS.T @ FXS
    XiA = FXA.T @ FXA if nA > 0 else np.zeros((0, 0))
    gap = np.sum(XS * ZS) + np.sum(XA * ZA)
    r_d = H @ x + g - _adjoint(ZS, ZA, lay, n_x, L)
    res = Rm @ x[:L] - c
    obj = 0.5 * (res @ res)
    S = _schur(Zs, (XiS, XiA), H, lay, False)
    return (XS, XA), (FXS, FXA, FZS, FZA), (XiS, XiA), gap, r_d, obj, S


@njit(**NUMBA_FLAGS_IEEE)
def _cho_solve_upper(U, b):
    """``(Uᵀ U)⁻¹ b`` for upper-triangular U (only its upper triangle is read), laid out for a
    row-major U (sos_ipm's): the forward substitution subtracts four rows of U at a time from the
    unknowns below them (contiguous loops: they vectorise), the backward one sums four rows
    side by side instead of one chain of dependent subtractions.  Each unknown still subtracts
    its terms in the order of the one-at-a-time loops, so the result is theirs to the bit
    (naive.cho_solve_upper)."""
    n = b.shape[0]
    y = b.copy()
    k = 0
    while k + 4 <= n:  # Uᵀ y = b: y[i] = (b[i] − Σ_{k<i} U[k, i] y[k]) / U[i, i], k ascending
        t0 = y[k] / U[k, k]
        t1 = (y[k + 1] - U[k, k + 1] * t0) / U[k + 1, k + 1]
        t2 = ((y[k + 2] - U[k, k + 2] * t0) - U[k + 1, k + 2] * t1) / U[k + 2, k + 2]
        t3 = (((y[k + 3] - U[k, k + 3] * t0) - U[k + 1, k + 3] * t1) - U[k + 2, k + 3] * t2) / U[k + 3, k + 3]
        y[k], y[k + 1], y[k + 2], y[k + 3] = t0, t1, t2, t3
        r0, r1, r2, r3 = U[k, k + 4 :], U[k + 1, k + 4 :], U[k + 2, k + 4 :], U[k + 3, k + 4 :]
        rest = y[k + 4 :]  # views from 0: no negative-index checks in the loop (it vectorises)
        for i in range(n - k - 4):
            rest[i] = (((rest[i] - r0[i] * t0) - r1[i] * t1) - r2[i] * t2) - r3[i] * t3
        k += 4
    for j in range(k, n):
        y[j] /= U[j, j]
        for i in range(j + 1, n):
            y[i] -= U[j, i] * y[j]
    i = n - 1
    while i >= 3:  # U x = y: x[i] = (y[i] − Σ_{j>i} U[i, j] x[j]) / U[i, i], j descending
        s0, s1, s2, s3 = y[i], y[i - 1], y[i - 2], y[i - 3]
        m = n - 1 - i
        r0, r1, r2, r3 = U[i, i + 1 :], U[i - 1, i + 1 :], U[i - 2, i + 1 :], U[i - 3, i + 1 :]
        x = y[i + 1 :]
        for u in range(m):
            xj = x[m - 1 - u]
            s0 -= r0[m - 1 - u] * xj
            s1 -= r1[m - 1 - u] * xj
            s2 -= r2[m - 1 - u] * xj
            s3 -= r3[m - 1 - u] * xj
        t0 = s0 / U[i, i]
        t1 = (s1 - U[i - 1, i] * t0) / U[i - 1, i - 1]
        t2 = ((s2 - U[i - 2, i] * t0) - U[i - 2, i - 1] * t1) / U[i - 2, i - 2]
        t3 = (((s3 - U[i - 3, i] * t0) - U[i - 3, i - 1] * t1) - U[i - 3, i - 2] * t2) / U[i - 3, i - 3]
        y[i], y[i - 1], y[i - 2], y[i - 3] = t0, t1, t2, t3
        i -= 4
    for j in range(i, -1, -1):
        s = y[j]
        for k in range(n - 1, j, -1):
            s -= U[j, k] * y[k]
        y[j] = s / U[j, j]
    return y


@njit(**NUMBA_FLAGS_IEEE)
def _refined_solve(M, U, b, refine):
    """``M⁻¹ b`` from the Cholesky factor U of M (or of M + δI) with ``refine`` steps of
    iterative refinement against M."""
    x = _cho_solve_upper(U, b)
    for _ in range(refine):
        x += _cho_solve_upper(U, b - M @ x)
    return x


@njit(**NUMBA_FLAGS_IEEE)
def _tridiagonal(C):  # noqa: C901 - Numba kernel: one Householder step per column, its loops inline
    """Householder reduction of a symmetric (n, n) C to the tridiagonal ``QᵀCQ`` (Golub and Van
    Loan, Alg. 8.3.1): its diagonal d (n,) and off-diagonal e (n − 1,); the same eigenvalues."""
    n = C.shape[0]
    A = C.copy()
    e = np.zeros(max(n - 1, 0))
    v = np.empty(n)
    w = np.empty(n)
    for k in range(n - 2):
        o = k + 1  # the trailing block A[o:, o:] and the column below the diagonal, A[o:, k]
        m = n - o
        alpha = 0.0
        for i in range(m):
            v[i] = A[o + i, k]
            alpha += v[i] * v[i]
        alpha = np.sqrt(alpha)
        if alpha == 0.0:
            continue
        if v[0] > 0.0:
            alpha = -alpha
        v[0] -= alpha  # H x = alpha e_1 with H = I − β v vᵀ
        vv = 0.0
        for i in range(m):
            vv += v[i] * v[i]
        beta = 2.0 / vv
        pv = 0.0
        for i in range(m):  # p = β B v, row by row of the symmetric B
            s = 0.0
            for j in range(m):
                s += A[o + i, o + j] * v[j]
            w[i] = beta * s
            pv += w[i] * v[i]
        half = 0.5 * beta * pv
        for i in range(m):  # w = p − (β pᵀv / 2) v; B ← B − v wᵀ − w vᵀ
            w[i] -= half * v[i]
        for i in range(m):
            for j in range(m):
                A[o + i, o + j] -= v[i] * w[j] + w[i] * v[j]
        e[k] = alpha
    for k in range(max(n - 2, 0), n - 1):
        e[k] = A[k + 1, k]
    d = np.empty(n)
    for i in range(n):
        d[i] = A[i, i]
    return d, e


@njit(**NUMBA_FLAGS_IEEE)
def _count_below(d, e, sigma):
    """How many eigenvalues of the tridiagonal (d, e) are below sigma (Sturm's sequence: the
    negative pivots of its LDLᵀ minus sigma)."""
    count = 0
    q = 1.0
    tiny = 1e-300
    for i in range(d.shape[0]):
        off = e[i - 1] * e[i - 1] / q if i > 0 else 0.0
        q = d[i] - sigma - off
        if q == 0.0:
            q = -tiny  # a zero pivot counts as below: the count is then an upper bound
        if q < 0.0:
            count += 1
    return count


@njit(**NUMBA_FLAGS_IEEE)
def _smallest_eigenvalue(C):
    """The smallest eigenvalue of a symmetric (n, n) C, to ~1e-15 of its spectral width: a
    Householder tridiagonalisation and bisection by Sturm counts within Gershgorin's bounds —
    what a step length needs, at a fraction of a full eigenvalue solver's cost."""
    d, e = _tridiagonal(C)
    n = d.shape[0]
    lo, hi = np.inf, -np.inf
    for i in range(n):
        r = (abs(e[i - 1]) if i > 0 else 0.0) + (abs(e[i]) if i < n - 1 else 0.0)
        lo = min(lo, d[i] - r)
        hi = max(hi, d[i] + r)
    width = hi - lo
    if width <= 0.0:
        return lo
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if _count_below(d, e, mid) >= 1:
            hi = mid
        else:
            lo = mid
        if hi - lo <= 1e-15 * width:
            break
    return 0.5 * (lo + hi)


@njit(**NUMBA_FLAGS_IEEE)
def _lambda_min(F, D):
    """The smallest eigenvalue of ``F D Fᵀ`` (+inf for an empty block)."""
    if F.shape[0] == 0:
        return np.inf
    return _smallest_eigenvalue(F @ D @ F.T)


@njit(**NUMBA_FLAGS_IEEE)
def _max_step(F, dXS, dXA, dZS, dZA):
    """Largest t with ``X + t ΔX ⪰ 0`` and ``Z + t ΔZ ⪰ 0`` for both blocks (inf when every
    direction is PSD); F = the inverse factors (X_S, X_A, Z_S, Z_A) of :func:`_hkm_state`."""
    lam = min(
        min(_lambda_min(F[0], dXS), _lambda_min(F[1], dXA)),
        min(_lambda_min(F[2], dZS), _lambda_min(F[3], dZA)),
    )
    return np.inf if lam >= 0.0 else -1.0 / lam


@njit(**NUMBA_FLAGS_IEEE)
def _hkm_direction(sigma_mu, corr, Zs, Xi, MU, r_d, lay, L):
    """The HKM direction ``ΔZ = σμX⁻¹ − Z − corr − sym(X⁻¹ ΔX Z)`` with Δx from the Schur system
    (MU = (M, the Cholesky factor U of M or of M + δI, the refinement steps against M)):
    returns (Δx, ΔX_S, ΔX_A, ΔZ_S, ΔZ_A)."""
    ZS, ZA = Zs
    XiS, XiA = Xi
    n_x = r_d.shape[0]
    baseS = sigma_mu * XiS - ZS - corr[0]
    baseA = sigma_mu * XiA - ZA - corr[1]
    rhs = -r_d + _adjoint(baseS, baseA, lay, n_x, L)
    dx = _refined_solve(MU[0], MU[1], rhs, MU[2])
    dXS, dXA = _gram_mats(dx, lay, ZS.shape[0], ZA.shape[0], L)
    dZS = baseS - _sym_triple(XiS, dXS, ZS)
    dZA = baseA - _sym_triple(XiA, dXA, ZA)
    return dx, dXS, dXA, dZS, dZA


@njit(**NUMBA_FLAGS_IEEE)
def _hkm_step(x, Zs, state, MU, lay, consts):
    """Mehrotra's predictor-corrector step of the HKM direction from (x, Z = (Z_S, Z_A)), the
    ``state`` = (X, F, X⁻¹, r_d, gap) of :func:`_hkm_state` and MU of :func:`_hkm_direction`;
    ``consts`` = (the barrier parameter, the fraction of the step to the boundary both parts
    take).  Returns the new (x, Z_S, Z_A)."""
    ZS, ZA = Zs
    (XS, XA), F, Xi, r_d, gap = state
    degree, frac = consts
    L = x.shape[0] - lay[8].shape[0]
    zero = (np.zeros_like(ZS), np.zeros_like(ZA))
    dx, dXS, dXA, dZS, dZA = _hkm_direction(0.0, zero, Zs, Xi, MU, r_d, lay, L)
    t_aff = min(1.0, _max_step(F, dXS, dXA, dZS, dZA))
    gap_aff = np.sum((XS + t_aff * dXS) * (ZS + t_aff * dZS))
    gap_aff += np.sum((XA + t_aff * dXA) * (ZA + t_aff * dZA))
    sigma = (gap_aff / gap) ** 3
    corr = (_sym_triple(Xi[0], dXS, dZS), _sym_triple(Xi[1], dXA, dZA))
    dx, dXS, dXA, dZS, dZA = _hkm_direction(sigma * gap / degree, corr, Zs, Xi, MU, r_d, lay, L)
    t = min(1.0, frac * _max_step(F, dXS, dXA, dZS, dZA))
    return x + t * dx, (ZS + t * dZS, ZA + t * dZA)


@njit(**NUMBA_FLAGS_IEEE)
def _grid_keep(W, steps, rtol, tie):
    """One row of W (N, 6) per occupied grid cell (``downsample.grid_downsample``): per
    coordinate, cells of width ``(max - min) / steps`` from the minimum, ``floor(steps) + 1`` of
    them (the last reaching past the maximum), one cell where the width is at most ``rtol`` × the
    largest; the cell of row i is ``floor((W[i] - min) / width + tie)``.  Each cell keeps its
    first member, in row order, within ``tie`` of the members' nearest to their mean.  Returns
    the kept rows (one a cell, cells in key order).

    The arithmetic is that of the NumPy expressions the function had, in their order: cells by a
    stable sort of their row-major key, a cell's sum row after row, a distance's squares summed
    left to right (tests/test_downsample.py holds the per-cell loop)."""
    n_cells = int(np.floor(steps)) + 1
    key = _grid_keys(W, steps, rtol, tie, n_cells)
    return _cell_choice(W, key, _stable_order(key, n_cells**6), tie)


@njit(**NUMBA_FLAGS_IEEE)
def _grid_keys(W, steps, rtol, tie, n_cells):
    """(N,) row-major cell key of each row of W (N, 6) (:func:`_grid_keep`)."""
    n = W.shape[0]
    lo = W[0].copy()
    hi = W[0].copy()
    for i in range(1, n):
        for c in range(6):
            lo[c] = min(lo[c], W[i, c])
            hi[c] = max(hi[c], W[i, c])
    width = (hi - lo) / steps
    flat = width <= rtol * width.max()
    key = np.zeros(n, dtype=np.int64)
    # coordinate by coordinate, so that the loop over rows is a vector loop: the same key
    for c in range(6):
        if flat[c]:
            for i in range(n):
                key[i] = key[i] * n_cells
        else:
            lo_c, cell_c = lo[c], width[c]
            for i in range(n):
                q = min(max(int(np.floor((W[i, c] - lo_c) / cell_c + tie)), 0), n_cells - 1)
                key[i] = key[i] * n_cells + q
    return key


@njit(**NUMBA_FLAGS_IEEE)
def _stable_order(key, n_keys):
    """(N,) the order of a stable sort of ``key`` (N,) in [0, n_keys): counting sort when the
    keys are few (the usual 3^6 = 729 cells), else a merge sort."""
    n = key.shape[0]
    if n_keys > max(4 * n, 4096):
        return np.argsort(key, kind="mergesort")
    count = np.zeros(n_keys + 1, dtype=np.int64)
    for i in range(n):
        count[key[i] + 1] += 1
    for k in range(n_keys):
        count[k + 1] += count[k]
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        order[count[key[i]]] = i
        count[key[i]] += 1
    return order


@njit(**NUMBA_FLAGS_IEEE)
def _cell_choice(W, key, order, tie):
    """The kept row of each run of equal keys along ``order`` (:func:`_grid_keep`)."""
    n = W.shape[0]
    keep = np.empty(n, dtype=np.int64)
    dist = np.empty(n)  # each member's distance, computed once
    n_keep = 0
    mean = np.empty(6)
    s = 0
    while s < n:
        e = s + 1
        while e < n and key[order[e]] == key[order[s]]:
            e += 1
        mean[:] = W[order[s]]
        for j in range(s + 1, e):
            for c in range(6):
                mean[c] += W[order[j], c]
        mean /= e - s
        best = np.inf
        for j in range(s, e):
            dist[j] = _row_distance(W, order[j], mean)
            best = min(best, dist[j])
        j = s
        while dist[j] > best + tie:
            j += 1
        keep[n_keep] = order[j]
        n_keep += 1
        s = e
    return keep[:n_keep]


@njit(**NUMBA_FLAGS_IEEE)
def _row_distance(W, i, mean):
    """|W[i] - mean| as np.linalg.norm(axis=1) sums it: the squares left to right."""
    acc = 0.0
    for c in range(6):
        x = W[i, c] - mean[c]
        acc += x * x
    return np.sqrt(acc)

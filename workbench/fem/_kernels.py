"""Private ``@njit`` kernels of the condensed contact solve, of the sparse factor's
blocked triangular solves, of the element loops of the nonlinear wall and pad and of the
mesh obstacles' point-triangle distances (math only; the callers in ``contact.py``,
``sparse_factor.py``, ``svk.py``, ``nonlinear.py`` and ``obstacles.py`` own validation).
NumPy references: ``tests/naive.py`` (the point-triangle distance's: trimesh's ``closest_point``).

Imported as ``workbench.fem._kernels`` (the folder installs under ``workbench``); Numba's
on-disk cache of these kernels is keyed by this file's timestamp, so an edit here also
retires the entries compiled when the module was called ``fem._kernels``."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from workbench.config import NUMBA_FLAGS, NUMBA_FLAGS_IEEE, NUMBA_FLAGS_PARALLEL


@njit(**NUMBA_FLAGS_PARALLEL)
def _normal_rows(C: np.ndarray, nodes: np.ndarray, nrm: np.ndarray, out: np.ndarray) -> None:
    """``out[k, :] = Σ_a nrm[nodes[k], a] C[3 nodes[k] + a, :]``: the compliance rows
    of each node projected on its normal (reads three contiguous rows of C per node,
    no gathered copy of C)."""
    m = C.shape[1]
    for k in prange(nodes.size):
        i = nodes[k]
        n0, n1, n2 = nrm[i, 0], nrm[i, 1], nrm[i, 2]
        r0, r1, r2 = 3 * i, 3 * i + 1, 3 * i + 2
        for j in range(m):
            out[k, j] = n0 * C[r0, j] + n1 * C[r1, j] + n2 * C[r2, j]


@njit(**NUMBA_FLAGS_PARALLEL)
def _normal_block(G: np.ndarray, nodes: np.ndarray, nrm: np.ndarray, out: np.ndarray) -> None:
    """``out[k, l] = Σ_b G[k, 3 nodes[l] + b] nrm[nodes[l], b]`` = n_kᵀ C_kl n_l."""
    for k in prange(out.shape[0]):
        for l in range(nodes.size):
            j = nodes[l]
            out[k, l] = G[k, 3 * j] * nrm[j, 0] + G[k, 3 * j + 1] * nrm[j, 1] + G[k, 3 * j + 2] * nrm[j, 2]


@njit(**NUMBA_FLAGS)
def _lower_unit_rows(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray, X: np.ndarray) -> None:
    """In place ``X <- L⁻¹ X`` for a unit lower-triangular ``L`` in CSR (its stored
    diagonal ignored) and ``X`` (n, k): row by row, each entry of L read once for all k
    columns (SuperLU reads the factor once per column)."""
    k = X.shape[1]
    acc = np.empty(k)
    for i in range(X.shape[0]):
        for c in range(k):
            acc[c] = X[i, c]
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j < i:
                v = data[p]
                for c in range(k):
                    acc[c] -= v * X[j, c]
        for c in range(k):
            X[i, c] = acc[c]


@njit(**NUMBA_FLAGS)
def _upper_rows(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray, X: np.ndarray) -> None:
    """In place ``X <- U⁻¹ X`` for an upper-triangular ``U`` in CSR with its diagonal
    stored, ``X`` (n, k), from the last row up."""
    k = X.shape[1]
    acc = np.empty(k)
    for i in range(X.shape[0] - 1, -1, -1):
        d = 0.0
        for c in range(k):
            acc[c] = X[i, c]
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j > i:
                v = data[p]
                for c in range(k):
                    acc[c] -= v * X[j, c]
            elif j == i:
                d = data[p]
        for c in range(k):
            X[i, c] = acc[c] / d


@njit(**NUMBA_FLAGS)
def _svk_element_loop(  # noqa: C901, PLR0913, PLR0915 - Numba kernel: one fused loop per element over flat arrays
    G: np.ndarray,
    w: np.ndarray,
    dofs: np.ndarray,
    u: np.ndarray,
    mu: float,
    lam: float,
    slot: np.ndarray,
    data: np.ndarray,
    r: np.ndarray,
    tangent: bool,
) -> None:
    """St. Venant–Kirchhoff internal force and tangent, element by element, added into ``r``
    (N,) and the CSR values ``data`` (entry (a, b) of element e at ``slot[(e n_k + a) n_k + b]``).

    G : (e, q, nn, 3) scalar shape-function gradients; w : (e, q) weights × det J; dofs :
    (e, 3 nn) global dof of local dof 3 n + i (node n, component i).  Per Gauss point, with
    ``B_ni = (F ∇N_n)_i``: ``K[(n,i),(p,m)] += w (δ_im ∇N_n·S∇N_p + λ B_ni B_pm + μ B_nm B_pi
    + μ (F Fᵀ)_im ∇N_n·∇N_p)``, ``r[(n,i)] += w (P ∇N_n)_i`` (``wall_nonlinear`` module
    docstring); each (n, p) pair once, the transposed block copied."""
    n_e, n_q, nn = G.shape[0], G.shape[1], G.shape[2]
    nk = 3 * nn
    Ke = np.zeros((nk, nk))
    F = np.empty((3, 3))
    S = np.empty((3, 3))
    P = np.empty((3, 3))
    FF = np.empty((3, 3))
    B = np.empty((nn, 3))
    SG = np.empty((nn, 3))
    Gq = np.empty((nn, 3))
    for e in range(n_e):
        if tangent:
            Ke[:, :] = 0.0
        for q in range(n_q):
            wq = w[e, q]
            for n in range(nn):
                for J in range(3):
                    Gq[n, J] = G[e, q, n, J]
            for i in range(3):
                for J in range(3):
                    F[i, J] = 1.0 if i == J else 0.0
            for n in range(nn):
                for i in range(3):
                    un = u[dofs[e, 3 * n + i]]
                    for J in range(3):
                        F[i, J] += un * Gq[n, J]
            trE = 0.0
            for I in range(3):
                for J in range(3):
                    c = -1.0 if I == J else 0.0
                    for i in range(3):
                        c += F[i, I] * F[i, J]
                    S[I, J] = mu * c  # 2 mu E, E = (FᵀF - I) / 2
                    if I == J:
                        trE += 0.5 * c
            for I in range(3):
                S[I, I] += lam * trE
            for i in range(3):
                for J in range(3):
                    c = 0.0
                    for L in range(3):
                        c += F[i, L] * S[L, J]
                    P[i, J] = c
            for n in range(nn):
                for i in range(3):
                    pg = P[i, 0] * Gq[n, 0] + P[i, 1] * Gq[n, 1] + P[i, 2] * Gq[n, 2]
                    r[dofs[e, 3 * n + i]] += wq * pg
            if not tangent:
                continue
            for i in range(3):
                for m in range(3):
                    FF[i, m] = wq * mu * (F[i, 0] * F[m, 0] + F[i, 1] * F[m, 1] + F[i, 2] * F[m, 2])
            for n in range(nn):
                for i in range(3):
                    B[n, i] = F[i, 0] * Gq[n, 0] + F[i, 1] * Gq[n, 1] + F[i, 2] * Gq[n, 2]
                    SG[n, i] = wq * (S[i, 0] * Gq[n, 0] + S[i, 1] * Gq[n, 1] + S[i, 2] * Gq[n, 2])
            wl, wm = wq * lam, wq * mu
            for n in range(nn):
                g0, g1, g2 = Gq[n, 0], Gq[n, 1], Gq[n, 2]
                bn0, bn1, bn2 = B[n, 0], B[n, 1], B[n, 2]
                for p in range(n, nn):
                    H = g0 * SG[p, 0] + g1 * SG[p, 1] + g2 * SG[p, 2]
                    D = g0 * Gq[p, 0] + g1 * Gq[p, 1] + g2 * Gq[p, 2]
                    bp0, bp1, bp2 = B[p, 0], B[p, 1], B[p, 2]
                    a, b = 3 * n, 3 * p
                    Ke[a, b] += H + wl * bn0 * bp0 + wm * bn0 * bp0 + FF[0, 0] * D
                    Ke[a, b + 1] += wl * bn0 * bp1 + wm * bn1 * bp0 + FF[0, 1] * D
                    Ke[a, b + 2] += wl * bn0 * bp2 + wm * bn2 * bp0 + FF[0, 2] * D
                    Ke[a + 1, b] += wl * bn1 * bp0 + wm * bn0 * bp1 + FF[1, 0] * D
                    Ke[a + 1, b + 1] += H + wl * bn1 * bp1 + wm * bn1 * bp1 + FF[1, 1] * D
                    Ke[a + 1, b + 2] += wl * bn1 * bp2 + wm * bn2 * bp1 + FF[1, 2] * D
                    Ke[a + 2, b] += wl * bn2 * bp0 + wm * bn0 * bp2 + FF[2, 0] * D
                    Ke[a + 2, b + 1] += wl * bn2 * bp1 + wm * bn1 * bp2 + FF[2, 1] * D
                    Ke[a + 2, b + 2] += H + wl * bn2 * bp2 + wm * bn2 * bp2 + FF[2, 2] * D
        if not tangent:
            continue
        for n in range(nn):  # the lower blocks are the upper ones transposed
            for p in range(n + 1, nn):
                for i in range(3):
                    for m in range(3):
                        Ke[3 * p + m, 3 * n + i] = Ke[3 * n + i, 3 * p + m]
        base = e * nk * nk
        for a in range(nk):
            for b in range(nk):
                data[slot[base + a * nk + b]] += Ke[a, b]


@njit(**NUMBA_FLAGS)
def _neo_hookean_element_loop(  # noqa: C901, PLR0913, PLR0915 - Numba kernel: one fused loop per element over flat arrays
    G: np.ndarray,
    dx: np.ndarray,
    edofs: np.ndarray,
    u: np.ndarray,
    mu: float,
    kappa: float,
    slot: np.ndarray,
    data: np.ndarray,
    r: np.ndarray,
) -> float:
    """Decoupled neo-Hookean internal force and tangent of one quadrature rule, added into ``r``
    (N,) and the CSR values ``data`` (entry (a c, b d) of element e at ``slot[((e nn + a) 3 + c)
    3 nn + 3 b + d]``); returns the smallest det F met (≤ 0: an element inverted, nothing valid).

    G : (e, q, nn, 3) shape-function gradients; dx : (e, q) weights × det J; edofs : (e, nn, 3)
    global dofs.  With ``h = F⁻ᵀ∇N``, ``f = F∇N``, ``s = (F − I₁/3 F⁻ᵀ)∇N`` per node and
    ``a = J^(-2/3)`` (``workbench/fem/nonlinear.py`` module docstring, contracted with the gradients):
    ``K[a c, b d] += dx (μa δ_cd ∇N_a·∇N_b − ⅔μa (s_ac h_bd + h_ac f_bd) + (μa I₁/3 − κ ln J)
    h_bc h_ad + κ h_ac h_bd)``, ``r[a c] += dx (P ∇N_a)_c``."""
    n_e, n_q, nn = G.shape[0], G.shape[1], G.shape[2]
    nk = 3 * nn
    F = np.empty((3, 3))
    Fi = np.empty((3, 3))  # F⁻ᵀ
    P = np.empty((3, 3))
    Sd = np.empty((3, 3))
    h = np.empty((nn, 3))
    f = np.empty((nn, 3))
    s = np.empty((nn, 3))
    Ke = np.zeros((nk, nk))
    jmin = np.inf
    for e in range(n_e):
        Ke[:, :] = 0.0
        for q in range(n_q):
            w = dx[e, q]
            for c in range(3):
                for l in range(3):
                    F[c, l] = 1.0 if c == l else 0.0
            for a in range(nn):
                for c in range(3):
                    ua = u[edofs[e, a, c]]
                    for l in range(3):
                        F[c, l] += ua * G[e, q, a, l]
            c00 = F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1]
            c01 = F[1, 2] * F[2, 0] - F[1, 0] * F[2, 2]
            c02 = F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0]
            J = F[0, 0] * c00 + F[0, 1] * c01 + F[0, 2] * c02
            jmin = min(jmin, J)
            if J <= 0.0:
                continue
            # F⁻ᵀ = cofactor(F) / J
            Fi[0, 0], Fi[0, 1], Fi[0, 2] = c00 / J, c01 / J, c02 / J
            Fi[1, 0] = (F[0, 2] * F[2, 1] - F[0, 1] * F[2, 2]) / J
            Fi[1, 1] = (F[0, 0] * F[2, 2] - F[0, 2] * F[2, 0]) / J
            Fi[1, 2] = (F[0, 1] * F[2, 0] - F[0, 0] * F[2, 1]) / J
            Fi[2, 0] = (F[0, 1] * F[1, 2] - F[0, 2] * F[1, 1]) / J
            Fi[2, 1] = (F[0, 2] * F[1, 0] - F[0, 0] * F[1, 2]) / J
            Fi[2, 2] = (F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]) / J
            I1 = 0.0
            for c in range(3):
                for l in range(3):
                    I1 += F[c, l] * F[c, l]
            ma = mu * J ** (-2.0 / 3.0)
            lnJ = np.log(J)
            for c in range(3):
                for l in range(3):
                    Sd[c, l] = F[c, l] - I1 / 3.0 * Fi[c, l]
                    P[c, l] = ma * Sd[c, l] + kappa * lnJ * Fi[c, l]
            for a in range(nn):
                for c in range(3):
                    ga0, ga1, ga2 = G[e, q, a, 0], G[e, q, a, 1], G[e, q, a, 2]
                    r[edofs[e, a, c]] += w * (P[c, 0] * ga0 + P[c, 1] * ga1 + P[c, 2] * ga2)
                    h[a, c] = Fi[c, 0] * ga0 + Fi[c, 1] * ga1 + Fi[c, 2] * ga2
                    f[a, c] = F[c, 0] * ga0 + F[c, 1] * ga1 + F[c, 2] * ga2
                    s[a, c] = Sd[c, 0] * ga0 + Sd[c, 1] * ga1 + Sd[c, 2] * ga2
            k_id = w * ma
            k_dev = w * 2.0 / 3.0 * ma
            k_cross = w * (ma * I1 / 3.0 - kappa * lnJ)
            k_vol = w * kappa
            for a in range(nn):
                for b in range(nn):
                    D = 0.0
                    for l in range(3):
                        D += G[e, q, a, l] * G[e, q, b, l]
                    for c in range(3):
                        for d in range(3):
                            v = (
                                -k_dev * (s[a, c] * h[b, d] + h[a, c] * f[b, d])
                                + k_cross * h[b, c] * h[a, d]
                                + k_vol * h[a, c] * h[b, d]
                            )
                            if c == d:
                                v += k_id * D
                            Ke[3 * a + c, 3 * b + d] += v
        base = e * nk * nk
        for i in range(nk):
            for j in range(nk):
                data[slot[base + i * nk + j]] += Ke[i, j]
    return jmin


# ------------------------------------------------------------------ point-triangle distances
# trimesh.triangles.closest_point (Ericson, Real-Time Collision Detection §5.1.5) one pair at a
# time, operation for operation: its NumPy rows become scalars, so these kernels compile with
# NUMBA_FLAGS_IEEE (no FMA contraction or reassociation) and give its numbers bit for bit.


@njit(**NUMBA_FLAGS_IEEE)
def _dot3(a0: float, a1: float, a2: float, b0: float, b1: float, b2: float) -> float:
    """``a·b`` summed in NumPy's order for a row of three (``np.dot(a * b, ones)``)."""
    return a0 * b0 + a1 * b1 + a2 * b2


@njit(**NUMBA_FLAGS_IEEE)
def _closest_on_triangle(
    tris: np.ndarray, t: int, x: np.ndarray, i: int, L: float, zero: float
) -> tuple[float, float, float, float]:
    """The point of triangle ``tris[t]`` (3 corners × 3) closest to ``x[i]`` and its distance,
    computed in the frame centred at ``x[i]`` and scaled by ``L`` — ``closest_point((tris[t] -
    x[i]) / L, 0) * L``, then ``+ x[i]`` — with trimesh's region tests (tolerance ``zero``) in its
    order: a collapsed edge AB first (the segment AC), then vertex A, vertex B, edge AB, vertex C,
    edge AC, edge BC, the face."""
    x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
    a0, a1, a2 = (tris[t, 0, 0] - x0) / L, (tris[t, 0, 1] - x1) / L, (tris[t, 0, 2] - x2) / L
    b0, b1, b2 = (tris[t, 1, 0] - x0) / L, (tris[t, 1, 1] - x1) / L, (tris[t, 1, 2] - x2) / L
    c0, c1, c2 = (tris[t, 2, 0] - x0) / L, (tris[t, 2, 1] - x1) / L, (tris[t, 2, 2] - x2) / L
    ab0, ab1, ab2 = b0 - a0, b1 - a1, b2 - a2
    ac0, ac1, ac2 = c0 - a0, c1 - a1, c2 - a2
    # the query point is the origin: p - a = 0 - a (as trimesh subtracts, signed zeros alike)
    ap0, ap1, ap2 = 0.0 - a0, 0.0 - a1, 0.0 - a2
    d1 = _dot3(ab0, ab1, ab2, ap0, ap1, ap2)
    d2 = _dot3(ac0, ac1, ac2, ap0, ap1, ap2)
    bp0, bp1, bp2 = 0.0 - b0, 0.0 - b1, 0.0 - b2
    d3 = _dot3(ab0, ab1, ab2, bp0, bp1, bp2)
    d4 = _dot3(ac0, ac1, ac2, bp0, bp1, bp2)
    cp0, cp1, cp2 = 0.0 - c0, 0.0 - c1, 0.0 - c2
    d5 = _dot3(ab0, ab1, ab2, cp0, cp1, cp2)
    d6 = _dot3(ac0, ac1, ac2, cp0, cp1, cp2)
    vc = d1 * d4 - d3 * d2
    vb = d5 * d2 - d1 * d6
    va = d3 * d6 - d5 * d4
    if ab0 == 0.0 and ab1 == 0.0 and ab2 == 0.0:
        # A = B: the segment AC (a point if C = A too); trimesh writes it over vertex A's result
        ls = _dot3(ac0, ac1, ac2, ac0, ac1, ac2)
        f = _dot3(ap0, ap1, ap2, ac0, ac1, ac2) / ls if ls > 0.0 else 0.0
        f = min(max(f, 0.0), 1.0)
        r0, r1, r2 = a0 + f * ac0, a1 + f * ac1, a2 + f * ac2
    elif d1 < zero and d2 < zero:
        r0, r1, r2 = a0, a1, a2
    elif d3 > -zero and d4 <= d3:
        r0, r1, r2 = b0, b1, b2
    elif vc < zero and d1 > -zero and d3 < zero:
        v = d1 / (d1 - d3)
        r0, r1, r2 = a0 + v * ab0, a1 + v * ab1, a2 + v * ab2
    elif d6 > -zero and d5 <= d6:
        r0, r1, r2 = c0, c1, c2
    elif vb < zero and d2 > -zero and d6 < zero:
        w = d2 / (d2 - d6)
        r0, r1, r2 = a0 + w * ac0, a1 + w * ac1, a2 + w * ac2
    elif va < zero and (d4 - d3) > -zero and (d5 - d6) > -zero:
        d43 = d4 - d3
        w = d43 / (d43 + (d5 - d6))
        r0, r1, r2 = b0 + w * (c0 - b0), b1 + w * (c1 - b1), b2 + w * (c2 - b2)
    else:
        denom = 1.0 / (va + vb + vc)
        v = vb * denom
        w = vc * denom
        r0, r1, r2 = a0 + ab0 * v + ac0 * w, a1 + ab1 * v + ac1 * w, a2 + ab2 * v + ac2 * w
    q0, q1, q2 = r0 * L, r1 * L, r2 * L
    return q0 + x0, q1 + x1, q2 + x2, np.sqrt(_dot3(q0, q1, q2, q0, q1, q2))


@njit(**NUMBA_FLAGS_IEEE)
def _point_triangle_pairs(
    tris: np.ndarray,
    x: np.ndarray,
    owner: np.ndarray,
    tri: np.ndarray,
    L: float,
    zero: float,
    pts: np.ndarray,
    dist: np.ndarray,
) -> None:
    """``pts[k]`` (m, 3), ``dist[k]`` (m,): the point of triangle ``tris[tri[k]]`` closest to
    ``x[owner[k]]`` and its distance (:func:`_closest_on_triangle`)."""
    for k in range(tri.size):
        p0, p1, p2, d = _closest_on_triangle(tris, tri[k], x, owner[k], L, zero)
        pts[k, 0], pts[k, 1], pts[k, 2], dist[k] = p0, p1, p2, d


@njit(**NUMBA_FLAGS_IEEE)
def _nearest_of_candidates(
    tris: np.ndarray,
    x: np.ndarray,
    cand: np.ndarray,
    L: float,
    zero: float,
    pts: np.ndarray,
    dist: np.ndarray,
    which: np.ndarray,
) -> None:
    """Per point ``x[i]``, the nearest of its candidate triangles ``cand[i]`` (n, k): its
    closest point ``pts[i]``, distance ``dist[i]`` and triangle ``which[i]``, the first of equal
    distances and the first NaN as ``argmin`` picks them (:func:`_closest_on_triangle`)."""
    for i in range(cand.shape[0]):
        best_j = 0
        b0, b1, b2, best = _closest_on_triangle(tris, cand[i, 0], x, i, L, zero)
        if best == best:  # a NaN distance is argmin's pick at once
            for j in range(1, cand.shape[1]):
                p0, p1, p2, d = _closest_on_triangle(tris, cand[i, j], x, i, L, zero)
                if d < best or d != d:
                    best_j, b0, b1, b2, best = j, p0, p1, p2, d
                    if d != d:
                        break
        pts[i, 0], pts[i, 1], pts[i, 2], dist[i] = b0, b1, b2, best
        which[i] = cand[i, best_j]

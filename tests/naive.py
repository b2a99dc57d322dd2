"""Slow, obviously-correct NumPy references of every kernel (stumpy ``naive.py`` style).

These follow the thesis equations literally, element by element or fully
vectorized, without sharing code with ``workbench``.  ``fw_vectorized`` is
also the "vectorized NumPy reference" that benchmarks time against.
"""

from __future__ import annotations

import numpy as np

TANGENTIAL_RTOL = 1e-12  # same sticking rule as workbench.config (restated, not imported)


def pressure_center(centers, areas, pressures):
    """Eq. 3.7."""
    f = pressures * areas
    return (centers * f[:, None]).sum(0) / f.sum()


def fw_loop(centers, normals, areas, pressures, twist, mu):
    """One frictional wrench by an explicit loop over elements, Eqs. 3.6–3.8."""
    o = pressure_center(centers, areas, pressures)
    v, w = np.asarray(twist[:3], float), np.asarray(twist[3:], float)
    f = np.zeros(3)
    tau = np.zeros(3)
    for c, n, a, p in zip(centers, normals, areas, pressures, strict=True):
        r = c - o
        u = v + np.cross(w, r)
        t = (np.eye(3) - np.outer(n, n)) @ u
        tn = np.linalg.norm(t)
        if tn <= TANGENTIAL_RTOL * np.linalg.norm(u):
            continue
        df = -mu * p * a * t / tn
        f += df
        tau += np.cross(r, df)
    return np.concatenate([f, tau])


def fw_vectorized(centers, normals, areas, pressures, twists, mu):
    """(K, 6) frictional wrenches, fully vectorized over (K, N) with NumPy."""
    o = pressure_center(centers, areas, pressures)
    r = centers - o  # (N, 3)
    v = twists[:, None, :3]  # (K, 1, 3)
    w = twists[:, None, 3:]
    u = v + np.cross(w, r[None])  # (K, N, 3)
    d = np.einsum("knj,nj->kn", u, normals)
    t = u - d[..., None] * normals[None]
    tn = np.linalg.norm(t, axis=2)
    un = np.linalg.norm(u, axis=2)
    slip = tn > TANGENTIAL_RTOL * un
    s = np.where(slip, pressures * areas / np.where(slip, tn, 1.0), 0.0)  # (K, N)
    g = s[..., None] * t
    f = g.sum(axis=1)
    tau = np.cross(r[None], g).sum(axis=1)
    return -mu * np.hstack([f, tau])


def normal_wrench(centers, normals, areas, pressures):
    """Eq. 3.2 discretised."""
    o = pressure_center(centers, areas, pressures)
    g = (pressures * areas)[:, None] * normals
    return -np.concatenate([g.sum(0), np.cross(centers - o, g).sum(0)])


def triangle_geometry(vertices, faces):
    """Centroids, unit normals (right-hand rule) and areas of triangles, one at a time."""
    c, n, a = [], [], []
    for f in faces:
        p0, p1, p2 = vertices[f[0]], vertices[f[1]], vertices[f[2]]
        cr = np.cross(p1 - p0, p2 - p0)
        c.append((p0 + p1 + p2) / 3)
        a.append(0.5 * np.linalg.norm(cr))
        n.append(cr / np.linalg.norm(cr))
    return np.array(c), np.array(n), np.array(a)


def random_profile(rng, n, curved=True):
    """Random elements: points on a bumpy patch with normals from its gradient."""
    xy = rng.uniform(-0.01, 0.01, (n, 2))
    if curved:
        z = 30.0 * xy[:, 0] ** 2 - 20.0 * xy[:, 1] ** 2 + 5.0 * xy[:, 0] * xy[:, 1]
        grad = np.column_stack([60.0 * xy[:, 0] + 5.0 * xy[:, 1], -40.0 * xy[:, 1] + 5.0 * xy[:, 0]])
    else:
        z = np.zeros(n)
        grad = np.zeros((n, 2))
    centers = np.column_stack([xy, z])
    normals = np.column_stack([-grad, np.ones(n)])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    areas = rng.uniform(0.5, 1.5, n) * 4e-6
    pressures = rng.uniform(0.0, 2e5, n)
    return centers, normals, areas, pressures


def monomial_hessians(x, expo):
    """(N, n, n, L) Hessians ``∂_j ∂_k x^{d_κ}`` of every monomial, term by term —
    the slow reference for ``QuarticLS.hessian_subspace``."""
    n = x.shape[1]
    powers = x[:, :, None] ** np.arange(expo.max() + 1)[None, None, :]
    out = np.empty((x.shape[0], n, n, expo.shape[0]))
    for j in range(n):
        for k in range(j, n):
            e = expo.copy()
            coef = e[:, j].astype(float)
            e[:, j] = np.maximum(e[:, j] - 1, 0)
            coef = coef * e[:, k]
            e[:, k] = np.maximum(e[:, k] - 1, 0)
            term = coef[None, :] * np.ones((x.shape[0], 1))
            for i in range(n):
                term = term * powers[:, i, e[:, i]]
            out[:, j, k] = term
            out[:, k, j] = term
    return out


def monomial_gradients(x, expo):
    """(N, n, L) gradients ``∂_j x^{d_κ} = d_j x^{d_κ - e_j}`` of every monomial, term by
    term — the slow reference for ``QuarticLS``'s gradients and values (the kernel
    ``limit_surface._kernels._cubic_gradients``)."""
    n = x.shape[1]
    out = np.empty((x.shape[0], n, expo.shape[0]))
    for j in range(n):
        e = expo.copy()
        coef = e[:, j].astype(float)
        e[:, j] = np.maximum(e[:, j] - 1, 0)
        term = coef[None, :] * np.ones((x.shape[0], 1))
        for i in range(n):
            term = term * x[:, i : i + 1] ** e[None, :, i]
        out[:, j] = term
    return out


def normal_rows(C, nodes, nrm):
    """``n_kᵀ C[k-block, :]`` per node by reshaping (reference of workbench.fem._kernels._normal_rows)."""
    n = C.shape[0] // 3
    return np.einsum("ka,kaj->kj", nrm[nodes], C.reshape(n, 3, -1)[nodes])


def normal_block(G, nodes, nrm):
    """``Σ_b G[k, 3 j + b] n_jb`` over the listed nodes j (reference of _normal_block)."""
    n = G.shape[1] // 3
    return np.einsum("kjb,jb->kj", G.reshape(len(G), n, 3)[:, nodes, :], nrm[nodes])


def lower_unit_solve(L, B):
    """Slow reference of ``workbench.fem._kernels._lower_unit_rows``: forward substitution with a
    dense unit lower-triangular ``L`` (n, n) (its diagonal ignored) on ``B`` (n, k)."""
    X = np.array(B, dtype=float)
    for i in range(len(X)):
        for j in range(i):
            X[i] -= L[i, j] * X[j]
    return X


def upper_solve(U, B):
    """Slow reference of ``workbench.fem._kernels._upper_rows``: back substitution with a dense
    upper-triangular ``U`` (n, n) on ``B`` (n, k)."""
    X = np.array(B, dtype=float)
    for i in range(len(X) - 1, -1, -1):
        for j in range(i + 1, len(X)):
            X[i] -= U[i, j] * X[j]
        X[i] /= U[i, i]
    return X


def isotropic_elasticity_form():
    """The hand-written isotropic elasticity form ``2μ ε(u):ε(v) + λ tr ε(u) tr ε(v)`` that
    workbench/fem/wall.py used before scikit-fem's ``linear_elasticity`` (field values ``mu``, ``lam``)."""
    from skfem import BilinearForm
    from skfem.helpers import ddot, sym_grad, trace

    @BilinearForm
    def form(u, v, w):
        eu, ev = sym_grad(u), sym_grad(v)
        return 2.0 * w["mu"] * ddot(eu, ev) + w["lam"] * trace(eu) * trace(ev)

    return form


def rodrigues(v):
    """(K, 3, 3) rotation matrices of axis-angle vectors (K, 3) by Rodrigues' formula (what
    grasp/robust.py computed before scipy's ``Rotation.from_rotvec``)."""
    v = np.asarray(v, float)
    th = np.linalg.norm(v, axis=-1, keepdims=True)
    k = np.divide(v, th, out=np.zeros_like(v), where=th > 0)
    K = np.zeros((*v.shape[:-1], 3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -k[..., 2], k[..., 1], -k[..., 0]
    K = K - np.swapaxes(K, -1, -2)
    s, c = np.sin(th)[..., None], np.cos(th)[..., None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def point_triangle_closest(tris, x, L, zero=1e-13):
    """Slow reference of ``workbench.fem._kernels._closest_on_triangle``: trimesh's
    ``closest_point`` (Ericson's region tests, whole rows at a time) on the triangles (m, 3, 3)
    moved to the query points ``x`` (m, 3) and scaled by ``L``, then back — what
    ``MeshObstacle`` computed before the kernel.  ``zero`` must be trimesh's own ``tol.zero``
    (its region tests read that).  Returns the closest points (m, 3) and distances (m,)."""
    from trimesh.constants import tol
    from trimesh.triangles import closest_point

    assert zero == tol.zero, "trimesh's closest_point tests regions with its own tol.zero"
    local = (np.asarray(tris, float) - x[:, None, :]) / L
    q = closest_point(local, np.zeros((len(x), 3))) * L
    return q + x, np.linalg.norm(q, axis=1)


def point_triangle_pairs(tris, x, owner, tri, L, zero, pts, dist):
    """``workbench.fem._kernels._point_triangle_pairs`` (same arguments) by
    :func:`point_triangle_closest`."""
    pts[:], dist[:] = point_triangle_closest(tris[tri], x[owner], L, zero)


def nearest_of_candidates(tris, x, cand, L, zero, pts, dist, which):
    """``workbench.fem._kernels._nearest_of_candidates`` (same arguments): every candidate by
    :func:`point_triangle_closest`, then ``argmin`` per point."""
    n, k = cand.shape
    p, d = point_triangle_closest(tris[cand.ravel()], np.repeat(x, k, axis=0), L, zero)
    j = d.reshape(n, k).argmin(axis=1)
    rows = np.arange(n)
    pts[:], dist[:], which[:] = p.reshape(n, k, 3)[rows, j], d.reshape(n, k)[rows, j], cand[rows, j]


def svec_kron(Z, Y):
    """The matrix of ``U ↦ svec(½(Z U Y + Y U Z))`` built column by column from its definition:
    svec = the upper triangle by columns, off-diagonal entries times √2."""
    n = len(Z)
    idx = [(i, j) for j in range(n) for i in range(j + 1)]

    def svec(U):
        return np.array([U[i, j] * (1.0 if i == j else np.sqrt(2.0)) for i, j in idx])

    cols = []
    for k, l in idx:
        U = np.zeros((n, n))
        U[k, l] = U[l, k] = 1.0 if k == l else 1.0 / np.sqrt(2.0)
        cols.append(svec(0.5 * (Z @ U @ Y + Y @ U @ Z)))
    return np.array(cols).T


def cho_solve_upper(U, b):
    """``(Uᵀ U)⁻¹ b`` by the two substitutions one unknown at a time, each sum in index order (the
    order the quartic IPM's kernel keeps): forward ``Uᵀ y = b`` with k ascending, then back
    ``U x = y`` subtracting column by column from the last."""
    n = len(b)
    y = np.array(b, dtype=float)
    for i in range(n):
        s = y[i]
        for k in range(i):
            s -= U[k, i] * y[k]
        y[i] = s / U[i, i]
    for i in range(n - 1, -1, -1):
        y[i] /= U[i, i]
        for k in range(i):
            y[k] -= U[k, i] * y[i]
    return y


def _svec_maps(n):
    """(to_vec (n², m), from_vec (m, n²)) dense: svec (upper triangle by columns, off-diagonals
    times √2) to row-major ravel and back (for symmetric matrices)."""
    idx = [(i, j) for j in range(n) for i in range(j + 1)]
    to_vec = np.zeros((n * n, len(idx)))
    for p, (i, j) in enumerate(idx):
        w = 1.0 if i == j else 1.0 / np.sqrt(2.0)
        to_vec[i * n + j, p] = to_vec[j * n + i, p] = w
    return to_vec, to_vec.T


def hkm_reference(Rm, c, G, n_S, n_A, x0, tol=(1e-8, 1e-20, 1e-8, 60, 0.99)):
    """The quartic fit's HKM interior point (sos_ipm.py) in dense NumPy, step by step:
    ``min ½‖Rm x[:L] − c‖²`` s.t. ``smat(G x) ⪰ 0`` (n_S) and ``smat(x[L:]) ⪰ 0`` (n_A), from the
    strictly feasible x0 with Z = X⁻¹, Mehrotra's predictor-corrector, the Schur matrix
    ``H + Σ Gᵀ (Z ⊛ X⁻¹) G`` built column by column (:func:`svec_kron`) and solved by
    ``np.linalg.solve``; ``tol`` = (gap, gap floor, residual, iterations, step fraction) as
    config's ``sos_ipm_*``: it stops when the gap is below ``gap`` of the objective or ``floor`` of
    ½‖c‖² and the dual residual below ``residual`` of 1 + max|Rᵀc|.  Returns (x, [X_S, X_A],
    iterations) or None without convergence."""
    gap_tol, floor_tol, res_tol, max_iter, frac = tol
    L, n_x = Rm.shape[1], len(x0)
    tS, fS = _svec_maps(n_S)
    tA, fA = _svec_maps(n_A)
    GA = np.hstack([np.zeros((n_A * (n_A + 1) // 2, L)), np.eye(n_A * (n_A + 1) // 2)])
    blocks = [(np.asarray(G, float), tS, fS, n_S)] + ([(GA, tA, fA, n_A)] if n_A else [])
    H = np.zeros((n_x, n_x))
    H[:L, :L] = Rm.T @ Rm
    g = np.zeros(n_x)
    g[:L] = -Rm.T @ c

    def mats(v):
        return [(t @ (Gb @ v)).reshape(n, n) for Gb, t, _, n in blocks]

    def adjoint(Us):
        pairs = zip(blocks, Us, strict=True)
        return sum(Gb.T @ (f @ (0.5 * (U + U.T)).ravel()) for (Gb, _, f, _), U in pairs)

    def max_step(Ps, Ds):
        Fs = [np.linalg.inv(np.linalg.cholesky(P)) for P in Ps]
        lam = min(np.linalg.eigvalsh(F @ D @ F.T)[0] for F, D in zip(Fs, Ds, strict=True))
        return np.inf if lam >= 0 else -1.0 / lam

    x = np.array(x0, float)
    Zs = [np.linalg.inv(X) for X in mats(x)]
    scale, floor = 1.0 + np.abs(g).max(), floor_tol * 0.5 * (c @ c)
    degree = float(n_S + n_A)
    for it in range(max_iter):
        Xs = mats(x)
        Xi = [np.linalg.inv(X) for X in Xs]
        gap = sum(np.sum(X * Z) for X, Z in zip(Xs, Zs, strict=True))
        r_d = H @ x + g - adjoint(Zs)
        obj = 0.5 * np.sum((Rm @ x[:L] - c) ** 2)
        if gap <= max(gap_tol * obj, floor) and np.abs(r_d).max() <= res_tol * scale:
            return x, Xs, it
        M = H + sum(Gb.T @ svec_kron(Z, Y) @ Gb for (Gb, *_), Z, Y in zip(blocks, Zs, Xi, strict=True))

        def direction(sigma_mu, corr, Xi=Xi, M=M, r_d=r_d, Zs=Zs):
            base = [sigma_mu * Y - Z - k for Y, Z, k in zip(Xi, Zs, corr, strict=True)]
            dx = np.linalg.solve(M, -r_d + adjoint(base))
            dX = mats(dx)
            dZ = [b - 0.5 * (Y @ D @ Z + (Y @ D @ Z).T) for b, Y, D, Z in zip(base, Xi, dX, Zs, strict=True)]
            return dx, dX, dZ

        dx, dX, dZ = direction(0.0, [0.0 * Z for Z in Zs])
        t_aff = min(1.0, max_step(Xs + Zs, dX + dZ))
        quads = zip(Xs, dX, Zs, dZ, strict=True)
        gap_aff = sum(np.sum((X + t_aff * D) * (Z + t_aff * E)) for X, D, Z, E in quads)
        corr = [0.5 * (Y @ D @ E + (Y @ D @ E).T) for Y, D, E in zip(Xi, dX, dZ, strict=True)]
        dx, dX, dZ = direction((gap_aff / gap) ** 3 * gap / degree, corr)
        t = min(1.0, frac * max_step(Xs + Zs, dX + dZ))
        x, Zs = x + t * dx, [Z + t * E for Z, E in zip(Zs, dZ, strict=True)]
    return None


def frame_coordinates(points, c, frame):
    """(n, 3) coordinates (u, v, z) of ``points`` (n, 3) from ``c`` along ``frame`` rows (a, e1,
    e2): each a sum of three products, left to right (the compiled pre-selection's arithmetic)."""
    r = np.asarray(points, float) - c
    a, e1, e2 = frame
    return np.column_stack([r[:, 0] * e[0] + r[:, 1] * e[1] + r[:, 2] * e[2] for e in (e1, e2, a)])


def faces_may_overlap(V, F, c, frame, box, tol):
    """Faces whose (u, v, z) bounding box meets ``box`` widened by ``tol``, and whether each meets
    it narrowed by ``tol``: one face at a time."""
    uvz = frame_coordinates(V, c, frame)
    out, sure = [], []
    for f, tri in enumerate(F):
        p = uvz[tri]
        lo, hi = p.min(axis=0), p.max(axis=0)
        if all(lo[k] <= box[2 * k + 1] + tol and hi[k] >= box[2 * k] - tol for k in range(3)):
            out.append(f)
            sure.append(all(lo[k] <= box[2 * k + 1] - tol and hi[k] >= box[2 * k] + tol for k in range(3)))
    return np.array(out, dtype=np.int64), np.array(sure, dtype=bool)


def elements_may_touch(cen, nrm, area, rows, c, frame, box, facing_max, tol):  # noqa: PLR0913 - the kernel's arguments
    """The rows whose element has area, a normal with n·a below facing_max + tol and a centre in
    ``box`` widened by ``tol``."""
    a = frame[0]
    uvz = frame_coordinates(cen[rows], c, frame)
    facing = nrm[rows, 0] * a[0] + nrm[rows, 1] * a[1] + nrm[rows, 2] * a[2] < facing_max + tol
    ok = (area[rows] > 0) & facing
    for k in range(3):
        ok &= (uvz[:, k] >= box[2 * k] - tol) & (uvz[:, k] <= box[2 * k + 1] + tol)
    return rows[ok]


def front_most(u, v, z, idx, u_lo, v_lo, cell, n_v, reach):  # noqa: PLR0913 - the kernel's arguments
    """The elements ``idx`` within ``reach`` of their footprint bin's least z, by a dict of bins."""
    front = {}
    bins = {}
    for i in idx:
        b = int(np.floor((u[i] - u_lo) / cell)) * n_v + int(np.floor((v[i] - v_lo) / cell))
        bins[i] = b
        front[b] = min(front.get(b, np.inf), z[i])
    visible = np.zeros(len(u), dtype=bool)
    for i in idx:
        visible[i] = z[i] <= front[bins[i]] + reach
    return visible


def front_surface(cen, normal, area, c, frame, pad, poly, window, filter_window, max_edge, min_facing):  # noqa: PLR0913 - a press's settings, flat
    """A REACH pad's reachable surface by NumPy alone, every element tested (the press's algorithm
    before its compiled passes): ``(visible (n,) bool, z (n,))``, or ``(None, None)`` when no
    element faces the jaw inside the footprint.  ``pad`` (w, l) is a centred rectangle, or
    ``poly`` (k, 2) the footprint (even-odd rule); coordinates by the frame's matrix products."""
    a, e1, e2 = frame
    if poly is None:
        (u_lo, v_lo), v_hi = (-pad[0] / 2, -pad[1] / 2), pad[1] / 2
    else:
        (u_lo, v_lo), v_hi = poly.min(axis=0), poly.max(axis=0)[1]
    lo, hi = window
    rel = cen - c
    u, v, z = rel @ e1, rel @ e2, rel @ a
    facing = normal @ a < -min_facing
    if poly is None:
        inside = (np.abs(u) <= pad[0] / 2) & (np.abs(v) <= pad[1] / 2)
    else:
        inside = np.zeros(len(u), bool)
        for (x0, y0), (x1, y1) in zip(poly, np.roll(poly, -1, axis=0), strict=True):
            if y0 != y1:
                inside ^= ((y0 > v) != (y1 > v)) & (u < x0 + (v - y0) * ((x1 - x0) / (y1 - y0)))
    keep = inside & facing & (area > 0)
    if filter_window:
        keep &= (z >= lo) & (z <= hi)
    if not keep.any():
        return None, None
    idx = np.flatnonzero(keep)
    iu = np.floor((u[idx] - u_lo) / max_edge).astype(int)
    iv = np.floor((v[idx] - v_lo) / max_edge).astype(int)
    bins = iu * (int((v_hi - v_lo) / max_edge) + 2) + iv
    order = np.lexsort((z[idx], bins))
    first = np.r_[True, bins[order][1:] != bins[order][:-1]]
    front_z = np.repeat(z[idx][order][first], np.diff(np.r_[np.flatnonzero(first), len(order)]))
    visible = np.zeros(len(cen), dtype=bool)
    visible[idx[order]] = z[idx][order] <= front_z + 2 * max_edge
    return visible, z


def author_grid(L, level):
    """The author's twist grid (``twists_author.sample_twists_author``) by NumPy expressions: the
    offset axes (sphere point × offsets d1, d2, row-major), then the axes through o, at each pitch,
    then the near-translations once a pitch (the reference of ``_kernels._author_grid``)."""
    from workbench.twists import translation_twists, twists_from_plucker
    from workbench.twists_author import AUTHOR_LEVELS, _near_translations, _offsets, author_sphere

    lv = AUTHOR_LEVELS[level]
    c = np.asarray(lv.coeffs)
    half = np.r_[c * L.min(), c * L.max()]
    d = np.unique(np.r_[-half, 0.0, half])
    pitches = np.unique(np.r_[-np.asarray(lv.pitch_factors), 0.0, lv.pitch_factors]) * L.mean()
    w = author_sphere(lv.n_axes)
    iw, i1, i2 = (
        g.ravel() for g in np.meshgrid(np.arange(len(w)), np.arange(len(d)), np.arange(len(d)), indexing="ij")
    )
    omega = np.vstack([w[iw], author_sphere(lv.n_through)])
    p = np.vstack([_offsets(w[iw], d[i1], d[i2]), np.zeros((lv.n_through, 3))])
    m = np.cross(p, omega)
    rot = [twists_from_plucker(omega, m, np.full(len(omega), h)) for h in pitches]
    trans = translation_twists(_near_translations())
    return np.vstack(rot + [trans] * len(pitches))

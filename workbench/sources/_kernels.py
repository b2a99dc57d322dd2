"""Private ``@njit`` kernels of the profile sources: math only, no validation (``reach.py``).

A pad's press looks at a few thousand of a mesh's faces and sub-triangles; these kernels pick,
in one compiled pass each, a *superset* of the ones that can pass the press's exact tests (a
margin ``tol`` wider than each test), so that the exact NumPy tests that follow run on the
superset alone and decide exactly as they would on everything.  Coordinates are taken along the
jaw frame's rows ``frame = [a, e1, e2]`` (3, 3) from the point ``c`` (3,); ``box`` (6,) is
``(u_lo, u_hi, v_lo, v_hi, z_lo, z_hi)`` [m], u along e1, v along e2, z along a.  Flags come from
``config``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..config import NUMBA_FLAGS_IEEE


@njit(**NUMBA_FLAGS_IEEE)
def _faces_may_overlap(V, F, c, frame, box, tol):
    """``(faces, sure)``: the ascending indices (k,) of the faces ``F`` (f, 3) of vertices ``V``
    (n, 3) [m] whose bounding box in the frame may overlap ``box`` (each bound widened by ``tol``
    [m]), and (k,) bool, True for those that overlap it with every bound narrowed by ``tol``
    (which pass the exact test whatever the round-off of their coordinates below ``tol``)."""
    n = V.shape[0]
    uvz = np.empty((n, 3))
    for i in range(n):
        rx, ry, rz = V[i, 0] - c[0], V[i, 1] - c[1], V[i, 2] - c[2]
        for k in range(3):
            # column 0: along e1 (u), 1: along e2 (v), 2: along a (z)
            r = frame[(k + 1) % 3]
            uvz[i, k] = rx * r[0] + ry * r[1] + rz * r[2]
    out = np.empty(F.shape[0], dtype=np.int64)
    sure = np.empty(F.shape[0], dtype=np.bool_)
    m = 0
    for f in range(F.shape[0]):
        ok = True
        inner = True
        for k in range(3):
            p, q, s = uvz[F[f, 0], k], uvz[F[f, 1], k], uvz[F[f, 2], k]
            lo, hi = min(p, min(q, s)), max(p, max(q, s))
            if lo > box[2 * k + 1] + tol or hi < box[2 * k] - tol:
                ok = False
                break
            if lo > box[2 * k + 1] - tol or hi < box[2 * k] + tol:
                inner = False
        if ok:
            out[m] = f
            sure[m] = inner
            m += 1
    return out[:m], sure[:m]


@njit(**NUMBA_FLAGS_IEEE)
def _elements_may_touch(cen, nrm, area, rows, c, frame, box, facing_max, tol):  # noqa: PLR0913 - Numba kernel: flat arrays and scalars
    """The entries (ascending, as ``rows`` is) of ``rows`` (m,) whose element — centre ``cen``,
    unit normal ``nrm`` (3,) and area ``area`` of the full arrays — has ``area > 0``, a normal
    that may face the jaw (``n·a < facing_max + tol``) and a centre that may lie in ``box``
    (each bound widened by ``tol`` [m])."""
    out = np.empty(rows.shape[0], dtype=np.int64)
    a, e1, e2 = frame[0], frame[1], frame[2]
    m = 0
    for t in range(rows.shape[0]):
        i = rows[t]
        if not area[i] > 0:
            continue
        if nrm[i, 0] * a[0] + nrm[i, 1] * a[1] + nrm[i, 2] * a[2] >= facing_max + tol:
            continue
        rx, ry, rz = cen[i, 0] - c[0], cen[i, 1] - c[1], cen[i, 2] - c[2]
        u = rx * e1[0] + ry * e1[1] + rz * e1[2]
        if u < box[0] - tol or u > box[1] + tol:
            continue
        v = rx * e2[0] + ry * e2[1] + rz * e2[2]
        if v < box[2] - tol or v > box[3] + tol:
            continue
        z = rx * a[0] + ry * a[1] + rz * a[2]
        if z < box[4] - tol or z > box[5] + tol:
            continue
        out[m] = i
        m += 1
    return out[:m]


@njit(**NUMBA_FLAGS_IEEE)
def _front_most(u, v, z, idx, u_lo, v_lo, cell, n_v, reach):  # noqa: PLR0913 - Numba kernel: flat arrays and scalars
    """(n,) bool: which of the elements ``idx`` (k,) — of coordinates ``u, v, z`` (n,) each [m] —
    lie at most ``reach`` [m] behind the front-most (least z) element of their footprint bin, the
    bins being cells of side ``cell`` from ``(u_lo, v_lo)`` numbered ``iu · n_v + iv``."""
    k = idx.shape[0]
    visible = np.zeros(u.shape[0], dtype=np.bool_)
    if k == 0:
        return visible
    bins = np.empty(k, dtype=np.int64)
    for t in range(k):
        i = idx[t]
        bins[t] = np.int64(np.floor((u[i] - u_lo) / cell)) * n_v + np.int64(np.floor((v[i] - v_lo) / cell))
    lo, hi = bins.min(), bins.max()
    if hi - lo < max(16 * k, 65536):
        # one slot a bin over the range the elements span (the footprint's bins)
        front = np.full(hi - lo + 1, np.inf)
        for t in range(k):
            b = bins[t] - lo
            front[b] = min(front[b], z[idx[t]])
        for t in range(k):
            i = idx[t]
            visible[i] = z[i] <= front[bins[t] - lo] + reach
        return visible
    # a range too wide for a slot a bin (cells far finer than the footprint): the bins' runs in sorted order
    order = np.argsort(bins, kind="mergesort")
    start = 0
    while start < k:
        end = start
        best = np.inf
        while end < k and bins[order[end]] == bins[order[start]]:
            best = min(best, z[idx[order[end]]])
            end += 1
        for t in range(start, end):
            i = idx[order[t]]
            visible[i] = z[i] <= best + reach
        start = end
    return visible


@njit(**NUMBA_FLAGS_IEEE)
def _concat_runs(lo, hi):
    """The integer ranges ``lo[k]:hi[k]`` (each (r,) int64, ``hi >= lo``) one after another, as
    one (Σ (hi − lo),) int64 array."""
    n = 0
    for k in range(lo.shape[0]):
        n += hi[k] - lo[k]
    out = np.empty(n, dtype=np.int64)
    m = 0
    for k in range(lo.shape[0]):
        for i in range(lo[k], hi[k]):
            out[m] = i
            m += 1
    return out

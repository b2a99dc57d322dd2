"""Private ``@njit`` kernels: math only, no validation (see ``wrench.py``).

Geometry is passed structure-of-arrays (``rx, ry, rz, nx, ny, nz, wgt``) so the
inner loop over elements vectorizes.  ``r`` is the torque arm ``c_i - o``,
``wgt = p_i * a_i`` (or a quadrature weight times pressure).  Flags come from
``config``.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from .config import NUMBA_FLAGS, NUMBA_FLAGS_IEEE, NUMBA_FLAGS_PARALLEL


@njit(inline="always", **NUMBA_FLAGS)
def _slip_scale(vx, vy, vz, wx, wy, wz, rx, ry, rz, nx, ny, nz, wgt, rtol2):  # noqa: PLR0913 — inlined Numba kernel: flat scalars
    """Tangential velocity ``t`` at one element and ``wgt / |t|`` (Eq. 3.6).

    Returns ``(tx, ty, tz, s)`` with ``s = 0`` where the element sticks
    (``|t| <= rtol |u|``, including ``u = 0``), so it contributes exactly 0.
    """
    # velocity of the object point at the element: u = v + omega x r (Eq. 3.3)
    ux = vx + wy * rz - wz * ry
    uy = vy + wz * rx - wx * rz
    uz = vz + wx * ry - wy * rx
    d = ux * nx + uy * ny + uz * nz
    tx = ux - d * nx
    ty = uy - d * ny
    tz = uz - d * nz
    t2 = tx * tx + ty * ty + tz * tz
    u2 = ux * ux + uy * uy + uz * uz
    # max() keeps the sqrt argument positive; the select zeroes sticking
    # elements (no 0/0, no NaN) and vectorizes as a blend.
    inv = wgt / np.sqrt(max(t2, 1e-300))
    s = inv if t2 > rtol2 * u2 else 0.0
    return tx, ty, tz, s


@njit(**NUMBA_FLAGS_PARALLEL)
def _fw_segments(twists, seg_twist, seg_lo, seg_hi, rx, ry, rz, nx, ny, nz, wgt, mu, rtol2, out):  # noqa: PLR0913 — Numba kernel: flat arrays
    """Frictional wrenches of segments, Eqs. 3.6–3.8: segment j sums the
    elements ``seg_lo[j]:seg_hi[j]`` under twist ``twists[seg_twist[j]]``.

    A batch of K twists on N elements is K segments spanning ``0:N``; the
    adaptive quadrature uses one segment per cell's Gauss points.  Segments
    run in parallel; each one's sum is serial, so results are deterministic.

    twists : (K, 6) float, [v; omega] at the pressure center
    seg_twist, seg_lo, seg_hi : (S,) int
    rx..nz : (P,) float, torque arms c_i - o and unit normals
    wgt    : (P,) float, p_i * a_i (or quadrature weight times pressure)
    out    : (S, 6) float, written in place
    """
    n_seg = seg_twist.shape[0]
    for j in prange(n_seg):
        k = seg_twist[j]
        vx = twists[k, 0]
        vy = twists[k, 1]
        vz = twists[k, 2]
        wx = twists[k, 3]
        wy = twists[k, 4]
        wz = twists[k, 5]
        fx = 0.0
        fy = 0.0
        fz = 0.0
        mx = 0.0
        my = 0.0
        mz = 0.0
        lo = seg_lo[j]
        hi = seg_hi[j]
        # views + a loop from 0: Numba can then drop the negative-index
        # wraparound checks, which would otherwise block vectorization (3x)
        sx = rx[lo:hi]
        sy = ry[lo:hi]
        sz = rz[lo:hi]
        ux = nx[lo:hi]
        uy = ny[lo:hi]
        uz = nz[lo:hi]
        sw = wgt[lo:hi]
        for i in range(hi - lo):
            tx, ty, tz, s = _slip_scale(
                vx, vy, vz, wx, wy, wz, sx[i], sy[i], sz[i], ux[i], uy[i], uz[i], sw[i], rtol2
            )
            gx = s * tx
            gy = s * ty
            gz = s * tz
            fx += gx
            fy += gy
            fz += gz
            mx += sy[i] * gz - sz[i] * gy
            my += sz[i] * gx - sx[i] * gz
            mz += sx[i] * gy - sy[i] * gx
        out[j, 0] = -mu * fx
        out[j, 1] = -mu * fy
        out[j, 2] = -mu * fz
        out[j, 3] = -mu * mx
        out[j, 4] = -mu * my
        out[j, 5] = -mu * mz


@njit(**NUMBA_FLAGS)
def _normal_wrench(rx, ry, rz, nx, ny, nz, wgt, out):
    """Normal wrench Eq. 3.2 discretised: ``-sum p a [n; r x n]``.

    rx..nz, wgt : (N,) float;  out : (6,) float, written in place.
    """
    fx = 0.0
    fy = 0.0
    fz = 0.0
    mx = 0.0
    my = 0.0
    mz = 0.0
    for i in range(rx.shape[0]):
        gx = wgt[i] * nx[i]
        gy = wgt[i] * ny[i]
        gz = wgt[i] * nz[i]
        fx += gx
        fy += gy
        fz += gz
        mx += ry[i] * gz - rz[i] * gy
        my += rz[i] * gx - rx[i] * gz
        mz += rx[i] * gy - ry[i] * gx
    out[0] = -fx
    out[1] = -fy
    out[2] = -fz
    out[3] = -mx
    out[4] = -my
    out[5] = -mz


@njit(**NUMBA_FLAGS)
def _cell_slots(table, ids, n, slots, new_rows):
    """Slots of quadrature cells by id in an open-addressing hash table, the missing ids
    added (``surfaces._CellGeometry``): one compiled pass per call, where a lookup in sorted
    ids (searchsorted, insert) takes a dozen NumPy calls.

    table : (2, C) int64, ids (-1: empty) and their slots; C a power of two, more than
        ``len(ids)`` entries left empty (the caller grows it), so every probe ends
    ids : (m,) int64, none -1;  n : slots held (new ids get n, n + 1, ... in order of
        first appearance)
    slots : (m,) int64, written: each id's slot
    new_rows : (m,) int64, written: ``[:k]`` the row of each new id's first appearance
    Returns k, the number of ids added.
    """
    mask = table.shape[1] - 1
    shift = 32  # 32 - log2(C)
    c = table.shape[1]
    while c > 1:
        c >>= 1
        shift -= 1
    k = 0
    for i in range(ids.shape[0]):
        key = ids[i]
        # Knuth's multiplicative hash of 31 bits of the key (with its high bits folded in; the
        # product stays below 2**63): spreads out the runs of consecutive ids the cells of a
        # level hold, which would otherwise fill runs of entries that linear probing crawls
        h = (((key ^ (key >> 31)) & 0x7FFFFFFF) * 2654435761 & 0xFFFFFFFF) >> shift
        while table[0, h] != key and table[0, h] != -1:
            h = (h + 1) & mask  # linear probing
        if table[0, h] == -1:
            table[0, h] = key
            table[1, h] = n + k
            new_rows[k] = i
            k += 1
        slots[i] = table[1, h]
    return k


@njit(inline="always", **NUMBA_FLAGS_IEEE)
def _axis_offset(om, d1, d2, p):
    """Writes p (3,) ⊥ ω (3,) with coordinates (d1, d2) on the two axes other than ω's dominant
    component (the first of equal magnitudes, as np.argmax), the third solving p·ω = 0."""
    k = 0
    for c in range(1, 3):
        if abs(om[c]) > abs(om[k]):
            k = c
    j1 = 1 if k == 0 else 0
    j2 = 1 if k == 2 else 2
    p[j1] = d1
    p[j2] = d2
    p[k] = -(d1 * om[j1] + d2 * om[j2]) / om[k]


@njit(**NUMBA_FLAGS_IEEE)
def _author_grid(w, d, through, pitches, trans):
    """The author's twist grid (``twists_author.sample_twists_author``): (K, 6) unit twists, rows in
    the order of its NumPy expressions — each offset axis ``w[a]`` (n_w, 3) at offsets
    ``(d[i], d[j])`` (d (n_d,)), a, i, j row-major, then the axes ``through`` (n_t, 3) the pressure
    centre, all at ``pitches[0]``, again at each later pitch (p (n_p,)), then the translations
    ``trans`` (36, 6) once a pitch.  Each value is rounded as the NumPy expressions round it (no
    FMA): the offset's dependent coordinate, ``m = p × ω`` as ``np.cross``, ``e = ω / |ω|`` with
    the squares summed left to right, ``h e + m``."""
    n_w, n_d, n_t, n_p = w.shape[0], d.shape[0], through.shape[0], pitches.shape[0]
    n_rot = n_w * n_d * n_d + n_t
    out = np.empty((n_rot * n_p + trans.shape[0] * n_p, 6))
    p = np.empty(3)
    om = np.empty(3)
    for r in range(n_rot):
        if r < n_w * n_d * n_d:
            a = r // (n_d * n_d)
            d1 = d[(r // n_d) % n_d]
            d2 = d[r % n_d]
            for c in range(3):
                om[c] = w[a, c]
            _axis_offset(om, d1, d2, p)
        else:
            for c in range(3):
                om[c] = through[r - n_w * n_d * n_d, c]
                p[c] = 0.0
        m0 = p[1] * om[2] - p[2] * om[1]
        m1 = p[2] * om[0] - p[0] * om[2]
        m2 = p[0] * om[1] - p[1] * om[0]
        norm = np.sqrt(om[0] * om[0] + om[1] * om[1] + om[2] * om[2])
        e0, e1, e2 = om[0] / norm, om[1] / norm, om[2] / norm
        for q in range(n_p):
            h = pitches[q]
            row = q * n_rot + r
            out[row, 0] = h * e0 + m0
            out[row, 1] = h * e1 + m1
            out[row, 2] = h * e2 + m2
            out[row, 3] = e0
            out[row, 4] = e1
            out[row, 5] = e2
    base = n_rot * n_p
    for q in range(n_p):
        for t in range(trans.shape[0]):
            for c in range(6):
                out[base + q * trans.shape[0] + t, c] = trans[t, c]
    return out

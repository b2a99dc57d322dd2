"""A fine surface binned in a uniform grid of cells, so that a pad's query reads only the cells
under it: the candidates of a press cost the patch's size, not the mesh's.

A pad pressed on a mesh looks at the sub-triangles whose centres lie in a box in the jaw's frame
(its footprint, along its stroke).  Testing every sub-triangle of the mesh costs the mesh's size
per press — a 1 mm subdivision of a thesis bottle has 10⁴–10⁵ of them and the settle presses a
grasp tens of times.  :class:`SurfaceIndex` sorts them once by cell; :meth:`SurfaceIndex.within`
tests the occupied cells' bounding spheres against the box and returns the sub-triangles of the
cells that may reach into it, a superset of those inside, which the caller then tests exactly.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._kernels import _concat_runs

__all__ = ["SurfaceIndex", "concat_runs"]


@dataclass(frozen=True)
class SurfaceIndex:
    """Sub-triangle centres ``centers`` (n, 3) [m] grouped by the grid cell of edge ``cell`` [m]
    they fall in.

    cell_centers : (c, 3) [m] the occupied cells' centres; starts : (c + 1,) the run of each cell
    in ``order`` (n,), the sub-triangles' indices grouped by cell.  Read-only arrays.
    """

    cell: float
    cell_centers: np.ndarray = field(repr=False)
    starts: np.ndarray = field(repr=False)
    order: np.ndarray = field(repr=False)

    @classmethod
    def build(cls, centers: np.ndarray, cell: float) -> SurfaceIndex:
        """The index of ``centers`` (n, 3) [m] on cells of edge ``cell`` [m] (> 0)."""
        c = np.asarray(centers, float)
        if c.ndim != 2 or c.shape[1] != 3 or not np.isfinite(c).all():
            raise ValueError(f"centers must be a finite (n, 3) array [m]; got shape {np.shape(centers)}")
        if not (np.isfinite(cell) and cell > 0):
            raise ValueError(f"cell must be a grid cell's edge [m], > 0; got {cell!r}")
        lo = c.min(axis=0) if len(c) else np.zeros(3)
        ijk = np.floor((c - lo) / cell).astype(np.int64)
        dims = ijk.max(axis=0) + 1 if len(c) else np.ones(3, np.int64)
        key = (ijk[:, 0] * dims[1] + ijk[:, 1]) * dims[2] + ijk[:, 2]
        order = np.argsort(key, kind="stable")
        keys, first = np.unique(key[order], return_index=True)
        cells = np.column_stack(np.unravel_index(keys, tuple(int(d) for d in dims)))
        arrays = (lo + (cells + 0.5) * cell, np.r_[first, len(c)].astype(np.int64), order.astype(np.int64))
        for a in arrays:
            a.flags.writeable = False
        return cls(float(cell), *arrays)

    def within(self, origin: np.ndarray, frame: tuple, box: tuple) -> np.ndarray:
        """Sorted indices (m,) of the sub-triangles of every cell that may hold a centre inside
        ``box`` = ``(u_lo, u_hi, v_lo, v_hi, z_lo, z_hi)`` [m], coordinates along ``frame`` =
        ``(a, e1, e2)`` (unit (3,) each: z along ``a``, u along ``e1``, v along ``e2``) from
        ``origin`` (3,) [m]: every centre inside the box is among them (the cell's bounding
        sphere is tested), some outside it too."""
        a, e1, e2 = frame
        u_lo, u_hi, v_lo, v_hi, z_lo, z_hi = box
        rel = self.cell_centers - np.asarray(origin, float)
        r = 0.5 * np.sqrt(3.0) * self.cell * (1 + 1e-9)  # the cell's half-diagonal, rounded up
        u = rel @ e1
        near = (u >= u_lo - r) & (u <= u_hi + r)
        v = rel @ e2
        near &= (v >= v_lo - r) & (v <= v_hi + r)
        z = rel @ a
        near &= (z >= z_lo - r) & (z <= z_hi + r)
        cells = np.flatnonzero(near)
        if len(cells) == 0:
            return np.empty(0, dtype=np.int64)
        return np.sort(self.order[concat_runs(self.starts[cells], self.starts[cells + 1])])


def concat_runs(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The integer ranges ``lo[k]:hi[k]`` (each (r,), ``hi >= lo``) concatenated in order, as one
    (Σ (hi − lo),) int64 array — ``np.concatenate([np.arange(a, b) for a, b in zip(lo, hi)])``
    without the Python loop."""
    lo, hi = np.ascontiguousarray(lo, np.int64), np.ascontiguousarray(hi, np.int64)
    if lo.shape != hi.shape or lo.ndim != 1 or (hi < lo).any():
        raise ValueError(
            f"concat_runs takes two (r,) integer arrays with hi >= lo; got shapes {lo.shape} and {hi.shape}"
        )
    return _concat_runs(lo, hi)

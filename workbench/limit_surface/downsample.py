"""Grid downsampling of wrench samples for training (the author's ``downsamplewrench.m``,
"thesis-code" protocol of issue 12).

The normalised wrenches' bounding box is cut into cells of side ``(max − min) / steps``
per dimension (``steps = 2.5``: three cells per dimension, the last reaching past the
maximum), and each occupied cell keeps the one sample nearest to the mean of the
samples in it.  A dense twist grid thus trains on a few hundred wrenches spread over
the wrench set instead of thousands crowded where the grid is dense.

Departure: a sample exactly on an inner cell boundary belongs to both cells in the
code (closed intervals) and to the upper one here (measure zero for computed wrenches).
"""

from __future__ import annotations

import numpy as np

from .. import config
from .normalize import check_wrenches


def grid_downsample(wrenches, steps: float = 2.5) -> np.ndarray:
    """Indices (sorted, unique) of one wrench per occupied grid cell.

    wrenches : (N, 6) float (normalised, e.g. ``W / w_max``).
    steps : cells per dimension = ``floor(steps) + 1`` starts at ``min + k·(max − min)/steps``;
        a dimension whose range is at most ``config.TOL.subspace_rtol`` × the largest is one cell.
    """
    W = check_wrenches(wrenches)
    if not (np.isfinite(steps) and steps > 0):
        raise ValueError(f"steps must be a positive number of cell widths per range; got {steps}")
    lo, hi = W.min(axis=0), W.max(axis=0)
    width = (hi - lo) / steps
    n_cells = int(np.floor(steps)) + 1
    # a range at rounding-noise level (a flat contact tilted by 1e-9 rad) is one cell, as an
    # exactly zero one is — the PCA subspace's notion of a dropped direction
    flat = width <= config.TOL.subspace_rtol * width.max()
    idx = np.where(flat, 0, np.floor((W - lo) / np.where(flat, 1.0, width))).astype(np.int64)
    idx = np.clip(idx, 0, n_cells - 1)
    key = np.ravel_multi_index(idx.T, (n_cells,) * 6)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    ends = np.r_[starts[1:], len(ks)]
    keep = []
    for s, e in zip(starts, ends, strict=True):
        members = order[s:e]
        centre = W[members].mean(axis=0)
        keep.append(members[np.argmin(np.linalg.norm(W[members] - centre, axis=1))])
    return np.unique(np.asarray(keep, dtype=np.int64))


__all__ = ["grid_downsample"]

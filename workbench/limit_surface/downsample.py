"""Grid downsampling of wrench samples for training (the author's ``downsamplewrench.m``,
the "thesis-code" protocol).

The normalised wrenches' bounding box is cut into cells of side ``(max − min) / steps``
per dimension (``steps = 2.5``: three cells per dimension, the last reaching past the
maximum), and each occupied cell keeps the one sample nearest to the mean of the
samples in it.  A dense twist grid thus trains on a few hundred wrenches spread over
the wrench set instead of thousands crowded where the grid is dense.

Departures: a sample on an inner cell boundary belongs to both cells in the code (closed
intervals) and to the upper one here, "on" meaning within ``config.TOL.downsample_tie_atol``
cell widths, so that round-off cannot move it across; members equally near their cell's mean
(the two of a two-member cell always; mirror images on a symmetric contact) keep the first in
sample order, not whichever the round-off of the distances happens to favour (MATLAB's ``min``
keeps the first of exact ties, but which ties are exact is round-off there too).  Both make
the training set a function of the contact, not of its last bits: without them a profile
perturbed by 1e-14 can swap mirror twists and move the 6DLS model by percents.
"""

from __future__ import annotations

import numbers

import numpy as np

from .. import config
from .normalize import check_wrenches


def grid_downsample(wrenches, steps: float = 2.5) -> np.ndarray:
    """Indices (sorted, unique) of one wrench per occupied grid cell.

    wrenches : (N, 6) float (normalised, e.g. ``W / w_max``).
    steps : cells per dimension = ``floor(steps) + 1`` starts at ``min + k·(max − min)/steps``;
        a dimension whose range is at most ``config.TOL.subspace_rtol`` × the largest is one cell.
    Each cell keeps its member nearest the members' mean, the first in sample order among
    members within ``config.TOL.downsample_tie_atol`` of the nearest (read at call time).
    """
    W = check_wrenches(wrenches)
    # at most 1,000 cell widths a range: (floor(steps) + 1)^6 cells must index in int64
    if isinstance(steps, bool) or not isinstance(steps, numbers.Real) or not 0 < steps <= 1000:
        raise ValueError(
            f"steps must be a positive number of cell widths per range, at most 1000 (the author's "
            f"2.5); got {steps!r}"
        )
    Wt = np.ascontiguousarray(W.T)  # (6, N): per-coordinate passes run along contiguous memory
    lo, hi = Wt.min(axis=1), Wt.max(axis=1)
    width = (hi - lo) / steps
    n_cells = int(np.floor(steps)) + 1
    # a range at rounding-noise level (a flat contact tilted by 1e-9 rad) is one cell, as an
    # exactly zero one is — the PCA subspace's notion of a dropped direction
    flat = width <= config.TOL.subspace_rtol * width.max()
    tie = config.TOL.downsample_tie_atol
    cell = np.where(flat, 1.0, width)[:, None]
    idx = np.where(flat[:, None], 0, np.floor((Wt - lo[:, None]) / cell + tie)).astype(np.int64)
    key = np.ravel_multi_index(np.clip(idx, 0, n_cells - 1, out=idx), (n_cells,) * 6)
    order = np.argsort(key, kind="stable")  # cells in key order, members in sample order
    ks = key[order]
    starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    counts = np.diff(np.r_[starts, len(ks)])
    Ws = W[order]
    # one pass over all cells instead of a loop per cell (docs/decisions.md); the sums are row
    # after row as
    # W[members].mean(axis=0) adds them, so the means, distances and kept indices are those of
    # the per-cell loop to the last bit
    means = np.add.reduceat(Ws, starts, axis=0) / counts[:, None]
    d = np.linalg.norm(Ws - np.repeat(means, counts, axis=0), axis=1)
    near = d <= np.repeat(np.minimum.reduceat(d, starts) + tie, counts)
    # the first member within the tie of its cell's nearest (it is in the cell: the nearest is)
    first = np.flatnonzero(near)
    keep = order[first[np.searchsorted(first, starts)]]
    return np.unique(keep.astype(np.int64))


__all__ = ["grid_downsample"]

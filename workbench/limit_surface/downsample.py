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
from ._kernels import _grid_keep
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
    return _grid_downsample(W, check_steps(steps))


def check_steps(steps: object) -> float:
    """``steps`` as a float if it is a positive number of cell widths per range, at most 1,000
    (``(floor(steps) + 1)^6`` cells must index in int64), else ValueError."""
    if isinstance(steps, bool) or not isinstance(steps, numbers.Real) or not 0 < steps <= 1000:
        raise ValueError(
            f"steps must be a positive number of cell widths per range, at most 1000 (the author's "
            f"2.5); got {steps!r}"
        )
    return float(steps)


def _grid_downsample(W: np.ndarray, steps: float) -> np.ndarray:
    """:func:`grid_downsample` of checked wrenches W (N, 6) and steps."""
    # one compiled pass over the cells (docs/decisions.md), each cell's mean and distances added
    # in the order W[members].mean(axis=0) and np.linalg.norm add them, so the kept rows are those
    # of the per-cell loop; a range at rounding-noise level (a flat contact tilted by 1e-9 rad) is
    # one cell, as an exactly zero one is — the PCA subspace's notion of a dropped direction
    tol = config.TOL
    keep = _grid_keep(np.ascontiguousarray(W), steps, tol.subspace_rtol, tol.downsample_tie_atol)
    return np.sort(keep)


__all__ = ["check_steps", "grid_downsample"]

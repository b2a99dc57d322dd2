"""Private ``@njit`` kernels of a profile's per-element rows: math only, no validation
(``profile.py``).

Each redoes one NumPy expression on C-ordered ``(n, 3)`` rows with the same arithmetic, so
the result is NumPy's to the last bit, in one pass instead of NumPy's several (its reductions
and broadcasts over rows of three run far below memory speed):

* :func:`_row_norms` — ``np.linalg.norm(x, axis=1)``: ``sqrt((x0² + x1²) + x2²)``;
* :func:`_rows_over` — ``x / d[:, None]``;
* :func:`_rows_minus` — ``x - c``;
* :func:`_column_sums` — ``x.sum(axis=0)``, and :func:`_weighted_column_sums`
  ``(w[:, None] * x).sum(axis=0)``: NumPy reduces a C-ordered array's first axis row after row;
* :func:`_column_ranges` — ``x.max(axis=0) - x.min(axis=0)``.

No fastmath (``config.NUMBA_FLAGS_IEEE``): NumPy rounds every product and sum on its own.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .config import NUMBA_FLAGS_IEEE


@njit(**NUMBA_FLAGS_IEEE)
def _row_norms(x):
    """(n,) the Euclidean length of each row of ``x`` (n, 3)."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = np.sqrt(x[i, 0] * x[i, 0] + x[i, 1] * x[i, 1] + x[i, 2] * x[i, 2])
    return out


@njit(**NUMBA_FLAGS_IEEE)
def _rows_over(x, d):
    """(n, 3) each row of ``x`` (n, 3) divided by its ``d`` (n,)."""
    out = np.empty(x.shape)
    for i in range(x.shape[0]):
        for j in range(3):
            out[i, j] = x[i, j] / d[i]
    return out


@njit(**NUMBA_FLAGS_IEEE)
def _rows_minus(x, c):
    """(n, 3) each row of ``x`` (n, 3) less ``c`` (3,)."""
    out = np.empty(x.shape)
    for i in range(x.shape[0]):
        for j in range(3):
            out[i, j] = x[i, j] - c[j]
    return out


@njit(**NUMBA_FLAGS_IEEE)
def _column_sums(x):
    """(3,) the sum of the rows of ``x`` (n, 3), added first row to last."""
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for i in range(x.shape[0]):
        s0 += x[i, 0]
        s1 += x[i, 1]
        s2 += x[i, 2]
    return np.array([s0, s1, s2])


@njit(**NUMBA_FLAGS_IEEE)
def _weighted_column_sums(w, x):
    """(3,) ``Σ_i w_i x_i`` of the rows of ``x`` (n, 3) and weights ``w`` (n,), added first row
    to last."""
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for i in range(x.shape[0]):
        s0 += w[i] * x[i, 0]
        s1 += w[i] * x[i, 1]
        s2 += w[i] * x[i, 2]
    return np.array([s0, s1, s2])


@njit(**NUMBA_FLAGS_IEEE)
def _column_ranges(x):
    """(k,) the largest less the smallest entry of each column of ``x`` (n, k), n >= 1."""
    k = x.shape[1]
    hi = x[0].copy()
    lo = x[0].copy()
    for i in range(1, x.shape[0]):
        for j in range(k):
            v = x[i, j]
            if v > hi[j]:
                hi[j] = v
            if v < lo[j]:
                lo[j] = v
    return hi - lo

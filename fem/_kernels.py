"""Private ``@njit`` kernels of the condensed contact solve and of the sparse factor's
blocked triangular solves (math only; the callers in ``contact.py`` and
``sparse_factor.py`` own validation).  NumPy references: ``tests/naive.py``.

Imported as ``workbench.fem._kernels`` (the folder installs under ``workbench``); Numba's
on-disk cache of these kernels is keyed by this file's timestamp, so an edit here also
retires the entries compiled when the module was called ``fem._kernels``."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from workbench.config import NUMBA_FLAGS, NUMBA_FLAGS_PARALLEL


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

"""Tangent planes of limit-surface models found by cutting-plane refinement (Kelley).

A cut ``a·s <= b`` is a tangent plane of a model in its own frame (contact frame C,
μ = 1, unit normal force), so it stays valid for every pose, μ and force of any
contact carrying that model: a store passed to many calls (a sweep over grasps and
disturbances of the same profiles) lets each model be refined once.  The store is an
explicit argument — never hidden in a contact — and holds a reference to each model
it has cuts for (keys are identities).
"""

from __future__ import annotations

import numpy as np

from ... import config


class CutStore:
    """Mutable store of tangent-plane cuts per limit-surface model (see module docstring)."""

    def __init__(self) -> None:
        # per model: (model, A buffer (m, 6), b buffer (m,), [first, end) of the live cuts).  The
        # live cuts are a slice of the buffers, so rows() is a view, not a restack: a program is
        # assembled many times between adds, and restacking the cuts, each time or after every
        # add, was a visible share of a sensitivity margin row (docs/decisions.md).  An
        # add writes past the live slice and dropping the oldest moves `first`, so a view handed
        # out earlier never changes; a full buffer is replaced by a new one, not overwritten.
        # An entry exists from its first add on, so its live slice is never empty.
        self._cuts: dict[int, list] = {}

    def __len__(self) -> int:
        return sum(end - first for _, _, _, first, end in self._cuts.values())

    def rows(self, model) -> tuple[np.ndarray, np.ndarray]:
        """(k, 6), (k,) cuts of ``model``, oldest first (empty arrays if none), read-only."""
        entry = self._cuts.get(id(model))
        if entry is None or entry[0] is not model:
            return np.zeros((0, 6)), np.zeros(0)
        _, A, B, first, end = entry
        A, B = A[first:end], B[first:end]
        A.flags.writeable = B.flags.writeable = False  # the views only: the store appends
        return A, B

    def add(self, model, a: np.ndarray, b: float) -> None:
        """Store ``a s <= b``; beyond ``config.TOL.max_stored_cuts`` the oldest goes (the newest
        must stay, or the refinement would re-solve the same program)."""
        entry = self._cuts.get(id(model))
        if entry is None or entry[0] is not model:
            entry = [model, np.zeros((0, 6)), np.zeros(0), 0, 0]
            self._cuts[id(model)] = entry
        _, A, B, first, end = entry
        first = max(first, end - (config.TOL.max_stored_cuts - 1))  # read now; keep room for this one
        if end == len(A):  # full: the live cuts into a new buffer with as much room again
            n = end - first
            A2, B2 = np.empty((max(2 * n, 64), 6)), np.empty(max(2 * n, 64))
            A2[:n], B2[:n] = A[first:end], B[first:end]
            A, B, first, end = A2, B2, 0, n
        A[end], B[end] = a, b
        entry[1:] = [A, B, first, end + 1]

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
        self._cuts: dict[int, tuple[object, list[np.ndarray], list[float]]] = {}
        # the stacked rows of a model since its last add: a program is assembled many times
        # between adds (a margin's bisection), and stacking ~2,000 cuts each time took 12 % of
        # a sensitivity margin row (measured)
        self._stacked: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def __len__(self) -> int:
        return sum(len(a) for _, a, _ in self._cuts.values())

    def rows(self, model) -> tuple[np.ndarray, np.ndarray]:
        """(k, 6), (k,) cuts of ``model`` (empty arrays if none)."""
        entry = self._cuts.get(id(model))
        if entry is None or entry[0] is not model or not entry[1]:
            return np.zeros((0, 6)), np.zeros(0)
        stacked = self._stacked.get(id(model))
        if stacked is None:
            stacked = (np.array(entry[1]), np.array(entry[2]))
            for arr in stacked:
                arr.flags.writeable = False  # shared by every caller until the next add
            self._stacked[id(model)] = stacked
        return stacked

    def add(self, model, a: np.ndarray, b: float) -> None:
        """Store ``a s <= b``; beyond ``config.TOL.max_stored_cuts`` the oldest goes (the newest
        must stay, or the refinement would re-solve the same program)."""
        self._stacked.pop(id(model), None)
        entry = self._cuts.get(id(model))
        if entry is None or entry[0] is not model:
            entry = (model, [], [])
            self._cuts[id(model)] = entry
        _, A, B = entry
        while A and len(A) >= config.TOL.max_stored_cuts:
            del A[0], B[0]
        A.append(np.asarray(a, float))
        B.append(float(b))

"""Contact-wrench model and the 6D friction cone (thesis §3.4, Eqs. 3.25–3.30;
6DFC Eq. IV.2).

A contact wrench is ``c = w + w⊥`` (Eq. 3.25): the friction limit surface
shifted to the normal wrench.  Both scale linearly with the force of the
profile pair: for a normalised profile (``F = 1``) with limit surface
``f`` and normal wrench ``ŵ⊥``, a contact pressed with ``F`` transmits
``f((c - F ŵ⊥) / F) <= 1``.  The 6DFC lets ``F`` (the paper's ``f_C``) vary in
``[0, f_max]``: ``C = {c | ∃ f_C: f((c - f_C ŵ⊥)/f_C) <= 1, 0 <= f_C <= f_max}``; the grasp
layer builds that cone from the limit surface's linearisation
(:func:`workbench.grasp.contacts.limit_surface_contact`) and writes its rows once for all
solvers (:mod:`workbench.grasp.resistance.program`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import LimitSurfaceModel
from .linearize import linearize


@dataclass(frozen=True)
class ContactWrenchModel:
    """Limit surface and normal wrench of a *normalised* profile (F = 1)."""

    limit_surface: LimitSurfaceModel
    normal_wrench: np.ndarray  # (6,) ŵ⊥ for F = 1

    def value(self, c: np.ndarray, F: float = 1.0) -> np.ndarray:
        """Eq. 3.26: ``f(c - F ŵ⊥)`` for the model scaled by ``F``; <= 1 inside."""
        return self.limit_surface.scaled(F).value(np.asarray(c) - F * self.normal_wrench)

    def inner_vertices(self, M: int, F: float = 1.0, **kw) -> np.ndarray:
        """Eq. 3.27: (M, 6) vertices ``F (ŝ_m + ŵ⊥)``."""
        lin = linearize(self.limit_surface, M, "inner", **kw)
        return F * (lin.vertices + self.normal_wrench)

    def outer(self, M: int, F: float = 1.0, **kw) -> tuple[np.ndarray, np.ndarray]:
        """Eq. 3.28: ``A c <= b`` with ``A (c - F ŵ⊥) <= F b̂``."""
        lin = linearize(self.limit_surface, M, "outer", **kw)
        return lin.A, F * (lin.b + lin.A @ self.normal_wrench)

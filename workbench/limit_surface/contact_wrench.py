"""Contact-wrench model and the 6D friction cone (thesis §3.4, Eq. 3.25-3.30;
6DFC paper Eq. IV.2).

A contact wrench is ``c = w + w⊥`` (Eq. 3.25): the friction limit surface
shifted to the normal wrench.  Both scale linearly with the force of the
profile pair: for a normalised profile (``F = 1``) with limit surface
``f`` and normal wrench ``ŵ⊥``, a contact pressed with ``F`` transmits
``f((c - F ŵ⊥) / F) <= 1``.  The 6DFC lets ``F`` (the paper's ``f_C``) vary in
``[0, f_max]``: ``C = {c | ∃ f_C: f((c - f_C ŵ⊥)/f_C) <= 1, 0 <= f_C <= f_max}``.
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
        """Eq. (3.26): ``f(c - F ŵ⊥)`` for the model scaled by ``F``; <= 1 inside."""
        return self.limit_surface.scaled(F).value(np.asarray(c) - F * self.normal_wrench)

    def inner_vertices(self, M: int, F: float = 1.0, **kw) -> np.ndarray:
        """Eq. (3.27): (M, 6) vertices ``F (ŝ_m + ŵ⊥)``."""
        lin = linearize(self.limit_surface, M, "inner", **kw)
        return F * (lin.vertices + self.normal_wrench)

    def outer(self, M: int, F: float = 1.0, **kw) -> tuple[np.ndarray, np.ndarray]:
        """Eq. (3.28): ``A c <= b`` with ``A (c - F ŵ⊥) <= F b̂``."""
        lin = linearize(self.limit_surface, M, "outer", **kw)
        return lin.A, F * (lin.b + lin.A @ self.normal_wrench)


@dataclass(frozen=True)
class FrictionCone6D:
    """6DFC, Eq. (3.29)-(3.30) / IV.2, linearised.

    H-representation over ``z = [c; f_C]`` (7,): ``A z <= b`` with rows
    ``n_mᵀ c - f_C (n_mᵀ ŵ⊥ + b̂_m) <= 0``, ``-f_C <= 0`` and ``f_C <= f_max``.
    V-representation: ``0`` and ``f_max (ŝ_m + ŵ⊥)`` — the cone over the
    inner contact-wrench polytope.
    """

    A: np.ndarray  # (m + 2, 7)
    b: np.ndarray  # (m + 2,)
    vertices: np.ndarray  # (M + 1, 6)
    f_max: float

    def contains(self, c: np.ndarray, f_c: float, tol: float = 1e-9) -> bool:
        """Whether contact wrench ``c`` is feasible with force ``f_c`` (outer)."""
        z = np.append(np.asarray(c, dtype=float), f_c)
        scale = max(1.0, float(np.abs(self.b).max()))
        return bool((self.A @ z <= self.b + tol * scale).all())


def friction_cone_6d(model: ContactWrenchModel, M: int, f_max: float, **kw) -> FrictionCone6D:
    """Linearised 6DFC of a contact-wrench model with M directions."""
    if not np.isfinite(f_max) or f_max <= 0:
        raise ValueError(f"f_max must be > 0; got {f_max}")
    outer = linearize(model.limit_surface, M, "outer", **kw)
    inner = linearize(model.limit_surface, M, "inner", **kw)
    n, bh = outer.A, outer.b
    rows = np.hstack([n, -(n @ model.normal_wrench + bh)[:, None]])
    A = np.vstack([rows, np.r_[np.zeros(6), -1.0], np.r_[np.zeros(6), 1.0]])
    b = np.concatenate([np.zeros(len(rows)), [0.0, f_max]])
    verts = np.vstack([np.zeros(6), f_max * (inner.vertices + model.normal_wrench)])
    return FrictionCone6D(A, b, verts, float(f_max))

"""Common interface of 6D limit-surface models (thesis §3.3).

A model is fitted in *normalised* wrench coordinates ``x̂ = w ⊘ scale``
(Eq. 3.10, ``scale`` = ``w_max`` with degenerate entries guarded) and is a
homogeneous function ``f̂`` of degree ``d`` (2 for the ellipsoid, 4 for the
quartic); the limit surface is ``f̂(x̂) = 1``.  Public methods take and return
*raw* wrenches.  Multiplying all wrenches by ``F`` (force scaling of a profile
pair, §3.3.6.1) only scales ``w_max``, see :meth:`scaled`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .normalize import Subspace


@dataclass(frozen=True)
class LimitSurfaceModel:
    """Base class; subclasses implement ``_value_n``, ``_gradient_n`` (and
    ``_hessian_n`` where needed) in normalised coordinates."""

    w_max: np.ndarray  # (6,) maximal magnitudes per component
    scale: np.ndarray  # (6,) divisor used for normalisation (w_max, guarded)
    subspace: Subspace  # PCA subspace the data spans
    info: dict = field(default_factory=dict, compare=False)  # solver, fallback, timings

    degree: int = 0

    # -- normalised coordinates (overridden) ----------------------------------
    def _value_n(self, x: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def _gradient_n(self, x: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    # -- raw wrenches ----------------------------------------------------------
    @property
    def dim(self) -> int:
        """Dimension of the fitted subspace (3 for a planar contact)."""
        return self.subspace.dim

    def _as_rows(self, w: Any) -> tuple[np.ndarray, bool]:
        arr = np.asarray(w, dtype=np.float64)
        single = arr.ndim == 1
        arr = np.atleast_2d(arr)
        if arr.ndim != 2 or arr.shape[1] != 6:
            raise ValueError(f"wrenches must have shape (N, 6) or (6,); got {np.shape(w)}")
        return arr, single

    def value(self, w: Any) -> np.ndarray | float:
        """``f(w)``; ``<= 1`` inside the limit surface (Eq. 3.9). w : (N, 6) or (6,)."""
        arr, single = self._as_rows(w)
        v = self._value_n(arr / self.scale)
        return float(v[0]) if single else v

    def gradient(self, w: Any) -> np.ndarray:
        """``∇_w f(w)`` at raw wrenches, (N, 6) or (6,)."""
        arr, single = self._as_rows(w)
        g = self._gradient_n(arr / self.scale) / self.scale
        return g[0] if single else g

    def scaled(self, factor: float) -> LimitSurfaceModel:
        """The model for all wrenches multiplied by ``factor`` (e.g. ``F``)."""
        factor = float(factor)
        if not np.isfinite(factor) or factor <= 0:
            raise ValueError(f"scale factor must be > 0; got {factor}")
        return replace(self, w_max=self.w_max * factor, scale=self.scale * factor)

    def fitting_error(self, wrenches: Any, kind: str = "eq3.18") -> float:
        """Mean fitting error over (raw) wrenches.

        ``"eq3.18"``: thesis Eq. 3.18, ``|f(ŵ) - 1|``.  ``"radial"``:
        ``|f(ŵ)^(1/d) - 1|``, the relative radial distance to the surface.  For a
        point at radius ``ρ`` times the surface's, Eq. 3.18 gives
        ``|ρ^d - 1| ≈ d |ρ - 1|``: it charges a quartic twice what it charges
        an ellipsoid for the same geometric miss; the radial error does not.
        A zero wrench (a twist that slides nothing, as the author's grid holds) scores 1 in
        both: no limit surface passes through the origin; drop such rows to leave them out.
        """
        arr, _ = self._as_rows(wrenches)
        if len(arr) == 0:
            raise ValueError("fitting_error needs at least one wrench (a mean over none is undefined)")
        f = self._value_n(arr / self.scale)
        if kind == "eq3.18":
            return float(np.mean(np.abs(f - 1.0)))
        if kind == "radial":
            return float(np.mean(np.abs(np.maximum(f, 0.0) ** (1.0 / self.degree) - 1.0)))
        raise ValueError(f"kind must be 'eq3.18' or 'radial'; got {kind!r}")

    def linearize(self, M: int, kind: str = "inner", *, directions: str = "cube", seed: int = 0):
        """Inner vertices (Eqs. 3.19–3.21) or outer tangent half-spaces
        (Eqs. 3.22–3.24); see :mod:`workbench.limit_surface.linearize`."""
        from .linearize import linearize

        return linearize(self, M, kind, directions=directions, seed=seed)

"""Pressure models: power law (thesis Eqs. 2.14, 4.3, Xydas et al.)."""

from __future__ import annotations

import numpy as np


def power_law(r: np.ndarray, r_max: float, k: float, p0: float = 1.0) -> np.ndarray:
    """``p(r) = p0 [1 - (r / r_max)^k]^(1/k)`` for ``0 <= r <= r_max``, 0 beyond.

    k = 2 is Hertzian, k -> inf uniform (Eq. 2.14); r : (n,) distances [m].
    """
    if not (np.isfinite(r_max) and r_max > 0):
        raise ValueError(f"r_max must be > 0; got {r_max}")
    if not k > 0:
        raise ValueError(f"k must be > 0; got {k}")
    s = np.clip(np.asarray(r, dtype=float) / r_max, 0.0, 1.0)
    if np.isinf(k):
        # the k -> inf limit: p0 inside, 0 from the rim on (every finite k gives 0 at s = 1)
        return np.where(s < 1.0, float(p0), 0.0)
    return p0 * (1.0 - s**k) ** (1.0 / k)

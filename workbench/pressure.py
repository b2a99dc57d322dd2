"""Pressure models: power law (thesis Eqs. 2.14, 4.3, Xydas et al.)."""

from __future__ import annotations

from dataclasses import dataclass

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


@dataclass(frozen=True)
class PowerLawFit:
    """A power law (Eq. 4.3) fitted to pressures: exponent ``k``, scale ``p0`` [the pressures'
    unit], ``r_max`` [m] (the largest r, where the law is 0), the relative RMS residual
    ``rms_rel`` (RMS of the residuals over the RMS of the pressures) and ``at_bound`` (k is an
    end of the search interval, which fits as well as any k inside: the data do not fix k)."""

    k: float
    p0: float
    r_max: float
    rms_rel: float
    at_bound: bool


def fit_power_law(
    r: np.ndarray, p: np.ndarray, r_max: float | None = None, k_range: tuple[float, float] = (0.5, 1000.0)
) -> PowerLawFit:
    """Least-squares fit of Eq. 4.3, ``p ≈ p0 [1 − (r / r_max)^k]^(1/k)``, to pressures ``p`` (n,)
    at distances ``r`` (n,) [m] (the thesis's r: the y component of a point's distance to the
    object's centre, Fig 4.2(d)).  ``r_max`` : default ``max(r)`` (the thesis: "the maximal
    distance of any point on the contact surface"); ``k_range`` : the interval searched for k
    (log-uniformly bounded; for each k the best p0 is the linear least-squares one).
    Raises ``ValueError`` for fewer than 3 points, non-finite or negative input, or no pressure."""
    from scipy.optimize import minimize_scalar

    r = np.asarray(r, dtype=float)
    p = np.asarray(p, dtype=float)
    if r.ndim != 1 or r.shape != p.shape or r.size < 3:
        raise ValueError(
            f"r and p must be (n,) arrays of one length n >= 3; got shapes {r.shape} and {p.shape}"
        )
    if not (np.isfinite(r).all() and np.isfinite(p).all()) or (r < 0).any() or (p < 0).any():
        raise ValueError("r and p must be finite and >= 0 (distances [m], pressures)")
    if not (p > 0).any():
        raise ValueError("no positive pressure to fit: the contact carries no load")
    r_max = float(r.max()) if r_max is None else float(r_max)
    if not (np.isfinite(r_max) and r_max > 0 and r_max >= r.max()):
        raise ValueError(f"r_max must be > 0 and >= max(r) = {r.max():.6g} m; got {r_max}")
    lo, hi = (float(x) for x in k_range)
    if not (0 < lo < hi < np.inf):
        raise ValueError(f"k_range must be (lo, hi) with 0 < lo < hi < inf; got {k_range}")

    def best(log_k: float) -> tuple[float, float]:
        shape = power_law(r, r_max, float(np.exp(log_k)))
        p0 = float(shape @ p / (shape @ shape)) if shape @ shape > 0 else 0.0
        return p0, float(np.sum((p - p0 * shape) ** 2))

    res = minimize_scalar(
        lambda t: best(t)[1], bounds=(np.log(lo), np.log(hi)), method="bounded", options={"xatol": 1e-8}
    )
    log_k, at_bound = float(res.x), False
    sse = best(log_k)[1]
    # an end of the interval that fits as well: the data do not fix k inside it (a pressure flat
    # to the rim makes every large k alike), so the end is the answer, flagged
    tie = sse + 1e-12 * float(p @ p)
    for end in (np.log(hi), np.log(lo)):
        if best(end)[1] <= tie:
            log_k, at_bound = float(end), True
            break
    p0, sse = best(log_k)
    return PowerLawFit(float(np.exp(log_k)), p0, r_max, float(np.sqrt(sse / float(p @ p))), at_bound)

"""Rank correlation of predictions with measurements, robust to last-bit noise.

Mirror-symmetric grasp locations give predicted stiffnesses equal to the last bit or two
(relative gaps of 1e-16 measured on the cup's map); Spearman's rank correlation breaks such
near-ties by that noise, which differs between runs (thread counts, solve order) — and moved
a reported correlation by 0.0016.  Values equal to ``digits`` significant digits rank as ties.
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

__all__ = ["rank_correlation", "significant"]


def significant(x: Any, digits: int = 12) -> np.ndarray:
    """``x`` rounded to ``digits`` significant digits (zeros and non-finite values kept);
    ``digits`` a positive int (ValueError otherwise)."""
    if isinstance(digits, bool) or not isinstance(digits, numbers.Integral) or digits < 1:
        raise ValueError(
            f"digits must be a positive int (significant digits kept, e.g. the default 12); got {digits!r}"
        )
    x = np.asarray(x, dtype=np.float64)
    mag = np.abs(x)
    safe = np.isfinite(mag) & (mag > 0)
    exp = np.floor(np.log10(np.where(safe, mag, 1.0)))
    scale = 10.0 ** (digits - 1 - exp)
    return np.where(safe, np.round(x * scale) / scale, x)


def rank_correlation(pred: Any, measured: Any, digits: int = 12) -> float:
    """Spearman's rank correlation of ``pred`` (n,) with ``measured`` (n,), both rounded to
    ``digits`` (a positive int) significant digits first (module docstring); NaN for fewer
    than 2 pairs.  Every value must be finite: a NaN or inf (a failed or rigid grasp) has no
    rank — leave such pairs out first (ValueError; every caller masks them already)."""
    pred, measured = np.asarray(pred, float), np.asarray(measured, float)
    if pred.shape != measured.shape or pred.ndim != 1:
        raise ValueError(
            f"pred and measured must be (n,) arrays of one length; got {pred.shape}, {measured.shape}"
        )
    for name, v in (("pred", pred), ("measured", measured)):
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise ValueError(
                f"{name} must be finite to be ranked; got {v[bad[0]]} at index {bad[0]} ({bad.size} of "
                f"{v.size} not finite). Leave those pairs out first, e.g. ok = np.isfinite(pred) & "
                "np.isfinite(measured); rank_correlation(pred[ok], measured[ok])"
            )
    if len(pred) < 2:
        return float("nan")
    from scipy.stats import spearmanr

    return float(spearmanr(significant(pred, digits), significant(measured, digits)).statistic)

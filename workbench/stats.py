"""Rank correlation of predictions with measurements, robust to last-bit noise.

Mirror-symmetric grasp locations give predicted stiffnesses equal to the last bit or two
(relative gaps of 1e-16 measured on the cup's map); Spearman's rank correlation breaks such
near-ties by that noise, which differs between runs (thread counts, solve order) — and moved
a reported correlation by 0.0016.  Values equal to ``digits`` significant digits rank as ties.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["rank_correlation", "significant"]


def significant(x: Any, digits: int = 12) -> np.ndarray:
    """``x`` rounded to ``digits`` significant digits (zeros and non-finite values kept)."""
    x = np.asarray(x, dtype=np.float64)
    mag = np.abs(x)
    safe = np.isfinite(mag) & (mag > 0)
    exp = np.floor(np.log10(np.where(safe, mag, 1.0)))
    scale = 10.0 ** (digits - 1 - exp)
    return np.where(safe, np.round(x * scale) / scale, x)


def rank_correlation(pred: Any, measured: Any, digits: int = 12) -> float:
    """Spearman's rank correlation of ``pred`` (n,) with ``measured`` (n,), both rounded to
    ``digits`` significant digits first (module docstring); NaN for fewer than 2 pairs."""
    pred, measured = np.asarray(pred, float), np.asarray(measured, float)
    if pred.shape != measured.shape or pred.ndim != 1:
        raise ValueError(
            f"pred and measured must be (n,) arrays of one length; got {pred.shape}, {measured.shape}"
        )
    if len(pred) < 2:
        return float("nan")
    from scipy.stats import spearmanr

    return float(spearmanr(significant(pred, digits), significant(measured, digits)).statistic)

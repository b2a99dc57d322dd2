"""Rank correlation of predictions with measurements, robust to solver noise.

Mirror-symmetric grasp locations give predicted stiffnesses equal up to the solver's accuracy:
the last bit or two for a linear solve (relative gaps of 1e-16 measured on the cup's map), ~1e-11
for the nonlinear wall's Newton curves (two runs differing only in the sparse factor's ordering
moved a held-out Spearman percentile from 0.188 to 0.200).  Spearman's rank correlation breaks
such near-ties by that noise.  Here values whose sorted neighbours lie within
``config.TOL.rank_tie_rtol`` (relative) form one tie group with the average rank — a gap test, not
rounding, so no rounding boundary can split a near-tie.
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

__all__ = ["rank_correlation", "tie_ranks"]


def tie_ranks(x: Any, rtol: float) -> np.ndarray:
    """Ranks 1..n of ``x`` (n,) with ties averaged, a tie being a run of sorted values each
    within ``rtol`` (relative to the larger magnitude) of the one before — as scipy's
    ``rankdata(method="average")`` when ``rtol`` is 0."""
    x = np.asarray(x, dtype=np.float64)
    order = np.argsort(x, kind="stable")
    s = x[order]
    gap = np.abs(np.diff(s)) > rtol * np.maximum(np.abs(s[1:]), np.abs(s[:-1]))
    group = np.concatenate([[0], np.cumsum(gap)])
    mean_rank = np.bincount(group, np.arange(1.0, len(s) + 1)) / np.bincount(group)
    ranks = np.empty(len(s))
    ranks[order] = mean_rank[group]
    return ranks


def rank_correlation(pred: Any, measured: Any, rtol: float | None = None) -> float:
    """Spearman's rank correlation of ``pred`` (n,) with ``measured`` (n,), values within
    ``rtol`` (default ``config.TOL.rank_tie_rtol``, read now) of each other ranked as ties
    (module docstring); NaN for fewer than 2 pairs or when either side is all one tie.  Every
    value must be finite: a NaN or inf (a failed or rigid grasp) has no rank — leave such pairs
    out first (ValueError; every caller masks them already)."""
    from . import config

    rtol = config.TOL.rank_tie_rtol if rtol is None else rtol
    if isinstance(rtol, bool) or not isinstance(rtol, numbers.Real) or not 0 <= rtol <= 1e-3:
        raise ValueError(
            f"rtol must be a relative gap in [0, 1e-3] below which values tie (default "
            f"config.TOL.rank_tie_rtol = {config.TOL.rank_tie_rtol:g}); got {rtol!r}"
        )
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
    a, b = tie_ranks(pred, rtol), tie_ranks(measured, rtol)
    a, b = a - a.mean(), b - b.mean()
    denom = np.sqrt((a @ a) * (b @ b))
    return float(a @ b / denom) if denom > 0 else float("nan")

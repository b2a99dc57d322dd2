"""The resistance margin of a grasp against a disturbance: the largest ``s`` with ``s w``
resisted, by bisection on ``log s`` (thesis §4.1.3.2's capacity, Fig 4.4), and the error of
one model's margins against the truth's."""

from __future__ import annotations

import numbers
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = [
    "MARGIN_SPAN",
    "check_span",
    "check_steps",
    "margin_rel_err",
    "margin_vs_truth",
    "resistance_margin",
]

#: margins are bisected in [1/MARGIN_SPAN, MARGIN_SPAN] (0 below, MARGIN_SPAN above)
MARGIN_SPAN = 64.0


def check_steps(steps: Any, name: str = "steps") -> int:
    """``steps`` (bisection steps of :func:`resistance_margin`) as an int >= 1, else ``ValueError``:
    with no step the bisection returns its lower end ``1/span`` whatever the margin."""
    if isinstance(steps, (bool, np.bool_)) or not isinstance(steps, numbers.Integral) or steps < 1:
        raise ValueError(
            f"{name} must be an integer >= 1 (bisection steps on log2 s, resolution 2 log2(span) / 2^steps); "
            f"got {steps!r} — pass a whole number of steps, e.g. {name}=12 (0.2 % at the default span; "
            "with no step the margin would be the bracket's lower end 1/span, not the grasp's)"
        )
    return int(steps)


def check_span(span: Any) -> float:
    """``span`` (margins are bisected in ``[1/span, span]``) as a float > 1, else ``ValueError``."""
    if (
        isinstance(span, (bool, np.bool_))
        or not isinstance(span, numbers.Real)
        or not (np.isfinite(span) and span > 1)
    ):
        raise ValueError(
            f"span must be a number > 1 (margins are bisected in [1/span, span], default {MARGIN_SPAN}); "
            f"got {span!r}"
        )
    return float(span)


def resistance_margin(
    resisted: Callable[[np.ndarray], bool], w: np.ndarray, steps: int, span: float = MARGIN_SPAN
) -> float:
    """Largest ``s`` in ``[1/span, span]`` with ``resisted(s w)`` (0 below, ``span`` above).

    resisted : ``(6,) -> bool``, e.g. ``partial(resists, contacts, mu=mu)``; w : (6,) the
    disturbance; steps : bisection steps on ``log2 s``, an integer >= 1 (resolution
    ``2 log2(span) / 2^steps``); span : > 1.
    The resistible set is convex and contains 0 (the squeeze forces balance), so resistance
    is monotone along the ray and the bisection finds ``s*``.
    """
    if not callable(resisted):
        raise ValueError(
            f"resisted must be a callable (6,) wrench -> bool, e.g. partial(resists, contacts, mu=mu); "
            f"got {type(resisted).__name__}"
        )
    w = np.asarray(w, dtype=float)
    if w.shape != (6,):
        raise ValueError(f"w must be a (6,) wrench [f; tau]; got shape {w.shape}")
    if not np.isfinite(w).all():
        raise ValueError(f"w must be a finite (6,) wrench; got non-finite entries: {w.tolist()}")
    steps = check_steps(steps)
    span = check_span(span)
    if resisted(span * w):
        return float(span)
    if not resisted(w / span):
        return 0.0
    lo, hi = -np.log2(span), np.log2(span)
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        if resisted(2.0**mid * w):
            lo = mid
        else:
            hi = mid
    return float(2.0**lo)


def margin_vs_truth(s_m: np.ndarray, true_margin: np.ndarray, span: float = MARGIN_SPAN) -> dict:
    """Capacity error of a model's margins (n,) against the truth's (n,), where both are
    finite and inside ``(0, span)``: median |log ratio|, its sign (> 0: optimistic)."""
    span = check_span(span)
    s_m, true_margin = np.asarray(s_m, float), np.asarray(true_margin, float)
    if s_m.shape != true_margin.shape:
        raise ValueError(
            f"margins and true margins must have one shape; got {s_m.shape}, {true_margin.shape}"
        )
    ok = (s_m > 0) & (true_margin > 0) & (s_m < span) & (true_margin < span)
    lr = np.log(s_m[ok] / true_margin[ok])
    return {
        "n": int(ok.sum()),
        "median_abs_log_ratio": float(np.median(np.abs(lr))) if ok.any() else float("nan"),
        "median_log_ratio": float(np.median(lr)) if ok.any() else float("nan"),
        "optimistic_fraction": float((lr > 0).mean()) if ok.any() else float("nan"),
    }


def margin_rel_err(s_m: np.ndarray, true_margin: np.ndarray) -> float | None:
    """Median ``|s / s_true − 1|`` of a model's margins (n,) against the truth's (n,) over the
    pairs where both are > 0 (None if there is none).

    Unlike :func:`margin_vs_truth` it keeps margins at the bracket's upper end ``span`` (where
    the bisection stops: the grasp resists at least that much), so a pair with both there counts
    as agreeing."""
    s_m, true_margin = np.asarray(s_m, float), np.asarray(true_margin, float)
    if s_m.shape != true_margin.shape:
        raise ValueError(
            f"margins and true margins must have one shape; got {s_m.shape}, {true_margin.shape}"
        )
    ok = (true_margin > 0) & (s_m > 0)
    rel = np.abs(s_m[ok] / true_margin[ok] - 1)
    return float(np.median(rel)) if ok.any() else None

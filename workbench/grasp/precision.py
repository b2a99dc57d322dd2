"""Precision and recall of "resisted" predictions against the truth, and the best recall a
model's margins reach at a required precision (the sensitivity study's matched precision)."""

from __future__ import annotations

import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["check_levels", "matched_precision", "recall_at_least", "scores"]


def scores(pred: np.ndarray, truth: np.ndarray) -> dict:
    """Precision, recall, F1 (their harmonic mean, thesis §4.1.3.4), accuracy (the fraction
    predicted right) and the number of positives of boolean predictions (n,) against the truth
    (n,); NaN where undefined (no positive prediction, no positive truth, no grasp)."""
    pred, truth = np.asarray(pred), np.asarray(truth)
    if pred.shape != truth.shape or pred.dtype != bool or truth.dtype != bool:
        raise ValueError(
            f"pred and truth must be boolean arrays of one shape; got {pred.dtype} {pred.shape}, "
            f"{truth.dtype} {truth.shape}"
        )
    tp = int((pred & truth).sum())
    fp = int((pred & ~truth).sum())
    fn = int((~pred & truth).sum())
    precision = tp / (tp + fp) if tp + fp else float("nan")
    recall = tp / (tp + fn) if tp + fn else float("nan")
    return {
        "precision": precision,
        "recall": recall,
        "f1": 2 * tp / (2 * tp + fp + fn) if tp + fp + fn else float("nan"),
        "accuracy": float((pred == truth).mean()) if len(pred) else float("nan"),
        "positives": int(pred.sum()),
    }


def check_levels(levels: Any) -> None:
    """``levels`` a sequence of precision levels in (0, 1] (:func:`matched_precision`'s);
    ValueError saying what it got otherwise (an experiment's ``check_config`` calls it too)."""
    if isinstance(levels, str) or not np.iterable(levels):
        raise ValueError(
            f"levels must be a sequence of precision levels in (0, 1], e.g. [0.9, 0.95]; got {levels!r} "
            f"(a single level: pass [{levels!r}])"
        )
    for level in levels:
        if isinstance(level, bool) or not isinstance(level, numbers.Real) or not 0 < level <= 1:
            raise ValueError(
                f"levels must be precision levels in (0, 1] (fractions, not percent: 0.9 for 90 %); got "
                f"{level!r} in {list(levels)!r}"
            )


def _check_matched(margins: Any, truth: Any, levels: Any) -> tuple[np.ndarray, np.ndarray]:
    """``margins`` (n,) float without NaN and ``truth`` (n,) bool; ValueError naming
    :func:`matched_precision`'s arguments otherwise, and for levels outside (0, 1]
    (:func:`check_levels`)."""
    m, t = np.asarray(margins), np.asarray(truth)
    if m.ndim != 1 or m.dtype == bool or not np.issubdtype(m.dtype, np.number):
        raise ValueError(
            f"margins must be an (n,) array of numbers (resistance margins s*, one per disturbance); "
            f"got {m.dtype} shape {m.shape}"
        )
    m = m.astype(float)
    if np.isnan(m).any():
        raise ValueError(
            f"margins must not be NaN (a NaN is neither resisted nor not); got {int(np.isnan(m).sum())} "
            f"NaN of {m.size} at index {int(np.argmax(np.isnan(m)))} — leave those disturbances out of "
            "margins and truth"
        )
    if t.shape != m.shape or t.dtype != bool:
        raise ValueError(
            f"truth must be an (n,) boolean array like margins {m.shape} (True: the truth resists); got "
            f"{t.dtype} shape {t.shape} — convert 0/1 with np.asarray(truth, bool)"
        )
    check_levels(levels)
    return m, t


def matched_precision(margins: Any, truth: Any, levels: Sequence[float]) -> dict:
    """Precision-recall curve of ``margins >= t`` over every threshold t, and for each
    precision level the best recall at precision >= level (and its t; NaN if the
    model never reaches it).  ``t = 1`` is the model's plain prediction.

    margins : (n,) resistance margins (no NaN); truth : (n,) bool, whether the truth resists;
    levels : sequence of precision levels in (0, 1].  ValueError otherwise.
    """
    margins, truth = _check_matched(margins, truth, levels)
    ts = np.unique(margins[margins > 0])
    curve = [(float(t), *(scores(margins >= t, truth)[k] for k in ("precision", "recall"))) for t in ts]
    out = {
        "threshold": [c[0] for c in curve],
        "precision": [c[1] for c in curve],
        "recall": [c[2] for c in curve],
    }
    best = []
    for level in levels:
        ok = [c for c in curve if c[1] >= level]
        best.append(max(ok, key=lambda c: (c[2], -c[0])) if ok else (float("nan"),) * 3)
    out["at_levels"] = {"level": levels, "recall": [b[2] for b in best], "threshold": [b[0] for b in best]}
    return out


def recall_at_least(matched: dict, better: list[str], worse: list[str], levels: list[float]) -> dict:
    """``{str(level): bool}``: at each precision level of :func:`matched_precision` results
    ``matched`` ({model: result at ``levels``}), whether every model of ``better`` has at
    least the recall of every model of ``worse``.  A model that never reaches a level (recall
    NaN) counts 0 there: it cannot be made that precise."""
    for m in [*better, *worse]:
        if len(matched[m]["at_levels"]["recall"]) != len(levels):
            raise ValueError(
                f"{m}: {len(matched[m]['at_levels']['recall'])} recalls for {len(levels)} precision levels "
                "— pass the levels matched_precision was given"
            )

    def recall(m: str, j: int) -> float:
        return float(np.nan_to_num(matched[m]["at_levels"]["recall"][j]))

    return {
        str(level): all(recall(a, j) >= recall(b, j) for a in better for b in worse)
        for j, level in enumerate(levels)
    }

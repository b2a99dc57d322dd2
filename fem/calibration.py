"""One-scalar calibration of a simulated stiffness map against a measured one (issue 13).

A linear wall's stiffness is proportional to its Young's modulus (and to E·t³ in
bending), so the model is calibrated by one factor ``c``: ``log c`` is the median of
``log(s_measured / s_model)`` over training grasps, and the prediction
``c · s_model`` is scored on the held-out grasps by the Spearman rank correlation and
the median ``|log(c · s_model / s_measured)|``.

With 30–50 grasps per object a single random half gives a noisy score, so
:func:`split_scores` also reports its spread over many random halves; ``groups`` gives
one factor per group (e.g. the lower and upper half of the heights) — the
measurement that tells whether a stiffness varying over the object (thickness, a
stiffer shoulder) is what one factor misses.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import spearmanr


def _check(model: np.ndarray, measured: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    model, measured = np.asarray(model, float), np.asarray(measured, float)
    if model.ndim != 1 or model.shape != measured.shape:
        raise ValueError(
            f"model and measured must be (n,) stiffness arrays; got {model.shape}, {measured.shape}"
        )
    if not (
        (model > 0).all()
        and (measured > 0).all()
        and np.isfinite(model).all()
        and np.isfinite(measured).all()
    ):
        raise ValueError(
            "stiffness values must be finite and > 0 [N/m]; leave rigid and failed grasps out first"
        )
    return model, measured


def calibrate(
    model: np.ndarray, measured: np.ndarray, train: np.ndarray, groups: np.ndarray | None = None
) -> np.ndarray:
    """(n,) factor per grasp: ``exp(median log(measured / model))`` over the training grasps
    of its group.  model, measured : (n,) [N/m]; train : (k,) indices; groups : (n,) int
    labels (default one group); a group without training grasps gets the overall factor."""
    model, measured = _check(model, measured)
    train = np.asarray(train, int)
    g = np.zeros(model.size, int) if groups is None else np.asarray(groups)
    if g.shape != model.shape:
        raise ValueError(f"groups must be (n,) = {model.shape}; got {g.shape}")
    lr = np.log(measured / model)
    c = np.full(model.size, np.median(lr[train]))
    for label in np.unique(g):
        t = train[g[train] == label]
        if t.size:
            c[g == label] = np.median(lr[t])
    return np.exp(c)


def held_out(
    model: np.ndarray, measured: np.ndarray, train: np.ndarray, groups: np.ndarray | None = None
) -> dict:
    """Scores on the grasps not in ``train``: ``spearman`` and ``median_abs_log_ratio``."""
    model, measured = _check(model, measured)
    pred = model * calibrate(model, measured, train, groups)
    test = np.setdiff1d(np.arange(model.size), train)
    return {
        "spearman": float(spearmanr(pred[test], measured[test]).statistic),
        "median_abs_log_ratio": float(np.median(np.abs(np.log(pred[test] / measured[test])))),
    }


def split_scores(
    model: np.ndarray,
    measured: np.ndarray,
    *,
    groups: np.ndarray | None = None,
    n_splits: int = 200,
    seed: int = 0,
) -> dict:
    """:func:`held_out` over ``n_splits`` random halves: median, 10th and 90th percentile of
    each score."""
    model, measured = _check(model, measured)
    rng = np.random.default_rng(seed)
    n = model.size
    rows = [held_out(model, measured, rng.permutation(n)[: n // 2], groups) for _ in range(n_splits)]
    out = {}
    for key in ("spearman", "median_abs_log_ratio"):
        v = np.array([r[key] for r in rows])
        out[key] = {
            "median": float(np.median(v)),
            "p10": float(np.percentile(v, 10)),
            "p90": float(np.percentile(v, 90)),
        }
    out["n_splits"] = n_splits
    return out


__all__ = ["calibrate", "held_out", "split_scores"]

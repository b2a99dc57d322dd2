"""One-scalar calibration of a simulated stiffness map against a measured one (thesis §4.3.3.1).

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

:func:`missing_physics` gives the measurements that tell which physics the calibrated
linear wall lacks where it falls short: a bound on any compliance in series with the
wall (pads, fingers) from the stiffest measured grasp, the residual against the closing
the model predicts relative to the object's width (large deflection), and the scores
away from the clamped edges of the model (its boundary conditions).
"""

from __future__ import annotations

import numpy as np

from workbench.stats import rank_correlation


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
    return _scores(model * calibrate(model, measured, train, groups), measured, train)


def stiffness_scores(pred: np.ndarray, measured: np.ndarray) -> dict:
    """How well stiffnesses ``pred`` (n,) [N/m] predict the measured ones (n,) [N/m], the two
    scores of every comparison with a measured map: ``spearman`` (their rank correlation,
    :func:`workbench.stats.rank_correlation`) and ``median_abs_log_ratio`` (the median of
    ``|log(pred / measured)|``: 0.1 is a typical error of about 10 %).  Both finite and > 0."""
    return {
        "spearman": rank_correlation(pred, measured),
        "median_abs_log_ratio": float(np.median(np.abs(np.log(pred / measured)))),
    }


def _scores(pred: np.ndarray, measured: np.ndarray, train: np.ndarray) -> dict:
    test = np.setdiff1d(np.arange(measured.size), train)
    return stiffness_scores(pred[test], measured[test])


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
    return split_scores_of(
        lambda train: model * calibrate(model, measured, train, groups),
        measured,
        n_splits=n_splits,
        seed=seed,
    )


def split_scores_of(predict, measured: np.ndarray, *, n_splits: int = 200, seed: int = 0) -> dict:
    """:func:`split_scores` of a model calibrated by any fit: ``predict(train)`` returns the
    (n,) stiffness [N/m] of the model calibrated on the grasps ``train`` (k,) — e.g. a
    nonlinear wall, whose stiffness at a force is not proportional to E.  The same random
    halves as :func:`split_scores` for the same ``seed``.  A half whose calibrated model
    predicts a non-finite stiffness (e.g. a load curve that stops below the force at that
    E) is left out of the statistics and counted in ``n_failed``."""
    measured = np.asarray(measured, float)
    rng = np.random.default_rng(seed)
    n = measured.size
    rows, failed = [], 0
    for _ in range(n_splits):
        train = rng.permutation(n)[: n // 2]
        pred = np.asarray(predict(train), float)
        if not np.isfinite(pred).all():
            failed += 1
            continue
        rows.append(_scores(pred, measured, train))
    out: dict = {"n_failed": failed}
    if not rows:
        raise ValueError(f"the model predicted a non-finite stiffness on all {n_splits} halves")
    for key in ("spearman", "median_abs_log_ratio"):
        v = np.array([r[key] for r in rows])
        out[key] = {
            "median": float(np.median(v)),
            "p10": float(np.percentile(v, 10)),
            "p90": float(np.percentile(v, 90)),
        }
    out["n_splits"] = n_splits
    return out


def missing_physics(  # noqa: PLR0913 — four (n,) arrays of one grasp list, then independent keyword settings
    model: np.ndarray,
    measured: np.ndarray,
    *,
    width: np.ndarray,
    clamp_distance: np.ndarray,
    force: float = 10.0,
    near: float = 0.015,
    rigid: float | None = None,
    n_splits: int = 200,
    seed: int = 0,
) -> dict:
    """Measurements of what a one-factor calibration of ``model`` leaves unexplained.

    model, measured : (n,) stiffness per grasp [N/m] (``>= rigid`` or non-finite: rigid
        or failed; such grasps are left out of the scores).
    width : (n,) the object's width along each grasp axis [m] (distance between its
        two contact points).
    clamp_distance : (n,) height of each grasp from the nearest clamped edge of the
        model's wall [m] (``np.inf`` where nothing is clamped).
    force : jaw force of the measurements [N] (closing = force / stiffness).
    near : grasps closer than this to a clamp [m] are "near" (the clamp's reach).
    rigid : [N/m]; None reads ``config.TOL.rigid_stiffness_threshold``.

    Returns a dict:

    * ``series_compliance_bound_m_per_N`` = 1 / (largest finite measured stiffness):
      a compliance ``c`` in series (pads, fingers) would make every measurement
      ``1 / (1/s + c) < 1/c``, so ``c`` is at most this; ``series_effect_at_median``
      is the most it could lower the median calibrated model value, ``1 − 1/(1 + s c)``.
    * ``closing_fraction``: ``log(measured / (k · model))`` (``k`` the all-grasp factor)
      against the closing the calibrated model predicts divided by the width — Spearman,
      and per bin the median residual and the median / largest measured closing ÷ width.
      Residuals that rise with it while the measured closings level off are a
      large-deflection response a small-strain linear model cannot give.
    * ``away_from_clamps``: :func:`split_scores` on the grasps at least ``near`` from a
      clamp, and the measured stiffness of the grasps the model calls rigid there.
    """
    from workbench import config

    rigid = config.TOL.rigid_stiffness_threshold if rigid is None else float(rigid)
    model, measured = np.asarray(model, float), np.asarray(measured, float)
    width, clamp_distance = np.asarray(width, float), np.asarray(clamp_distance, float)
    if not (model.shape == measured.shape == width.shape == clamp_distance.shape) or model.ndim != 1:
        raise ValueError(
            "model, measured, width and clamp_distance must be (n,) arrays of one length; got "
            f"{model.shape}, {measured.shape}, {width.shape}, {clamp_distance.shape}"
        )
    if not (np.isfinite(width).all() and (width > 0).all()):
        raise ValueError("width must be finite and > 0 [m] (the distance between a grasp's two points)")
    ok = np.isfinite(model) & (model < rigid) & np.isfinite(measured) & (measured < rigid)
    if ok.sum() < 4:
        raise ValueError(f"need at least 4 grasps that neither side calls rigid; got {int(ok.sum())}")
    k = float(np.exp(np.median(np.log(measured[ok] / model[ok]))))
    res, frac, meas_frac = (np.full(model.size, np.nan) for _ in range(3))  # rigid grasps: NaN
    res[ok] = np.log(measured[ok] / (k * model[ok]))
    frac[ok] = force / (k * model[ok]) / width[ok]
    meas_frac[ok] = force / measured[ok] / width[ok]
    bound = 1.0 / float(measured[ok].max())
    s_med = k * float(np.median(model[ok]))
    bins = []
    for lo, hi in ((0.0, 0.2), (0.2, 0.4), (0.4, 0.6), (0.6, np.inf)):
        m = ok & (frac >= lo) & (frac < hi)
        if m.any():
            bins.append(
                {
                    "predicted_closing_over_width": [lo, None if np.isinf(hi) else hi],
                    "n": int(m.sum()),
                    "median_residual": float(np.median(res[m])),
                    "measured_closing_over_width_median": float(np.median(meas_frac[m])),
                    "measured_closing_over_width_max": float(np.max(meas_frac[m])),
                }
            )
    far = ok & (clamp_distance >= near)
    rigid_near = (clamp_distance < near) & ~(np.isfinite(model) & (model < rigid))
    return {
        "calibration_factor": k,
        "series_compliance_bound_m_per_N": bound,
        "series_effect_at_median": 1.0 - 1.0 / (1.0 + s_med * bound),
        "closing_fraction": {
            "spearman_residual": rank_correlation(res[ok], frac[ok]),
            "bins": bins,
            "measured_closing_over_width_max": float(meas_frac[ok].max()),
        },
        "away_from_clamps": {
            "near_m": near,
            "n": int(far.sum()),
            "n_all": int(ok.sum()),
            "scores": split_scores(model[far], measured[far], n_splits=n_splits, seed=seed)
            if far.sum() >= 4
            else None,
            "model_rigid_near_clamps_measured": [float(x) for x in measured[rigid_near]],
        },
    }


def one_factor_validation(
    model: np.ndarray, measured: np.ndarray, rng: np.random.Generator, *, heights: np.ndarray, E: float
) -> tuple[dict, np.ndarray, np.ndarray]:
    """The one-factor calibration of a linear wall of Young's modulus ``E`` [Pa] on a random
    half of the grasps, scored on the other half: ``(scores, train, test)``.

    model, measured : (n,) stiffness per grasp [N/m]; non-finite (a failed model grasp) or
        ``>= config.TOL.rigid_stiffness_threshold`` (rigid) grasps are left out.
    rng : draws the half (one permutation of the usable grasps; ``train`` its first half).
    heights : (n,) grasp heights [m]: the two-factor scores split them at their median.

    ``scores``: held-out Spearman (scipy's, ties by the values as given) and median
    ``|log(c s_model / s_measured)|`` with ``c = exp(median log(measured / model))`` over
    ``train``; ``calibrated`` (``E_effective_Pa = c E``, ``scale = c``); the all-grasp
    Spearman and median uncalibrated log ratio; the counts; :func:`split_scores` over random
    halves, and with one factor per half of the heights.  ``train``, ``test`` : index arrays.
    """
    from scipy.stats import spearmanr

    from workbench import config

    model, measured = np.asarray(model, float), np.asarray(measured, float)
    heights = np.asarray(heights, float)
    if not (model.ndim == 1 and model.shape == measured.shape == heights.shape):
        raise ValueError(
            "model, measured and heights must be (n,) arrays of one length; got "
            f"{model.shape}, {measured.shape}, {heights.shape}"
        )
    rigid = config.TOL.rigid_stiffness_threshold
    idx = np.flatnonzero(np.isfinite(model) & (model < rigid) & (measured < rigid))
    if idx.size < 4:
        raise ValueError(f"need at least 4 grasps that neither side calls rigid or failed; got {idx.size}")
    train = rng.permutation(idx)[: len(idx) // 2]
    test = np.setdiff1d(idx, train)
    log_c = float(np.median(np.log(measured[train] / model[train])))
    pred = model[test] * np.exp(log_c)
    scores = {
        "spearman": float(spearmanr(pred, measured[test]).statistic),
        "median_abs_log_ratio": float(np.median(np.abs(np.log(pred / measured[test])))),
        "calibrated": {"E_effective_Pa": E * np.exp(log_c), "scale": float(np.exp(log_c))},
        "spearman_all": float(spearmanr(model[idx], measured[idx]).statistic),
        "uncalibrated_median_log_ratio": float(np.median(np.log(model[idx] / measured[idx]))),
        "n_train": int(train.size),
        "n_test": int(test.size),
        "rigid_measured": int((measured >= rigid).sum()),
        "rigid_fem": int(np.sum(model >= rigid)),
        # one random half is noisy at 30-50 grasps: the same scores over 200 random halves,
        # and with one factor per half of the heights (a stiffness varying with height)
        "over_random_halves": split_scores(model[idx], measured[idx]),
        "two_factors_by_height": split_scores(
            model[idx], measured[idx], groups=(heights[idx] > np.median(heights[idx])).astype(int)
        ),
    }
    return scores, train, test


def uncalibrated_scores(
    model: np.ndarray, measured: np.ndarray, *, rigid: np.ndarray, failed: np.ndarray
) -> dict:
    """The model's stiffness against the measured map as it comes (no factor), over the grasps
    that neither calls rigid nor the model failed at.

    model, measured : (n,) stiffness per grasp [N/m]; a measured value
        ``>= config.TOL.rigid_stiffness_threshold`` is rigid (the maps mark rigid with 8e10);
    rigid, failed : (n,) bool, the model's flags (:func:`workbench.fem.wall_grasps.stiffness_at`).

    Returns ``{"n", "spearman", "median_log_ratio", "median_abs_log_ratio"}`` (the log ratio
    ``log(model / measured)``), or ``{"n", "note"}`` below 3 such grasps.
    """
    from workbench.config import TOL

    model, measured = np.asarray(model, float), np.asarray(measured, float)
    rigid_model, failed = np.asarray(rigid, bool), np.asarray(failed, bool)
    if not (model.ndim == 1 and model.shape == measured.shape == rigid_model.shape == failed.shape):
        raise ValueError(
            "model, measured, rigid and failed must be (n,) arrays of one length, one entry per grasp; "
            f"got {model.shape}, {measured.shape}, {rigid_model.shape}, {failed.shape}"
        )
    ok = ~rigid_model & ~failed & ~(measured >= TOL.rigid_stiffness_threshold)
    if ok.sum() < 3:
        return {
            "n": int(ok.sum()),
            "note": "fewer than 3 grasps that neither the model nor the measurement calls rigid "
            "(or failed): no comparison",
        }
    scores = stiffness_scores(model[ok], measured[ok])
    return {
        "n": int(ok.sum()),
        "spearman": scores["spearman"],
        "median_log_ratio": float(np.median(np.log(model[ok] / measured[ok]))),
        "median_abs_log_ratio": scores["median_abs_log_ratio"],
    }


__all__ = [
    "calibrate",
    "held_out",
    "missing_physics",
    "one_factor_validation",
    "split_scores",
    "stiffness_scores",
    "uncalibrated_scores",
]

"""Table 4.6's scoring (thesis §4.3.4): grasp qualities thresholded at σ, scored by balanced
accuracy on held-out grasps against whichever truth is given (simulated, engine, real).

A quality given as a cost ``x`` (the minimal force f⊥ or work W; ``inf`` when the task wrench
is not resisted) becomes ``q = 1 − x / X_max`` with ``X_max`` fitted on the training grasps
(:func:`~workbench.grasp.threshold.fit_normaliser`); a quality already in [0, 1] (q_robust,
Eq. 2.101) is thresholded as it is.  :func:`training_split` draws which grasps train.
"""

from __future__ import annotations

import numbers

import numpy as np

from ..seeds import check_seed
from .threshold import balanced_accuracy_interval, fit_normaliser, held_out_accuracy

__all__ = ["quality_table", "training_split"]


def training_split(n: int, train_fraction: float, seed: int | np.random.Generator) -> np.ndarray:
    """(n,) bool, True: a training grasp — each of ``n`` grasps independently with probability
    ``train_fraction`` in (0, 1) (one uniform draw per grasp from a generator seeded with
    ``seed``, in grasp order), so the training share is ``train_fraction`` on average, not
    exactly."""
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, numbers.Integral) or n < 0:
        raise ValueError(f"n must be a number of grasps, an integer >= 0; got {n!r}")
    if (
        isinstance(train_fraction, (bool, np.bool_))
        or not isinstance(train_fraction, numbers.Real)
        or not 0 < train_fraction < 1
    ):
        raise ValueError(
            f"train_fraction must be in (0, 1) (the share of grasps the normalisers are fitted on); got "
            f"{train_fraction!r} — a percentage? 50 % is 0.5"
        )
    return np.random.default_rng(check_seed(seed)).random(n) < train_fraction


def quality_table(  # noqa: PLR0913 — labelled grasps, metrics, threshold, bootstrap: no natural group
    truth,
    train,
    groups,
    names,
    *,
    qualities: dict | None = None,
    costs: dict | None = None,
    sigma: float = 0.5,
    n_resamples: int = 2000,
    seed: int = 0,
) -> dict:
    """Balanced accuracy of each quality on the held-out grasps, per group and overall, with a
    bootstrap interval of the overall one.

    truth, train : (n,) bool — each grasp's success and whether it is a training grasp;
    groups : (n,) labels (object names); names : the labels reported, in order;
    qualities : {metric: (n,) quality}, predicted success iff ``q >= sigma``;
    costs : {metric: (n,) cost >= 0, inf = unresisted}, normalised on the training grasps.

    Returns ``{"accuracy": {metric: {name: BA or None, "All": BA}}, "interval_95": {metric:
    (low, high) or None}, "normalisers": {metric: X_max}}``.
    """
    truth = np.asarray(truth, bool)
    train = np.asarray(train, bool)
    qualities, costs = dict(qualities or {}), dict(costs or {})
    if not qualities and not costs:
        raise ValueError("quality_table needs at least one quality or cost to score")
    normalisers = {}
    for metric, x in costs.items():
        x = np.asarray(x, float)
        normalisers[metric] = fit_normaliser(x[train], truth[train], sigma)
        qualities[metric] = 1.0 - x / normalisers[metric]
    accuracy, interval = {}, {}
    for metric, q in qualities.items():
        predicted = np.asarray(q, float) >= sigma
        accuracy[metric] = held_out_accuracy(predicted, truth, train, groups, names)
        interval[metric] = balanced_accuracy_interval(
            predicted[~train], truth[~train], n_resamples=n_resamples, seed=seed
        )
    return {"accuracy": accuracy, "interval_95": interval, "normalisers": normalisers}

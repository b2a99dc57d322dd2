"""A continuous grasp quality scored against the binary outcomes of physical trials, its
success threshold chosen only by leave-one-grasp-out cross-validation (6DFC, ICRA 2020 §V:
AP / AR, mAP / mAR; thesis §4.3.1.2: balanced accuracy).

Each trial has a ``group`` (its grasp: the repeats of one grasp pose share it), a ``quality``
(higher = predicted more likely to succeed; ±inf allowed, NaN refused) and a real ``success``.
A grasp's prediction ``quality >= t`` uses a threshold ``t`` fitted on the *other* grasps
only (:func:`loo_group_thresholds`), so the scores of :func:`crossval_scores` are held-out
scores; :func:`roc_auc`, :func:`average_precision` and :func:`average_recall` need no
threshold.  mAP / mAR are these per object, averaged over objects by the caller;
:func:`seed_summary` gives mean ± std over robustness seeds.
"""

from __future__ import annotations

import numbers
import warnings
from collections.abc import Callable, Hashable, Sequence

import numpy as np

from ..plausible import ImplausibleWarning
from .precision import scores
from .threshold import _bools, balanced_accuracy

__all__ = [
    "average_precision",
    "average_recall",
    "best_threshold",
    "crossval_scores",
    "loo_group_thresholds",
    "roc_auc",
    "roc_curve_points",
    "seed_summary",
]

_FMAX = float(np.finfo(float).max)


def _check(quality, success) -> tuple[np.ndarray, np.ndarray]:
    """``quality`` (n,) float without NaN and ``success`` (n,) bool (0/1 accepted)."""
    q = np.asarray(quality)
    if q.ndim != 1 or q.size == 0 or q.dtype == bool or not np.issubdtype(q.dtype, np.number):
        raise ValueError(
            f"quality must be a non-empty (n,) array of numbers, one per trial; got {q.dtype} shape "
            f"{q.shape} — a boolean prediction is scored with balanced_accuracy, not here"
        )
    q = q.astype(float)
    nan = np.isnan(q)
    if nan.any():
        raise ValueError(
            f"quality must not be NaN (a NaN ranks neither above nor below a threshold); got "
            f"{int(nan.sum())} NaN of {q.size}, first at trial {int(np.argmax(nan))} — drop those trials "
            "from quality, success and group, or give a failed evaluation -inf (predicted to fail)"
        )
    s = _bools(success, "success")
    if s.shape != q.shape:
        raise ValueError(
            f"quality and success must have one shape (n,), one entry per trial; got {q.shape} and {s.shape}"
        )
    return q, s


def _check_group(group, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The distinct labels of ``group`` (n,) in sorted order and each trial's index into them."""
    g = np.asarray(group)
    if g.shape != (n,):
        raise ValueError(
            f"group must be an (n,) array of grasp labels, one per trial like quality ({n},); got shape "
            f"{g.shape}"
        )
    if g.dtype.kind in "fc" and np.isnan(g).any():
        raise ValueError(
            f"group must not be NaN (a NaN label equals no other, not even itself); got one at trial "
            f"{int(np.argmax(np.isnan(g)))} — label every trial with its grasp index"
        )
    labels, inverse = np.unique(g, return_inverse=True)
    if labels.size < 2:
        raise ValueError(
            f"leave-one-grasp-out needs at least 2 groups (grasps); got {labels.size} — without another "
            "grasp there is nothing to fit a held-out grasp's threshold on"
        )
    return labels, inverse.reshape(-1)


def _warn_one_class(s: np.ndarray, what: str) -> None:
    """Warn (:class:`~workbench.plausible.ImplausibleWarning`, at the caller of the public scorer)
    when the outcomes ``s`` (n,) bool hold one class only: every trial a success, or every one a
    failure, leaves nothing to tell apart — ``what`` says what the score is then."""
    n_pos = int(s.sum())
    if 0 < n_pos < s.size:
        return
    cls = "successes" if n_pos else "failures"
    warnings.warn(
        f"all {s.size} trials are {cls}: {what} — a score of one class says nothing about telling "
        "successes from failures; score trials with both outcomes (e.g. pool objects or add the "
        "grasps that failed)",
        ImplausibleWarning,
        stacklevel=3,
    )


def roc_auc(quality, success) -> float:
    """Area under the ROC curve: the Mann–Whitney statistic, the probability that a random
    success has a higher quality than a random failure, ties counting 1/2.

    quality : (n,) float (±inf allowed, no NaN); success : (n,) bool.

    NaN when ``success`` holds one class only, with an
    :class:`~workbench.plausible.ImplausibleWarning` (:func:`_warn_one_class`).
    """
    q, s = _check(quality, success)
    _warn_one_class(s, "roc_auc is NaN: there is no pair of a success and a failure to rank")
    return _roc_auc(q, s)


def _roc_auc(q: np.ndarray, s: np.ndarray) -> float:
    """:func:`roc_auc` of checked arrays, without the one-class warning."""
    n_pos = int(s.sum())
    n_neg = s.size - n_pos
    if n_pos == 0 or n_neg == 0:
        return float("nan")
    # average ranks (ties share the mean of their ranks): U = rank sum of successes − n+(n+ + 1)/2
    order = np.argsort(q, kind="stable")
    sq = q[order]
    first = np.flatnonzero(np.r_[True, sq[1:] != sq[:-1]])
    size = np.diff(np.r_[first, q.size])
    ranks = np.empty(q.size)
    ranks[order] = np.repeat(first + (size + 1) / 2.0, size)
    u = ranks[s].sum() - n_pos * (n_pos + 1) / 2.0
    return float(u / (n_pos * n_neg))


def _pr_curve(q: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Precision and recall (k,) of ``q >= t`` for each distinct quality t, highest first."""
    order = np.argsort(-q, kind="stable")
    sq, ss = q[order], s[order]
    last = np.flatnonzero(np.r_[sq[1:] != sq[:-1], True])  # the last trial of each tie group
    tp = np.cumsum(ss)[last]
    predicted = last + 1
    return tp / predicted, tp / s.sum()


def roc_curve_points(quality, success) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The curves behind :func:`roc_auc` and :func:`average_precision`, for a figure: false and
    true positive rates (k + 1,) from (0, 0), and precision and recall (k,), of ``quality >= t``
    for the k distinct qualities t, highest first (trials of one quality enter together).
    NaN rates where a class is absent."""
    q, s = _check(quality, success)
    order = np.argsort(-q, kind="stable")
    sq, ss = q[order], s[order]
    last = np.flatnonzero(np.r_[sq[1:] != sq[:-1], True])
    tp = np.cumsum(ss)[last].astype(float)
    fp = (last + 1) - tp
    n_pos, n_neg = float(s.sum()), float((~s).sum())
    tpr = np.r_[0.0, tp / n_pos] if n_pos else np.full(last.size + 1, np.nan)
    fpr = np.r_[0.0, fp / n_neg] if n_neg else np.full(last.size + 1, np.nan)
    precision = tp / (last + 1)
    recall = tp / n_pos if n_pos else np.full(last.size, np.nan)
    return fpr, tpr, precision, recall


def average_precision(quality, success) -> float:
    """Average precision: ``Σ_k (R_k − R_{k−1}) P_k`` over the distinct qualities t_k, highest
    first, with P_k, R_k the precision and recall of ``quality >= t_k`` and R_0 = 0 — the
    step-wise area under the precision–recall curve (as sklearn's ``average_precision_score``;
    no interpolation).  Trials of one quality enter together.

    quality : (n,) float (±inf allowed, no NaN); success : (n,) bool.

    NaN without any success (recall undefined); 1 without any failure — either with an
    :class:`~workbench.plausible.ImplausibleWarning` (:func:`_warn_one_class`).
    """
    q, s = _check(quality, success)
    _warn_one_class(
        s,
        "average_precision is 1 whatever the quality (every precision is 1)"
        if s.any()
        else "average_precision is NaN (no success to recall)",
    )
    return _average_precision(q, s)


def _average_precision(q: np.ndarray, s: np.ndarray) -> float:
    """:func:`average_precision` of checked arrays, without the one-class warning."""
    if not s.any():
        return float("nan")
    precision, recall = _pr_curve(q, s)
    return float(np.sum(np.diff(recall, prepend=0.0) * precision))


#: the thresholds of :func:`average_recall`: the REACH lab's comparison of grasp qualities with
#: physical outcomes (ipc-graspsim ``tools/grasping/compare_ipc_phys.py``: t = 0, 0.1, …, 1.0)
RECALL_THRESHOLDS = tuple(np.linspace(0.0, 1.0, 11))


def average_recall(quality, success, thresholds: Sequence[float] = RECALL_THRESHOLDS) -> float:
    """Average recall: the mean over ``thresholds`` of the recall of ``quality >= t`` — for a
    quality in [0, 1] (a robust quality: the mean over pose samples), the 11 thresholds 0, 0.1,
    …, 1 of the comparison script of the REACH lab (the 6DFC paper reports mAR without a
    formula; its authors' public comparison code averages the recall over this grid).

    A quality that says "success" everywhere (constant 1) has AR 1 only at t <= 1; a constant
    0 is recalled at t = 0 only (AR 1/11).  quality : (n,) float (±inf allowed, no NaN);
    success : (n,) bool; thresholds : the grid (non-empty, finite), fractions in [0, 1]
    (:func:`_check_thresholds`: a grid in per cent is refused when the qualities lie in [0, 1]).

    NaN without any success; without a failure, a quality that says "success" everywhere has
    AR 1 — either with an :class:`~workbench.plausible.ImplausibleWarning`
    (:func:`_warn_one_class`).
    """
    q, s = _check(quality, success)
    t = _check_thresholds(thresholds, q)
    _warn_one_class(
        s,
        "average_recall counts the recalled successes only (a quality constant 1 scores 1)"
        if s.any()
        else "average_recall is NaN (no success to recall)",
    )
    return _average_recall(q, s, t)


def _average_recall(q: np.ndarray, s: np.ndarray, t: np.ndarray) -> float:
    """:func:`average_recall` of checked arrays and thresholds, without the one-class warning."""
    if not s.any():
        return float("nan")
    return float(np.mean([(q[s] >= ti).mean() for ti in t]))


def _fractions(t: np.ndarray) -> str:
    return ", ".join(repr(round(float(x), 12)) for x in t)


def _check_thresholds(thresholds, q: np.ndarray) -> np.ndarray:
    """``thresholds`` (k,) as a float array: finite fractions in [0, 1], the scale of the
    qualities they cut (a robust quality is a success rate).  Outside [0, 1] — a grid in per
    cent, 0-100 — the grid is refused when the finite qualities ``q`` lie in [0, 1] (a threshold
    above them all recalls nothing and silently drags the average down) and passes with an
    :class:`~workbench.plausible.ImplausibleWarning` for a quality on another scale (this module
    scores any quality, so such a grid may be meant)."""
    try:
        t = np.asarray(thresholds, dtype=float)
    except (TypeError, ValueError):
        t = np.asarray([np.nan])
    if isinstance(thresholds, str) or t.ndim != 1 or t.size == 0 or not np.isfinite(t).all():
        single = f" (a single threshold: pass [{thresholds!r}])" if t.ndim == 0 else ""
        raise ValueError(
            f"thresholds must be a non-empty (k,) array of finite fractions in [0, 1], e.g. "
            f"{_fractions(np.asarray(RECALL_THRESHOLDS))}; got {thresholds!r}{single}"
        )
    outside = (t < 0) | (t > 1)
    if not outside.any():
        return t
    if t.min() >= 0 and t.max() <= 100:
        fix = f"per cent? pass {_fractions(t / 100)}"
    else:
        fix = f"pass fractions in [0, 1], e.g. the default {_fractions(np.asarray(RECALL_THRESHOLDS))}"
    finite = q[np.isfinite(q)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    got = f"got {_fractions(t)} ({int(outside.sum())} outside [0, 1])"
    if 0 <= lo and hi <= 1:
        raise ValueError(
            f"thresholds must be fractions in [0, 1], the scale of the qualities they cut (here all in "
            f"[{lo:g}, {hi:g}]: a threshold outside recalls every success or none); {got} — {fix}"
        )
    warnings.warn(
        f"thresholds are meant as fractions in [0, 1] (a robust quality's scale); {got} for qualities "
        f"in [{lo:g}, {hi:g}] — kept for a quality on another scale; otherwise {fix}",
        ImplausibleWarning,
        stacklevel=3,
    )
    return t


def _cut(a: float, b: float) -> float:
    """A threshold t with ``a < t <= b`` (a < b distinct qualities): their midpoint; the
    largest finite float next to an infinite end, so that exactly the infinite qualities lie
    beyond it; 0 between -inf and +inf; ``b`` when the midpoint rounds onto ``a``."""
    if np.isfinite(a) and np.isfinite(b):
        t = a / 2 + b / 2  # no overflow near the float limits
    elif np.isfinite(b):
        t = -_FMAX
    elif np.isfinite(a):
        t = _FMAX
    else:
        t = 0.0
    return t if a < t <= b else b


def best_threshold(quality, success) -> float:
    """The threshold t maximising the balanced accuracy of ``quality >= t`` on these trials
    (thesis §4.3.1.2; one class only: that class's recall, as :func:`balanced_accuracy`).

    quality : (n,) float (±inf allowed, no NaN); success : (n,) bool.

    Candidates, with v_1 < … < v_m the distinct qualities: ``-inf`` (every trial predicted to
    succeed), a cut between each v_i and v_{i+1} (their midpoint; next to an infinite v, the
    largest finite float on that side, so the cut parts the infinite qualities from all finite
    ones — a held-out finite quality beyond the training range falls with the finite ones; 0
    between -inf and +inf) and ``+inf`` (none predicted to succeed; left out when v_m = +inf,
    where it predicts the same as the cut below v_m).  Balanced accuracies are compared exactly,
    as integer ratios.

    Ties: the optimal candidates form runs of consecutive candidates (plateaus of the
    balanced accuracy in t); the widest run, counted in candidates (so in distinct
    qualities spanned: the choice depends on the ranking only and commutes with any
    increasing transform of the quality), wins, the lowest of equally wide runs; within it
    the middle candidate, the lower of the two middle ones for an even count.  A constant
    quality thus gives ``-inf``.
    """
    q, s = _check(quality, success)
    v, inverse = np.unique(q, return_inverse=True)
    inverse = inverse.reshape(-1)
    pos = np.bincount(inverse, weights=s, minlength=v.size).astype(np.int64)
    neg = np.bincount(inverse, weights=~s, minlength=v.size).astype(np.int64)
    # candidate k = 0..m predicts success for the distinct qualities v[k:]
    tp = np.r_[np.cumsum(pos[::-1])[::-1], 0]
    tn = np.r_[0, np.cumsum(neg)]
    n_pos, n_neg = int(pos.sum()), int(neg.sum())
    if n_pos and n_neg:
        score = tp * n_neg + tn * n_pos  # balanced accuracy × 2 n+ n−
    else:
        score = tp if n_pos else tn
    cand = np.array([-np.inf, *(_cut(v[i], v[i + 1]) for i in range(v.size - 1)), np.inf])
    if v[-1] == np.inf:
        cand, score = cand[:-1], score[:-1]
    best = score == score.max()
    # runs of consecutive optimal candidates: [start, stop)
    edges = np.diff(np.r_[0, best.astype(np.int8), 0])
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    r = int(np.argmax(stops - starts))  # the first (lowest) of the widest
    return float(cand[starts[r] + (stops[r] - starts[r] - 1) // 2])


Fit = Callable[[np.ndarray, np.ndarray], float]


def loo_group_thresholds(quality, success, group, fit: Fit = best_threshold) -> dict[Hashable, float]:
    """Leave-one-grasp-out thresholds: for each group g, ``fit`` on the trials whose group is
    not g.

    quality : (n,) float (±inf allowed, no NaN); success : (n,) bool; group : (n,) labels,
    the grasp of each trial (at least 2 distinct);
    fit : ``fit(quality_train (k,) float, success_train (k,) bool) -> float`` — called once
        per group with fresh copies of the training rows only, never any row of g
        (default :func:`best_threshold`).

    Returns ``{g: threshold}`` in sorted group order, labels as Python scalars.
    """
    q, s = _check(quality, success)
    labels, inverse = _check_group(group, q.size)
    out: dict[Hashable, float] = {}
    for k, label in enumerate(labels):
        train = inverse != k
        t = fit(q[train].copy(), s[train].copy())
        if (
            isinstance(t, (bool, np.bool_))
            or not isinstance(t, (numbers.Real, np.floating, np.integer))
            or np.isnan(t)
        ):
            raise ValueError(
                f"fit must return a threshold (a float, ±inf allowed); got {t!r} for held-out group "
                f"{label!r} — return e.g. best_threshold(quality, success)"
            )
        out[label.item() if isinstance(label, np.generic) else label] = float(t)
    return out


def crossval_scores(quality, success, group, fit: Fit = best_threshold) -> dict:
    """Held-out scores of ``quality >= threshold[group]``, each grasp's threshold fitted on
    the other grasps (:func:`loo_group_thresholds`), and the threshold-free scores of the
    quality itself.

    quality : (n,) float (±inf allowed, no NaN); success : (n,) bool; group : (n,) grasp
    labels (at least 2 distinct); fit : as in :func:`loo_group_thresholds`.

    Returns a dict:
      ``balanced_accuracy``, ``accuracy``, ``precision``, ``recall``, ``f1`` of the held-out
      predictions (precision NaN without a predicted success, recall NaN without a real one,
      f1 ``2tp / (2tp + fp + fn)``, NaN when that is 0/0); ``tp``, ``fp``, ``fn``, ``tn``;
      ``n``, ``n_success``, ``n_groups``;
      ``thresholds`` ``{group: t}`` and ``threshold_median`` / ``_min`` / ``_max`` over groups;
      ``roc_auc``, ``average_precision``, ``average_recall`` of the quality (no threshold);
      ``predicted`` (n,) bool.

    When every trial is a success (or every one a failure) the values are as documented —
    balanced accuracy the recall of that class alone, ``roc_auc`` NaN — and an
    :class:`~workbench.plausible.ImplausibleWarning` says so (one warning, not one per score).
    """
    q, s = _check(quality, success)
    labels, inverse = _check_group(group, q.size)
    thresholds = loo_group_thresholds(q, s, group, fit)
    t = np.array(list(thresholds.values()))
    predicted = q >= t[inverse]
    tp = int((predicted & s).sum())
    fp = int((predicted & ~s).sum())
    fn = int((~predicted & s).sum())
    tn = int((~predicted & ~s).sum())
    pr = scores(predicted, s)
    ba = balanced_accuracy(predicted, s)
    _warn_one_class(
        s,
        f"balanced_accuracy {ba:g} is the recall of the {'successes' if s.any() else 'failures'} alone "
        "and roc_auc is NaN",
    )
    return {
        "balanced_accuracy": ba,
        "accuracy": (tp + tn) / q.size,
        "precision": pr["precision"],
        "recall": pr["recall"],
        "f1": 2 * tp / (2 * tp + fp + fn) if 2 * tp + fp + fn else float("nan"),
        "tp": tp,
        "fp": fp,
        "fn": fn,
        "tn": tn,
        "n": int(q.size),
        "n_success": int(s.sum()),
        "n_groups": int(labels.size),
        "thresholds": thresholds,
        "threshold_median": float(np.median(t)),
        "threshold_min": float(t.min()),
        "threshold_max": float(t.max()),
        "roc_auc": _roc_auc(q, s),
        "average_precision": _average_precision(q, s),
        "average_recall": _average_recall(q, s, np.asarray(RECALL_THRESHOLDS)),
        "predicted": predicted,
    }


def seed_summary(results: Sequence[dict]) -> dict[str, dict]:
    """Mean ± std over robustness seeds of every numeric key (e.g. "mAP ± std over 5 seeds").

    results : one dict per seed (e.g. :func:`crossval_scores` outputs).  A key whose value
        is a real number (not a bool) in one dict must be one in every dict (ValueError
        otherwise); other values (arrays, dicts) are skipped.

    Returns ``{key: {"mean": m, "std": sd, "n": seeds}}``, ``sd`` the sample standard
    deviation (ddof = 1; NaN for one seed).  A NaN in any seed makes that key's mean NaN.
    """
    if isinstance(results, dict) or not isinstance(results, Sequence) or len(results) == 0:
        raise ValueError(
            f"results must be a non-empty list of dicts, one per seed; got {type(results).__name__} "
            f"{results!r:.80}"
        )
    for i, r in enumerate(results):
        if not isinstance(r, dict):
            raise ValueError(f"results must hold dicts, one per seed; got {type(r).__name__} at index {i}")

    def numeric(x) -> bool:
        return isinstance(x, numbers.Real) and not isinstance(x, (bool, np.bool_))

    keys = list(dict.fromkeys(k for r in results for k, x in r.items() if numeric(x)))
    out: dict[str, dict] = {}
    for key in keys:
        bad = [i for i, r in enumerate(results) if not numeric(r.get(key))]
        if bad:
            good = next(i for i, r in enumerate(results) if numeric(r.get(key)))
            raise ValueError(
                f"{key!r} is a number in seed {good} but missing or not a number in seed {bad[0]} "
                f"({results[bad[0]].get(key)!r}) — summarise results of one function and config"
            )
        x = np.array([float(r[key]) for r in results])
        with np.errstate(invalid="ignore"):
            mean = float(x.mean())
            std = float(np.sqrt(np.sum((x - mean) ** 2) / (x.size - 1))) if x.size > 1 else float("nan")
        out[str(key)] = {"mean": mean, "std": std, "n": int(x.size)}
    return out

"""Binary grasp-success prediction from a quality: balanced accuracy and the normaliser
(thesis §4.3.1.2, §4.3.4).

A quality ``q = 1 − x / X_max`` (``x`` the minimal work W or the minimal force f⊥,
Eq. 4.6 / §4.3.3.2) predicts success iff ``q >= σ`` (σ = 0.5 in the thesis), that is iff
``x <= (1 − σ) X_max``.  The thesis chose ``W_max`` and ``f⊥max`` "based on the collected
physical data"; :func:`fit_normaliser` makes that choice on training grasps, as the
``X_max`` whose prediction has the best balanced accuracy.
"""

from __future__ import annotations

import numbers

import numpy as np

__all__ = ["balanced_accuracy", "balanced_accuracy_interval", "fit_normaliser", "held_out_accuracy"]


def _bools(a, name: str) -> np.ndarray:
    arr = np.asarray(a)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty (n,) array of booleans; got shape {arr.shape}")
    if arr.dtype != bool:
        if arr.dtype.kind not in "iuf" or not np.isin(arr, (0, 1)).all():
            raise ValueError(
                f"{name} must hold booleans (or 0/1); got dtype {arr.dtype} with values "
                f"{np.unique(arr)[:5].tolist()} — threshold the quality first (q >= sigma)"
            )
        arr = arr.astype(bool)
    return arr


def balanced_accuracy(predicted, truth) -> float:
    """Mean of the recalls of the two classes (thesis §4.3.1.2: each grasp weighted by
    the inverse prevalence of its true class).

    predicted, truth : (n,) bool — predicted and real success (0/1 accepted).

    When ``truth`` holds one class only, the recall of that class (the other recall is
    undefined).
    """
    p = _bools(predicted, "predicted")
    t = _bools(truth, "truth")
    if p.shape != t.shape:
        raise ValueError(f"predicted and truth must have one shape; got {p.shape} and {t.shape}")
    recalls = []
    for c in (True, False):
        sel = t == c
        if sel.any():
            recalls.append(float((p[sel] == c).mean()))
    return float(np.mean(recalls))


def balanced_accuracy_interval(
    predicted, truth, *, level: float = 0.95, n_resamples: int = 2000, seed: int = 0
) -> tuple[float, float] | None:
    """Percentile bootstrap interval of :func:`balanced_accuracy` over the grasps (each
    resample draws ``n`` grasps with replacement, keeping prediction and truth paired;
    ``scipy.stats.bootstrap``), at confidence ``level`` in (0, 1).

    predicted, truth : (n,) bool.  Returns ``(low, high)``, or ``None`` when ``truth`` holds
    fewer than two grasps of either class (a resample would often lack that class, and the
    statistic would change meaning between resamples).
    """
    from scipy.stats import bootstrap

    from ..seeds import check_seed

    p, t = _bools(predicted, "predicted"), _bools(truth, "truth")
    if p.shape != t.shape:
        raise ValueError(f"predicted and truth must have one shape; got {p.shape} and {t.shape}")
    if isinstance(level, bool) or not isinstance(level, numbers.Real) or not 0 < level < 1:
        raise ValueError(f"level must be a confidence in (0, 1), e.g. 0.95; got {level!r}")
    if isinstance(n_resamples, bool) or not isinstance(n_resamples, numbers.Integral) or n_resamples < 100:
        raise ValueError(f"n_resamples must be an integer >= 100 (e.g. 2000); got {n_resamples!r}")
    if min(int(t.sum()), int((~t).sum())) < 2:
        return None

    def stat(pp: np.ndarray, tt: np.ndarray, axis: int = -1) -> np.ndarray:
        pos, neg = tt.sum(axis), (~tt).sum(axis)
        with np.errstate(invalid="ignore", divide="ignore"):
            tpr = (pp & tt).sum(axis) / pos
            tnr = (~pp & ~tt).sum(axis) / neg
        # a resample without one class: the other class's recall, as balanced_accuracy says
        return np.where(pos == 0, tnr, np.where(neg == 0, tpr, 0.5 * (tpr + tnr)))

    res = bootstrap(
        (p, t),
        stat,
        paired=True,
        vectorized=True,
        confidence_level=float(level),
        n_resamples=int(n_resamples),
        method="percentile",
        rng=np.random.default_rng(check_seed(seed, generator=False)),
    )
    return float(res.confidence_interval.low), float(res.confidence_interval.high)


def _check_sigma(sigma) -> float:
    """The quality threshold σ as a float in [0, 1), else a ValueError naming the fix: the
    quality ``q = 1 − x / X_max`` is at most 1, so σ >= 1 predicts nothing a success (50: a
    threshold in per cent), and a negative σ counts grasps needing more than ``X_max`` as
    successes — ``X_max`` is then no longer the largest work or force a success may need."""
    if (
        isinstance(sigma, (bool, np.bool_))
        or not isinstance(sigma, numbers.Real)
        or not (np.isfinite(sigma) and 0 <= sigma < 1)
    ):
        number = isinstance(sigma, numbers.Real) and not isinstance(sigma, (bool, np.bool_))
        if number and 1 < sigma <= 100:
            fix = f" — per cent? pass {float(sigma) / 100:g}"  # a threshold in per cent (50 for 0.5)
        elif number and -1 < sigma < 0:
            fix = f" — a negative threshold predicts success beyond X_max; sign slip? pass {-float(sigma):g}"
        elif number and np.isfinite(sigma):
            fix = " — pass e.g. 0.5 (the thesis's)"
        else:
            fix = ""
        raise ValueError(
            f"sigma must be a finite quality threshold < 1 and >= 0 (0.5 in the thesis); got {sigma!r}{fix}"
        )
    return float(sigma)


def fit_normaliser(values, truth, sigma: float = 0.5) -> float:
    """``X_max`` (``W_max`` or ``f⊥max``) that best predicts ``truth`` from ``values``
    by ``q = 1 − x / X_max >= sigma``.

    values : (n,) float — the training grasps' W [J] or f⊥ [N], >= 0; ``np.inf`` for
        an unresisted grasp, always predicted to fail (``q = −inf``).
    truth : (n,) bool — their real success.
    sigma : the quality threshold σ in [0, 1) (0.5 in the thesis, §4.3.4; :func:`_check_sigma`).

    Success is predicted iff ``x <= t`` with ``t = (1 − σ) X_max``.  Candidate ``t``:
    the midpoints between consecutive distinct finite values, ``v_1 / 2`` (every grasp
    predicted to fail, unless ``v_1 = 0``) and ``2 v_k`` (every resisted grasp predicted
    to succeed), ``v_1 < … < v_k`` the sorted distinct finite values; only ``t > 0``
    (``X_max > 0``).  The candidate of largest balanced accuracy wins; ties go to the
    median of the tied candidates in ``t`` order (the lower of the two middle ones for
    an even count), the middle of the best plateau.  Returns ``t / (1 − σ)``.

    Raises ``ValueError`` when no value is finite and > 0 (every ``X_max`` predicts
    the same, so none is fitted).
    """
    x = np.asarray(values, dtype=float)
    t_true = _bools(truth, "truth")
    if x.shape != t_true.shape:
        raise ValueError(f"values and truth must have one shape (n,); got {x.shape} and {t_true.shape}")
    bad = np.isnan(x) | (x < 0)
    if bad.any():
        k = int(np.argmax(bad))
        raise ValueError(f"values must be >= 0 (np.inf: unresisted); got {x[k]} at grasp {k}")
    sigma = _check_sigma(sigma)
    v = np.unique(x[np.isfinite(x)])
    if v.size == 0 or v[-1] <= 0:
        raise ValueError(
            "fit_normaliser needs some finite value > 0: with every grasp unresisted (inf) or at 0, "
            "any X_max predicts the same"
        )
    cand = np.concatenate([[v[0] / 2], (v[:-1] + v[1:]) / 2, [2 * v[-1]]])
    cand = cand[cand > 0]
    score = np.array([balanced_accuracy(x <= t, t_true) for t in cand])
    # scores are ratios of counts: equal ones differ by round-off only
    best = np.flatnonzero(score >= score.max() - 1e-12)
    t = float(cand[best[(len(best) - 1) // 2]])
    return t / (1.0 - sigma)


def held_out_accuracy(predicted, truth, train, groups, names) -> dict:
    """Balanced accuracy on the held-out grasps (``~train``), per group and overall.

    predicted, truth, train : (n,) bool — prediction, real success, training grasps;
    groups : (n,) labels (e.g. object names); names : the labels to report, in order.

    Returns ``{name: accuracy or None (no held-out grasp of it), ..., "All": accuracy}``.
    """
    p, t = _bools(predicted, "predicted"), _bools(truth, "truth")
    held = ~_bools(train, "train")
    g = np.asarray(groups)
    if not (p.shape == t.shape == held.shape == g.shape):
        raise ValueError(
            f"predicted, truth, train and groups must have one shape (n,); got {p.shape}, {t.shape}, "
            f"{held.shape}, {g.shape}"
        )
    if not held.any():
        raise ValueError("train marks every grasp: no held-out grasp to score")
    out: dict = {}
    for name in names:
        sel = held & (g == name)
        out[name] = balanced_accuracy(p[sel], t[sel]) if sel.any() else None
    out["All"] = balanced_accuracy(p[held], t[held])
    return out

"""workbench.grasp.crossval: threshold-free scores (AUC, AP, AR) against hand counts and slow
references, the best balanced-accuracy threshold and its tie rule, and leave-one-grasp-out
cross-validation that never shows a fit the held-out grasp (a spy, and a leak that noise
exposes)."""

import itertools

import numpy as np
import pytest

from workbench.grasp.crossval import (
    average_precision,
    average_recall,
    best_threshold,
    crossval_scores,
    loo_group_thresholds,
    roc_auc,
    roc_curve_points,
    seed_summary,
)
from workbench.grasp.threshold import balanced_accuracy

FMAX = np.finfo(float).max

# 5 trials, hand-counted below: qualities with a tie at 0.8 between a success and a failure
Q5 = np.array([0.9, 0.8, 0.8, 0.4, 0.1])
S5 = np.array([1, 1, 0, 0, 1], bool)


def _auc_pairs(q, s):
    """Every (success, failure) pair: 1 if the success ranks higher, 1/2 for a tie."""
    pos, neg = q[s], q[~s]
    wins = sum(1.0 if a > b else 0.5 if a == b else 0.0 for a, b in itertools.product(pos, neg))
    return wins / (pos.size * neg.size)


def _pr_slow(q, s):
    """(precision, recall) of ``q >= t`` for each distinct t, highest first, by counting."""
    out = []
    for t in sorted(set(q.tolist()), reverse=True):
        tp = sum(1 for qi, si in zip(q, s, strict=True) if qi >= t and si)
        fp = sum(1 for qi, si in zip(q, s, strict=True) if qi >= t and not si)
        out.append((tp / (tp + fp), tp / int(s.sum())))
    return out


def _ap_slow(q, s):
    ap, last = 0.0, 0.0
    for p, r in _pr_slow(q, s):
        ap += (r - last) * p
        last = r
    return ap


def _random_tied(rng, n=60):
    """Qualities on a coarse grid (many ties), some ±inf, and outcomes loosely following them."""
    q = rng.integers(0, 8, n).astype(float)
    q[rng.random(n) < 0.05] = -np.inf
    q[rng.random(n) < 0.05] = np.inf
    s = rng.random(n) < 1 / (1 + np.exp(-(np.nan_to_num(q, posinf=9, neginf=-2) - 4) / 2))
    return q, s


def test_roc_auc_by_hand_and_against_all_pairs(rng):
    # successes 0.9, 0.8, 0.1 vs failures 0.8, 0.4: 0.9 wins 2, 0.8 ties 1 and wins 1, 0.1 wins 0
    assert roc_auc(Q5, S5) == pytest.approx(3.5 / 6)
    assert roc_auc([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1]) == pytest.approx(0.75)  # sklearn's doc example
    for _ in range(20):
        q, s = _random_tied(rng)
        assert roc_auc(q, s) == pytest.approx(_auc_pairs(q, s), abs=1e-12)
    assert roc_auc([3.0, 3.0, 3.0], [1, 0, 1]) == 0.5  # all tied


def test_roc_auc_single_class_is_nan():
    assert np.isnan(roc_auc([0.1, 0.5, 0.9], [1, 1, 1]))
    assert np.isnan(roc_auc([0.1, 0.5, 0.9], [0, 0, 0]))


def test_average_precision_by_hand_and_against_a_slow_scan(rng):
    # t=0.9: P 1, R 1/3; t=0.8 (tie, both enter): P 2/3, R 2/3; t=0.4: R unchanged; t=0.1: P 3/5, R 1
    assert average_precision(Q5, S5) == pytest.approx(1 / 3 * 1 + 1 / 3 * 2 / 3 + 1 / 3 * 3 / 5)
    assert average_precision(Q5, S5) == pytest.approx(34 / 45)
    assert average_precision([0.1, 0.4, 0.35, 0.8], [0, 0, 1, 1]) == pytest.approx(5 / 6)  # sklearn doc
    for _ in range(20):
        q, s = _random_tied(rng)
        assert average_precision(q, s) == pytest.approx(_ap_slow(q, s), abs=1e-12)
    assert average_precision([0.2, 0.7], [1, 1]) == 1.0  # no failure
    assert np.isnan(average_precision([0.2, 0.7], [0, 0]))  # no success: recall undefined


def test_average_recall_by_hand_on_the_reach_labs_grid(rng):
    # successes at 0.95, 0.85, 0.15: all three recalled at t = 0 and 0.1, two at t = 0.2 ... 0.8
    # (7 thresholds), one at 0.9, none at 1.0: (2 + 7 * 2/3 + 1/3) / 11 = 7/11
    q = [0.95, 0.85, 0.75, 0.45, 0.15]
    s = [1, 1, 0, 0, 1]
    assert average_recall(q, s) == pytest.approx(7 / 11, abs=1e-12)
    assert average_recall(np.zeros(4), [1, 0, 1, 1]) == pytest.approx(1 / 11)  # a constant 0
    assert average_recall(np.ones(4), [1, 0, 1, 1]) == 1.0
    assert average_recall(q, s, thresholds=[0.5]) == pytest.approx(2 / 3)
    for _ in range(20):
        q, s = _random_tied(rng)
        grid = np.linspace(0, 1, 11)
        recalls = [np.mean([qi >= t for qi, si in zip(q, s, strict=True) if si]) for t in grid]
        slow = np.mean(recalls)
        assert average_recall(q, s) == pytest.approx(slow, abs=1e-12)
    assert np.isnan(average_recall([0.2, 0.7], [0, 0]))
    with pytest.raises(ValueError, match="thresholds"):
        average_recall(q, s, thresholds=[])


def test_best_threshold_separates_a_separable_set():
    q = np.array([0.31, -0.2, 0.9, 0.05, 0.62, 0.4, 0.1])
    s = q > 0.35  # failures up to 0.31, successes from 0.4
    t = best_threshold(q, s)
    assert 0.31 < t < 0.4
    assert t == pytest.approx(0.355)  # the midpoint
    assert balanced_accuracy(q >= t, s) == 1.0


def test_best_threshold_is_optimal_against_a_scan(rng):
    """Its balanced accuracy equals the best over every midpoint and both ends, each scored by
    threshold.balanced_accuracy; and its choice depends on the ranking only."""
    for _ in range(30):
        q, s = _random_tied(rng, n=40)
        v = np.unique(q[np.isfinite(q)])
        grid = np.r_[-np.inf, -FMAX, (v[:-1] + v[1:]) / 2, v, FMAX, np.inf]
        best = max(balanced_accuracy(q >= g, s) for g in grid)
        t = best_threshold(q, s)
        assert balanced_accuracy(q >= t, s) == pytest.approx(best, abs=1e-12)
        f = np.exp(q / 3) - 5  # increasing, maps ±inf to +inf and -5
        f[q == -np.inf] = -np.inf
        np.testing.assert_array_equal(f >= best_threshold(f, s), q >= t)


def test_best_threshold_tie_rule_by_hand():
    # accuracy counts (balanced: 3 successes, 3 failures) of the cuts -inf, 1.5, 2.5, 3.5, 4.5, +inf:
    # 3, 4, 3, 4, 4, 3 — optimal runs {1.5} and {3.5, 4.5}; the widest wins, its lower middle: 3.5
    q = np.array([1.0, 2.0, 3.0, 4.0, 4.0, 5.0])
    s = np.array([0, 1, 0, 1, 0, 1], bool)
    assert balanced_accuracy(q >= 1.5, s) == balanced_accuracy(q >= 3.5, s) == pytest.approx(2 / 3)
    assert best_threshold(q, s) == 3.5
    # constant quality: both ends (-inf: all, +inf: none) score 1/2, one run of two -> -inf
    assert best_threshold([0.3, 0.3, 0.3], [1, 0, 1]) == -np.inf


def test_best_threshold_with_infinite_qualities():
    # -inf (e.g. unresisted) fails, every finite one succeeds: the cut is the lowest finite float
    q = np.array([-np.inf, -np.inf, 0.0, 1.0, np.inf])
    s = np.array([0, 0, 1, 1, 1], bool)
    assert best_threshold(q, s) == -FMAX
    assert best_threshold([0.0, 1.0, np.inf], [0, 0, 1]) == FMAX
    assert best_threshold([-np.inf, np.inf], [0, 1]) == 0.0
    # adjacent floats: the midpoint rounds onto the lower one, so the upper one is the cut
    a = 1.0
    b = np.nextafter(a, 2.0)
    t = best_threshold([a, b], [0, 1])
    assert a < t <= b


def test_loo_never_shows_a_fit_the_held_out_grasp():
    """A spy fit records the rows it is handed (qualities are distinct, so they name the rows)."""
    rng = np.random.default_rng(7)
    group = np.repeat(np.array([3, 11, 5, 8]), 4)
    q = rng.permutation(group.size).astype(float) / 10
    s = rng.random(group.size) < 0.5
    seen = []

    def spy(q_train, s_train):
        assert not np.shares_memory(q_train, q)
        rows = [int(np.flatnonzero(q == x)[0]) for x in q_train]
        np.testing.assert_array_equal(s_train, s[rows])
        seen.append(set(rows))
        return 0.5

    thresholds = loo_group_thresholds(q, s, group, fit=spy)
    assert list(thresholds) == [3, 5, 8, 11]  # sorted labels, Python ints
    assert all(type(k) is int for k in thresholds)
    assert len(seen) == 4
    for label, rows in zip([3, 5, 8, 11], seen, strict=True):
        assert rows == set(np.flatnonzero(group != label).tolist())  # every other row, none of its own


def _noise_trials(seed, n_grasps=25, repeats=5):
    """125 trials shaped like the physical ones whose quality is pure noise: one random code per
    grasp (so it only names the grasp), and each grasp its own success rate ~ U(0, 1)."""
    rng = np.random.default_rng(seed)
    group = np.repeat(np.arange(n_grasps), repeats)
    rate = rng.random(n_grasps)
    code = rng.permutation(n_grasps).astype(float)
    return code[group], rng.random(group.size) < rate[group], group


def test_noise_exposes_a_leaky_fit():
    """On a quality that carries no information, held-out balanced accuracy is 1/2 in expectation
    for any procedure that never sees the held-out grasp.  Over 40 seeds (standard error of the
    mean ≈ 0.015): the correct procedure stays within 0.5 ± 0.05; a fit handed the full data
    through a closure (the in-sample threshold) scores clearly higher on the same noise, and
    one that peeks at the held-out grasp's outcomes far higher."""
    honest, in_sample, peeking = [], [], []
    for seed in range(40):
        q, s, group = _noise_trials(seed)

        def leaky(q_train, s_train, q=q, s=s):
            return best_threshold(q, s)  # ignores the training subset: the full data

        def peek(q_train, s_train, q=q, s=s):
            held = np.setdiff1d(q, q_train)[0]  # the code missing from the training rows
            return held - 0.5 if s[q == held].mean() >= 0.5 else held + 0.5

        honest.append(crossval_scores(q, s, group)["balanced_accuracy"])
        in_sample.append(crossval_scores(q, s, group, fit=leaky)["balanced_accuracy"])
        peeking.append(crossval_scores(q, s, group, fit=peek)["balanced_accuracy"])
        # the leaky fit's held-out score is the in-sample score
        assert in_sample[-1] == pytest.approx(balanced_accuracy(q >= best_threshold(q, s), s))
    honest, in_sample, peeking = map(np.array, (honest, in_sample, peeking))
    assert abs(honest.mean() - 0.5) < 0.05
    assert in_sample.mean() - honest.mean() > 0.04  # paired difference, standard error ≈ 0.01
    assert in_sample.mean() > 0.55
    assert peeking.mean() > 0.7


def test_crossval_scores_by_hand():
    # grasps a (q 0.9: 2 successes), b (0.5: 1 success, 1 failure), c (0.1: 2 failures)
    q = np.array([0.9, 0.9, 0.5, 0.5, 0.1, 0.1])
    s = np.array([1, 1, 1, 0, 0, 0], bool)
    group = np.array(["a", "a", "b", "b", "c", "c"])
    got = crossval_scores(q, s, group)
    # without a: {b, c} best cut 0.3 (BA 5/6); without b: 0.5 separates; without c: 0.7 (BA 5/6)
    assert got["thresholds"] == {"a": pytest.approx(0.3), "b": pytest.approx(0.5), "c": pytest.approx(0.7)}
    np.testing.assert_array_equal(got["predicted"], [1, 1, 1, 1, 0, 0])
    assert (got["tp"], got["fp"], got["fn"], got["tn"]) == (3, 1, 0, 2)
    assert got["balanced_accuracy"] == pytest.approx((1 + 2 / 3) / 2)
    assert got["accuracy"] == pytest.approx(5 / 6)
    assert got["precision"] == pytest.approx(3 / 4)
    assert got["recall"] == 1.0
    assert got["f1"] == pytest.approx(6 / 7)
    assert (got["n"], got["n_success"], got["n_groups"]) == (6, 3, 3)
    assert got["threshold_median"] == pytest.approx(0.5)
    assert (got["threshold_min"], got["threshold_max"]) == (pytest.approx(0.3), pytest.approx(0.7))
    assert got["roc_auc"] == pytest.approx(8.5 / 9)  # 0.9 beats 3 failures twice; 0.5: tie + 2 wins
    assert got["average_precision"] == pytest.approx(2 / 3 * 1 + 1 / 3 * 3 / 4)
    q = np.array([0.9, 0.9, 0.5, 0.5, 0.1, 0.1])
    s = np.array([1, 1, 1, 0, 0, 0], bool)
    grid = [np.mean(q[s] >= t) for t in np.linspace(0, 1, 11)]
    assert got["average_recall"] == pytest.approx(np.mean(grid))


def test_constant_quality_and_single_class():
    group = np.repeat(np.arange(5), 3)
    s = np.arange(15) % 2 == 0
    got = crossval_scores(np.full(15, 0.4), s, group)
    assert got["balanced_accuracy"] == 0.5
    assert got["roc_auc"] == 0.5
    one_class = crossval_scores(np.linspace(0, 1, 15), np.ones(15, bool), group)
    assert np.isnan(one_class["roc_auc"])
    assert one_class["balanced_accuracy"] == 1.0  # every threshold -inf: all predicted to succeed


def test_bad_input_is_refused_with_the_fix():
    q, s, group = np.array([0.1, np.nan, 0.3, 0.5]), np.array([0, 1, 1, 0]), np.array([0, 0, 1, 1])
    for f in (roc_auc, average_precision, average_recall, best_threshold):
        with pytest.raises(ValueError, match=r"must not be NaN.*1 NaN of 4, first at trial 1.*drop"):
            f(q, s)
    with pytest.raises(ValueError, match="must not be NaN"):
        crossval_scores(q, s, group)
    ok = np.array([0.1, 0.2, 0.3, 0.5])
    with pytest.raises(ValueError, match="balanced_accuracy"):
        roc_auc(ok > 0.2, s)  # a prediction, not a quality
    with pytest.raises(ValueError, match="one shape"):
        average_precision(ok, s[:3])
    with pytest.raises(ValueError, match="booleans"):
        roc_auc(ok, [0, 2, 1, 0])
    with pytest.raises(ValueError, match="at least 2 groups"):
        loo_group_thresholds(ok, s, [1, 1, 1, 1])
    with pytest.raises(ValueError, match=r"group must be an \(n,\)"):
        crossval_scores(ok, s, [0, 1])
    with pytest.raises(ValueError, match="group must not be NaN"):
        crossval_scores(ok, s, [0.0, np.nan, 1.0, 1.0])
    with pytest.raises(ValueError, match="fit must return a threshold"):
        crossval_scores(ok, s, group, fit=lambda q, s: float("nan"))


def test_seed_summary():
    runs = [{"ap": 0.5, "n": 10, "ok": True, "t": {"a": 1.0}}, {"ap": 0.7, "n": 12, "ok": False, "t": {}}]
    got = seed_summary(runs)
    assert set(got) == {"ap", "n"}  # bools and dicts skipped
    assert got["ap"] == {"mean": pytest.approx(0.6), "std": pytest.approx(np.sqrt(0.02)), "n": 2}
    assert got["n"]["mean"] == 11.0 and got["n"]["std"] == pytest.approx(np.sqrt(2))
    assert np.isnan(seed_summary(runs[:1])["ap"]["std"])  # one seed: no spread
    per_seed = [crossval_scores(*_noise_trials(seed)) for seed in range(3)]
    summary = seed_summary(per_seed)
    ap = [r["average_precision"] for r in per_seed]
    assert summary["average_precision"]["mean"] == pytest.approx(np.mean(ap))
    assert summary["average_precision"]["std"] == pytest.approx(np.std(ap, ddof=1))
    with pytest.raises(ValueError, match="'ap' is a number in seed 0 but missing"):
        seed_summary([{"ap": 0.5}, {"ar": 0.5}])
    with pytest.raises(ValueError, match="non-empty list of dicts"):
        seed_summary([])


def test_roc_curve_points_integrate_to_the_auc_and_ap():
    # the trapezoid area under the returned ROC points is the Mann-Whitney AUC (ties: diagonal
    # steps, counted 1/2), and the step sum over the PR points is the AP
    rng = np.random.default_rng(7)
    q = rng.integers(0, 6, 40).astype(float)
    s = rng.random(40) < 0.6
    fpr, tpr, prec, rec = roc_curve_points(q, s)
    assert fpr[0] == 0 and tpr[0] == 0 and fpr[-1] == 1 and tpr[-1] == 1
    area = float(np.sum(np.diff(fpr) * (tpr[1:] + tpr[:-1]) / 2))
    assert abs(area - roc_auc(q, s)) < 1e-12
    assert abs(float(np.sum(np.diff(rec, prepend=0.0) * prec)) - average_precision(q, s)) < 1e-12

"""workbench.grasp.threshold: balanced accuracy (thesis §4.3.1.2), the fitted normaliser
X_max (§4.3.4) against hand counts and a brute-force threshold scan, the held-out
accuracy per group, and bad input."""

import numpy as np
import pytest

from workbench.grasp import balanced_accuracy, fit_normaliser, q_force, q_work
from workbench.grasp.threshold import held_out_accuracy


def test_balanced_accuracy_by_hand():
    truth = np.array([1, 1, 1, 1, 0, 0], bool)
    pred = np.array([1, 1, 1, 0, 0, 1], bool)
    # recall of successes 3/4, of failures 1/2
    assert balanced_accuracy(pred, truth) == pytest.approx((3 / 4 + 1 / 2) / 2)
    assert balanced_accuracy([1, 0, 1], [1, 1, 1]) == pytest.approx(2 / 3)  # one class: its recall
    assert balanced_accuracy([0, 0], [0, 0]) == 1.0


def test_held_out_accuracy_by_hand():
    """Per object on the held-out grasps (None without any), and over all of them."""
    truth = np.array([1, 0, 1, 1, 0, 1, 0], bool)
    pred = np.array([1, 1, 0, 1, 0, 1, 1], bool)
    train = np.array([0, 0, 0, 1, 1, 0, 0], bool)
    groups = np.array(["a", "a", "a", "b", "b", "c", "c"])
    got = held_out_accuracy(pred, truth, train, groups, ["a", "b", "c"])
    # a: successes 1/2 recalled, failures 0/1; b: none held out; c: 1/1 and 0/1
    # All: successes (0, 2, 5) 2/3, failures (1, 6) 0/2
    assert got == {"a": 0.25, "b": None, "c": 0.5, "All": pytest.approx(1 / 3)}
    assert list(got) == ["a", "b", "c", "All"]
    with pytest.raises(ValueError, match="one shape"):
        held_out_accuracy(pred, truth, train[:-1], groups, ["a"])
    with pytest.raises(ValueError, match="no held-out grasp"):
        held_out_accuracy(pred, truth, np.ones(7, bool), groups, ["a"])


def test_fit_normaliser_separates_a_separable_set():
    W = np.array([0.2, 0.05, 1.5, 0.9, 0.1, np.inf, 2.0, 0.3])
    truth = W < 0.5  # low work succeeds; the unresisted grasp fails
    sigma = 0.5
    W_max = fit_normaliser(W, truth, sigma)
    pred = q_work(W, W_max) >= sigma
    assert balanced_accuracy(pred, truth) == 1.0
    # the only perfect threshold lies between 0.3 and 0.9: its midpoint
    assert (1 - sigma) * W_max == pytest.approx(0.6)
    assert fit_normaliser(W, truth, 0.8) == pytest.approx(0.6 / 0.2)


def test_fit_normaliser_ties_and_inf():
    # one class only: predicting every resisted grasp a success (t = 2 v_max) is perfect
    x = np.array([1.0, 2.0, 3.0, 4.0])
    assert (1 - 0.5) * fit_normaliser(x, np.ones(4, bool)) == pytest.approx(8.0)
    # t = 1.5 and t = 3.5 both reach balanced accuracy 3/4 (by hand: recalls 1/2 + 1 and
    # 1 + 1/2): the lower middle of the tied candidates
    truth = np.array([True, False, True, False])
    assert (1 - 0.5) * fit_normaliser(x, truth) == pytest.approx(1.5)
    assert balanced_accuracy(x <= 1.5, truth) == balanced_accuracy(x <= 3.5, truth) == 0.75
    # unresisted grasps are failures whatever X_max is
    x = np.array([1.0, np.inf, 2.0])
    X = fit_normaliser(x, np.array([True, True, False]))
    assert q_force(np.inf, X) < 0.5 and q_force(1.0, X) >= 0.5 and q_force(2.0, X) < 0.5


def test_threshold_rejects_bad_input():
    with pytest.raises(ValueError, match="one shape"):
        balanced_accuracy([True, False], [True])
    with pytest.raises(ValueError, match="booleans"):
        balanced_accuracy([0.2, 0.9], [True, False])
    with pytest.raises(ValueError, match="non-empty"):
        balanced_accuracy([], [])
    with pytest.raises(ValueError, match=">= 0"):
        fit_normaliser([1.0, -2.0], [True, False])
    with pytest.raises(ValueError, match=">= 0"):
        fit_normaliser([1.0, np.nan], [True, False])
    with pytest.raises(ValueError, match="sigma"):
        fit_normaliser([1.0, 2.0], [True, False], sigma=1.0)
    with pytest.raises(ValueError, match="finite value > 0"):
        fit_normaliser([np.inf, np.inf], [True, False])
    with pytest.raises(ValueError, match="one shape"):
        fit_normaliser([1.0, 2.0, 3.0], [True, False])


# --- added: brute-force references ---------------------------------------------------------


def _recalls_by_loop(pred, truth):
    """Balanced accuracy by counting, one grasp at a time (classes present only)."""
    hits, counts = {True: 0, False: 0}, {True: 0, False: 0}
    for p, t in zip(pred, truth, strict=True):
        counts[bool(t)] += 1
        hits[bool(t)] += bool(p) == bool(t)
    recalls = [hits[c] / counts[c] for c in (True, False) if counts[c]]
    return sum(recalls) / len(recalls)


def test_balanced_accuracy_matches_counting(rng):
    for n in (1, 2, 7, 50):
        for _ in range(5):
            truth = rng.random(n) < 0.3
            pred = rng.random(n) < 0.6
            assert balanced_accuracy(pred, truth) == pytest.approx(_recalls_by_loop(pred, truth), rel=1e-15)
            # 0/1 integers are the same booleans
            assert balanced_accuracy(pred.astype(int), truth.astype(float)) == balanced_accuracy(pred, truth)


def test_fit_normaliser_reaches_the_best_achievable_accuracy(rng):
    """Whatever X_max, the prediction ``x <= t`` is one of: nobody, or ``x <= v_i`` for a
    distinct finite value v_i — so the best balanced accuracy is the maximum over those few
    predictions (by counting).  The fitted threshold reaches it, lies strictly between
    values (never on one, where a rounding would flip a grasp) and unresisted grasps fail."""
    for trial in range(20):
        x = np.round(rng.exponential(1.0, 30), 2)  # rounded: ties among the values
        x[rng.random(30) < 0.1] = np.inf
        truth = (x < 1.0) ^ (rng.random(30) < 0.2)  # low values succeed, with label noise
        v = np.unique(x[np.isfinite(x)])
        options = [np.zeros(30, bool)] + [x <= vi for vi in v]
        best = max(_recalls_by_loop(p, truth) for p in options)
        for sigma in (0.5, 0.2):
            t = (1 - sigma) * fit_normaliser(x, truth, sigma)
            assert _recalls_by_loop(x <= t, truth) == pytest.approx(best, abs=1e-12), trial
            assert t > 0 and not np.isclose(v, t, rtol=1e-9, atol=0).any()
            assert not (x <= t)[np.isinf(x)].any()


def test_threshold_rejects_careless_labels_and_sigma():
    with pytest.raises(
        ValueError, match=r"truth must hold booleans \(or 0/1\); got dtype int64 with values \[0, 2\]"
    ):
        balanced_accuracy([True, False], np.array([0, 2]))
    with pytest.raises(ValueError, match=r"predicted must be a non-empty \(n,\) array.*got shape \(1, 2\)"):
        balanced_accuracy([[True, False]], [True, False])
    with pytest.raises(ValueError, match="booleans"):
        balanced_accuracy(["yes", "no"], [True, False])
    for sigma in (True, np.inf, np.nan, 1.5, [0.5]):
        with pytest.raises(ValueError, match="sigma must be a finite quality threshold < 1"):
            fit_normaliser([1.0, 2.0], [True, False], sigma=sigma)
    with pytest.raises(ValueError, match="finite value > 0"):
        fit_normaliser([0.0, np.inf], [True, False])  # only a zero and an unresisted grasp
    with pytest.raises(ValueError, match="train must hold booleans"):
        held_out_accuracy([True, False], [True, False], [0.5, 0.0], ["a", "a"], ["a"])

"""Table 4.6's scoring: the bootstrap interval of a balanced accuracy against its analytic
standard error, and the quality table against a hand computation."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.grasp.quality_table import quality_table, training_split
from workbench.grasp.threshold import balanced_accuracy, balanced_accuracy_interval


def test_the_interval_has_the_analytic_width_of_a_balanced_accuracy():
    # BA = (TPR + TNR) / 2 of independent classes: SE = sqrt(p1 q1 / n1 + p2 q2 / n2) / 2,
    # a 95 % interval about 2 x 1.96 SE wide for large n
    rng = np.random.default_rng(3)
    n = 4000
    truth = rng.random(n) < 0.4
    pred = np.where(truth, rng.random(n) < 0.8, rng.random(n) < 0.3)
    lo, hi = balanced_accuracy_interval(pred, truth, n_resamples=2000, seed=1)
    n1, n2 = truth.sum(), (~truth).sum()
    se = 0.5 * np.sqrt(0.8 * 0.2 / n1 + 0.7 * 0.3 / n2)
    assert hi - lo == pytest.approx(2 * 1.959964 * se, rel=0.1)
    assert lo < balanced_accuracy(pred, truth) < hi


def test_a_perfect_predictor_has_a_point_interval_and_one_class_has_none():
    truth = np.array([True, False] * 10)
    assert balanced_accuracy_interval(truth, truth, n_resamples=200) == (1.0, 1.0)
    # fewer than two grasps of a class: no interval (a resample would often lack the class)
    one = np.array([True] * 9 + [False])
    assert balanced_accuracy_interval(one, one, n_resamples=200) is None


@pytest.mark.parametrize(
    "kwargs, match",
    [({"level": 95}, "level must be a confidence"), ({"n_resamples": 10}, "n_resamples must be")],
)
def test_the_interval_refuses_a_percent_level_and_too_few_resamples(kwargs, match):
    t = np.array([True, False] * 5)
    with pytest.raises(ValueError, match=match):
        balanced_accuracy_interval(t, t, **kwargs)


def test_quality_table_by_hand():
    # 8 grasps, the first four training: a cost normalised there, a quality as it is
    truth = np.array([1, 1, 0, 0, 1, 0, 1, 0], bool)
    train = np.array([1, 1, 1, 1, 0, 0, 0, 0], bool)
    cost = np.array([1.0, 2.0, 5.0, np.inf, 1.5, 6.0, 7.0, 0.5])
    q = np.array([0.9, 0.8, 0.1, 0.2, 0.7, 0.6, 0.1, 0.2])
    groups = np.array(["a", "b"] * 4)
    out = quality_table(
        truth, train, groups, ["a", "b"], qualities={"q": q}, costs={"c": cost}, n_resamples=200
    )
    # training: successes cost 1, 2, failures 5, inf -> the best thresholds t lie in (2, 5);
    # fit_normaliser takes the midpoint 3.5 between 2 and 5, X_max = t / (1 - 0.5) = 7
    assert out["normalisers"]["c"] == pytest.approx(7.0)
    # held out: costs 1.5, 6, 7, 0.5 -> predicted success iff cost <= 3.5: T F F T;
    # truth T F T F -> recalls 1/2 and 1/2
    assert out["accuracy"]["c"]["All"] == pytest.approx(0.5)
    # q >= 0.5 on the held-out grasps: T T F F against T F T F -> 0.5
    assert out["accuracy"]["q"]["All"] == pytest.approx(0.5)
    # group a holds grasps 4 and 6 (T, T): predicted T, F by the cost -> recall 1/2
    assert out["accuracy"]["c"]["a"] == pytest.approx(0.5)
    assert set(out["interval_95"]) == {"q", "c"}
    with pytest.raises(ValueError, match="at least one quality"):
        quality_table(truth, train, groups, ["a"])


@pytest.mark.parametrize(("n", "fraction", "seed"), [(0, 0.5, 1), (7, 0.5, 1), (120, 0.3, 42), (33, 0.9, 5)])
def test_the_training_split_is_one_uniform_draw_per_grasp(n, fraction, seed):
    split = training_split(n, fraction, seed)
    assert split.dtype == bool and split.shape == (n,)
    # the minimal-work experiments' split: grasp i trains iff its uniform draw is below the fraction
    np.testing.assert_array_equal(split, np.random.default_rng(seed).random(n) < fraction)
    np.testing.assert_array_equal(split, training_split(n, fraction, np.random.default_rng(seed)))


def test_the_training_share_is_the_fraction_on_average():
    n, f = 100_000, 0.3
    share = training_split(n, f, 0).mean()
    assert abs(share - f) < 4 * np.sqrt(f * (1 - f) / n)  # binomial: within 4 standard errors
    assert not np.array_equal(training_split(50, 0.5, 0), training_split(50, 0.5, 1))


@pytest.mark.parametrize("fraction", [0.0, 1.0, 50, True])
def test_the_training_split_refuses_a_fraction_outside_0_1(fraction):
    with pytest.raises(ValueError, match="train_fraction must be in"):
        training_split(10, fraction, 0)

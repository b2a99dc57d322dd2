"""workbench.grasp.precision: precision/recall of "resisted" predictions and matched precision."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.grasp.precision import matched_precision, recall_at_least, scores


def test_scores_by_hand():
    pred = np.array([True, True, False, False, True])
    truth = np.array([True, False, True, False, True])
    # tp 2, fp 1, fn 1, tn 1: F1 = 2·(2/3)(2/3)/(4/3) = 2/3, accuracy 3/5
    assert scores(pred, truth) == {
        "precision": 2 / 3,
        "recall": 2 / 3,
        "f1": 2 / 3,
        "accuracy": 3 / 5,
        "positives": 3,
    }
    # precision 1/2, recall 1: F1 = 2·(1/2)·1/(3/2) = 2/3 as the harmonic mean
    lopsided = scores(np.array([True, True, False]), np.array([True, False, False]))
    assert lopsided["f1"] == pytest.approx(2 * 0.5 * 1.0 / 1.5)
    assert lopsided["accuracy"] == pytest.approx(2 / 3)
    none = scores(np.zeros(3, bool), np.zeros(3, bool))
    assert np.isnan(none["precision"]) and np.isnan(none["recall"]) and none["positives"] == 0
    with pytest.raises(ValueError, match="boolean"):
        scores(np.array([1, 0]), np.array([True, False]))
    with pytest.raises(ValueError, match="one shape"):
        scores(np.ones(3, bool), np.ones(2, bool))


def test_matched_precision_on_a_hand_made_ranking():
    truth = np.array([True, True, True, False, True, False])
    margins = np.array([3.0, 2.5, 2.0, 1.8, 1.2, 0.5])
    out = matched_precision(margins, truth, [0.8, 1.0])
    # t = 1.2 keeps the top 5: precision 4/5, recall 1; t = 2.0: precision 1, recall 3/4
    assert out["at_levels"]["recall"] == [1.0, 0.75]
    assert out["at_levels"]["threshold"] == [1.2, 2.0]
    assert np.isnan(matched_precision(np.zeros(6), truth, [0.5])["at_levels"]["recall"][0])


def test_recall_at_least_per_level():
    """Every 'better' model's recall >= every 'worse' one's, per level; a level never reached
    (NaN) counts as recall 0."""
    truth = np.array([True, True, True, False, True, False])
    levels = [0.6, 1.0]
    # at t = 0.5 both keep every grasp: precision 4/6 >= 0.6 with recall 1
    good = matched_precision(np.array([3.0, 2.5, 2.0, 1.8, 1.2, 0.5]), truth, levels)  # recall 1, 3/4
    poor = matched_precision(np.array([0.5, 2.5, 2.0, 1.8, 1.2, 3.0]), truth, levels)  # a failure on top
    assert good["at_levels"]["recall"] == [1.0, 0.75]
    assert poor["at_levels"]["recall"][0] == 1.0 and np.isnan(poor["at_levels"]["recall"][1])
    matched = {"good": good, "poor": poor}
    assert recall_at_least(matched, ["good"], ["poor"], levels) == {"0.6": True, "1.0": True}
    assert recall_at_least(matched, ["poor"], ["good"], levels) == {"0.6": True, "1.0": False}
    assert recall_at_least(matched, ["poor"], ["poor"], levels) == {"0.6": True, "1.0": True}  # 0 >= 0
    with pytest.raises(ValueError, match="precision levels"):
        recall_at_least(matched, ["good"], ["poor"], [0.8])


@pytest.mark.parametrize(
    ("margins", "truth", "levels", "match"),
    [
        ([2.0, np.nan, 1.0], [True, True, False], [0.9], r"margins must not be NaN .*1 NaN of 3 at index 1"),
        (
            [2.0, 1.0],
            [True, False],
            0.9,
            r"levels must be a sequence .*got 0.9 \(a single level: pass \[0.9\]\)",
        ),
        ([2.0, 1.0], [True, False], [90], r"levels must be precision levels in \(0, 1\] .*got 90 in \[90\]"),
        ([2.0, 1.0], [True, False], [0.0], r"precision levels in \(0, 1\].*got 0.0"),
        (np.ones((2, 2)), np.ones((2, 2), bool), [0.5], r"margins must be an \(n,\) array .*shape \(2, 2\)"),
        (
            [2.0, 1.0],
            [1, 0],
            [0.9],
            r"truth must be an \(n,\) boolean array like margins \(2,\) .*; got int64 .*asarray\(truth, bool",
        ),
        ([2.0, 1.0, 3.0], [True, False], [0.9], r"truth must be .*got bool shape \(2,\)"),
        (["a", "b"], [True, False], [0.9], r"margins must be an \(n,\) array of numbers"),
    ],
)
def test_matched_precision_refuses_careless_input_by_its_own_argument_names(margins, truth, levels, match):
    if isinstance(truth, list):
        truth = np.array(truth)
    with pytest.raises(ValueError, match=match):
        matched_precision(margins, truth, levels)

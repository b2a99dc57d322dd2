"""workbench.stats: rank correlation that solver noise cannot move."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import rankdata, spearmanr

from workbench import config
from workbench.stats import rank_correlation, tie_ranks


def test_near_ties_rank_as_ties_whatever_their_last_bits():
    measured = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    pred = np.array([10.0, 20.0, 30.0, 30.0, 50.0, 60.0])
    up, down = pred.copy(), pred.copy()
    up[2], down[3] = np.nextafter(30.0, 40.0), np.nextafter(30.0, 40.0)  # one ulp, either order
    assert spearmanr(up, measured).statistic != spearmanr(down, measured).statistic  # raw: moved
    tied = rank_correlation(pred, measured)
    assert rank_correlation(up, measured) == rank_correlation(down, measured) == tied
    assert rank_correlation(pred, measured) == pytest.approx(spearmanr(pred, measured).statistic)


def test_careless_input_and_two_pairs():
    assert np.isnan(rank_correlation([1.0], [2.0]))
    # two pairs rank like scipy's (the stiffness figures score held-out halves of two grasps)
    assert rank_correlation([1.0, 2.0], [3.0, 5.0]) == pytest.approx(1.0)
    assert rank_correlation([2.0, 1.0], [3.0, 5.0]) == pytest.approx(-1.0)
    assert np.isnan(rank_correlation([1.0, 1.0 + 1e-12], [3.0, 5.0]))  # one tie: no ranking
    with pytest.raises(ValueError, match="one length"):
        rank_correlation([1.0, 2.0, 3.0], [1.0, 2.0])


def test_newton_accuracy_near_ties_rank_as_ties_and_no_rounding_boundary_splits_them():
    """The nonlinear wall's symmetric grasps: equal to ~1e-11 (two runs: 63.390167084061716 and
    63.39016708444205).  Rounding to 12 digits splits such a pair when it straddles a boundary
    (…0841 | …0844); the gap test ties it in every run, and equals scipy on the tied data."""
    rng = np.random.default_rng(3)
    measured = rng.permutation(8).astype(float)
    exact = np.array([63.390167084, 70.2, 41.4, 63.390167084, 102.5, 61.99, 70.06, 55.0])
    ref = spearmanr(exact, measured).statistic  # scipy: the exact tie averaged
    for noise in (1e-11, -1e-11, 3e-10):
        pred = exact.copy()
        pred[3] *= 1 + noise
        assert spearmanr(pred, measured).statistic != ref  # raw Spearman moves with the noise
        assert rank_correlation(pred, measured) == pytest.approx(ref, rel=1e-14)
    # a real gap (1e-6) is not noise: ranked apart, as scipy does
    pred = exact.copy()
    pred[3] *= 1 + 1e-6
    assert rank_correlation(pred, measured) == pytest.approx(spearmanr(pred, measured).statistic, rel=1e-14)


def test_tie_ranks_are_scipys_average_ranks_at_zero_tolerance():
    rng = np.random.default_rng(0)
    for _ in range(20):
        x = rng.integers(0, 6, rng.integers(1, 30)).astype(float) * rng.choice([1.0, -0.5])
        assert np.array_equal(tie_ranks(x, 0.0), rankdata(x, method="average"))
    # a chain of gaps each within rtol is one tie group (1, 1+1e-10, 1+2e-10, 2)
    assert tie_ranks([1.0 + 2e-10, 2.0, 1.0, 1.0 + 1e-10], 1e-9).tolist() == [2.0, 4.0, 2.0, 2.0]


def test_the_tie_tolerance_is_read_from_config_at_call_time():
    pred, measured = [1.0, 1.0 + 1e-7, 2.0], [1.0, 2.0, 3.0]
    assert rank_correlation(pred, measured) == pytest.approx(1.0)  # 1e-7 apart: ranked apart
    with config.override(rank_tie_rtol=1e-6):
        assert rank_correlation(pred, measured) == pytest.approx(spearmanr([1, 1, 2], measured).statistic)


@pytest.mark.parametrize(
    ("pred", "measured", "match"),
    [
        (
            [1.0, np.nan, 3.0, 4.0],
            [1.0, 2.0, 3.0, 4.0],
            r"pred must be finite to be ranked; got nan at index 1",
        ),
        (
            [1.0, 2.0, 3.0, 4.0],
            [1.0, np.inf, 3.0, -np.inf],
            r"measured must be finite .*got inf at index 1 \(2",
        ),
    ],
)
def test_non_finite_values_are_refused_not_ranked(pred, measured, match):
    with pytest.raises(ValueError, match=match + r".*Leave those pairs out first"):
        rank_correlation(pred, measured)


@pytest.mark.parametrize("rtol", [-1e-9, 0.01, float("nan"), True, "1e-9"])
def test_rtol_must_be_a_small_relative_gap(rtol):
    with pytest.raises(ValueError, match=r"rtol must be a relative gap in \[0, 1e-3\] .*got"):
        rank_correlation([1.2, 1.4, 3.0], [1.0, 2.0, 3.0], rtol=rtol)

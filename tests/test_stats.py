"""workbench.stats: rank correlation that last-bit noise cannot move."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import spearmanr

from workbench.stats import rank_correlation, significant


def test_near_ties_rank_as_ties_whatever_their_last_bits():
    measured = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    pred = np.array([10.0, 20.0, 30.0, 30.0, 50.0, 60.0])
    up, down = pred.copy(), pred.copy()
    up[2], down[3] = np.nextafter(30.0, 40.0), np.nextafter(30.0, 40.0)  # one ulp, either order
    assert spearmanr(up, measured).statistic != spearmanr(down, measured).statistic  # raw: moved
    tied = rank_correlation(pred, measured)
    assert rank_correlation(up, measured) == rank_correlation(down, measured) == tied
    assert rank_correlation(pred, measured) == pytest.approx(spearmanr(pred, measured).statistic)


def test_significant_digits_and_careless_input():
    x = np.array([123456.789012345, -0.000123456789012345, 0.0, np.inf, np.nan])
    r = significant(x, 6)
    assert r[0] == 123457.0 and r[1] == pytest.approx(-0.000123457, rel=1e-12)
    assert r[2] == 0.0 and r[3] == np.inf and np.isnan(r[4])
    assert np.isnan(rank_correlation([1.0], [2.0]))
    # two pairs rank like scipy's (the stiffness figures score held-out halves of two grasps)
    assert rank_correlation([1.0, 2.0], [3.0, 5.0]) == pytest.approx(1.0)
    assert rank_correlation([2.0, 1.0], [3.0, 5.0]) == pytest.approx(-1.0)
    with pytest.raises(ValueError, match="one length"):
        rank_correlation([1.0, 2.0, 3.0], [1.0, 2.0])


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


@pytest.mark.parametrize("digits", [0, -1, 2.5, True])
def test_digits_must_be_a_positive_int(digits):
    with pytest.raises(ValueError, match=rf"digits must be a positive int .*got {digits!r}"):
        rank_correlation([1.2, 1.4, 3.0], [1.0, 2.0, 3.0], digits=digits)
    assert rank_correlation([1.2, 1.4, 3.0], [1.0, 3.0, 2.0], digits=1) == pytest.approx(
        spearmanr([1, 1, 3], [1, 3, 2]).statistic  # 1.2 and 1.4 tie at one digit
    )

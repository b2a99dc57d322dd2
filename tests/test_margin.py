"""workbench.grasp.margin: the bisected resistance margin against the analytic one, and the
capacity error of margins against a truth's."""

from __future__ import annotations

from functools import partial

import numpy as np
import pytest

from workbench.grasp import point_contact, resists
from workbench.grasp.margin import MARGIN_SPAN, margin_rel_err, margin_vs_truth, resistance_margin


def _antipodal(F: float) -> list:
    return [
        point_contact([0.03, 0, 0], [1, 0, 0], F, n_edges=64),
        point_contact([-0.03, 0, 0], [-1, 0, 0], F, n_edges=64),
    ]


def test_margin_of_antipodal_point_contacts_is_2_mu_F_over_mg():
    """Two antipodal point contacts (64-gon inner cone, aligned with gravity) hold s·mg iff
    s <= 2μF/(mg)."""
    mu, F = 0.5, 10.0
    resisted = partial(resists, _antipodal(F), mu=mu)
    for mg in (2.0, 5.0, 20.0):
        s_star = resistance_margin(resisted, np.array([0.0, -mg, 0, 0, 0, 0]), steps=14)
        exact = 2 * mu * F / mg
        # inner 64-gon: support along y is μF cos(π/64) at worst; bisection resolution 2^(12/2^14)
        assert exact * np.cos(np.pi / 64) * (1 - 1e-3) <= s_star <= exact * (1 + 1e-6), (mg, s_star, exact)
    assert resistance_margin(resisted, np.array([0, 0, 0, 1.0, 0, 0]), steps=4) == 0.0  # no torsion
    # beyond the span: the cap, not a bisected value
    assert resistance_margin(resisted, np.array([0.0, -1e-3, 0, 0, 0, 0]), steps=4) == MARGIN_SPAN


def test_margin_counts_the_deciders_calls_it_needs():
    calls = []

    def resisted(v):  # a threshold at |v| <= 3
        calls.append(v)
        return np.linalg.norm(v) <= 3.0

    s = resistance_margin(resisted, np.array([1.0, 0, 0, 0, 0, 0]), steps=20)
    assert s == pytest.approx(3.0, rel=2 * np.log(2) * 12 / 2**20) and s <= 3.0
    assert len(calls) == 22  # the two ends, then one per step


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"w": np.zeros(5), "steps": 3}, r"w must be a \(6,\) wrench \[f; tau\]; got shape \(5,\)"),
        (
            {"w": np.array([np.nan, 0, 0, 0, 0, 0]), "steps": 3},
            r"w must be a finite \(6,\) wrench; got non-finite entries: \[nan, 0.0,",
        ),
        ({"w": np.ones(6), "steps": -1}, "steps must be an integer >= 1 .*got -1"),
        ({"w": np.ones(6), "steps": 2.5}, "steps must be an integer >= 1 .*got 2.5"),
        ({"w": np.ones(6), "steps": True}, "steps must be an integer >= 1 .*got True"),
        ({"w": np.ones(6), "steps": 3, "span": 1.0}, r"span must be a number > 1 .*got 1.0"),
        (
            {"w": np.ones(6), "steps": 3, "span": "64"},
            r"span must be a number > 1 .*default 64.0\); got '64'",
        ),
    ],
)
def test_careless_margin_input_is_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        resistance_margin(lambda v: True, **kwargs)


def test_margin_vs_truth_by_hand():
    s = np.array([2.0, 0.5, 0.0, 64.0, 1.0])
    t = np.array([1.0, 1.0, 1.0, 1.0, 1.0])
    out = margin_vs_truth(s, t)  # the zero and the capped margin are left out
    assert out["n"] == 3
    assert out["median_abs_log_ratio"] == pytest.approx(np.log(2.0))
    assert out["median_log_ratio"] == 0.0 and out["optimistic_fraction"] == pytest.approx(1 / 3)
    assert np.isnan(margin_vs_truth(np.zeros(2), np.ones(2))["median_abs_log_ratio"])
    with pytest.raises(ValueError, match="one shape"):
        margin_vs_truth(np.ones(3), np.ones(2))


def test_margin_rel_err_is_the_median_relative_error_over_pairs_both_positive():
    # pairs: (2, 1) -> 1, (1, 2) -> 0.5, (0, 1) left out, (3, 0) left out, (span, span) -> 0
    s = np.array([2.0, 1.0, 0.0, 3.0, MARGIN_SPAN])
    t = np.array([1.0, 2.0, 1.0, 0.0, MARGIN_SPAN])
    assert margin_rel_err(s, t) == pytest.approx(0.5, rel=1e-15)
    # margin_vs_truth leaves out the pair at the span as well: (2, 1) and (1, 2) remain
    assert margin_vs_truth(s, t)["n"] == 2
    assert margin_rel_err(s[:2], t[:2]) == pytest.approx(0.75, rel=1e-15)  # median of 1 and 0.5
    assert margin_rel_err(np.zeros(3), np.ones(3)) is None
    with pytest.raises(ValueError, match="one shape"):
        margin_rel_err(np.ones(3), np.ones(4))

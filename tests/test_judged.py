"""Engine-judged scores: each number against a count by hand of a small made-up table."""

import numpy as np
import pytest

from workbench.grasp.judged import model_tables, recall_gain_claims, verdict_limit_tables

HELD = {0: np.array([1, 1, 0, 0, 1], bool), 1: np.array([1, 0, 0, 1, 1], bool)}
EXACT = {0: np.array([1, 0, 0, 0, 1], bool), 1: np.array([1, 0, 0, 0, 1], bool)}
PRED = {
    "planar": {0: np.array([1, 0, 0, 0, 0], bool), 1: np.array([1, 0, 0, 0, 0], bool)},
    "6dls": {0: np.array([1, 1, 0, 0, 1], bool), 1: np.array([1, 0, 1, 0, 1], bool)},
}


def test_model_tables_count_by_hand():
    t = model_tables(PRED, HELD, EXACT, [0, 1], {"planar": 1.0, "6dls": 2.0})
    # planar seed 0: tp 1, fn 2 -> recall 1/3; seed 1: tp 1, fn 2 -> 1/3; precision 1 both
    assert t["planar"]["vs_engine"]["recall"]["mean"] == pytest.approx(1 / 3)
    assert t["planar"]["vs_engine"]["precision"]["mean"] == pytest.approx(1.0)
    # 6dls seed 0 exact match (acc 1); seed 1: pred 1,0,1,0,1 vs 1,0,0,1,1 -> acc 3/5
    assert t["6dls"]["vs_engine"]["accuracy"]["mean"] == pytest.approx(0.8)
    assert t["6dls"]["vs_engine"]["accuracy"]["std"] == pytest.approx(np.std([1.0, 0.6], ddof=1))
    # against the exact truth: 6dls seed 0 has one false positive (index 1) -> precision 2/3
    assert t["6dls"]["vs_exact_6dfw"]["precision"]["mean"] == pytest.approx((2 / 3 + 2 / 3) / 2)
    assert t["6dls"]["ms_per_grasp"] == 2.0


def test_verdict_limits_reread_the_recorded_motion():
    trials = {
        s: [{"drift_mm": d, "turn_deg": a} for d, a in rows]
        for s, rows in {0: [(1, 1), (3, 3), (8, 1), (20, 50), (1, 9)], 1: [(0, 0)] * 5}.items()
    }
    out = verdict_limit_tables(PRED, trials, [0, 1], ((2.0, 2.0), (9.0, 10.0)))
    # seed 0 holds 1/5 at 2 mm 2 deg and 4/5 at 9 mm 10 deg; seed 1 holds all
    assert out["2mm_2deg"]["held_fraction"] == pytest.approx((0.2 + 1.0) / 2)
    assert out["9mm_10deg"]["held_fraction"] == pytest.approx((0.8 + 1.0) / 2)
    # at 9 mm 10 deg seed 0 truth is 1,1,1,0,1: 6dls pred 1,1,0,0,1 -> acc 4/5; seed 1 all held: 3/5
    assert out["9mm_10deg"]["models"]["6dls"]["accuracy"] == pytest.approx(0.7)
    assert out["9mm_10deg"]["ranking_by_accuracy"] == ["6dls", "planar"]


def test_recall_gain_claim_needs_comparable_precision():
    def table(recall, precision):
        metrics = {"recall": recall, "precision": precision, "f1": 0.5, "accuracy": 0.5}
        return {"vs_engine": {k: {"mean": v} for k, v in metrics.items()}}

    got = recall_gain_claims({"6dls": table(0.8, 0.90), "planar": table(0.6, 0.94), "6dfw": table(0.7, 1.0)})
    assert got["6dls_over_planar"]["engine_gain_pts"]["recall"] == pytest.approx(20.0)
    assert got["6dls_over_planar"]["reproduced"]  # precision 4 points below: comparable
    assert not got["6dls_over_6dfw"]["reproduced"]  # 10 points below: not
    assert "6dls_over_3dls_nonplanar" not in got


def test_careless_tables_are_refused():
    with pytest.raises(ValueError, match="boolean"):
        model_tables(
            {"6dls": {0: np.array([1, 0, 2])}}, {0: HELD[0][:3]}, {0: EXACT[0][:3]}, [0], {"6dls": 1.0}
        )
    trials = {0: [{"drift_mm": 1.0, "turn_deg": 1.0}] * 5}
    with pytest.raises(ValueError, match="probably in radians"):
        verdict_limit_tables(PRED, trials, [0], [(5.0, 0.0873)])  # the turn in radians
    with pytest.raises(ValueError, match="millimetres"):
        verdict_limit_tables(PRED, trials, [0], [(0.005, 5.0)])  # the drift in metres
    with pytest.raises(ValueError, match="percentage points"):
        recall_gain_claims({}, {"planar": 0.26})
    # a trial not simulated (no motion recorded, None from JSON) is held at no limit
    got = verdict_limit_tables({"6dls": {0: np.array([True])}}, {0: [{"drift_mm": None, "turn_deg": None}]},
                               [0], [(9.0, 10.0)])  # fmt: skip
    assert got["9mm_10deg"]["held_fraction"] == 0.0

"""workbench.engine_trials.reality: the engine's verdicts and excursions scored against the real
REACH cube trials (balanced accuracy, ROC AUC), checked against a pairwise count."""

import numpy as np
import pytest

pytest.importorskip("mujoco")

from workbench.engine_trials.reality import excursion, reach_cube_inputs, score_reach  # noqa: E402


def _row(grasp: int, drift_mm: float, turn_deg: float) -> dict:
    held = drift_mm <= 5.0 and turn_deg <= 5.0
    timing = {"wall_s": 1.0, "simulated_s": 2.0}
    return {"grasp": grasp, "held": held, "drift_mm": drift_mm, "turn_deg": turn_deg, **timing}


def test_the_auc_ranks_every_real_repeat_by_its_grasps_excursion():
    trials, _ = reach_cube_inputs()
    rng = np.random.default_rng(3)
    grasps = sorted(set(trials.grasp_index.tolist()))
    rows = [_row(g, float(rng.uniform(0, 8)), float(rng.uniform(0, 8))) for g in grasps]
    got = score_reach(rows)
    # the reference: every (real success, real failure) pair of repeats, the success ranked above
    # when its grasp's object moved less (ties count a half) — Mann-Whitney's U over the pairs
    moved = {r["grasp"]: max(r["drift_mm"] / 5.0, r["turn_deg"] / 5.0) for r in rows}
    m = np.array([moved[g] for g in trials.grasp_index])
    ok, bad = m[trials.success.astype(bool)], m[~trials.success.astype(bool)]
    pairs = (ok[:, None] < bad[None, :]).sum() + 0.5 * (ok[:, None] == bad[None, :]).sum()
    assert got["roc_auc"] == pytest.approx(pairs / (ok.size * bad.size), abs=1e-12)
    # the verdict's rates from the same rows: held iff the excursion is within the limits
    held = m <= 1.0
    real = trials.success.astype(bool)
    assert got["true_positive_rate"] == pytest.approx((held & real).sum() / real.sum())
    assert got["true_negative_rate"] == pytest.approx((~held & ~real).sum() / (~real).sum())


def test_excursion_is_the_larger_of_drift_and_turn_in_units_of_their_limits():
    assert excursion({"drift_mm": 2.5, "turn_deg": 1.0}, 5.0, 5.0) == 0.5
    assert excursion({"drift_mm": 1.0, "turn_deg": 10.0}, 5.0, 5.0) == 2.0

"""Physical gripper trials judged by every model (workbench.grasp.gripper_trials): independent
pose streams per grasp and seed, the flat row of the nominal and pose-sampled contacts (a pose
squarely on the REACH cube holds under pose noise; a pose beside it misses every sample), and
the scores against the real outcomes, counted by hand."""

from types import SimpleNamespace

import numpy as np
import pytest
import trimesh

from workbench.grasp.gripper_eval import gripper_contact, judge_contact
from workbench.grasp.gripper_trials import (
    best_quality,
    crossval_by_model,
    judge_models,
    nominal_fields,
    pose_seed,
    robust_fields,
    verdict_scores,
)
from workbench.grasp.inputs import Task
from workbench.grasp.pose_robust import PoseNoise
from workbench.limit_surface import LimitSurfaceCache
from workbench.sources.gripper import yumi
from workbench.sources.trials import default_mesh_path

MASS = 0.003  # kg, the REACH cube
TASK = {"task": Task(mass=MASS, com=np.zeros(3), down=(0.0, 0.0, -1.0)), "mu": 0.3}  # judge_contact's


@pytest.fixture(scope="module")
def cube():
    return trimesh.load(default_mesh_path(), force="mesh")


def _top_down(x: float = 0.0) -> np.ndarray:
    """YuMi above the cube approaching along −z, jaws closing along x, tips 12 mm below the top
    face, shifted by x [m] (as in tests/test_gripper_eval.py)."""
    T = np.eye(4)
    T[:3, :3] = [[1, 0, 0], [0, -1, 0], [0, 0, -1]]
    T[:3, 3] = [x, 0.0, 0.015 - 0.012 + yumi().tooltips[0][2, 3]]
    return T


def test_each_grasp_and_seed_draws_its_own_pose_stream():
    a = pose_seed(0, 3, 1).random(4)
    np.testing.assert_array_equal(a, pose_seed(0, 3, 1).random(4))  # same seed, same poses
    np.testing.assert_array_equal(a, np.random.default_rng([0, 3, 1]).random(4))
    for other in ((1, 3, 1), (0, 4, 1), (0, 3, 0), (0, 1, 3)):
        assert not np.array_equal(a, pose_seed(*other).random(4)), other


def test_the_nominal_fields_are_each_models_verdict_of_the_recomputed_contact(cube):
    cache = LimitSurfaceCache()
    row = nominal_fields(cube, yumi(), _top_down(), ("soft_point", "point"), TASK, cache)
    c = gripper_contact(cube, yumi(), _top_down())
    for m in ("soft_point", "point"):
        v = judge_contact(c, m, cache=cache, **TASK)
        assert row[f"nominal/{m}/margin"] == v.margin and row[f"nominal/{m}/held"] == v.resisted
    assert row["nominal/soft_point/held"] and row["nominal_touches"] and row["pressed_touches"]
    # the cube's faces are 3 cm wide, the pads lie wholly on them: each contact is a patch
    assert all(a > 10 for a in row["nominal_area_mm2"])
    verdicts, secs = judge_models(c, ("soft_point",), TASK, cache)
    assert verdicts["soft_point"].margin == row["nominal/soft_point/margin"] and secs["soft_point"] >= 0


def test_robust_fields_hold_on_the_face_and_miss_beside_the_cube(cube):
    noise = PoseNoise(3, 0.001, 0.001)
    cache = LimitSurfaceCache()
    on = robust_fields(cube, yumi(), _top_down(), noise, pose_seed(0, 0, 0), ("soft_point",), TASK, cache)
    assert on["robust_misses"] == 0 and on["robust/soft_point/p_held"] == 1.0
    assert 0.9 < on["robust/soft_point/q"] <= 1.0  # 3 g in a 20 N grip: a margin near 1
    off = robust_fields(
        cube, yumi(), _top_down(x=0.2), noise, pose_seed(0, 0, 0), ("soft_point",), TASK, cache
    )
    assert off["robust_misses"] == 3 and off["robust/soft_point/q"] == 0.0
    assert off["robust/soft_point/p_held"] == 0.0


def _trials():
    # grasps 0 and 2 always held (2 trials each), grasp 1 never
    return SimpleNamespace(
        grasp_index=np.array([0, 0, 1, 1, 2, 2]), success=np.array([True, True, False, False, True, True])
    )


def test_verdict_scores_count_each_trial_of_a_grasp():
    rows = {
        f"{g}/0": {"grasp": g, "seed": 0, "nominal/m/held": held, "pressed/m/held": False}
        for g, held in ((0, True), (1, True), (2, False))
    }
    out = verdict_scores(_trials(), rows, ["m"])["m"]
    # nominal: per trial T T T T F F against T T F F T T — tp 2, fp 2, fn 2, tn 0
    n = out["nominal"]
    assert (n["precision"], n["recall"], n["f1"], n["accuracy"]) == (0.5, 0.5, 0.5, 2 / 6)
    assert n["balanced_accuracy"] == 0.25  # recall of the successes 0.5, of the failures 0
    p = out["pressed"]  # nothing held: no positive prediction
    assert np.isnan(p["precision"]) and p["recall"] == 0.0 and p["f1"] == 0.0 and p["accuracy"] == 2 / 6


def test_crossval_by_model_scores_every_quality_and_seed():
    # seed 0's robust quality ranks the held grasps above the dropped one, seed 1's the reverse
    q = {0: (0.9, 0.1), 1: (0.2, 0.8), 2: (0.7, 0.3)}
    rows = {}
    for g in (0, 1, 2):
        for s in (0, 1):
            rows[f"{g}/{s}"] = {"grasp": g, "seed": s, "robust/m/q": q[g][s], "robust/m/p_held": q[g][s]}
        rows[f"{g}/0"].update({"nominal/m/margin": q[g][0], "pressed/m/margin": q[g][1]})
    scores, per_grasp = crossval_by_model(_trials(), rows, ["m"], 2)
    s = scores["m"]
    assert s["nominal"]["roc_auc"] == 1.0 and s["pressed"]["roc_auc"] == 0.0
    assert s["robust_seed0"]["roc_auc"] == 1.0 and s["robust_held_seed0"]["roc_auc"] == 1.0
    assert s["robust"]["roc_auc"] == {"mean": 0.5, "std": pytest.approx(np.sqrt(0.5)), "n": 2}
    assert s["nominal"]["n"] == 6 and s["nominal"]["n_groups"] == 3
    assert per_grasp["m"] == {"nominal": {0: 0.9, 1: 0.2, 2: 0.7}, "pressed": {0: 0.1, 1: 0.8, 2: 0.3}}


def test_the_best_quality_is_the_highest_balanced_accuracy_ties_broken_by_auc():
    def plain(ba, auc):
        return {"balanced_accuracy": ba, "roc_auc": auc}

    def over_seeds(ba, auc):
        return {"balanced_accuracy": {"mean": ba}, "roc_auc": {"mean": auc}}

    scores = {
        "a": {
            "nominal": plain(0.7, 0.8),
            "pressed": plain(float("nan"), 0.99),
            "robust": over_seeds(0.7, 0.9),
            "robust_held": over_seeds(0.6, 1.0),
        },
        "b": {
            "nominal": plain(0.5, 0.5),
            "pressed": plain(0.5, 0.5),
            "robust": over_seeds(0.2, 0.3),
            "robust_held": over_seeds(0.7, float("nan")),
        },
    }
    assert best_quality(scores) == {
        "model": "a",
        "quality": "robust",
        "balanced_accuracy": 0.7,
        "roc_auc": 0.9,
    }

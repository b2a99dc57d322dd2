"""Table 4.6's rows and scoring (workbench.grasp.work_table) on hand-made rows whose
normalisers and balanced accuracies follow by hand, the nonlinear work along a linear load
curve (f²/2s), and the candidates of a cylinder.  A candidate's row (grasp_row) runs on the
measured objects in tests/test_parallel.py and the minimal-work quick run."""

import json

import numpy as np
import pytest

from workbench.grasp.work_table import (
    TASKS,
    GraspRowSettings,
    candidate_grasps,
    inf_for_nan,
    largest_jaw_force,
    measured_map,
    nan_if_none,
    nonlinear_work,
    nonlinear_work_table,
    table_4_6,
)

# eight grasps, the first four training; success iff W < 1 J
W = [0.2, 2.0, 0.4, 3.0, 0.3, 2.5, 0.1, 4.0]
F_SUM = [2.0, None, 4.0, 30.0, 3.0, 25.0, 1.0, 40.0]  # None: unresisted (inf)
Q_ROBUST = [0.9, 0.1, 0.2, 0.8, 0.6, 0.7, 0.3, 0.4]
OBJECTS = ["a", "b", "a", "b", "a", "a", "b", "b"]
SPLIT = np.array([True] * 4 + [False] * 4)


def _rows():
    rows = []
    for w, f, q, o in zip(W, F_SUM, Q_ROBUST, OBJECTS, strict=True):
        entry = {"truth": w < 1, "q_robust": q, "f_sum": f, "W": w, "W_fem": w}
        rows.append({"object": o, **{t: dict(entry) for t in TASKS}})
    return rows


def test_nan_if_none_and_inf_for_nan():
    assert np.isnan(nan_if_none(None)) and nan_if_none(3) == 3.0
    np.testing.assert_array_equal(inf_for_nan(_rows(), TASKS[0], "f_sum"), [2, np.inf, 4, 30, 3, 25, 1, 40])


def test_table_4_6_by_hand():
    table, normalisers, balance = table_4_6(_rows(), SPLIT, ["a", "b"], 0.5, 0)
    for t in TASKS:
        # W: the training values' best cut is between 0.4 and 2.0 (t = 1.2), W_max = t / (1 - σ)
        assert normalisers[t]["W_max_J"] == pytest.approx(2.4, rel=1e-12)
        assert normalisers[t]["W_fem_max_J"] == pytest.approx(2.4, rel=1e-12)
        # f: between 4 and 30 (the unresisted grasp fails at any f_max), t = 17
        assert normalisers[t]["f_max_N"] == pytest.approx(34.0, rel=1e-12)
        # held out: W 0.3, 2.5, 0.1, 4.0 and f 3, 25, 1, 40 are all told apart
        assert table[t]["q_work"]["All"] == 1.0 and table[t]["q_force"]["All"] == 1.0
        # q_robust >= 0.5 predicts 0.6 (success), 0.7 (failure) to succeed and 0.3 (success),
        # 0.4 (failure) to fail: each class half right; per object a: (T, F) both predicted
        # success, b: (T, F) both failure — one recall 1 and one 0 each
        assert table[t]["q_robust"] == {"a": 0.5, "b": 0.5, "All": 0.5}
        assert set(table[t]["interval_95"]) == {"q_robust", "q_force", "q_work", "q_work_fem"}
        assert balance[t] == {"success": 4, "failure": 4, "held_out": {"a": [1, 1], "b": [1, 1]}}


def _nl_row(forces, s_fem, W_fem, truth=True):
    entry = {"forces": forces, "W_fem": W_fem, "W": W_fem, "truth": truth}
    return {"s_fem": s_fem, **{t: entry for t in TASKS}}


LINEAR = {  # 1e4 N/m per jaw up to 20 N
    "curve": {"closing": [0.0, 1e-3, 2e-3], "jaw_forces": [[0, 0], [10, 10], [20, 20]]},
    "on_clamp": False,
}


def test_largest_jaw_force_and_nonlinear_work():
    row = _nl_row([[5.0, 10.0], [2.0, 2.0]], 1e4, 125 / 2e4)
    assert largest_jaw_force(row) == 10.0
    assert nonlinear_work(row, TASKS[0], LINEAR) == pytest.approx(125 / 2e4, rel=1e-12)
    assert nonlinear_work(row, TASKS[0], {"curve": None}) == np.inf  # no curve: predicted to fail
    assert nonlinear_work(_nl_row([[5.0, 10.0]], float("inf"), 0.0), TASKS[0], {"curve": None}) == 0.0
    unresisted = _nl_row([[np.nan, np.nan], [1.0, 1.0]], 1e4, None)
    assert np.isnan(largest_jaw_force(_nl_row([[np.nan, np.nan]], 1e4, None)))
    assert largest_jaw_force(unresisted) == 1.0
    assert nonlinear_work(unresisted, TASKS[0], LINEAR) == np.inf


def test_nonlinear_work_table_on_linear_curves_matches_the_linear_work():
    forces = [1.0, 2.0, 3.0, 4.0, 1.5, 2.5, 3.5, 4.5]  # success iff below 3 N
    rows = [_nl_row([[f, f]], 1e4, 2 * f**2 / 2e4, f < 3) for f in forces]
    objs = np.array(["a", "b"] * 4)
    split = np.array([True] * 4 + [False] * 4)
    table = nonlinear_work_table(rows, [LINEAR] * 8, split, objs, ["a", "b"], 0.5)
    for t in TASKS:
        ratio = table[t]["W_nonlinear_over_linear"]
        assert ratio["n"] == 8 and ratio["median"] == pytest.approx(1.0, rel=1e-12)
        for label in ("q_work_map", "q_work_fem_linear", "q_work_fem_nonlinear"):
            assert table[t][label] == {"a": 1.0, "b": 1.0, "All": 1.0}


def test_grasp_row_settings_from_a_run_config():
    config = {
        "seed": 3,
        "grasp_force": 10.0,
        "profiles": "reach",
        "jaw": [0.02, 0.04],
        "reach_closing_mm": 1.0,
        "mu": 0.5,
        "M": 200,
        "mass_kg": {"cup": 0.18},
        "robust_samples": 30,
        "work_representation": "model",
        "safety": 1.25,
        "force_cap": 20.0,
        "closing_limit_mm": 5.0,
        "noise_samples": 8,
        "sigma_mu": 0.1,
        "sigma_force": 0.1,
    }
    s = GraspRowSettings.from_config(config)
    assert (s.jaw, s.reach_closing, s.closing_limit, s.mass_kg["cup"]) == ((0.02, 0.04), 1e-3, 5e-3, 0.18)


def test_candidate_grasps_of_a_cylinder():
    import trimesh

    mesh = trimesh.creation.cylinder(radius=0.035, height=0.12, sections=96)
    cands = candidate_grasps(mesh, "cylinder", 2, 3, 0.5)
    # heights evenly inside the z extent [-60, 60] mm: -20 and 20 mm; 3 axis angles each
    assert sorted({round(float(g["center"][2]), 9) for g in cands}) == [-0.02, 0.02]
    assert len(cands) == 6
    for g in cands:
        assert np.linalg.norm(np.asarray(g["p2"]) - g["p1"]) == pytest.approx(0.07, rel=1e-3)


def test_measured_map_refuses_a_file_without_measurements(tmp_path):
    path = tmp_path / "cup.json"
    path.write_text(json.dumps({"stiffness_locations": [[0, 0, 0], [0.01, 0, 0]]}))
    with pytest.raises(ValueError, match="needs the measured 'stiffness_map'"):
        measured_map(str(path))

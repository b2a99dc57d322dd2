"""The measured objects' walls at their grasps (workbench.fem.grasp_walls): file lookup, the
per-process memos' keys, the calibrated stiffness of a wall row, the gripper's series
compliance and the work along a load curve, against hand-computed values.  The FEM stages
themselves (wall_stiffness, calibrated_wall, load_curve) run on the measured objects in
tests/test_parallel.py and the minimal-work quick run (tests/test_experiments.py)."""

import hashlib

import numpy as np
import pytest

from workbench.fem.grasp_walls import (
    NonlinearWallSettings,
    WallSettings,
    calibrated_stiffness,
    mesh_digest,
    object_files,
    pose_work,
    series_compliance,
)


def test_object_files_finds_both_files_or_says_where_it_looked(tmp_path):
    (tmp_path / "meshes").mkdir()
    (tmp_path / "stiffness_maps").mkdir()
    (tmp_path / "meshes" / "cup.obj").write_text("v 0 0 0\n")
    with pytest.raises(ValueError, match=r"cup: .*cup\.obj or .*cup\.json not found — set data_dir"):
        object_files(tmp_path, "cup")
    (tmp_path / "stiffness_maps" / "cup.json").write_text("{}")
    mesh, smap = object_files(str(tmp_path), "cup")
    assert (mesh, smap) == (tmp_path / "meshes" / "cup.obj", tmp_path / "stiffness_maps" / "cup.json")


def test_mesh_digest_is_the_sha256_of_the_file_bytes(tmp_path):
    path = tmp_path / "m.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\n")
    assert mesh_digest(str(path)) == hashlib.sha256(b"v 0 0 0\nv 1 0 0\n").hexdigest()
    mesh_digest.cache_clear()


def test_settings_from_a_run_config_convert_millimetres():
    config = {
        "E": 2.5e9,
        "nu": 0.4,
        "thickness": 5e-4,
        "mesh": [48, 24],
        "jaw": [0.02, 0.04],
        "nl_mesh": [16, 8],
        "nl_step_mm": 0.5,
        "nl_max_closing_mm": 15.0,
    }
    assert WallSettings.from_config(config) == WallSettings(2.5e9, 0.4, 5e-4, (48, 24), (0.02, 0.04))
    nl = NonlinearWallSettings.from_config(config)
    assert (nl.mesh, nl.step, nl.max_closing, nl.jaw) == ((16, 8), 0.5e-3, 15e-3, (0.02, 0.04))
    hash(WallSettings.from_config(config))  # hashable: a memo key


def test_calibrated_stiffness_of_a_wall_row():
    assert calibrated_stiffness({"rigid": False, "failed": False, "stiffness": 400.0}, 0.25) == 100.0
    assert calibrated_stiffness({"rigid": True, "failed": False, "stiffness": 1e9}, 0.25) == np.inf
    assert calibrated_stiffness({"rigid": False, "failed": True, "stiffness": None}, 0.25) == np.inf


def test_series_compliance_is_the_tightest_bound_and_its_effect_at_each_median():
    key = "series_compliance_bound_m_per_N"
    validation = {"a": {"missing_physics": {key: 1e-4}}, "b": {"missing_physics": {key: 5e-5}}}
    predicted = {"a": np.array([100.0, 300.0, np.inf]), "b": np.array([1000.0, 2000.0])}
    s = series_compliance(validation, predicted)
    assert s["bound_m_per_N"] == 5e-5 and s["from_object"] == "b"
    # 1 - 1/(1 + s c): a median of 200 N/m (the rigid grasp left out) and of 1500 N/m
    assert s["effect_at_median"]["a"] == pytest.approx(1 - 1 / 1.01, rel=1e-12)
    assert s["effect_at_median"]["b"] == pytest.approx(1 - 1 / 1.075, rel=1e-12)


def _linear_curve(on_clamp=False):
    # a linear spring of 1e4 N/m per jaw, closed to 2 mm
    closing = [0.0, 1e-3, 2e-3]
    return {"curve": {"closing": closing, "jaw_forces": [[0, 0], [10, 10], [20, 20]]}, "on_clamp": on_clamp}


def test_pose_work_on_a_linear_curve_is_f_squared_over_2s():
    poses = [np.array([5.0, 10.0]), np.array([2.0, 2.0])]
    # Σ f²/2s per pose: (25 + 100) / 2e4 and (4 + 4) / 2e4; the larger one
    assert pose_work(_linear_curve(), poses) == pytest.approx(125 / 2e4, rel=1e-12)
    # a force past the curve's end (20 N): predicted to fail
    assert pose_work(_linear_curve(), [np.array([30.0, 1.0])]) == np.inf
    # unless the curve stopped on a clamp: the work up to its end, 20²/2s, and 1²/2s
    assert pose_work(_linear_curve(True), [np.array([30.0, 1.0])]) == pytest.approx(401 / 2e4, rel=1e-12)

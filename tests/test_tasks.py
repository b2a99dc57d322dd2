"""Task wrenches (thesis §4.3.3.3) and horizontal antipodal grasps against closed forms."""

import numpy as np
import pytest
import trimesh

from workbench.grasp.robust import G_ACC
from workbench.grasp.sampling import horizontal_grasps
from workbench.grasp.tasks import task_wrenches


def test_lifting_is_one_gravity_wrench():
    (w,) = task_wrenches("vertical_lifting", 0.5, [0.0, 0.01, 0.02], [1.0, 0.0, 0.0])
    f = np.array([0.0, 0.0, -0.5 * G_ACC])
    np.testing.assert_allclose(w, np.r_[f, np.cross([0.0, 0.01, 0.02], f)], atol=1e-12)


def test_rotation_about_the_grasp_axis_turns_gravity_in_the_object_frame():
    W = task_wrenches("lift_and_rotate", 1.0, [0.0, 0.0, 0.0], [2.0, 0.0, 0.0])  # axis need not be unit
    assert W.shape == (3, 6)
    g = G_ACC
    # object turned +90° about x: world "down" seen from the object is R_x(-90°)(0, 0, -1) = (0, -1, 0)
    np.testing.assert_allclose(W[0, :3], [0, 0, -g], atol=1e-12)
    np.testing.assert_allclose(W[1, :3], [0, -g / np.sqrt(2), -g / np.sqrt(2)], atol=1e-12)
    np.testing.assert_allclose(W[2, :3], [0, -g, 0], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(W[:, :3], axis=1), g)
    with pytest.raises(ValueError, match="task must be one of"):
        task_wrenches("pour", 1.0, [0, 0, 0], [1, 0, 0])
    with pytest.raises(ValueError, match="axis"):
        task_wrenches("lift_and_rotate", 1.0, [0, 0, 0], [0, 0, 0])
    # the trial's careless units: a 0.27 kg bottle given in grams, its centre in millimetres
    with pytest.raises(ValueError, match=r"mass must be an object mass .* got 270.*grams — pass 0.27"):
        task_wrenches("vertical_lifting", 270.0, [0, 0, 0.08], [1, 0, 0])
    with pytest.raises(ValueError, match=r"com must be in metres.*80 m from the origin.*millimetres"):
        task_wrenches("vertical_lifting", 0.27, [0, 0, 80.0], [1, 0, 0])
    with pytest.raises(
        ValueError, match=r"mass must be an object mass .* got 50.0.*grams — pass 0.05"
    ):  # a 50 g cup
        task_wrenches("vertical_lifting", 50.0, [0, 0, 0.05], [1, 0, 0])
    with pytest.raises(ValueError, match=r"mass must be a number \[kg\]"):
        task_wrenches("vertical_lifting", "0.5", [0, 0, 0.05], [1, 0, 0])


def test_horizontal_grasps_on_a_cylinder():
    m = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=128)
    g = horizontal_grasps(m, [-0.02, 0.0, 0.02], 4, 0.3)
    assert len(g) == 12  # every line through the axis is antipodal on a cylinder
    for x in g:
        assert x["width"] == pytest.approx(0.06, rel=1e-3)  # the 128-gon's sag at most
        assert abs(x["axis"][2]) < 1e-12 and np.allclose(x["center"][:2], 0.0, atol=1e-9)
        assert x["n1"] @ x["axis"] < -0.99 and x["n2"] @ x["axis"] > 0.99
    # a box seen along its diagonal is outside a small friction cone
    box = trimesh.creation.box((0.06, 0.04, 0.1))
    assert len(horizontal_grasps(box, [0.0], 8, 0.2, pad=None)) == 2  # 0° and 90° only
    with pytest.raises(ValueError, match="heights"):
        horizontal_grasps(m, [0.2], 4, 0.3)
    with pytest.raises(ValueError, match="n_angles"):
        horizontal_grasps(m, [0.0], 0, 0.3)


def test_task_wrenches_match_scipy_rotations_on_random_axes():
    """Rodrigues' formula in task_wrenches against scipy's Rotation (an independent path)."""
    from scipy.spatial.transform import Rotation

    from workbench.grasp.tasks import TASKS

    rng = np.random.default_rng(0)
    for _ in range(100):
        a, com, m = rng.normal(size=3), 0.05 * rng.normal(size=3), rng.uniform(0.1, 2.0)
        for task, degs in TASKS.items():
            turn = Rotation.from_rotvec(-np.radians(np.array(degs))[:, None] * a / np.linalg.norm(a))
            f = m * G_ACC * turn.apply([0.0, 0.0, -1.0])
            ref = np.concatenate([f, np.cross(com, f)], axis=1)
            np.testing.assert_allclose(task_wrenches(task, m, com, a), ref, rtol=1e-12, atol=1e-12)

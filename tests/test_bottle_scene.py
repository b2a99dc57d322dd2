"""The bottle-family grasp scene: its grasp frame, the wrench move into the object frame (against
a point force built in both frames), and the pool's grasps against the exact wall."""

import numpy as np
import pytest

from workbench.fem.bottle import Bottle, bottle_family
from workbench.sources.bottle_scene import bottle_grasp_pool, grasp_frame, wrenches_to_object


def test_grasp_frame_is_a_right_handed_frame_on_the_axis_with_up_in_its_xz_plane():
    axis, up = np.array([1.0, 2.0, 0.3]), np.array([0.1, 0.0, 1.0])
    R = grasp_frame(axis, up)
    assert R @ R.T == pytest.approx(np.eye(3), abs=1e-12)
    assert np.linalg.det(R) == pytest.approx(1.0)
    assert R[0] == pytest.approx(axis / np.linalg.norm(axis))
    # up lies in the frame's x-z plane, on the +z side
    assert R[1] @ up == pytest.approx(0.0, abs=1e-12) and R[2] @ up > 0
    with pytest.raises(ValueError, match="parallel to the grasp axis"):
        grasp_frame([0, 0, 2.0], [0, 0, 1.0])


def test_wrenches_to_object_is_the_same_point_force_seen_from_the_object():
    rng = np.random.default_rng(3)
    R = grasp_frame(rng.normal(size=3), [0, 0, 1.0])
    c = np.array([0.01, -0.02, 0.12])  # the grasp centre in the object frame [m]
    W_g, W_ref = [], []
    for _ in range(5):
        f_g, r_g = rng.normal(size=3), 0.05 * rng.normal(size=3)  # a force at a point, grasp frame
        W_g.append(np.r_[f_g, np.cross(r_g, f_g)])
        f_o, r_o = R.T @ f_g, c + R.T @ r_g  # the same force at the same point, object frame
        W_ref.append(np.r_[f_o, np.cross(r_o, f_o)])
    assert wrenches_to_object(np.array(W_g), R, c) == pytest.approx(np.array(W_ref), abs=1e-14)


def test_pool_grasps_sit_on_the_wall_through_the_section_centre_inside_the_cone():
    mu = 0.3
    pool = bottle_grasp_pool(4, 1, 0, [0.45, 0.6], 6, mu)
    family = bottle_family(4, 1, 0)
    assert len(pool) >= 4 and {g["bottle"] for g in pool} <= {0, 1, 2, 3}
    for g in pool:
        b = Bottle(family[g["bottle"]])
        z = g["height_fraction"] * family[g["bottle"]].height
        p1, p2, axis = (np.asarray(g[k]) for k in ("p1", "p2", "axis"))
        assert p1[2] == pytest.approx(z) and p2[2] == pytest.approx(z) and axis[2] == 0.0
        # on the exact wall to the mesh's chord error (1.5 mm edges on a ~35 mm radius: < 0.1 mm)
        d, n = b.signed_distance(np.vstack([p1, p2]))
        assert np.abs(d).max() < 1e-4
        # the line passes through the section's centre
        centre = np.r_[b.section(z)[0], z]
        off = (centre - p1) - ((centre - p1) @ axis) * axis
        assert np.linalg.norm(off) < 1e-9
        # both exact wall normals inside the friction cone (the mesh's facets decided; 1 deg slack)
        half = np.arctan(mu) + np.radians(1.0)
        assert np.arccos(-n[0] @ axis) <= half and np.arccos(n[1] @ axis) <= half


def test_pool_refuses_bad_heights_and_an_empty_cone():
    with pytest.raises(ValueError, match="height_fractions"):
        bottle_grasp_pool(2, 0, 0, [0.5, 30.0], 4, 0.3)
    with pytest.raises(ValueError, match="raise mu"):
        bottle_grasp_pool(2, 0, 0, [0.5], 2, 1e-4)


def test_careless_frames_wrenches_and_families_are_refused():
    R = grasp_frame([1.0, 0, 0])
    with pytest.raises(ValueError, match="must be a rotation"):
        wrenches_to_object(np.zeros((1, 6)), 2 * np.eye(3), [0, 0, 0.1])  # a scaled frame
    with pytest.raises(ValueError, match=r"\(n, 6\)"):
        wrenches_to_object(np.zeros((2, 3)), R, [0, 0, 0.1])  # forces without torques
    with pytest.raises(ValueError, match="centre"):
        wrenches_to_object(np.zeros((1, 6)), R, [0, 120.0, 0])  # millimetres: 120 m from the origin
    with pytest.raises(ValueError, match="axis must be a non-zero finite"):
        grasp_frame([0.0, 0, 0])
    with pytest.raises(ValueError, match="family_seed"):
        bottle_grasp_pool(2, 0, -1, [0.5], 4, 0.3)
    with pytest.raises(ValueError, match="n_asymmetric"):
        bottle_grasp_pool(2, 3, 0, [0.5], 4, 0.3)

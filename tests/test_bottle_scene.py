"""The bottle-family grasp scene: its grasp frame, the wrench move into the object frame (against
a point force built in both frames), the pool's grasps against the exact wall, and a seed's draw
of grasps from the pool (distinct, the seed's second stream, its wrenches moved back by hand)."""

import numpy as np
import pytest

from workbench.fem.bottle import Bottle, bottle_family
from workbench.sources.bottle_scene import (
    bottle_grasp_pool,
    draw_pool_grasps,
    grasp_frame,
    wrenches_to_object,
)


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


def _toy_pool(n: int) -> list[dict]:
    """n horizontal grasps at heights 5-15 cm with centres off the bottle's axis (the draw
    reads only ``axis`` and ``center``)."""
    rng = np.random.default_rng(7)
    angles = rng.uniform(0, np.pi, n)
    axes = np.c_[np.cos(angles), np.sin(angles), np.zeros(n)]
    centres = np.c_[0.003 * rng.normal(size=(n, 2)), rng.uniform(0.05, 0.15, n)]
    return [{"axis": a, "center": c} for a, c in zip(axes, centres, strict=True)]


def test_a_draw_is_distinct_pool_grasps_of_the_seeds_second_stream():
    pool = _toy_pool(12)
    W = np.random.default_rng(0).normal(size=(5, 6))
    idx, W_obj = draw_pool_grasps(pool, W, seed=4)
    assert idx.shape == (5,) and W_obj.shape == (5, 6)
    assert len(set(idx.tolist())) == 5 and ((idx >= 0) & (idx < 12)).all()  # no repeats
    # the stream [seed, 1], not the seed's own (which drew the disturbances)
    assert idx.tolist() == np.random.default_rng([4, 1]).choice(12, 5, replace=False).tolist()
    assert idx.tolist() != np.random.default_rng(4).choice(12, 5, replace=False).tolist()
    # the grasps depend on the seed, n and the pool's size, not on the wrenches
    assert draw_pool_grasps(pool, 3 * W, seed=4)[0].tolist() == idx.tolist()
    assert draw_pool_grasps(pool, W, seed=5)[0].tolist() != idx.tolist()
    # drawing the whole pool takes every grasp once
    whole, _ = draw_pool_grasps(pool, np.zeros((12, 6)), seed=4)
    assert sorted(whole.tolist()) == list(range(12))


def test_a_draws_wrenches_move_back_to_their_grasp_frames():
    """By hand, the inverse of the move: f_g = R f_o, τ_g = R (τ_o − c × f_o) with R and c of
    the grasp each wrench was drawn for."""
    pool = _toy_pool(9)
    W = np.random.default_rng(1).normal(size=(6, 6)) * [5, 5, 5, 0.2, 0.2, 0.2]
    idx, W_obj = draw_pool_grasps(pool, W, seed=0)
    for w, w_o, k in zip(W, W_obj, idx, strict=True):
        R, c = grasp_frame(pool[k]["axis"]), pool[k]["center"]
        f_o, tau_o = w_o[:3], w_o[3:]
        assert R @ f_o == pytest.approx(w[:3], abs=1e-12)
        assert R @ (tau_o - np.cross(c, f_o)) == pytest.approx(w[3:], abs=1e-12)
        # the object-frame wrench differs from the grasp-frame one (the grasps are turned and off-origin)
        assert not np.allclose(w_o, w)


def test_a_draw_refuses_more_grasps_than_the_pool_and_bad_wrenches():
    pool = _toy_pool(3)
    with pytest.raises(ValueError, match="without repeats from a pool of 3"):
        draw_pool_grasps(pool, np.zeros((4, 6)), seed=0)
    with pytest.raises(ValueError, match=r"\(n, 6\)"):
        draw_pool_grasps(pool, np.zeros((2, 3)), seed=0)
    with pytest.raises(ValueError, match="seed must be an integer"):
        draw_pool_grasps(pool, np.zeros((2, 6)), seed=-1)

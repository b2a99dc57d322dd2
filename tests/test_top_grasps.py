"""workbench.grasp.top_grasps: the top-grasp pose against its closed form, Fig 4.8's two axis
definitions against the analytic height bands of a box, and the tilt, finger and prefix rules."""

import numpy as np
import pytest
import trimesh

from workbench.grasp.top_grasps import (
    TopGraspSpec,
    finger_boxes,
    sample_top_grasps,
    top_grasp_pose,
    top_grasps,
)
from workbench.plausible import ImplausibleWarning
from workbench.sources.gripper import yumi

GRIPPER = yumi()


def _centroid(poly):
    """The area centroid of a simple polygon, by triangle fan (independent of the shoelace sum)."""
    a, tot, acc = poly[0], 0.0, np.zeros(2)
    for b, c in zip(poly[1:-1], poly[2:], strict=True):
        area = 0.5 * ((b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0])
        tot += area
        acc += area * (a + b + c) / 3
    return acc / tot


def _side_grasps(heights, half_width=0.02):
    return [{"p1": np.array([0.0, -half_width, h]), "p2": np.array([0.0, half_width, h])} for h in heights]


def test_the_pose_puts_the_pads_bottom_or_centre_on_the_axis():
    p1, p2 = np.array([-0.02, 0.01, 0.03]), np.array([0.02, 0.0, 0.03])
    axis = (p2 - p1) / np.linalg.norm(p2 - p1)
    cx = _centroid(GRIPPER.pad.outline)[0]
    for axis_at, below in (("jaw_bottom", 0.0), ("centre", GRIPPER.pad.outline[:, 0].max() - cx)):
        jaws = GRIPPER.jaws(top_grasp_pose(p1, p2, GRIPPER, axis_at))
        for j in jaws:  # each pad's lowest point `below` the axis height; the pads close along it
            assert j.outline_points[:, 2].min() == pytest.approx(0.03 - below, abs=1e-12)
        assert np.allclose(jaws[0].closing, axis, atol=1e-12) and np.allclose(
            jaws[1].closing, -axis, atol=1e-12
        )
        # the two tooltips straddle the grasp centre as far apart as in the gripper's file
        mid = 0.5 * (jaws[0].origin + jaws[1].origin)
        apart = np.linalg.norm(GRIPPER.tooltips[1][:3, 3] - GRIPPER.tooltips[0][:3, 3])
        assert np.linalg.norm(jaws[1].origin - jaws[0].origin) == pytest.approx(apart, abs=1e-12)
        assert abs((mid - 0.5 * (p1 + p2)) @ axis) < 1e-12
    with pytest.raises(ValueError, match="vertical"):
        top_grasp_pose([0, 0, 0], [0, 0, 0.03], GRIPPER)


def test_fig_4_8_the_jaw_bottom_axis_keeps_the_grasps_low_on_a_flat_box():
    """Grasps across a 40 mm wide box at heights h: the jaw-bottom axis keeps h >= clearance,
    the centre axis h >= clearance + (the pad's bottom - its area centroid)."""
    spec = TopGraspSpec(table_clearance=0.005)
    heights = np.linspace(0.0005, 0.0195, 39)
    drop = GRIPPER.pad.outline[:, 0].max() - _centroid(GRIPPER.pad.outline)[0]
    for axis_at, threshold in (("jaw_bottom", 0.005), ("centre", 0.005 + drop)):
        kept = top_grasps(_side_grasps(heights), GRIPPER, TopGraspSpec(axis_at=axis_at))
        assert [g["p1"][2] for g, _ in kept] == [h for h in heights if h >= threshold - 1e-12], axis_at
        assert kept.dropped["table"] == sum(h < threshold - 1e-12 for h in heights)
    assert spec.table_clearance == 0.005


def test_tilt_and_finger_rules():
    tilt = np.radians([9.9, 10.1])
    grasps = [
        {
            "p1": np.array([0.0, -0.02, 0.03]),
            "p2": np.array([0.0, 0.04 * np.cos(t) - 0.02, 0.03 + 0.04 * np.sin(t)]),
        }
        for t in tilt
    ]
    kept = top_grasps(grasps, GRIPPER)
    assert len(kept) == 1 and kept.dropped["tilted"] == 1 and kept[0][0] is grasps[0]
    # a neighbour surface 1 mm behind the jaw's pad face is inside the finger box; 30 mm away it is not
    (g,) = _side_grasps([0.01])
    pose = top_grasp_pose(g["p1"], g["p2"], GRIPPER)
    face_y = -GRIPPER.opening / 2  # jaw 0's pad face at the open gripper
    behind = np.array([[0.0, face_y - 0.001, 0.012]])
    far = np.array([[0.0, face_y - 0.03, 0.012]])
    assert top_grasps([g], GRIPPER, surface=behind).dropped["finger"] == 1
    assert len(top_grasps([g], GRIPPER, surface=far)) == 1
    # the box's corners: its depth behind the face is the pad's layer plus the finger's thickness
    boxes = finger_boxes(GRIPPER, pose, TopGraspSpec())
    ys = boxes[0][:, 1]
    assert ys.max() == pytest.approx(face_y, abs=1e-12)
    assert ys.min() == pytest.approx(face_y - GRIPPER.pad.thickness - 0.01, abs=1e-12)


def test_sampled_top_grasps_grow_by_prefix_and_keep_more_with_the_jaw_bottom_axis():
    box = trimesh.creation.box([0.08, 0.04, 0.02])
    box.apply_translation([0.0, 0.0, 0.01])
    small = sample_top_grasps(box, 4, 0.5, GRIPPER, seed=3, block=400)
    large = sample_top_grasps(box, 12, 0.5, GRIPPER, seed=3, block=400)
    assert [g["p1"].tolist() for g, _ in large[:4]] == [g["p1"].tolist() for g, _ in small]
    for g, _ in large:  # horizontal within 10 deg, the pads above the table's clearance
        axis = g["p2"] - g["p1"]
        assert abs(axis[2]) / np.linalg.norm(axis) <= np.sin(np.radians(10)) + 1e-12
    centre = sample_top_grasps(box, 12, 0.5, GRIPPER, TopGraspSpec(axis_at="centre"), seed=3, block=400)
    per_candidate = {k: len(v) / v.n_candidates for k, v in (("bottom", large), ("centre", centre))}
    assert per_candidate["bottom"] > 3 * per_candidate["centre"]


def test_the_spec_refuses_careless_values():
    for kwargs, match in (
        ({"axis_at": "bottom"}, "axis_at must be one of"),
        ({"max_tilt_deg": 100}, r"max_tilt_deg must be an angle in \[0, 90\]"),
        ({"table_clearance": 5.0}, "table_clearance .* probably in millimetres"),
        ({"finger": (0.01,)}, r"finger must be \(thickness, length\)"),
    ):
        with pytest.raises(ValueError, match=match):
            TopGraspSpec(**kwargs)
    with pytest.raises(ValueError, match="n must be an integer >= 1"):
        sample_top_grasps(trimesh.creation.box([0.03] * 3), 0, 0.5, GRIPPER)
    # found by a new-user trial: raw AttributeErrors, an object below or above the table, degrees
    # typed in radians
    box = trimesh.creation.box([0.03] * 3)  # centred: half of it under the table
    with pytest.raises(
        ValueError, match=r"must rest on the table z = 0 .*mesh.apply_translation\(\(0, 0, 0.015\)\)"
    ):
        sample_top_grasps(box, 5, 0.5, GRIPPER)
    box.apply_translation([0, 0, 0.015])
    with pytest.raises(ValueError, match="gripper must be a workbench.sources.gripper.Gripper"):
        sample_top_grasps(box, 5, 0.5, None)
    with pytest.raises(ValueError, match=r"spec must be .*TopGraspSpec \(or None: its defaults\); got dict"):
        sample_top_grasps(box, 5, 0.5, GRIPPER, {"axis_at": "centre"})
    with pytest.raises(ValueError, match="seed must be an integer >= 0"):
        sample_top_grasps(box, 5, 0.5, GRIPPER, seed=-1)
    with pytest.raises(ValueError, match=r"surface must be .* \(n, 3\)"):
        top_grasps([], GRIPPER, surface=np.zeros((5, 2)))
    with pytest.raises(ValueError, match="table_z must be the table's height"):
        top_grasps([], GRIPPER, table_z=float("nan"))
    with pytest.warns(ImplausibleWarning, match=r"is it in radians \(0.17 rad = 9.74 deg\)"):
        TopGraspSpec(max_tilt_deg=0.17)
    with pytest.raises(ValueError, match="must be an approach distance in"):
        TopGraspSpec(approach_dist=100)


def test_a_grasp_whose_pads_find_no_surface_is_dropped_not_kept_as_a_miss():
    # a 40 mm wide, 20 mm tall box: with the jaw-bottom axis each pad reaches up from the axis,
    # so at 10 mm it presses the side face, at 0.05 mm below the top edge it meets only a strip
    # no sub-triangle centre lies in (1 mm subdivision: centres at least ~0.1 mm inside an edge)
    box = trimesh.creation.box([0.08, 0.04, 0.02])
    box.apply_translation([0.0, 0.0, 0.01])
    grasps = _side_grasps([0.010, 0.02 - 5e-5])
    without = top_grasps(grasps, GRIPPER)
    kept = top_grasps(grasps, GRIPPER, mesh=box)
    assert len(without) == 2 and without.dropped["pad"] == 0
    assert len(kept) == 1 and kept[0][0] is grasps[0] and kept.dropped["pad"] == 1

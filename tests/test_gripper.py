"""workbench.sources.gripper: the YuMi of the REACH trials, its pad, its jaws, careless input."""

import dataclasses

import numpy as np
import pytest
import trimesh

from workbench.sources.gripper import (
    DATA_DIR,
    PadShape,
    check_rigid,
    gripper_from_yaml,
    points_in_polygon,
    yumi,
)
from workbench.sources.jaws import jaw_frame


def _pose(angle=0.7, axis=(1.0, 2.0, -0.5), t=(0.01, -0.02, 0.17)):
    T = trimesh.transformations.rotation_matrix(angle, axis)
    T[:3, 3] = t
    return T


def _cap(mesh, sign):
    """Area and area-weighted centroid (x, y) of the faces of ``mesh`` facing ``sign``·z."""
    front = mesh.face_normals[:, 2] * sign > 0.99
    a = mesh.area_faces[front]
    return a.sum(), (a[:, None] * mesh.triangles_center[front][:, :2]).sum(0) / a.sum()


def test_yumi_polygon_pad_area_and_centroid_by_hand():
    """The six-vertex pad of area_contact_generator.yaml: a 2.25 × 2 cm rectangle (x ∈ [-1.75, 0.5])
    plus a trapezoid (x ∈ [0.5, 1], width 2 → 1 cm): 4.5 + 0.75 = 5.25 cm², centroid
    x = (4.5·(-0.625) + 0.75·(0.5 + 1/6 / 0.75)) / 5.25 cm."""
    g = yumi()
    assert g.pad.area == pytest.approx(5.25e-4, rel=1e-12)
    xc = (4.5 * -0.625 + 0.75 * (0.5 + (0.25 - 2 * 0.125 / 3) / 0.75)) / 5.25 * 1e-2
    np.testing.assert_allclose(g.pad.centroid, [xc, 0.0], atol=1e-15)
    assert xc == pytest.approx(-4.3254e-3, abs=1e-7)
    np.testing.assert_allclose(g.pad.extent, [0.0275, 0.02], rtol=1e-12)
    assert g.pad.thickness == 0.003 and g.pad.stiffness == pytest.approx(1e6 / 0.003)
    assert (g.force, g.mu, g.opening, g.stroke) == (20.0, 0.3, 0.05, 0.025)
    assert g.finger_mesh.is_file() and g.name == "yumi_metal_spline"
    assert not g.pad.outline.flags.writeable and not g.tooltips.flags.writeable
    assert g.pad.area > 0  # stored counter-clockwise


def test_round_pad_mesh_against_its_triangles():
    """PadShape.from_mesh(round_pad.obj) against trimesh's face areas and area-weighted centres of
    either cap: the pad is 27.5 × 20 mm in the tooltip (x, y) plane, z ∈ [-3, 0] mm (its contact face
    at z = 0), the rounded end (a 16-segment half-disc of radius 10 mm) at +x."""
    mesh = trimesh.load(DATA_DIR / "round_pad.obj", force="mesh")
    np.testing.assert_allclose(mesh.bounds, [[-0.0175, -0.01, -0.003], [0.01, 0.01, 0.0]], atol=1e-12)
    pad = PadShape.from_mesh(mesh)
    for sign in (1, -1):
        area, centroid = _cap(mesh, sign)
        assert pad.area == pytest.approx(area, rel=1e-12)
        np.testing.assert_allclose(pad.centroid, centroid, atol=1e-12)
    # by hand: 1.75 × 2 cm rectangle + 16-gon half-disc 8 sin(π/16) cm² (the file's 8 decimals: 4e-8)
    half = 8 * np.sin(np.pi / 16)
    assert pad.area == pytest.approx((3.5 + half) * 1e-4, rel=1e-7)
    assert pad.thickness == pytest.approx(0.003)
    assert pad.outline[:, 0].max() == pytest.approx(0.01)  # the round end at +x
    # the YAML polygon approximates it: 3.6 % more area, centroid 0.42 mm towards +x
    poly = yumi().pad
    assert poly.area / pad.area - 1 == pytest.approx(0.0374, abs=1e-4)
    assert poly.centroid[0] - pad.centroid[0] == pytest.approx(4.21e-4, abs=1e-6)
    assert yumi("mesh").pad.area == pytest.approx(pad.area)


def test_yaml_tooltip_frames():
    """Tooltip z points from its jaw to the other (the closing direction), tooltip x is the gripper's
    approach z, the tooltips at (∓0.025, ∓1.1e-5, 0.160098) m."""
    g = yumi()
    o, x, z = g.tooltips[:, :3, 3], g.tooltips[:, :3, 0], g.tooltips[:, :3, 2]
    np.testing.assert_allclose(o, [[-0.025, -0.000011, 0.160098], [0.025, 0.000011, 0.160098]])
    np.testing.assert_allclose(z, [[1, 0, 0], [-1, 0, 0]])
    np.testing.assert_allclose(x, [[0, 0, 1], [0, 0, 1]])


def test_jaws_map_the_pad_with_e1_minus_tooltip_y():
    """An asymmetric pad: each jaw's outline, placed with origin + a e1 + b e2, equals the pad's
    tooltip-frame vertices (x, y, 0) carried by pose @ tooltip; so (e1, e2) = (-y, x)."""
    pad = PadShape.rectangle(0.01, 0.02, offset=(0.003, 0.004))
    np.testing.assert_allclose(pad.centroid, [0.003, 0.004], atol=1e-15)
    assert pad.area == pytest.approx(2e-4)
    g = dataclasses.replace(yumi(), pad=pad)
    pose = _pose()
    for jaw, tip in zip(g.jaws(pose), g.tooltips, strict=True):
        W = pose @ tip
        ref = (W @ np.c_[pad.outline, np.zeros(4), np.ones(4)].T).T[:, :3]
        np.testing.assert_allclose(jaw.outline_points, ref, atol=1e-15)
        np.testing.assert_allclose(jaw.e1, -W[:3, 1], atol=1e-15)
        np.testing.assert_allclose(jaw.outline, np.c_[-pad.outline[:, 1], pad.outline[:, 0]])
        a, e1, e2 = jaw_frame(jaw.closing, jaw.e2)
        np.testing.assert_array_equal(np.array([a, e1, e2]), np.array([jaw.closing, jaw.e1, jaw.e2]))
        np.testing.assert_allclose(jaw.e1, np.cross(jaw.e2, jaw.closing), atol=1e-15)
        assert jaw.stroke == 0.025
    j0, j1 = g.jaws(pose)
    np.testing.assert_allclose(j0.closing, -j1.closing, atol=1e-15)
    assert (j1.origin - j0.origin) @ j0.closing == pytest.approx(0.05)  # the jaws face each other


def test_points_in_polygon_against_matplotlib():
    from matplotlib.path import Path

    rng = np.random.default_rng(3)
    poly = np.array([[0, 0], [4, 0], [4, 3], [2, 1], [0, 3.0]])  # non-convex
    pts = rng.uniform(-1, 5, size=(5000, 2))
    np.testing.assert_array_equal(points_in_polygon(pts, poly), Path(poly).contains_points(pts))


# ------------------------------------------------------------------ careless input


def test_careless_pads():
    g = yumi()
    with pytest.raises(ValueError, match="millimetres.*0.001"):
        PadShape(g.pad.outline * 1000, 0.003, 1e6)
    with pytest.raises(ValueError, match="centimetres.*0.01"):
        PadShape(g.pad.outline * 100, 0.003, 1e6)
    with pytest.raises(ValueError, match="centimetres"):
        gripper_from_yaml(
            DATA_DIR / "yumi_metal_spline.yaml", DATA_DIR / "area_contact_generator.yaml", polygon_units="m"
        )
    with pytest.raises(ValueError, match="not a simple polygon"):
        PadShape([[0, 0], [0.01, 0.01], [0.01, 0], [0, 0.01]], 0.003, 1e6)  # a bow tie
    with pytest.raises(ValueError, match="zero area"):
        PadShape([[0, 0], [0.01, 0], [0.02, 0]], 0.003, 1e6)
    with pytest.raises(ValueError, match="at least 3"):
        PadShape([[0, 0], [0.01, 0], [0, 0]], 0.003, 1e6)
    with pytest.raises(ValueError, match="non-finite"):
        PadShape([[0, 0], [0.01, np.nan], [0, 0.01]], 0.003, 1e6)
    with pytest.raises(ValueError, match="millimetres"):
        PadShape(g.pad.outline, 3.0, 1e6)
    with pytest.raises(ValueError, match="MPa"):
        PadShape(g.pad.outline, 0.003, 1.0)
    turned = trimesh.load(DATA_DIR / "round_pad.obj", force="mesh")
    turned.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    with pytest.raises(ValueError, match="not flat"):
        PadShape.from_mesh(turned)


def test_careless_poses():
    g = yumi()
    pose = _pose()
    mm = pose.copy()
    mm[:3, 3] *= 1000
    mm[:3, 3] += 10  # a pose in millimetres
    with pytest.raises(ValueError, match="millimetres"):
        g.jaws(mm)
    scaled = pose.copy()
    scaled[:3, :3] *= 1000
    with pytest.raises(ValueError, match="not rigid.*scaled by 1000"):
        g.jaws(scaled)
    sheared = pose.copy()
    sheared[0, 1] += 0.01
    with pytest.raises(ValueError, match="not orthonormal"):
        g.jaws(sheared)
    with pytest.raises(ValueError, match="reflection"):
        g.jaws(pose @ np.diag([1, 1, -1, 1.0]))
    with pytest.raises(ValueError, match="transposed"):
        g.jaws(pose.T)
    with pytest.raises(ValueError, match="4×4"):
        g.jaws(pose[:3])
    np.testing.assert_array_equal(check_rigid(pose, "pose"), pose)


def test_careless_forces_and_friction():
    g = yumi()
    for bad in (0.0, -20.0, np.nan, np.inf, True):
        with pytest.raises(ValueError, match=r"jaw force in \(0, 500\] N|must be a number"):
            dataclasses.replace(g, force=bad)
    with pytest.raises(ValueError, match="millinewtons — pass 2 .*total force"):
        dataclasses.replace(g, force=2000.0)  # millinewtons, or a sum
    with pytest.raises(ValueError, match="more than any real jaw force"):
        dataclasses.replace(g, force=1e6)
    with pytest.raises(ValueError, match="probably in millinewtons — pass 20"):
        dataclasses.replace(g, force=20000.0)
    assert g.with_total_force(40.0).force == 20.0
    with pytest.raises(ValueError, match="probably in per cent — pass 0.3"):
        dataclasses.replace(g, mu=30.0)
    with pytest.raises(ValueError, match="> 0.*holds nothing"):
        dataclasses.replace(g, mu=0.0)
    for bad in (-0.3, 2.5):
        with pytest.raises(ValueError, match=r"\[0, 2\]"):
            dataclasses.replace(g, mu=bad)
    assert dataclasses.replace(g, mu=None).mu is None


def test_careless_tooltips():
    g = yumi()
    swapped = g.tooltips.copy()
    swapped[0, :3, 3], swapped[1, :3, 3] = g.tooltips[1, :3, 3], g.tooltips[0, :3, 3]
    with pytest.raises(ValueError, match="swapped tooltips"):
        dataclasses.replace(g, tooltips=swapped)
    # both whole poses exchanged is only a relabelling: still a valid gripper
    assert dataclasses.replace(g, tooltips=g.tooltips[::-1]).opening == 0.05
    with pytest.raises(ValueError, match="farther than the opening"):
        dataclasses.replace(g, opening=0.04)
    parallel = g.tooltips.copy()
    parallel[1] = g.tooltips[0]
    parallel[1, :3, 3] = g.tooltips[1, :3, 3]
    with pytest.raises(ValueError, match="opposite"):
        dataclasses.replace(g, tooltips=parallel)
    mm = g.tooltips.copy()
    mm[:, :3, 3] *= 1000
    with pytest.raises(ValueError, match="millimetres"):
        dataclasses.replace(g, tooltips=mm)
    with pytest.raises(ValueError, match=r"\(2, 4, 4\)"):
        dataclasses.replace(g, tooltips=g.tooltips[:1])
    with pytest.raises(ValueError, match="millimetres"):
        dataclasses.replace(g, opening=50.0)


def test_parallel_jaw_puts_the_open_jaws_on_the_gripper_x_axis_closing_towards_each_other():
    from workbench.sources.gripper import PadShape, parallel_jaw

    g = parallel_jaw(PadShape.rectangle(0.02, 0.04, thickness=0.005), 20.0, opening=0.1, mu=0.3)
    assert (g.opening, g.force, g.mu) == (0.1, 20.0, 0.3)
    T = np.eye(4)
    T[:3, 3] = [0.01, 0.02, 0.03]
    j0, j1 = g.jaws(T)
    np.testing.assert_allclose(j0.origin, [-0.04, 0.02, 0.03], atol=1e-15)
    np.testing.assert_allclose(j1.origin, [0.06, 0.02, 0.03], atol=1e-15)
    np.testing.assert_allclose(j0.closing, [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(j1.closing, [-1, 0, 0], atol=1e-15)
    # the pad's length (tooltip x) along the approach, gripper z: 40 mm tall, 20 mm wide
    for j in (j0, j1):
        pts = j.outline_points
        assert np.ptp(pts[:, 2]) == pytest.approx(0.04) and np.ptp(pts[:, 1]) == pytest.approx(0.02)
    with pytest.raises(ValueError, match="opening"):
        parallel_jaw(PadShape.rectangle(0.02, 0.04), 20.0, opening=100.0)

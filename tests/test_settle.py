"""The object settled between the jaws (workbench.grasp.settle): a cube gripped a few degrees off
square turns until both pads lie flat on its faces (analytic: the turn equals the jaws' tilt,
the patch is the whole pad with uniform pressure, the pressure centres on one line along the
closing axis), where each pad pressed alone touches a strip at its edge."""

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from workbench.grasp.gripper_eval import gripper_contact
from workbench.grasp.settle import normal_torque, settle_contact, turned_jaw
from workbench.sources.gripper import Gripper, PadShape

HALF = 0.015  # the cube's half side [m]
PAD = 0.01  # square pad side [m]


def _gripper(force: float = 20.0) -> Gripper:
    # tooltip frames in the gripper frame: z (closing) towards the other jaw, x = gripper z
    t1 = np.eye(4)
    t1[:3, :3] = [[0, 0, 1], [0, -1, 0], [1, 0, 0]]
    t1[:3, 3] = [-0.025, 0, 0]
    t2 = np.eye(4)
    t2[:3, :3] = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]
    t2[:3, 3] = [0.025, 0, 0]
    return Gripper("test", np.array([t1, t2]), PadShape.rectangle(PAD, PAD), force, mu=0.5, opening=0.05)


def _pose(tilt_deg: float = 0.0, shift=(0.0, 0.0, 0.0)) -> np.ndarray:
    T = np.eye(4)
    # a turn about the gripper's y axis, normal to the closing axis (gripper x)
    T[:3, :3] = Rotation.from_euler("y", tilt_deg, degrees=True).as_matrix()
    T[:3, 3] = shift
    return T


@pytest.fixture(scope="module")
def cube():
    return trimesh.creation.box((2 * HALF,) * 3)


def test_a_tilted_grasp_settles_flush(cube):
    c = gripper_contact(cube, _gripper(), _pose(5.0))
    assert c.touches and c.converged
    # the gripper turns back by the tilt: the pads end flat on the faces
    assert abs(np.degrees(c.tilt) - 5.0) < 0.05
    for prof in c.profiles:
        # the whole pad presses (polygon area 1e-4 m² to the 1 mm footprint discretisation)
        assert abs(prof.areas.sum() - PAD**2) / PAD**2 < 0.05
        p = prof.pressures
        assert p.std() / p.mean() < 0.02  # uniform: a flat face under a parallel rigid pad
        np.testing.assert_allclose(abs(prof.normal_wrench[0]), 20.0, rtol=1e-9)
    # both pressure centres on one line along the closing axis (no couple left)
    d = c.profiles[0].pressure_center - c.profiles[1].pressure_center
    axis = c.jaws[0].closing
    assert np.linalg.norm(d - (d @ axis) * axis) < 1e-4
    assert c.torque <= 1e-3


def test_pressed_jaw_by_jaw_touches_only_a_strip(cube):
    force, tilt = 2.0, np.radians(5.0)
    c = gripper_contact(cube, _gripper(force=force), _pose(5.0), settle=False)
    assert c.touches and c.tilt == 0.0
    # each tilted pad, pressed until its force along the closing axis is 2 N, meets the face in a
    # wedge along its edge: F = k L w² tan(t) / 2 (Winkler, pressure k × depth along the axis)
    k = _gripper().pad.stiffness
    w = np.sqrt(2 * force / (k * PAD * np.tan(tilt)))  # 3.7 mm of the 10 mm pad
    for p, jaw in zip(c.profiles, c.jaws, strict=True):
        assert abs(p.areas.sum() - w * PAD) / (w * PAD) < 0.05  # 1 mm elements across 3.7 mm
        np.testing.assert_allclose(abs(p.normal_wrench[:3] @ jaw.closing), force, rtol=1e-9)
    # the two strips' centres are apart sideways: a couple no free object holds still under
    d = c.profiles[0].pressure_center - c.profiles[1].pressure_center
    axis = c.jaws[0].closing
    assert np.linalg.norm(d - (d @ axis) * axis) > 2e-3
    assert c.torque > 0.05


def test_a_pad_pressed_to_its_force_on_a_cylinder_matches_the_line_contact():
    # a rigid flat Winkler pad pressed on a cylinder's side (radius R, the pad's length L along
    # the axis): h(x) = x²/2R behind first touch, so F = k L ∫ (d − x²/2R) dx over |x| < a = √(2Rd)
    # = (2/3) k L a³ / R: a band 2a = 2 (3 F R / 2 k L)^(1/3) wide, pressed d = a²/2R
    R, force = 0.02, 5.0
    cyl = trimesh.creation.cylinder(radius=R, height=0.1, sections=720)
    g = _gripper(force=force)
    L = PAD
    # the closing axis along the object's x, the pads' length along the cylinder's axis (z)
    c = gripper_contact(cyl, g, np.eye(4), settle=False, max_edge=2.5e-4)
    k = g.pad.stiffness
    a = (3 * force * R / (2 * k * L)) ** (1 / 3)  # 3.6 mm: the band lies inside the 10 mm pad
    band, d = 2 * a, a**2 / (2 * R)
    for p, depth in zip(c.profiles, c.depths, strict=True):
        assert abs(p.areas.sum() - band * L) / (band * L) < 0.03
        assert abs(depth - d) / d < 0.05


def test_a_square_grasp_needs_no_turn(cube):
    c = gripper_contact(cube, _gripper(), _pose(0.0))
    assert c.converged and np.degrees(c.tilt) < 1e-3


def test_a_pad_beside_the_object_is_a_miss_not_an_error(cube):
    c = gripper_contact(cube, _gripper(), _pose(0.0, shift=(0.0, 0.05, 0.0)))
    assert not c.touches and "touches nothing" in c.reason


def test_turned_jaw_is_a_rigid_motion(cube):
    jaw = _gripper().jaws(_pose(3.0))[0]
    R = Rotation.from_rotvec([0.1, -0.2, 0.05]).as_matrix()
    p = np.array([0.001, 0.002, -0.003])
    t = turned_jaw(jaw, R, p)
    np.testing.assert_allclose(t.origin - p, R @ (jaw.origin - p), atol=1e-15)
    np.testing.assert_allclose(np.cross(t.e2, t.closing), t.e1, atol=1e-12)
    # the unchecked fast path builds what the checked constructor builds from the moved vectors
    from workbench.sources.gripper import Jaw

    checked = Jaw(t.origin, t.closing, t.e1, t.e2, jaw.outline, jaw.stroke, jaw.stiffness)
    for name in ("origin", "closing", "e1", "e2", "outline"):
        np.testing.assert_array_equal(getattr(t, name), getattr(checked, name))
        assert not getattr(t, name).flags.writeable


def test_normal_torque_of_two_opposed_offset_patches():
    # two unit forces ±x through (0, ±h, 0): a couple of 2 h about z (by hand)
    from workbench.profile import ContactProfile

    h = 0.01
    a = ContactProfile([[-0.01, h, 0]], [[-1.0, 0, 0]], [1e-4], [1e4])  # pushes +x with 1 N
    b = ContactProfile([[0.01, -h, 0]], [[1.0, 0, 0]], [1e-4], [1e4])  # pushes -x with 1 N
    np.testing.assert_allclose(normal_torque([a, b], np.zeros(3)), [0, 0, -2 * h], atol=1e-15)


def test_settle_refuses_a_bad_force(cube):
    jaws = _gripper().jaws(_pose())
    for bad in (-1.0, 0.0, np.nan):
        with pytest.raises(ValueError, match="force"):
            settle_contact(jaws, lambda j: None, bad)

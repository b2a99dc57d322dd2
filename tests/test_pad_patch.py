"""The pad's reachable surface (workbench.sources.pad_patch) and the settle's torque Jacobian
(workbench.grasp.settle): each against a slow reference (bisection, the whole fine surface,
central differences) or a closed form."""

import numpy as np
import pytest
import trimesh
from naive import front_surface
from scipy.spatial.transform import Rotation

from workbench.grasp.settle import torque_jacobian
from workbench.sources import reach
from workbench.sources.gripper import Gripper, PadShape
from workbench.sources.pad_patch import PadPatch


def _random_patch(rng, m=200, k=2e8):
    axis = np.array([0.0, 0.0, 1.0])
    n = rng.normal(size=(m, 3)) * 0.3 + [0, 0, -1.0]
    n /= np.linalg.norm(n, axis=1)[:, None]
    z = rng.uniform(0, 2e-3, m)
    z[rng.integers(m)] = 0.0
    centers, areas = rng.uniform(-0.01, 0.01, (m, 3)), rng.uniform(1e-7, 1e-6, m)
    return PadPatch(centers, n, areas, z + 0.004, 0.004, axis, k)


def test_depth_for_force_inverts_the_axis_force_like_a_bisection():
    rng = np.random.default_rng(0)
    for _ in range(20):
        p = _random_patch(rng)
        force = rng.uniform(0.5, 40.0)
        lo, hi = 0.0, 1.0  # slow reference: bisection on the monotone axis force
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if p.axis_force(mid) < force else (lo, mid)
        d = p.depth_for_force(force)
        assert abs(d - 0.5 * (lo + hi)) <= 1e-12 + 1e-9 * d
        assert abs(p.axis_force(d) - force) <= 1e-9 * force


def test_a_flat_patch_is_pressed_by_force_over_stiffness_and_area():
    # m equal elements square to the axis at the first touch: F = k d Σ a
    m, a, k, f = 50, 2e-7, 3e8, 12.0
    normals = np.tile([0.0, 0.0, -1.0], (m, 1))
    p = PadPatch(np.zeros((m, 3)), normals, np.full(m, a), np.zeros(m), 0.0, [0, 0, 1.0], k)
    assert p.depth_for_force(f) == pytest.approx(f / (k * m * a), rel=1e-12)
    prof = p.profile(p.depth_for_force(f))
    np.testing.assert_allclose(prof.pressures, f / (m * a), rtol=1e-12)


def _gripper(force=10.0):
    t1, t2 = np.eye(4), np.eye(4)
    t1[:3, :3] = [[0, 0, 1], [0, -1, 0], [1, 0, 0]]
    t1[:3, 3] = [-0.04, 0, 0]
    t2[:3, :3] = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]
    t2[:3, 3] = [0.04, 0, 0]
    return Gripper("t", np.array([t1, t2]), PadShape.rectangle(0.02, 0.03), force, mu=0.5, opening=0.08)


def _slow_pad_profile(mesh, jaw, closing, k, max_edge=1e-3):
    """pad_profile's geometry on the whole fine surface (no index): every sub-triangle tested by
    NumPy (tests/naive.py)."""
    cen, normal, area = reach.fine_surface(mesh, max_edge)
    rel = cen - jaw.origin
    u, v, z = rel @ jaw.e1, rel @ jaw.e2, rel @ jaw.closing
    (u_lo, v_lo), (u_hi, v_hi) = jaw.outline.min(axis=0), jaw.outline.max(axis=0)
    near = (u >= u_lo - max_edge) & (u <= u_hi + max_edge) & (v >= v_lo - max_edge) & (v <= v_hi + max_edge)
    near &= (z >= -jaw.stroke) & (z <= jaw.stroke)
    cen, normal, area = cen[near], normal[near], area[near]
    frame = (jaw.closing, jaw.e1, jaw.e2)
    window = (-jaw.stroke, jaw.stroke)
    visible, z = front_surface(
        cen, normal, area, jaw.origin, frame, None, jaw.outline, window, True, max_edge, 0.1
    )
    patch = PadPatch(
        cen[visible], normal[visible], area[visible], z[visible], z[visible].min(), jaw.closing, k
    )
    return patch.profile(closing)


def test_pad_profile_through_the_index_equals_the_whole_surface_bit_for_bit():
    mesh = trimesh.creation.capsule(height=0.05, radius=0.02, count=[48, 48])
    g = _gripper()
    rng = np.random.default_rng(2)
    for _ in range(8):
        T = np.eye(4)
        T[:3, :3] = Rotation.from_rotvec(rng.normal(0, 0.15, 3)).as_matrix()
        T[:3, 3] = rng.normal(0, 0.004, 3)
        for jaw in g.jaws(T):
            fast = reach.pad_profile(mesh, jaw, closing=5e-4)
            slow = _slow_pad_profile(mesh, jaw, 5e-4, jaw.stiffness)
            for name in ("centers", "normals", "areas", "pressures"):
                np.testing.assert_array_equal(getattr(fast, name), getattr(slow, name))


def test_pad_profile_takes_one_of_closing_and_force():
    mesh = trimesh.creation.box((0.03, 0.03, 0.03))
    jaw = _gripper().jaws(np.eye(4))[0]
    for kw in ({}, {"closing": 1e-4, "force": 5.0}):
        with pytest.raises(ValueError, match="one of closing"):
            reach.pad_profile(mesh, jaw, **kw)
    prof = reach.pad_profile(mesh, jaw, force=5.0)
    np.testing.assert_allclose(abs(prof.normal_wrench[:3] @ jaw.closing), 5.0, rtol=1e-12)


def test_the_settle_jacobian_matches_central_differences_on_a_smooth_contact():
    # an ellipsoid between the pads: a smooth contact whose torque changes with the turn
    mesh = trimesh.creation.icosphere(subdivisions=5, radius=1.0)
    mesh.apply_scale([0.02, 0.03, 0.045])
    g = _gripper(force=20.0)
    jaws = g.jaws(np.eye(4))
    pivot = 0.5 * (jaws[0].origin + jaws[1].origin)
    b = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])

    def at(theta):
        R = Rotation.from_rotvec(theta @ b).as_matrix()
        turned = [j.turned(R, pivot) for j in jaws]
        pats = [reach.pad_patch(mesh, j, max_edge=5e-4) for j in turned]
        depths = [p.depth_for_force(20.0) for p in pats]
        return torque_jacobian(pats, depths, [j.closing for j in turned], pivot, b)

    theta = np.array([0.03, -0.05])
    _, jac = at(theta)
    h = 2e-3
    fd = np.column_stack([(at(theta + h * e)[0] - at(theta - h * e)[0]) / (2 * h) for e in np.eye(2)])
    assert np.abs(jac - fd).max() <= 0.03 * np.abs(fd).max()

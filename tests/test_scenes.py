"""workbench.sources.scenes: the elliptic-cylinder grasp of thesis §4.1.3 — the pressure of
Eq. 4.3 at every element, the grasp-axis force equal to the reading, the elements on the
cylinder, the second jaw the first turned by π about z (the grasp in equilibrium), the patch's
extent (its chord 2 b sin(half_angle) by hand, the patch's own y span) and bad parameters."""

import numpy as np
import pytest

from workbench.sources.scenes import (
    elliptic_cylinder_contact,
    elliptic_cylinder_grasp,
    elliptic_cylinder_patch_extent,
    elliptic_cylinder_solid,
)

A, B, HALF, LENGTH, K, FORCE = 0.03, 0.02, 0.6, 0.03, 2.4, 25.0


@pytest.fixture(scope="module")
def jaws():
    return elliptic_cylinder_grasp(A, B, HALF, LENGTH, K, FORCE, n_elements=300)


def test_pressure_follows_eq_4_3_and_the_reading_is_the_force(jaws):
    """p ∝ [1 − (|y| / r_max)^k]^(1/k), r_max = b sin(half_angle), one factor for all elements
    (it sets Σ p a n_x = −F: the jaw at +x pushes the object along −x with the reading F).
    The pressure is taken at each triangle's parametric centroid: u_c the mean of its
    vertices' angles u = atan2(y / b, x / a), y = b sin u_c."""
    right = jaws[0]
    r_max = B * np.sin(HALF)
    V = right.vertices[right.faces]  # (T, 3 vertices, 3)
    u_c = np.arctan2(V[..., 1] / B, V[..., 0] / A).mean(axis=1)
    shape = (1 - (np.abs(B * np.sin(u_c)) / r_max) ** K) ** (1 / K)
    ratio = right.pressures / shape
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)
    assert (right.pressures * right.areas) @ right.normals[:, 0] == pytest.approx(FORCE, rel=1e-12)
    assert right.normal_wrench[0] == pytest.approx(-FORCE, rel=1e-12)


def test_elements_lie_on_the_cylinder_patch_with_outward_normals(jaws):
    """Triangle vertices on (x/a)² + (y/b)² = 1, |u| <= half_angle, |z| <= length/2; centroids
    of flat triangles just inside; normals point away from the axis (x > 0 side)."""
    right = jaws[0]
    V = right.vertices
    np.testing.assert_allclose((V[:, 0] / A) ** 2 + (V[:, 1] / B) ** 2, 1.0, rtol=1e-12)
    assert np.abs(np.arctan2(V[:, 1] / B, V[:, 0] / A)).max() == pytest.approx(HALF, rel=1e-12)
    assert np.abs(V[:, 2]).max() == pytest.approx(LENGTH / 2, rel=1e-12)
    inward = (right.centers[:, 0] / A) ** 2 + (right.centers[:, 1] / B) ** 2
    assert (inward < 1).all() and (inward > 0.99).all()
    # the outward ellipse normal at a centroid's angle: (x / a², y / b²) direction
    g = np.c_[right.centers[:, 0] / A**2, right.centers[:, 1] / B**2, np.zeros(len(right))]
    g /= np.linalg.norm(g, axis=1, keepdims=True)
    assert (np.einsum("ij,ij->i", right.normals, g) > 0.99).all()


def test_the_second_jaw_is_the_first_turned_about_z_and_the_grasp_balances(jaws):
    right, left = jaws
    R = np.diag([-1.0, -1.0, 1.0])
    np.testing.assert_allclose(left.centers, right.centers @ R.T, atol=1e-15)
    np.testing.assert_allclose(left.normals, right.normals @ R.T, atol=1e-15)
    np.testing.assert_array_equal(left.pressures, right.pressures)
    # the two normal wrenches about the origin cancel: −Σ p a n and −Σ p a c × n
    total = np.zeros(6)
    for p in jaws:
        f = -(p.pressures * p.areas)[:, None] * p.normals
        total += np.r_[f.sum(0), np.cross(p.centers, f).sum(0)]
    np.testing.assert_allclose(total, 0.0, atol=1e-12 * FORCE)
    # symmetric about y = 0 and z = 0: the pressure centre on the x axis
    np.testing.assert_allclose(right.pressure_center[1:], 0.0, atol=1e-12)


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"a": 0.0}, "a must be > 0"),
        ({"b": -0.02}, "b must be > 0"),
        ({"half_angle": np.nan}, "half_angle must be > 0"),
        ({"half_angle": np.pi / 2}, "half_angle must be < π/2"),
        ({"length": np.inf}, "length must be > 0"),
        ({"force": 0.0}, r"jaw force in \(0, 500\] N"),
    ],
)
def test_bad_parameters_are_refused(kw, match):
    args = {"a": A, "b": B, "half_angle": HALF, "length": LENGTH, "k": K, "force": FORCE, **kw}
    with pytest.raises(ValueError, match=match):
        elliptic_cylinder_contact(**args, n_elements=50)
    with pytest.raises(ValueError, match="k must be > 0"):
        elliptic_cylinder_contact(A, B, HALF, LENGTH, 0.0, FORCE, n_elements=50)


def test_patch_extent_is_the_chord_between_the_patch_edges_and_the_contact_length(jaws):
    width, length = elliptic_cylinder_patch_extent(A, B, HALF, LENGTH)
    # by hand: the edges u = ±0.6 sit at y = ±b sin 0.6 = ±0.02 × 0.5646425 m
    assert width == pytest.approx(2 * 0.02 * 0.5646424733950354, rel=1e-15)
    assert length == LENGTH
    # the chord of the two edge points [a cos u, ±b sin u], and the patch's own span across y
    edge = np.array([A * np.cos(HALF), B * np.sin(HALF)])
    assert width == pytest.approx(np.linalg.norm(edge - edge * [1, -1]), rel=1e-15)
    V = jaws[0].vertices
    assert V[:, 1].max() - V[:, 1].min() == pytest.approx(width, rel=1e-12)
    # the cut solid a pad of this size touches: its y and z spans are the patch's
    span = np.ptp(elliptic_cylinder_solid(A, B, HALF, LENGTH).vertices, axis=0)
    assert span[1:] == pytest.approx([width, length], rel=1e-12)
    # a wider wrap: as half_angle -> π/2 the chord tends to the full minor axis 2 b (sin 1.5 = 0.9975)
    assert elliptic_cylinder_patch_extent(A, B, 1.5, LENGTH)[0] == pytest.approx(2 * B, rel=3e-3)
    with pytest.raises(ValueError, match="probably in degrees"):
        elliptic_cylinder_patch_extent(A, B, 34.0, LENGTH)

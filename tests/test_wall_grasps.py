"""stiffness_at / grasp_pairs on a meshed tube: the same stiffness as a direct squeeze,
rigid and failed flags with their reasons, careless locations."""

import numpy as np
import pytest
import trimesh

from workbench.fem.mesh_wall import radial_surface
from workbench.fem.wall import build_wall, squeeze
from workbench.fem.wall_grasps import RIGID_STIFFNESS, grasp_pairs, stiffness_at


@pytest.fixture(scope="module")
def tube():
    m = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=128)
    m.apply_translation([0, 0, 0.05])
    surf = radial_surface(m, z_range=(0.005, 0.08))  # the top 20 mm left out: "rigid" there
    return surf, build_wall(surf, thickness=0.5e-3, n_theta=32, n_z=8, z_range=surf.z_range)


def _pair(z, r=0.03):
    return np.array([[r, 0.0, z], [-r, 0.0, z]])


@pytest.mark.jit_only("over 15 s as pure Python")
def test_stiffness_is_the_squeeze_at_the_midpoint(tube):
    surf, wall = tube
    a, b = _pair(0.06), _pair(0.04)
    locs = np.vstack([a[:1], b[:1], a[1:], b[1:]])  # points i and i + n form grasp i
    rows = stiffness_at(wall, surf, locs)
    for row, z in zip(rows, (0.06, 0.04), strict=True):
        ref = squeeze(wall, np.array([0.0, 0.0, z]), np.array([-1.0, 0.0, 0.0])).stiffness
        assert row["stiffness"] == pytest.approx(ref, rel=1e-9)
        assert not row["rigid"] and not row["failed"] and row["reason"] is None


def test_rigid_and_failed_grasps_are_flagged_not_fatal(tube):
    surf, wall = tube
    top = _pair(0.09)  # above the modelled wall
    tilted = np.array([[0.03, 0.0, 0.05], [-0.03, 0.0, 0.06]])
    base = _pair(0.01)  # the jaw footprint reaches the clamped rim: the jaw rests on it
    locs = np.vstack([top[:1], tilted[:1], base[:1], top[1:], tilted[1:], base[1:]])
    rows = stiffness_at(wall, surf, locs)
    assert rows[0]["rigid"] and rows[0]["stiffness"] == RIGID_STIFFNESS
    assert rows[1]["failed"] and "not horizontal" in rows[1]["reason"]
    assert (
        rows[2]["rigid"] and "clamped edge" in rows[2]["reason"] and rows[2]["stiffness"] == RIGID_STIFFNESS
    )
    assert not rows[2]["failed"]


@pytest.mark.jit_only("over 15 s as pure Python")
def test_non_antipodal_pairs_are_flagged_with_the_chord_angle(tube, caplog):
    """On a circle, a chord between points φ apart makes (180° − φ)/2 with both normals:
    φ = 180° is antipodal (0°), φ = 100° gives 40° (kept), φ = 60° gives 60° (> 45°: flagged,
    still squeezed, and logged)."""
    from workbench.fem.wall_grasps import axis_normal_angles

    surf, wall = tube
    r, z = 0.03, 0.05
    phis = np.radians([180.0, 100.0, 60.0])
    a = np.tile([r, 0.0, z], (3, 1))
    b = np.column_stack([r * np.cos(phis), r * np.sin(phis), np.full(3, z)])
    np.testing.assert_allclose(axis_normal_angles(surf, a, b), [0.0, 40.0, 60.0], atol=0.5)
    with caplog.at_level("WARNING", logger="workbench.fem.wall_grasps"):
        rows = stiffness_at(wall, surf, np.vstack([a, b]))
    assert [row["non_antipodal"] for row in rows] == [False, False, True]
    assert rows[2]["axis_normal_deg"] == pytest.approx(60.0, abs=0.5)
    assert not rows[2]["failed"] and np.isfinite(rows[2]["stiffness"])
    assert "grasp 2 is not antipodal" in caplog.text and "grasp 1 " not in caplog.text
    caplog.clear()
    with caplog.at_level("WARNING", logger="workbench.fem.wall_grasps"):  # the caller's grasp numbers
        stiffness_at(wall, surf, np.vstack([a[2:], b[2:]]), grasp_ids=[17])
    assert "grasp 17 is not antipodal" in caplog.text
    # two coincident jaw points: no axis, a failure that says so (not "no wall under a jaw")
    (row,) = stiffness_at(wall, surf, np.vstack([a[:1], a[:1]]))
    assert row["failed"] and "coincide" in row["reason"] and not row["non_antipodal"]


@pytest.mark.parametrize(
    "locs, match",
    [
        (np.zeros((3, 3)), "2n points"),
        (np.zeros((4, 2)), r"\(2n, 3\)"),
        (
            np.vstack([_pair(0.05)[:1] * [0.9, 1, 1], _pair(0.05)[1:]]),
            "location 0 .* off the object's surface.*-3.00 mm off it",
        ),
        (_pair(0.05) * 1000, "locations 0, 1 .2 of 2. lie outside the object.s box.*probably in millimetres"),
        (_pair(0.05) * [0.95, 1, 1], r"locations 0, 1 \(2 of 2\) lie off the object.s surface"),
    ],
)
def test_careless_locations_are_refused(tube, locs, match):
    surf, _ = tube
    with pytest.raises(ValueError, match=match):
        grasp_pairs(locs, surf)

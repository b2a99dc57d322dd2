"""The object as the engine collides it (workbench.engine_trials.collision): convex slabs of a
non-convex object against its analytic surface, a grasp at a waist that only the slabs reach, and
how deep points lie inside the pieces (collision_gap.surface_gap)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from workbench.engine_trials.collision import collision_pieces, convex_slabs
from workbench.engine_trials.collision_gap import surface_gap
from workbench.engine_trials.settings import EngineSettings


def _dumbbell(neck_r: float = 0.01, sections: int = 64):
    """Two discs (r 30 mm, 10 mm thick) joined by a neck (r ``neck_r``, 40 mm long), axis z."""
    prof = [[0, -0.03], [0.03, -0.03], [0.03, -0.02], [neck_r, -0.02], [neck_r, 0.02], [0.03, 0.02],
            [0.03, 0.03], [0, 0.03]]  # fmt: skip
    return trimesh.creation.revolve(np.array(prof), sections=sections)


def _hourglass(n_z: int = 61, sections: int = 96):
    """A revolved waist r(z) = 20 mm + 8 mm (z / 30 mm)², |z| <= 30 mm: slope |dr/dz| <= 0.53."""
    z = np.linspace(-0.03, 0.03, n_z)
    r = 0.02 + 0.008 * (z / 0.03) ** 2
    prof = np.vstack([[0.0, z[0]], np.column_stack([r, z]), [0.0, z[-1]]])
    return trimesh.creation.revolve(prof, sections=sections)


def test_the_slabs_follow_a_waist_to_within_thickness_times_slope():
    mesh = _hourglass()
    h = 0.004
    pieces = convex_slabs(mesh, [0.0, 0.0, 1.0], h)
    assert len(pieces) == 15  # 60 mm in slabs of at most 4 mm
    pts, _ = trimesh.sample.sample_surface(mesh, 2000, seed=0)
    # how deep a surface point lies inside the union (> 0: the union bridges over it)
    depth = np.max([trimesh.proximity.signed_distance(p, pts) for p in pieces], axis=0)
    slope = 2 * 0.008 / 0.03  # |dr/dz| = 2 (8 mm) z / (30 mm)² at |z| = 30 mm
    assert depth.max() <= h * slope * 1.05
    # the hull bridges the waist by r(30 mm) - r(0) = 8 mm
    hull_depth = trimesh.proximity.signed_distance(mesh.convex_hull, np.array([[0.02, 0.0, 0.0]]))
    assert hull_depth[0] == pytest.approx(0.008, rel=0.02)
    assert depth.max() < hull_depth[0] / 3


def test_a_convex_object_is_its_hull_and_slab_zero_keeps_the_hull():
    box = trimesh.creation.box((0.03, 0.04, 0.05))
    (piece,) = collision_pieces(box, [0, 0, -1], 5e-3)
    assert piece.volume == pytest.approx(box.volume)
    (hull,) = collision_pieces(_dumbbell(), [0, 0, -1], 0.0)
    assert hull.volume == pytest.approx(_dumbbell().convex_hull.volume)
    pieces = collision_pieces(_dumbbell(), [0, 0, -1], 5e-3)
    assert len(pieces) == 12
    # the slabs' volume: the discs and neck exactly, but the two slabs where the neck meets a
    # disc (a frustum spanning the step): between the solid and its hull
    vol = sum(p.volume for p in pieces)
    assert _dumbbell().volume < vol < _dumbbell().convex_hull.volume


@pytest.mark.parametrize("bad", [5, -1e-3, float("nan"), True])
def test_object_slab_refuses_millimetres_and_nonsense(bad):
    with pytest.raises(ValueError, match="object_slab must be a thickness"):
        EngineSettings(object_slab=bad)


def _deepest_pad_contact(mesh, settings: EngineSettings) -> float:
    """Penetration [m] of the deepest pad-object contact of the open gripper at a dumbbell's neck."""
    import mujoco

    from workbench.engine_trials import EngineObject, EnginePad, TrialPhases, build_scene

    faces = ([-0.0105, 0.0, 0.0], [0.0105, 0.0, 0.0])  # 0.5 mm before the neck's surface
    model, info = build_scene(
        mesh, faces, [1.0, 0.0, 0.0], force=10.0, obj=EngineObject(mass=0.05, mu=0.5),
        pad=EnginePad(size=(0.01, 0.01, 0.005)), settings=settings, phases=TrialPhases(table=False),
    )  # fmt: skip
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    obj = info["object"]
    dist = [
        c.dist
        for c in data.contact[: data.ncon]
        if obj in (model.geom_bodyid[c.geom[0]], model.geom_bodyid[c.geom[1]])
    ]
    return -min(dist, default=0.0)


@pytest.mark.slow
def test_the_pads_meet_the_neck_of_the_slabs_and_start_inside_the_hull():
    """The open pads 0.5 mm before a dumbbell's 10 mm neck: the slabs leave them clear; as its hull
    (a 30 mm cylinder) the object has no neck and the pads start 20 mm inside it."""
    pytest.importorskip("mujoco")
    from workbench.engine_trials import EngineObject, EnginePad, simulate_grasp

    mesh = _dumbbell()
    assert _deepest_pad_contact(mesh, EngineSettings()) <= 0.0
    assert _deepest_pad_contact(mesh, EngineSettings(object_slab=0.0)) > 0.015
    grasp = {"p1": [-0.01, 0.0, 0.0], "p2": [0.01, 0.0, 0.0], "axis": [1.0, 0.0, 0.0]}
    obj, pad = EngineObject(mass=0.05, mu=0.5), EnginePad(size=(0.01, 0.01, 0.005))
    held = simulate_grasp(mesh, grasp, force=10.0, obj=obj, pad=pad)
    assert held.held and held.drift < 1e-3  # 2 μ F = 10 N against 0.5 N


def test_surface_gap_of_points_a_known_depth_inside_a_box():
    """A box is its own collision piece: each point's gap is its distance to the nearest face
    (by hand from the half-sizes 15 / 20 / 25 mm), 0 on a face and outside."""
    box = trimesh.creation.box((0.03, 0.04, 0.05))
    pts = np.array(
        [
            [0.013, 0.0, 0.0],  # 2 mm inside the face x = 15 mm
            [0.0, -0.0195, 0.01],  # 0.5 mm inside y = -20 mm
            [0.005, 0.01, 0.021],  # 4 mm below z = 25 mm (x: 10 mm, y: 10 mm)
            [0.0, 0.0, 0.0],  # the centre: 15 mm from x = ±15 mm
            [0.015, 0.0, 0.0],  # on a face
            [0.02, 0.0, 0.0],  # 5 mm outside
        ]
    )
    gap = surface_gap(box, pts, (0.0, 0.0, -1.0), 5e-3)
    np.testing.assert_allclose(gap, [0.002, 0.0005, 0.004, 0.015, 0.0, 0.0], atol=1e-12)
    # any leading shape: pairs of contact points give (k, 2)
    pairs = surface_gap(box, pts.reshape(3, 2, 3), (0.0, 0.0, -1.0), 5e-3)
    assert pairs.shape == (3, 2) and np.array_equal(pairs.ravel(), gap)
    with pytest.raises(ValueError, match=r"points must be \(\.\.\., 3\) positions"):
        surface_gap(box, pts.reshape(3, 6), (0.0, 0.0, -1.0), 5e-3)


def test_surface_gap_at_a_waist_is_the_hulls_bridge_and_the_slabs_follow_it():
    """A point on the hourglass's waist (r 20 mm at z 0): 8 mm inside its hull (r 28 mm there,
    the ends' radius), and within slab thickness x slope of the surface as slabs."""
    mesh = _hourglass()
    p = np.array([[0.02, 0.0, 0.0]])
    (hull_gap,) = surface_gap(mesh, p, (0.0, 0.0, -1.0), 0.0)
    assert hull_gap == pytest.approx(0.028 - 0.02, rel=0.02)
    h = 0.004
    (slab_gap,) = surface_gap(mesh, p, (0.0, 0.0, -1.0), h)
    assert 0.0 <= slab_gap <= h * (2 * 0.008 / 0.03) * 1.05

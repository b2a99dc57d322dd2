"""workbench.sources.reach: REACH profiles (Winkler on a sphere; the pipeline on a thesis object)."""

import numpy as np
import pytest

from workbench.grasp import gravity_wrench, resists


def test_reach_profile_of_a_sphere_is_winkler():
    """Flat pad closing δ on a sphere: F = π R k δ² (Winkler, δ ≪ R), contact on the axis."""
    import trimesh

    from workbench.sources.reach import WinklerPress, reach_profile

    R, k, d = 0.03, 2e8, 1e-3
    s = trimesh.creation.icosphere(subdivisions=5, radius=R)
    press = WinklerPress(closing=d, stiffness=k, max_edge=0.5e-3)
    p = reach_profile(s, [0, R, 0], [0, -1, 0], [0, 0, 1], press=press)
    assert p.F == pytest.approx(np.pi * R * k * d**2, rel=0.01)
    np.testing.assert_allclose(p.pressure_center[[0, 2]], 0.0, atol=1e-4)
    assert np.sqrt(np.hypot(p.centers[:, 0], p.centers[:, 2]).max() ** 2) == pytest.approx(
        np.sqrt(2 * R * d), rel=0.05
    )
    open_mesh = trimesh.Trimesh(s.vertices, s.faces[:-10])
    with pytest.raises(ValueError, match="watertight"):
        reach_profile(open_mesh, [0, R, 0], [0, -1, 0])
    with pytest.raises(ValueError, match="covers no part"):
        reach_profile(s, [0.5, R, 0], [0, -1, 0])


@pytest.mark.jit_only("over 15 s as pure Python")
def test_grasp_pipeline_on_a_thesis_object_if_available():
    """Antipodal sampling -> REACH profiles -> 6DLS -> resistance of the bottle's own weight."""
    from pathlib import Path

    import trimesh

    from workbench.grasp.models import ModelParameters, contact_sets
    from workbench.grasp.sampling import GraspSampling, antipodal_grasps
    from workbench.sources.jaws import with_axis_force
    from workbench.sources.reach import WinklerPress, reach_profile

    path = (
        Path(__file__).resolve().parents[2]
        / "shared/data/thesis_objects/0006_bottle-gen_smoothie_150x040x040-04.obj"
    )
    if not path.exists():
        pytest.skip("thesis objects not available")
    mesh = trimesh.load(path, force="mesh")
    grasps = antipodal_grasps(mesh, 3, 0.5, GraspSampling(table_z=0.0, clearance=0.03, max_width=0.1), seed=0)
    assert grasps
    g = grasps[0]
    # both jaws press with the same grasp-axis force (a force-sensor reading, §4.1.3.2)
    F = 10.0
    press = WinklerPress(closing=1e-3, max_edge=1e-3)
    profiles = [
        with_axis_force(reach_profile(mesh, g["p1"], g["axis"], press=press), g["axis"], F),
        with_axis_force(reach_profile(mesh, g["p2"], -g["axis"], press=press), g["axis"], F),
    ]
    assert all(len(p) > 10 for p in profiles)
    sets = [c for p in profiles for c in contact_sets(p, "6dls", ModelParameters(M=100, n_wrenches=400))]
    light = gravity_wrench(0.2 * 0.5 * F / 9.81, mesh.center_mass)
    heavy = gravity_wrench(5 * 0.5 * F / 9.81, mesh.center_mass)
    assert resists(sets, light, 0.5) and not resists(sets, heavy, 0.5)


def _flat_press(outline, center, max_edge):
    """A polygon pad pressed flat on the 60 × 60 mm top face of a box (approach -z, up +y: e2 = +y,
    e1 = e2 × a = -x), uniform compression."""
    import trimesh

    from workbench.sources.reach import WinklerPress, reach_profile

    box = trimesh.creation.box((0.06, 0.06, 0.02))
    press = WinklerPress(closing=1e-3, stiffness=1e9, max_edge=max_edge)
    return reach_profile(box, center, [0, 0, -1], [0, 1, 0], outline=outline, press=press)


@pytest.mark.parametrize("max_edge", [1e-3, 0.5e-3])
def test_polygon_pad_pressed_flat_covers_the_polygon(max_edge):
    """The YuMi pad (asymmetric along e2) on a big face: footprint area = polygon area and pressure
    centre = its centroid, placed at center + c1 e1 + c2 e2.  The error comes from the band of
    elements the boundary cuts (in or out by their centre): |ΔA| <= 0.25 · perimeter · max_edge
    (measured 0.05–0.07 here, 0.11 for the offset rectangle below), the centre within 0.2 max_edge
    (measured 0.06–0.09)."""
    from workbench.sources.gripper import polygon_centroid, yumi

    jaw = yumi().jaws(np.eye(4))[0]  # the pad in (e1, e2) coordinates
    poly = jaw.outline
    perimeter = np.linalg.norm(np.diff(np.vstack([poly, poly[:1]]), axis=0), axis=1).sum()
    assert perimeter == pytest.approx(2 * 0.0225 + 0.01 + 0.02 + 2 * np.hypot(0.005, 0.005))
    c = np.array([0.004, -0.006, 0.01])
    p = _flat_press(poly, c, max_edge)
    assert abs(p.areas.sum() - 5.25e-4) <= 0.25 * perimeter * max_edge
    c1, c2 = polygon_centroid(poly)
    assert (c1, c2) == pytest.approx((0.0, -4.3254e-3), abs=1e-7)
    expected = c + c1 * np.array([-1, 0, 0]) + c2 * np.array([0, 1, 0])
    assert np.linalg.norm(p.pressure_center - expected) <= 0.2 * max_edge
    np.testing.assert_allclose(p.pressures, 1e9 * 1e-3)


def test_offset_rectangle_pad_pressed_flat():
    """A 10 × 16 mm rectangle centred at (e1, e2) = (3, -5) mm: area 1.6 cm², centre offset by
    (3, -5) mm, i.e. (-3, -5) mm in x, y."""
    from workbench.sources.gripper import PadShape

    pad = PadShape.rectangle(0.01, 0.016, offset=(-0.005, -0.003))  # tooltip (x, y) -> (e1, e2) = (-y, x)
    poly = np.c_[-pad.outline[:, 1], pad.outline[:, 0]]
    c = np.array([0.002, 0.001, 0.01])
    p = _flat_press(poly, c, 0.5e-3)
    assert abs(p.areas.sum() - 1.6e-4) <= 0.25 * 0.052 * 0.5e-3
    np.testing.assert_allclose(p.pressure_center, c + [-0.003, -0.005, 0], atol=0.2 * 0.5e-3)


def test_pad_profile_reaches_within_its_stroke_and_misses_cleanly(caplog):
    """A YuMi jaw opened 20 mm above a face touches it (the whole pad, k · closing everywhere); one
    beyond its 25 mm stroke or moved sideways off the face touches nothing: None, logged at DEBUG."""
    import logging

    import trimesh

    from workbench.sources.reach import pad_profile

    box = trimesh.creation.box((0.06, 0.06, 0.02))  # top face at z = 0.01
    g = yumi_gripper()

    def jaw_at(height, x=0.0):
        # gripper x (jaw 0's closing) along -z, approach z along -y, y = z × x = +x
        R = np.array([[0, 1, 0], [0, 0, -1], [-1, 0, 0.0]])
        pose = np.eye(4)
        pose[:3, :3] = R
        pose[:3, 3] = [x, 0, 0.01 + height] - R @ g.tooltips[0, :3, 3]
        return g.jaws(pose)[0]

    jaw = jaw_at(0.02)
    np.testing.assert_allclose([jaw.origin, jaw.closing], [[0, 0, 0.03], [0, 0, -1]], atol=1e-12)
    p = pad_profile(box, jaw, closing=1e-3, max_edge=1e-3)
    assert abs(p.areas.sum() - 5.25e-4) <= 0.25 * 0.0886 * 1e-3
    np.testing.assert_allclose(p.pressures, jaw.stiffness * 1e-3)
    with caplog.at_level(logging.DEBUG, logger="workbench.sources.reach"):
        assert pad_profile(box, jaw_at(0.026), closing=1e-3) is None
        assert "covers no part" in caplog.text
        assert pad_profile(box, jaw_at(0.005, x=0.06), closing=1e-3) is None  # sideways off the face
    with pytest.raises(ValueError, match="must be (a closing )?> 0"):
        pad_profile(box, jaw, closing=0.0)
    with pytest.raises(ValueError, match="Jaw"):
        pad_profile(box, {"origin": jaw.origin}, closing=1e-3)
    with pytest.raises(ValueError, match="watertight"):
        pad_profile(trimesh.Trimesh(box.vertices, box.faces[:-2]), jaw, closing=1e-3)


def yumi_gripper():
    from workbench.sources.gripper import yumi

    return yumi()


def test_reach_profile_window_and_outline_errors():
    """window=(lo, hi) searches only that range along the approach; bad outlines and windows raise."""
    import trimesh

    from workbench.sources.reach import WinklerPress, reach_profile

    box = trimesh.creation.box((0.06, 0.06, 0.02))
    poly = [[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]]
    far = [0, 0, 0.03]  # 20 mm above the face
    with pytest.raises(ValueError, match="covers no part"):
        reach_profile(box, far, [0, 0, -1], [0, 1, 0], outline=poly)  # default ±10 mm
    press = WinklerPress(window=(0, 0.025), closing=1e-3)
    p = reach_profile(box, far, [0, 0, -1], [0, 1, 0], outline=poly, press=press)
    assert abs(p.areas.sum() - 4e-4) <= 0.25 * 0.08 * 1e-3
    with pytest.raises(ValueError, match="millimetres"):
        reach_profile(box, far, [0, 0, -1], outline=np.asarray(poly) * 1000, press=press)
    with pytest.raises(ValueError, match="lo < hi"):
        reach_profile(box, far, [0, 0, -1], outline=poly, press=WinklerPress(window=(0.025, 0)))


def test_jaw_profiles_are_reach_profile_then_checked_jaw_profile_bit_for_bit():
    """jaw_profiles checks the mesh, pad and press once for both jaws: each profile is, to the
    last bit, the public composition (reach_profile, then checked_jaw_profile), on a mesh in
    millimetres, and the refusals are theirs."""
    import trimesh

    from workbench.sources.jaws import checked_jaw_profile
    from workbench.sources.reach import WinklerPress, jaw_profiles, reach_profile

    mesh_mm = trimesh.creation.cylinder(radius=15.0, height=80.0, sections=48)
    mesh = trimesh.Trimesh(mesh_mm.vertices * 1e-3, mesh_mm.faces)
    axis = np.array([1.0, 0.2, 0.0]) / np.hypot(1.0, 0.2)
    for up, pad, force, closing in (
        ((0, 0, 1), (0.02, 0.04), 12.0, 1e-3),
        ((0, 1, 1), (0.015, 0.03), 7.5, 5e-4),
    ):
        for shift in (0.0, 0.011):  # through the axis, and a chord off it
            side = np.array([-axis[1], axis[0], 0.0]) * shift
            p1, p2 = side - 0.014 * axis, side + 0.014 * axis
            grasp = {"p1": p1, "p2": p2, "axis": axis}
            got = jaw_profiles(mesh_mm, grasp, force, up=up, pad=pad, closing=closing, units="mm")
            press = WinklerPress(closing=closing)
            for prof, point, approach in zip(got, (p1, p2), (axis, -axis), strict=True):
                want = checked_jaw_profile(
                    reach_profile(mesh, point, approach, up, pad=pad, press=press),
                    point,
                    approach,
                    force,
                    pad,
                )
                for name in ("centers", "normals", "areas", "pressures"):
                    assert np.array_equal(getattr(prof, name), getattr(want, name)), name
                assert prof.length_scale == want.length_scale
                assert abs(prof.normal_wrench[:3] @ axis) == pytest.approx(force, rel=1e-12)
    grasp = {"p1": -0.014 * axis, "p2": 0.014 * axis, "axis": axis}
    with pytest.raises(ValueError, match="up must not be parallel to the approach"):
        jaw_profiles(mesh, grasp, 10.0, up=axis)
    with pytest.raises(ValueError, match="covers no part of the object"):
        jaw_profiles(mesh, {"p1": grasp["p1"] + 0.3, "p2": grasp["p2"] + 0.3, "axis": axis}, 10.0)
    with pytest.raises(ValueError, match="pad must be the jaw face"):
        jaw_profiles(mesh, grasp, 10.0, pad=(0.02,))


def _box_grasp():
    import trimesh

    box = trimesh.creation.box((0.06, 0.05, 0.04))
    return box, {"p1": np.array([-0.03, 0, 0]), "p2": np.array([0.03, 0, 0]), "axis": np.array([1.0, 0, 0])}


def test_an_up_within_a_degree_of_the_approach_is_warned_about():
    # a new user's trial: up 1e-9 rad from the axis turned the pad by its last digits (626 or
    # 722 mm² of a 60 x 50 mm face), without a word
    import warnings

    from workbench.plausible import ImplausibleWarning
    from workbench.sources.reach import jaw_profiles

    box, g = _box_grasp()
    for up in ((1, 1e-9, 2e-9), (1, 0, 0.017)):  # 1.1e-7 and 0.97 deg
        with pytest.warns(ImplausibleWarning, match="deg from the approach"):
            jaw_profiles(box, g, 10.0, up=up)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        area = jaw_profiles(box, g, 10.0, up=(1, 0, 0.018))[0].areas.sum()  # 1.03 deg: no warning
    assert area == pytest.approx(0.02 * 0.04, rel=0.03)  # the pad's 20 x 40 mm on the face
    with pytest.raises(ValueError, match="must not be parallel"):
        jaw_profiles(box, g, 10.0, up=(2, 0, 0))


def test_a_millimetre_mesh_taken_for_metres_is_refused_before_it_is_refined():
    # the same trial: allow_scale=True let a 60 mm box in millimetres through, and its 1 mm
    # refinement asked for 61 GiB (a MemoryError); the pieces are counted first
    import time

    import trimesh

    from workbench.sources.reach import jaw_profiles, reach_profile

    big = trimesh.creation.box((60, 50, 40))
    g = {"p1": np.array([-30.0, 0, 0]), "p2": np.array([30.0, 0, 0]), "axis": np.array([1.0, 0, 0])}
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"units='mm'.*larger max_edge") as err:
        jaw_profiles(big, g, 10.0, allow_scale=True)
    assert "config.TOL.max_sub_triangles" in str(err.value)
    with pytest.raises(ValueError, match="max_sub_triangles"):
        reach_profile(big, [-30.0, 0, 0], [1.0, 0, 0], allow_scale=True)
    assert time.perf_counter() - t0 < 5.0  # refused from a count, nothing allocated

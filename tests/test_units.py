"""Unit guards: meshes and profiles whose size says "wrong unit" are rejected with
the likely unit and the fix; thesis-size inputs pass untouched."""

import dataclasses
import warnings

import numpy as np
import pytest
import trimesh

from workbench import ContactProfile, config
from workbench.grasp.sampling import antipodal_grasps
from workbench.plausible import ImplausibleWarning
from workbench.sources.reach import WinklerPress, reach_profile
from workbench.units import check_extent, length_factor, mesh_in_metres

R = 0.03  # a thesis-size object: 6 cm across


@pytest.fixture(scope="module")
def sphere_m():
    return trimesh.creation.icosphere(subdivisions=3, radius=R)


@pytest.fixture(scope="module")
def sphere_mm(sphere_m):
    mesh = sphere_m.copy()
    mesh.apply_scale(1000.0)
    return mesh


def test_check_extent_names_the_likely_unit():
    assert check_extent(0.15, "bottle") == 0.15
    with pytest.raises(ValueError) as exc:
        check_extent(150.0, "bottle")
    msg = str(exc.value)
    assert "bottle spans 150 m" in msg and "millimetres" in msg and "units='mm'" in msg
    assert "apply_scale(0.001)" in msg and "allow_scale=True" in msg
    # a mesh 20 units long is 2 cm in millimetres and 20 cm in centimetres: both are named, with
    # the size the second reading gives (a new-user trial's cm mesh was called only "mm")
    with pytest.raises(ValueError) as exc:
        check_extent(20.0, "box")
    msg = str(exc.value)
    assert "probably in millimetres: pass units='mm'" in msg
    assert "; or in centimetres (then 0.2 m across): pass units='cm'" in msg
    # converted twice: a metre mesh declared in mm
    with pytest.raises(ValueError, match="probably in metres: pass units='m' instead of units='mm'"):
        check_extent(0.06e-3, "bottle", units="mm")
    with pytest.raises(ValueError, match="converted to metres twice"):
        check_extent(0.06e-3, "bottle")
    assert check_extent(150.0, "bottle", allow_scale=True) == 150.0
    assert check_extent(1e-6, "patch", check_lower=False) == 1e-6
    assert check_extent(2.0 * (1 + 1e-15), "S1") > 2.0  # the thesis's 2 m surfaces, with rounding
    with pytest.raises(ValueError, match="finite length"):
        check_extent(float("nan"), "bottle")


def test_limits_are_read_at_call_time(monkeypatch):
    strict = dataclasses.replace(config.TOL, max_object_extent_m=0.1)
    monkeypatch.setattr(config, "TOL", strict)
    with pytest.raises(ValueError, match="more than TOL.max_object_extent_m = 0.1 m"):
        check_extent(0.15, "bottle")


def test_length_factor_is_shared_with_profile():
    from workbench import profile

    assert profile.length_factor is length_factor
    assert length_factor("mm") == 1e-3 and length_factor(0.5) == 0.5
    with pytest.raises(ValueError, match="units must be one of"):
        length_factor("inch")


def test_antipodal_grasps_metre_mesh_passes_mm_mesh_raises(sphere_m, sphere_mm):
    g = antipodal_grasps(sphere_m, 8, 0.5, seed=0)
    assert len(g) == 8
    # every antipodal chord of a sphere inside the friction cone is near a diameter
    assert all(2 * R * np.cos(np.arctan(0.5)) - 1e-3 <= x["width"] <= 2 * R for x in g)
    with pytest.raises(ValueError) as exc:
        antipodal_grasps(sphere_mm, 8, 0.5, seed=0)  # silently returned [] before
    msg = str(exc.value)
    assert "antipodal_grasps spans 60 m" in msg and "millimetres" in msg and "units='mm'" in msg


def test_antipodal_grasps_units_mm_scales_a_copy(sphere_m, sphere_mm):
    before = sphere_mm.vertices.copy()
    g_mm = antipodal_grasps(mesh_in_metres(sphere_mm, "object", units="mm"), 8, 0.5, seed=0)
    g_m = antipodal_grasps(sphere_m, 8, 0.5, seed=0)
    assert np.array_equal(sphere_mm.vertices, before)  # the caller's mesh is untouched
    for a, b in zip(g_mm, g_m, strict=True):
        np.testing.assert_allclose(a["p1"], b["p1"], rtol=0, atol=1e-12 * R)
        assert a["width"] == pytest.approx(b["width"], rel=1e-12)
    with pytest.raises(ValueError, match="less than TOL.min_object_extent_m"):
        mesh_in_metres(sphere_m, "object", units="mm")  # a metre mesh converted again


def test_reach_profile_units(sphere_m, sphere_mm):
    kw = {"press": WinklerPress(closing=1e-4, max_edge=0.5e-3)}
    p = reach_profile(sphere_m, [0, R, 0], [0, -1, 0], [0, 0, 1], **kw)
    fix = r"mesh_in_metres\(mesh, 'object', units='mm'\)"
    with pytest.raises(ValueError, match=rf"reach_profile spans 60 m .* millimetres: .*{fix}"):
        reach_profile(sphere_mm, [0, R, 0], [0, -1, 0], [0, 0, 1], **kw)  # was "max_iter exceeded!"
    in_m = mesh_in_metres(sphere_mm, "object", units="mm")
    q = reach_profile(in_m, [0, R, 0], [0, -1, 0], [0, 0, 1], **kw)  # center in metres
    assert len(q) == len(p)
    assert q.F == pytest.approx(p.F, rel=1e-12)
    np.testing.assert_allclose(q.pressure_center, p.pressure_center, rtol=0, atol=1e-12 * R)


def _patch(side, n=11):
    x, y = np.meshgrid(np.linspace(0, side, n), np.linspace(0, side, n))
    c = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    return c, np.tile([0.0, 0.0, 1.0], (n * n, 1)), np.full(n * n, (side / n) ** 2), np.ones(n * n)


def test_profile_upper_bound_only():
    c, nrm, a, p = _patch(0.02)
    assert ContactProfile(c, nrm, a, p).length_scale == pytest.approx(0.02, rel=1e-12)
    with pytest.raises(ValueError) as exc:
        ContactProfile(c * 1000, nrm, a * 1e6, p)  # a 20 mm patch given in millimetres
    msg = str(exc.value)
    assert "spans 20 m" in msg and "millimetres" in msg and "from_mesh(..., units='mm')" in msg
    # small contacts are legitimate (no lower bound): a 2 µm patch and a single element
    assert ContactProfile(c * 1e-4, nrm, a * 1e-8, p).length_scale == pytest.approx(2e-6, rel=1e-12)
    ContactProfile(c[:1], nrm[:1], a[:1], p[:1])


def test_allow_scale_survives_derived_profiles():
    c, nrm, a, p = _patch(20.0)
    big = ContactProfile(c, nrm, a, p, allow_scale=True)
    R90 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    for derived in (big.normalized(), big.with_pressures(2 * p), big.transformed(R90, [1.0, 0, 0])):
        assert derived.allow_scale and derived.length_scale == pytest.approx(20.0, rel=1e-12)


def test_from_mesh_units_fix_the_guard():
    c, *_ = _patch(20.0, n=3)  # 3 x 3 vertices, 20 mm side, in millimetres
    faces = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]])
    with pytest.raises(ValueError, match="spans 20 m"):
        ContactProfile.from_mesh(c, faces, 1.0)
    prof = ContactProfile.from_mesh(c, faces, 1.0, units="mm")
    assert prof.length_scale == pytest.approx(0.02, rel=1e-12)


def test_half_flipped_normals_warn():
    c, nrm, a, p = _patch(0.02)
    flipped = nrm.copy()
    flipped[::2] *= -1  # 61 of 121 elements wound the other way
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ContactProfile(c, nrm, a, p)
        assert not caught
        ContactProfile(c, flipped, a, p)
    assert len(caught) == 1 and caught[0].category is ImplausibleWarning
    msg = str(caught[0].message)
    # 61 flipped outnumber 60 right ones: the mean follows the majority, the 60 are reported
    assert "60 of 121 elements" in msg and "50%" in msg and "fix_normals" in msg


def test_normals_that_cancel_warn():
    # two equal triangles, one wound the other way: Σ f_i n_i is exactly zero, so there is no
    # mean normal to be "against" — the profile's net normal force is 0 N for a 1 N contact
    V = np.array([[0.0, 0, 0], [0.01, 0, 0], [0.01, 0.01, 0], [0.0, 0.01, 0]])
    with pytest.warns(ImplausibleWarning, match=r"normal forces cancel .*wound both ways.*fix_normals"):
        prof = ContactProfile.from_mesh(V, [[0, 1, 2], [0, 3, 2]], 1e4)
    assert np.linalg.norm((prof.forces[:, None] * prof.normals).sum(axis=0)) == pytest.approx(0.0, abs=1e-12)


def test_flip_detection_limits():
    # below the force fraction: 10 of 121 elements (8 %) flipped is not flagged; and a
    # profile whose normals are all flipped is self-consistent, so it cannot be (documented)
    c, nrm, a, p = _patch(0.02)
    few = nrm.copy()
    few[:10] *= -1
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        ContactProfile(c, few, a, p)
        ContactProfile(c, -nrm, a, p)
        # a cylinder wrap of ±60° (the sensitivity scene's 0.6 rad is narrower) never warns
        t = np.linspace(-np.pi / 3, np.pi / 3, 41)
        ring = np.column_stack([np.sin(t), np.cos(t), np.zeros_like(t)])
        ContactProfile(0.02 * ring, ring, np.full(41, 1e-6), np.ones(41))


@pytest.mark.jit_only("over 15 s as pure Python")
def test_planar_model_keeps_allow_scale():
    """Trial finding: a millimetre profile accepted with allow_scale=True was rejected
    again inside the planar model; it now gives the metre profile's verdict scaled."""
    from workbench.grasp import contact_sets
    from workbench.sources.scenes import elliptic_cylinder_grasp

    p = elliptic_cylinder_grasp(force=10.0, n_elements=100)[0]
    mm = ContactProfile(p.centers * 1e3, p.normals, p.areas * 1e6, p.pressures * 1e-6, allow_scale=True)
    (c,) = contact_sets(mm, "planar")
    assert c.force == pytest.approx(p.F, rel=1e-12)


def test_a_flat_mesh_is_refused():
    # a 40 x 40 x 1e-9 m "box" held 0.3 kg: its convex hull had no volume to judge the mass by
    from workbench.units import closed_mesh

    with pytest.raises(ValueError, match=r"is flat: .*thinnest side 2.5e-08 of the longest"):
        closed_mesh(trimesh.creation.box(extents=(0.04, 0.04, 1e-9)), "mesh")
    card = closed_mesh(trimesh.creation.box(extents=(0.085, 0.054, 0.00076)), "a credit card")
    assert card.volume == pytest.approx(0.085 * 0.054 * 0.00076)

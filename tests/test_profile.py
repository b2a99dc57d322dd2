"""ContactProfile: derived quantities and validation of every bad input."""

import naive
import numpy as np
import pytest
import trimesh

from workbench import ContactProfile

GOOD = dict(
    centers=np.array([[0.0, 0, 0], [0.01, 0, 0], [0, 0.01, 0.001]]),
    normals=np.array([[0.0, 0, 1], [0, 0, 1], [0, 0.1, 1]]) / np.array([[1.0], [1.0], [np.hypot(0.1, 1)]]),
    areas=np.array([1e-6, 2e-6, 1e-6]),
    pressures=np.array([1e5, 2e5, 0.0]),
)


def make(**over):
    kw = {k: np.array(v, copy=True) for k, v in GOOD.items()}
    kw.update(over)
    return ContactProfile(kw.pop("centers"), kw.pop("normals"), kw.pop("areas"), kw.pop("pressures"), **kw)


def test_derived_quantities():
    p = make()
    f = GOOD["pressures"] * GOOD["areas"]
    assert p.F == pytest.approx(f.sum(), rel=1e-15)
    np.testing.assert_allclose(p.pressure_center, (GOOD["centers"] * f[:, None]).sum(0) / f.sum())
    np.testing.assert_allclose((p.normalized_pressures * p.areas).sum(), 1.0, rtol=1e-15)
    assert p.normalized().F == pytest.approx(1.0, rel=1e-15)


def test_contact_frame_moves_pressure_center_to_origin(rng):
    prof = ContactProfile(*naive.random_profile(rng, 40))
    c = prof.in_contact_frame()
    np.testing.assert_allclose(c.pressure_center, 0.0, atol=1e-16)
    R = np.linalg.qr(rng.standard_normal((3, 3)))[0]
    R *= np.sign(np.linalg.det(R))
    cr = prof.in_contact_frame(R)
    np.testing.assert_allclose(cr.pressure_center, 0.0, atol=1e-16)
    np.testing.assert_allclose(cr.normals, prof.normals @ R.T, atol=1e-15)


@pytest.mark.parametrize(
    "field, value, match",
    [
        ("centers", [[np.nan, 0, 0], [0, 0, 0], [0, 0, 0]], "centers must be finite"),
        ("normals", [[0, 0, np.inf], [0, 0, 1], [0, 0, 1]], "normals must be finite"),
        ("areas", [1e-6, np.nan, 1e-6], "areas must be finite"),
        ("pressures", [1.0, np.inf, 1.0], "pressures must be finite"),
        ("pressures", [1e5, -3.2, 1.0], "pressures must be >= 0"),
        ("pressures", [0.0, 0.0, 0.0], "pressures are all zero"),
        ("areas", [1e-6, 0.0, 1e-6], "areas must be > 0"),
        ("areas", [1e-6, 1e-30, 1e-6], "areas: element 1 is degenerate"),
        ("normals", [[0, 0, 2.0], [0, 0, 1], [0, 0, 1]], "normals must be unit"),
        ("normals", [[0, 0, 0.0], [0, 0, 1], [0, 0, 1]], "zero normal"),
        ("areas", [1e-6, 1e-6], "areas has 2 elements but centers has 3"),
        ("pressures", [1.0, 1.0, 1.0, 1.0], "pressures has 4 elements"),
        ("centers", [[0, 0], [0, 0], [0, 0]], r"centers must have shape \(n, 3\)"),
        ("pressures", "abc", "pressures must be a numeric array"),
        ("pressures", [True, True, True], r"pressures must be a numeric array; got booleans \(a mask\?\)"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_field(field, value, match):
    with pytest.raises(ValueError, match=match):
        make(**{field: value})


def test_empty_profile_raises():
    with pytest.raises(ValueError, match="profile is empty"):
        ContactProfile(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0))


def test_near_unit_normals_renormalised_and_explicit_opt_in():
    p = make(normals=[[0, 0, 1 + 5e-7], [0, 0, 1], [0, 0, 1]])
    np.testing.assert_allclose(np.linalg.norm(p.normals, axis=1), 1.0, rtol=1e-15)
    p2 = make(normals=[[0, 0, 3.0], [0, 0, 1], [0, 0, 1]], normalize_normals=True)
    np.testing.assert_allclose(p2.normals[0], [0, 0, 1.0])


def test_profile_arrays_are_read_only():
    p = make()
    with pytest.raises(ValueError):
        p.pressures[0] = 5.0


def _grid_mesh(nx=4, ny=3):
    x, y = np.meshgrid(np.linspace(0, 3, nx), np.linspace(0, 2, ny), indexing="ij")
    verts = 0.01 * np.column_stack([x.ravel(), y.ravel(), 0.1 * x.ravel() ** 2])  # 3 x 2 cm
    idx = np.arange(nx * ny).reshape(nx, ny)
    quads = np.column_stack(
        [idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()]
    )
    tris = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return verts, quads, tris


def test_from_mesh_triangles_match_reference_geometry():
    verts, _, tris = _grid_mesh()
    p = ContactProfile.from_mesh(verts, tris, 2.0)
    c, n, a = naive.triangle_geometry(verts, tris)
    np.testing.assert_allclose(p.centers, c, rtol=1e-14)
    np.testing.assert_allclose(p.normals, n, atol=1e-14)
    np.testing.assert_allclose(p.areas, a, rtol=1e-14)
    assert (p.normals[:, 2] > 0).all()
    flipped = ContactProfile.from_mesh(verts, tris, 2.0, flip_normals=True)
    np.testing.assert_allclose(flipped.normals, -n, atol=1e-14)


def test_from_mesh_quads_and_units():
    verts, quads, tris = _grid_mesh()
    pq = ContactProfile.from_mesh(verts, quads, 1.0)
    pt = ContactProfile.from_mesh(verts, tris, 1.0)
    # planar-in-y warped quads: vector area equals the sum of its two triangles' areas projected
    assert pq.areas.sum() == pytest.approx(pt.areas.sum(), rel=2e-3)
    pmm = ContactProfile.from_mesh(verts * 1000.0, tris, 1.0, units="mm")
    np.testing.assert_allclose(pmm.areas, pt.areas, rtol=1e-12)
    with pytest.raises(ValueError, match="units must be one of"):
        ContactProfile.from_mesh(verts, tris, 1.0, units="inch")


def test_from_mesh_refuses_pressures_that_are_not_one_per_face():
    verts = np.array([[0, 0, 0], [1e-3, 0, 0], [1e-3, 1e-3, 0], [0, 1e-3, 0.0]])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    two = ContactProfile.from_mesh(verts, faces, [1.0, 3.0])
    assert two.F == pytest.approx(0.5e-6 * 1.0 + 0.5e-6 * 3.0, rel=1e-14)
    assert ContactProfile.from_mesh(verts, faces, 2.0).F == pytest.approx(2.0 * 1e-6, rel=1e-14)
    for bad in ([1.0, 2.0, 3.0], np.ones((2, 1)), np.ones(4)):  # 3 values, a column, per vertex
        with pytest.raises(
            ValueError,
            match=r"pressures must be one value per face, shape \(2,\) for the 2 faces, or a scalar",
        ):
            ContactProfile.from_mesh(verts, faces, bad)


def test_from_mesh_degenerate_triangles():
    verts, _, tris = _grid_mesh()
    bad = np.vstack([tris, [[0, 0, 1]]])
    with pytest.raises(ValueError, match="areas must be > 0"):
        ContactProfile.from_mesh(verts, bad, 1.0)
    p = ContactProfile.from_mesh(verts, bad, 1.0, drop_degenerate=True)
    assert len(p) == len(tris)
    with pytest.raises(ValueError, match="faces index vertices"):
        ContactProfile.from_mesh(verts, [[0, 1, 99]], 1.0)
    with pytest.raises(ValueError, match=r"faces must be an integer array of shape \(m, 3\) or \(m, 4\)"):
        ContactProfile.from_mesh(verts, [[0, 1]], 1.0)


def test_from_trimesh_and_meshio_roundtrip(tmp_path):
    import meshio

    verts, _, tris = _grid_mesh()
    pres = np.arange(len(tris), dtype=float) + 1.0
    tm = trimesh.Trimesh(verts, tris, process=False)
    a = ContactProfile.from_trimesh(tm, pres)
    path = tmp_path / "profile.vtu"
    a.to_meshio().write(path)
    b = ContactProfile.from_meshio(meshio.read(path))
    np.testing.assert_allclose(b.pressures, pres)
    np.testing.assert_allclose(b.centers, a.centers, rtol=1e-12)
    with pytest.raises(ValueError, match="cell data 'p' not in mesh"):
        ContactProfile.from_meshio(meshio.read(path), pressure="p")


def test_with_pressures_is_a_profile_made_afresh_bit_for_bit():
    # it checks only the new pressures, yet gives the numbers __init__ would: the normals divided
    # by their lengths once more, the same l_s, the same pressure checks and warnings
    rng = np.random.default_rng(7)
    c, n, a, _ = naive.random_profile(rng, 400)
    prof = ContactProfile(c, n * (1 + 1e-13), a, np.full(400, 1e4))
    p = rng.uniform(1e3, 1e5, 400)
    fast = prof.with_pressures(p)
    fresh = ContactProfile(prof.centers, prof.normals, prof.areas, p)
    for name in ("centers", "normals", "areas", "pressures", "pressure_center", "normal_wrench"):
        np.testing.assert_array_equal(getattr(fast, name), getattr(fresh, name))
    assert fast.length_scale == fresh.length_scale and fast.source is None
    assert not fast.normals.flags.writeable and not fast.pressures.flags.writeable
    with pytest.raises(ValueError, match="pressures"):
        prof.with_pressures(-p)
    with pytest.raises(ValueError):
        prof.with_pressures(p[:-1])
    # half the faces wound the other way: no warning while they carry almost nothing, one once
    # the new pressures load them
    m = np.where(np.arange(400)[:, None] < 200, 1.0, -1.0) * prof.normals
    light = ContactProfile(prof.centers, m, prof.areas, np.where(np.arange(400) < 200, 1e5, 1.0))
    with pytest.warns(Warning, match="normal"):
        light.with_pressures(np.full(400, 1e5))


def test_degenerate_area_rule_is_the_median_rule_whether_or_not_the_median_is_needed(rng):
    """An element is degenerate when its area is <= TOL.degenerate_area_rtol x the median area,
    the median found only when some area is that small against the largest: checked against the
    rule applied plainly on spreads on both sides of the shortcut."""
    from workbench import config
    from workbench.profile import _check_areas

    rtol = config.TOL.degenerate_area_rtol
    seen = {True: 0, False: 0}
    for spread in (0.0, 3.0, 8.0, 11.5, 12.0, 12.5, 14.0):
        for _ in range(40):
            n = int(rng.integers(1, 9))
            areas = 10.0 ** (-6 - spread * rng.random(n))
            if rng.random() < 0.3:  # an area exactly at the limit of the median
                areas[rng.integers(n)] = rtol * np.median(areas)
            degenerate = bool((areas <= rtol * np.median(areas)).any())
            seen[degenerate] += 1
            if degenerate:
                with pytest.raises(ValueError, match="is degenerate"):
                    _check_areas(areas)
            else:
                _check_areas(areas)
    assert min(seen.values()) >= 20, seen  # both verdicts exercised

"""radial_surface: analytic surfaces (cylinder, cone, ellipse, annulus) against their
formulas, the wall it builds against the analytic tube's, careless input, and the
shared meshes (skipped when absent)."""

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

from workbench.fem.mesh_wall import radial_surface
from workbench.fem.wall import build_wall, circle_surface, squeeze

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "deformable_objects"


def _cylinder(radius=0.03, height=0.1, sections=256):
    m = trimesh.creation.cylinder(radius=radius, height=height, sections=sections)
    m.apply_translation([0, 0, height / 2])
    return m


def _angle_deg(a, b):
    cos = np.einsum("ij,ij->i", a, b) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1)
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


def test_cylinder_points_and_normals():
    s = radial_surface(_cylinder(sections=256))
    th = np.linspace(0, 2 * np.pi, 97)
    z = np.linspace(s.z_range[0], s.z_range[1], 97)
    p, n = s(th, z)
    # the 256-gon lies between 30 cos(π/256) and 30 mm: 2.3 µm
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), 0.03, atol=2.5e-6)
    np.testing.assert_allclose(p[:, 2], z)
    assert _angle_deg(n, np.column_stack([np.cos(th), np.sin(th), 0 * th])).max() < 0.75  # ≤ half a facet
    assert np.isnan(s.thickness).all()  # a solid: one hit per ray


def test_cone_normal_tilts_with_the_taper():
    """r(z) = r0 + k z: the outward normal is ∝ (cos θ, sin θ, −k)."""
    r0, k, h = 0.02, 0.1, 0.1
    profile = np.array([[0.0, 0.0], [r0, 0.0], [r0 + k * h, h], [0.0, h]])
    m = trimesh.creation.revolve(profile, sections=256)
    s = radial_surface(m)
    th = np.linspace(0.1, 6.0, 41)
    z = np.linspace(0.02, 0.08, 41)
    p, n = s(th, z)
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), r0 + k * z, atol=5e-6)
    expect = np.column_stack([np.cos(th), np.sin(th), np.full_like(th, -k)])
    assert _angle_deg(n, expect).max() < 0.75


def test_elliptic_section_normals_follow_the_ellipse():
    """x²/a² + y²/b² = 1: the outward normal is ∝ (x/a², y/b²) — exercises r_θ."""
    a, b = 0.045, 0.03
    m = _cylinder(radius=0.03, sections=512)
    m.apply_scale([a / 0.03, 1.0, 1.0])
    s = radial_surface(m, n_theta=360)
    th = np.linspace(0, 2 * np.pi, 73)[:-1]
    z = np.full_like(th, 0.05)
    p, n = s(th, z)
    # the 512-gon's sag, (π/512)²/2 ≈ 2e-5 of the radius, doubles in the quadratic form
    np.testing.assert_allclose((p[:, 0] / a) ** 2 + (p[:, 1] / b) ** 2, 1.0, atol=1e-4)
    expect = np.column_stack([p[:, 0] / a**2, p[:, 1] / b**2, 0 * th])
    assert _angle_deg(n, expect).max() < 0.36  # half a facet of the 512-gon


def test_a_wall_solid_gives_its_thickness_and_the_outer_side():
    m = trimesh.creation.annulus(r_min=0.0295, r_max=0.03, height=0.1, sections=256)
    m.apply_translation([0, 0, 0.05])
    s = radial_surface(m)
    # both sides are 256-gons: their sags differ by 0.5 mm (1 − cos(π/256)) = 4e-8 m
    np.testing.assert_allclose(s.thickness, 0.5e-3, atol=1e-7)
    np.testing.assert_allclose(s.r, 0.03, atol=2.5e-6)


def test_the_wall_built_from_a_mesh_matches_the_analytic_tube():
    """Same tube, surface from the mesh vs from the formula: same squeeze stiffness."""
    kw = dict(thickness=0.5e-3, n_theta=32, n_z=8, z_range=(0.005, 0.095))
    walls = [build_wall(surf, **kw) for surf in (radial_surface(_cylinder()), circle_surface(0.03))]
    s = [squeeze(w, np.array([0.0, 0.0, 0.06]), np.array([1.0, 0.0, 0.0])).stiffness for w in walls]
    assert s[0] == pytest.approx(s[1], rel=2e-3)


def test_careless_meshes_are_refused():
    cyl = _cylinder()
    with pytest.raises(ValueError, match="millimetres"):
        radial_surface(cyl.copy().apply_scale(1000.0))
    open_mesh = cyl.copy()
    open_mesh.update_faces(np.arange(len(open_mesh.faces)) > 3)
    with pytest.raises(ValueError, match="not watertight"):
        radial_surface(open_mesh)
    # two bodies side by side: the rays along +x cross both
    offsets = ([0.01, 0, 0.05], [0.03, 0, 0.05])
    two = trimesh.util.concatenate(
        [trimesh.creation.box([0.01, 0.01, 0.1]).apply_translation(off) for off in offsets]
    )
    with pytest.raises(ValueError, match="not star-shaped about the axis"):
        radial_surface(two, centre=[0.0, 0.0], z_range=(0.01, 0.09))
    with pytest.raises(ValueError, match="within the mesh's heights"):
        radial_surface(cyl, z_range=(-0.01, 0.05))


@pytest.mark.skipif(not DATA.exists(), reason="deformable_objects data not available")
@pytest.mark.parametrize("name", ["plastic_cup", "mustard", "shampoo", "box", "w5"])
def test_the_shared_meshes_give_a_side_wall_through_the_measured_locations(name):
    mesh = trimesh.load(DATA / "meshes" / f"{name}.obj", force="mesh")
    s = radial_surface(mesh)
    height = np.ptp(mesh.bounds[:, 2])
    assert s.z_range[1] - s.z_range[0] > 0.8 * height  # the side wall is most of the object
    maps = DATA / "stiffness_maps" / f"{name}.json"
    if maps.exists():
        L = np.array(json.loads(maps.read_text())["stiffness_locations"])
        _, z, off = s.parameters(L)
        assert ((z >= s.z_range[0]) & (z <= s.z_range[1])).all()
        # the measured grasp points lie on the scanned surface (0.03 mm off the mesh;
        # the spline through the ray grid adds up to 0.3 mm on the mustard's shoulder)
        assert np.abs(off).max() < 0.5e-3


def test_ray_hits_are_cached_by_content_and_a_bad_file_is_cast_again(tmp_path, monkeypatch):
    """The second radial_surface of the same mesh reads its rays from the disk cache (no
    casting) and is the same surface bit for bit; another mesh gets its own file; a corrupt
    file is cast again and rewritten; with the cache off nothing is written."""
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path))
    first = radial_surface(_cylinder(sections=64))
    (path,) = tmp_path.glob("rays-*.npz")
    casts = []
    real = trimesh.ray.ray_triangle.RayMeshIntersector.intersects_location

    def counting(self, *a, **k):
        casts.append(1)
        return real(self, *a, **k)

    monkeypatch.setattr(trimesh.ray.ray_triangle.RayMeshIntersector, "intersects_location", counting)
    again = radial_surface(_cylinder(sections=64))
    assert not casts
    np.testing.assert_array_equal(again.r, first.r)
    np.testing.assert_array_equal(again.z, first.z)
    radial_surface(_cylinder(sections=65))
    assert len(casts) == 1 and len(list(tmp_path.glob("rays-*.npz"))) == 2
    path.write_bytes(b"not an npz")
    redone = radial_surface(_cylinder(sections=64))
    assert len(casts) == 2
    np.testing.assert_array_equal(redone.r, first.r)
    with np.load(path) as d:  # rewritten, whole
        assert d["counts"].sum() == d["dist"].size > 0
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", "off")
    radial_surface(_cylinder(sections=66))
    assert len(casts) == 3 and len(list(tmp_path.glob("rays-*.npz"))) == 2


def test_rays_that_hit_nothing_count_zero():
    """trimesh returns no hit as a (0,) array, not (0, 3): a torus's axis ray (a new user's
    object) crashed with 'operands could not be broadcast'."""
    import trimesh

    from workbench.fem.mesh_wall import _ray_hits

    box = trimesh.creation.box((0.02, 0.02, 0.02))
    counts, dists = _ray_hits(box, np.array([[0.0, 0.0, 0.05]]), np.array([[0.0, 0.0, 1.0]]))
    assert counts.tolist() == [0] and [d.size for d in dists] == [0]
    counts, dists = _ray_hits(box, np.array([[0.0, 0.0, 0.05]]), np.array([[0.0, 0.0, -1.0]]))
    assert counts.tolist() == [2] and np.allclose(dists[0], [0.04, 0.06])

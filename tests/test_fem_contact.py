"""Condensed-pad contact: LCP correctness and the compressible thin-layer (Winkler) limit."""

import numpy as np
import pytest

from workbench.fem.contact import solve_contact, solve_lcp
from workbench.fem.material import Material
from workbench.fem.obstacles import Cylinder, Plane, Sphere
from workbench.fem.pad import PadGeometry, condense_pad


def test_lcp_solution_is_complementary():
    rng = np.random.default_rng(0)
    B = rng.standard_normal((40, 40))
    A = B @ B.T + 40 * np.eye(40)
    d = rng.standard_normal(40)
    lam, _, _ = solve_lcp(A, d)
    w = A @ lam + d
    assert (lam >= 0).all() and (w >= -1e-10).all()
    assert np.abs(lam * w).max() <= 1e-10


@pytest.fixture(scope="module")
def thin_pad():
    # h = 1 mm, 0.5 mm face spacing: a/h = 3.2 for the indentation below
    geom = PadGeometry(width=0.012, length=0.012, thickness=0.001, nx=24, ny=24, nz=2)
    return condense_pad(geom, Material(E=1.0e6, nu=0.0), cache_dir=False)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_sphere_on_thin_compressible_layer_matches_winkler(thin_pad):
    # Winkler: p = (M/h)(δ - r²/2R), a = sqrt(2Rδ), F = π R M δ² / h   (M = E at nu = 0)
    R, delta = 0.05, 0.1e-3
    h = thin_pad.geometry.thickness
    sol = solve_contact(thin_pad, Sphere((0, 0, h + R), R), delta)
    M = thin_pad.material.p_wave
    a = np.sqrt(2 * R * delta)
    assert a / h >= 3
    F_w = np.pi * R * M * delta**2 / h
    assert sol.force == pytest.approx(F_w, rel=0.05)
    assert sol.max_penetration <= 1e-6 * h
    r = np.hypot(*thin_pad.face_xy.T)
    assert (sol.lam[r > 1.3 * a] == 0).all()  # no force well outside the contact radius


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_plane_and_no_contact(thin_pad):
    h = thin_pad.geometry.thickness
    far = solve_contact(thin_pad, Sphere((0, 0, h + 0.05 + 1e-3), 0.05), 0.0)
    assert not far.in_contact and far.force == 0.0
    flat = solve_contact(thin_pad, Plane((0, 0, h), (0, 0, -1)), 0.05e-3)
    assert flat.force > 0 and (flat.lam >= 0).all()
    with pytest.raises(ValueError, match="deeper than the layer"):
        solve_contact(thin_pad, Cylinder((0, 0, h + 0.01), (0, 1, 0), 0.01), 2 * h)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_extracted_profile_on_the_sphere(thin_pad):
    from workbench import frictional_wrenches, w_max
    from workbench.fem.extract import extract_profile

    R, delta = 0.05, 0.1e-3
    h = thin_pad.geometry.thickness
    sphere = Sphere((0, 0, h + R), R)
    sol = solve_contact(thin_pad, sphere, delta)
    prof = extract_profile(thin_pad, sol, sphere)
    # elements lie on the object surface, normals point out of the object (towards the jaw, -z)
    np.testing.assert_allclose(np.linalg.norm(prof.centers - sphere.center, axis=1), R, rtol=1e-12)
    assert (prof.normals[:, 2] < 0).all()
    # the profile carries the solved contact force (exactly, fem/extract.py); the normal
    # wrench pushes the object away (+z)
    assert prof.F == pytest.approx(sol.force, rel=1e-12)
    assert prof.normal_wrench[2] > 0.95 * prof.F
    np.testing.assert_allclose(prof.pressure_center[:2], 0.0, atol=1e-6)  # symmetric contact
    # and workbench computes its friction: planar-like cap -> f_x,max ≈ μF
    wm = w_max(prof, 0.5)
    assert wm[0] == pytest.approx(0.5 * prof.F, rel=0.01)
    assert np.isfinite(frictional_wrenches(prof, np.eye(6), 0.5)).all()
    assert (
        extract_profile(thin_pad, solve_contact(thin_pad, Sphere((0, 0, h + R + 1e-3), R), 0.0), sphere)
        is None
    )


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_extracted_profile_exports_to_vtu(thin_pad, tmp_path):
    import meshio

    from workbench import ContactProfile
    from workbench.fem.extract import extract_profile

    h = thin_pad.geometry.thickness
    sphere = Sphere((0, 0, h + 0.05), 0.05)
    prof = extract_profile(thin_pad, solve_contact(thin_pad, sphere, 0.1e-3), sphere)
    path = tmp_path / "profile.vtu"
    prof.to_meshio().write(path)
    back = ContactProfile.from_meshio(meshio.read(path))
    np.testing.assert_allclose(back.pressures, prof.pressures)
    # the quad winding reproduces the outward-from-object normals
    assert (np.einsum("ij,ij->i", back.normals, prof.normals) > 0.99).all()


CASES = {
    "sphere": (lambda h: Sphere((0, 0, h + 0.02), 0.02), 0.4e-3),
    "sphere off-center": (lambda h: Sphere((0.002, -0.0015, h + 0.015), 0.015), 0.3e-3),
    "cylinder": (lambda h: Cylinder((0, 0, h + 0.01), (0, 1, 0), 0.01), 0.3e-3),
    "tilted cylinder": (lambda h: Cylinder((0.001, 0, h + 0.012), (0.3, 1, 0), 0.012), 0.3e-3),
    "tilted plane": (lambda h: Plane((0, 0, h - 0.2e-3), (0.08, 0.05, -1)), 0.0),
}


@pytest.mark.parametrize("case", list(CASES))
def test_condensed_equals_full_mesh_linear_solve(case):
    from workbench.fem.contact import solve_contact_full

    geom = PadGeometry(width=0.008, length=0.01, thickness=0.002, nx=8, ny=10, nz=3)
    mat = Material(E=1.0e6, nu=0.45)
    make, delta = CASES[case]
    obs = make(geom.thickness)
    cond = solve_contact(condense_pad(geom, mat, cache_dir=False), obs, delta)
    full = solve_contact_full(geom, mat, obs, delta)
    assert cond.force > 0
    assert cond.force == pytest.approx(full.force, rel=1e-8)
    assert np.linalg.norm(cond.lam - full.lam) <= 1e-8 * np.linalg.norm(full.lam)
    assert full.max_penetration <= 1e-9 * geom.thickness


def test_mesh_obstacle_matches_the_analytic_sphere():
    import trimesh

    from workbench.fem.obstacles import MeshObstacle

    R = 0.02
    obs = MeshObstacle(trimesh.creation.icosphere(subdivisions=5, radius=R * 1000), units="mm")
    rng = np.random.default_rng(0)
    x = rng.normal(size=(200, 3))
    x *= (R * rng.uniform(0.5, 1.5, 200) / np.linalg.norm(x, axis=1))[:, None]
    d, n = obs.signed_distance(x)
    d_ref, n_ref = Sphere((0, 0, 0), R).signed_distance(x)
    assert np.abs(d - d_ref).max() <= 2e-3 * R  # faceting of a 20,480-triangle sphere
    assert (np.einsum("ij,ij->i", n, n_ref) > 0.99).all()
    with pytest.raises(ValueError, match="not watertight"):
        MeshObstacle(trimesh.Trimesh(*[np.eye(3), [[0, 1, 2]]]))


def test_mesh_obstacle_closest_is_exact_on_long_faces():
    """A cylinder of full-height side slivers (0.7 x 120 mm): the nearest centroids miss
    the closest face; the certified search equals a brute force over every face."""
    import trimesh
    from trimesh.triangles import closest_point

    from workbench.fem.obstacles import MeshObstacle

    R = 0.03
    mesh = trimesh.creation.cylinder(radius=R, height=0.12, sections=256)
    obs = MeshObstacle(mesh)
    rng = np.random.default_rng(1)
    th, z = rng.uniform(0, 2 * np.pi, 300), rng.uniform(-0.05, 0.05, 300)
    r = R + rng.uniform(-3e-3, 3e-3, 300)
    x = np.column_stack([r * np.cos(th), r * np.sin(th), z])
    _, d, _ = obs.closest(x)
    # slow reference: every point against every triangle
    tri = obs.mesh.triangles
    ref = np.array(
        [np.linalg.norm(closest_point(tri, np.repeat(p[None], len(tri), 0)) - p, axis=1).min() for p in x]
    )
    assert np.abs(d - ref).max() <= 1e-12
    # and the distance is the cylinder's up to the polygon's sag
    sag = R * (1 - np.cos(np.pi / 256))
    assert np.abs(d - np.abs(r - R)).max() <= sag + 1e-12


def test_mesh_obstacle_rejects_a_mesh_in_the_wrong_unit():
    import trimesh

    from workbench.config import TOL
    from workbench.fem.obstacles import MeshObstacle

    mm = trimesh.creation.icosphere(subdivisions=2, radius=20.0)  # a 40 mm ball written in mm
    with pytest.raises(ValueError, match=r"spans 40 m .*millimetres: pass units='mm'"):
        MeshObstacle(mm)
    with pytest.raises(ValueError, match="millimetres"):
        MeshObstacle(mm, units="m")  # declaring metres does not make a 40 m ball plausible
    ball = MeshObstacle(mm, units="mm")
    assert np.ptp(ball.mesh.vertices, axis=0).max() == pytest.approx(0.04, rel=1e-9)
    big = MeshObstacle(mm, allow_scale=True)  # a 40 m object on purpose
    assert np.ptp(big.mesh.vertices, axis=0).max() == pytest.approx(40.0)
    assert big.transformed(np.eye(4)).mesh.vertices.max() == pytest.approx(big.mesh.vertices.max())
    twice = trimesh.creation.icosphere(subdivisions=2, radius=20e-6)  # mm -> m applied twice: 40 µm
    with pytest.raises(ValueError, match="converted to metres twice"):
        MeshObstacle(twice)
    # the limits are the config's: just inside both passes unchanged
    for side in (TOL.max_object_extent_m * (1 - 1e-6), TOL.min_object_extent_m * (1 + 1e-6)):
        box = trimesh.creation.box(extents=[side] * 3)
        assert np.ptp(MeshObstacle(box).mesh.vertices, axis=0).max() == pytest.approx(side, rel=1e-9)
    big = trimesh.creation.box(extents=[2.0 * TOL.max_object_extent_m] * 3)
    with pytest.raises(ValueError, match=r"largest bounding-box side\) spans 4 m .*TOL.max_object_extent_m"):
        MeshObstacle(big)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_pad_on_a_thesis_object_if_available(thin_pad):
    from pathlib import Path

    from workbench.fem.extract import extract_profile
    from workbench.fem.obstacles import MeshObstacle

    path = (
        Path(__file__).resolve().parents[2]
        / "shared/data/thesis_objects/0006_bottle-gen_smoothie_150x040x040-04.obj"
    )
    if not path.exists():
        pytest.skip("thesis objects not available")
    obs = MeshObstacle(path)
    # put the bottle's outermost side point (max x) onto the pad face center: x -> -z
    top = obs.mesh.vertices[np.argmax(obs.mesh.vertices[:, 0])]
    h = thin_pad.geometry.thickness
    T = np.eye(4)
    T[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]  # rotation taking +x to -z
    T[:3, 3] = [-top[2], -top[1], h + top[0]]
    placed = obs.transformed(T, facing=(0, 0, -1))  # the bottle's wall is 0.4 mm: one-sided
    sol = solve_contact(thin_pad, placed, 0.2e-3)
    prof = extract_profile(thin_pad, sol, placed)
    assert prof is not None and prof.F > 0
    assert (prof.normals[:, 2] < 0).all()  # outward from the bottle, towards the jaw


def test_normal_projection_kernels_match_numpy():
    from naive import normal_block, normal_rows

    from workbench.fem._kernels import _normal_block, _normal_rows

    rng = np.random.default_rng(4)
    n = 37
    C = rng.standard_normal((3 * n, 3 * n))
    nrm = rng.standard_normal((n, 3))
    nodes = np.sort(rng.choice(n, 20, replace=False))
    G = np.empty((nodes.size, 3 * n))
    _normal_rows(C, nodes, nrm, G)
    assert np.allclose(G, normal_rows(C, nodes, nrm), rtol=1e-13, atol=1e-13)
    A = np.empty((nodes.size, nodes.size))
    _normal_block(G, nodes, nrm, A)
    assert np.allclose(A, normal_block(G, nodes, nrm), rtol=1e-13, atol=1e-12)


@pytest.mark.parametrize("fraction", [0.0, 0.3, 1.0])
def test_lcp_active_set_variants_agree_with_nnls(fraction, monkeypatch):
    """Direct-Cholesky and factor-once (Schur) active-set steps give the NNLS optimum."""
    from scipy.optimize import nnls

    import workbench.fem.contact as fc

    monkeypatch.setattr(fc, "SCHUR_FRACTION", fraction)
    rng = np.random.default_rng(5)
    X = rng.standard_normal((60, 60))
    A = X @ X.T / 60 + np.eye(60)
    d = rng.standard_normal(60)
    lam, _, method = fc.solve_lcp(A, d)
    L = np.linalg.cholesky(A)
    ref, _ = nnls(L.T, -np.linalg.solve(L, d))
    assert method == "pdas"
    assert np.abs(lam - ref).max() < 1e-10
    w = A @ lam + d
    assert lam.min() >= 0 and w.min() > -1e-12 and abs(lam @ w) < 1e-10

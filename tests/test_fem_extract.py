"""FEM profiles carry the solved force (workbench/fem/extract.py).

``λ_i`` is the magnitude of node i's contact force along the obstacle normal
``n_i`` (workbench/fem/contact.py), so the profile must have ``F = Σ p a = Σ λ`` and a
normal-wrench force ``−Σ p a n`` equal to the solution's ``−Σ λ_i n_i``.  The
second holds up to the spread of the normals within an element: with θ the
largest angle between two corner normals of a loaded quad, each element's
force-weighted mean of unit normals has length ≥ cos θ, so
``‖w⊥_f − (−Σ λ n)‖ ≤ (1 − cos θ) Σ λ`` (a bound from the solution alone).

Also the face grid, tributary areas, quad vector areas and nodal pressures the profile is
built from, and careless input.  ``thin_pad``, ``pad_cache`` and ``sphere_press`` are in
tests/conftest.py.
"""

import logging
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from workbench.fem import press
from workbench.fem.contact import ContactSolution, solve_contact
from workbench.fem.extract import (
    extract_profile,
    face_grid,
    nodal_pressures,
    quad_vector_areas,
    tributary_areas,
)
from workbench.fem.material import Material
from workbench.fem.obstacles import MeshObstacle, Plane, Sphere
from workbench.fem.pad import PadFace, PadGeometry

DELTAS_MM = [0.1, 0.25, 0.5, 1.0, 2.0, 3.0]  # conftest.SPHERE_PRESS_DELTAS_MM
MAT = Material(E=1.0e6, nu=0.45)  # as fem-fitting
BOTTLE = (
    Path(__file__).resolve().parents[2]
    / "shared/data/thesis_objects/0006_bottle-gen_smoothie_150x040x040-04.obj"
)


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
    # the profile carries the solved contact force (exactly, workbench/fem/extract.py); the normal
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


def _spread_bound(sol: ContactSolution, face_xy: np.ndarray) -> float:
    """1 − cos θ, θ the largest angle between two corner normals of a loaded quad."""
    quads, _ = face_grid(face_xy)
    q = quads[(sol.lam[quads] > 0).any(axis=1)]
    nn = sol.normals[q]  # (m, 4, 3)
    return float(1.0 - np.einsum("eij,ekj->eik", nn, nn).min())


def _check_force(prof, sol, face_xy):
    total = sol.lam.sum()
    assert total > 0
    # Σ p a = Σ λ: the required bound, and the exactness the construction gives
    assert abs(prof.F - total) / total <= 5e-3
    assert prof.F == pytest.approx(total, rel=1e-12)
    # normal wrench force = the solution's force on the object −Σ λ_i n_i (independent sum)
    f_sol = -(sol.lam[:, None] * sol.normals).sum(axis=0)
    np.testing.assert_allclose(sol.force_vector, f_sol, rtol=1e-14, atol=1e-14 * total)
    bound = _spread_bound(sol, face_xy)
    err = np.linalg.norm(prof.normal_wrench[:3] - f_sol)
    assert err <= bound * total
    # λ is along the obstacle normal, not the press axis: on a curved object the
    # resultant is shorter than Σ λ, and the profile's is too
    assert np.linalg.norm(prof.normal_wrench[:3]) < total


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
@pytest.mark.parametrize("delta_mm", DELTAS_MM)
def test_default_pad_on_a_sphere_profile_carries_the_solved_force(sphere_press, delta_mm):
    res = sphere_press
    d = delta_mm * 1e-3
    sol = res[d]
    prof = res.profile(d)  # press, then extract the profile
    _check_force(prof, sol, res.pad.face_xy)
    # R = 20 mm, 1 mm face spacing: the face nodes lie R - δ from the sphere's center, so
    # two corner normals of a quad (diagonal √2 mm) differ by at most √2 mm / (R - δ)
    assert _spread_bound(sol, res.pad.face_xy) <= 1 - np.cos(np.sqrt(2) * 1e-3 / (0.02 - d))
    # axisymmetric contact: the resultant is along the press axis
    assert np.abs(prof.normal_wrench[:2]).max() <= 1e-12 * sol.force
    assert prof.normal_wrench[2] > 0  # pushes the object away from the jaw
    np.testing.assert_allclose(prof.pressure_center[:2], 0.0, atol=1e-9)


@pytest.fixture(scope="module")
def bottle_press(pad_cache):
    if not BOTTLE.exists():
        pytest.skip(f"thesis objects not available ({BOTTLE.parent})")
    obs = MeshObstacle(BOTTLE)  # metres
    # the bottle's outermost side point (max x) onto the pad face center: x -> -z
    top = obs.mesh.vertices[np.argmax(obs.mesh.vertices[:, 0])]
    h = PadGeometry().thickness
    T = np.eye(4)
    T[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]
    T[:3, 3] = [-top[2], -top[1], h + top[0]]
    placed = obs.transformed(T, facing=(0, 0, -1))  # thin wall: one-sided distance
    return press(PadGeometry(), MAT, placed, [d * 1e-3 for d in DELTAS_MM], cache_dir=pad_cache)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
@pytest.mark.parametrize("delta_mm", DELTAS_MM)
def test_default_pad_on_a_thesis_bottle_profile_carries_the_solved_force(bottle_press, delta_mm):
    d = delta_mm * 1e-3
    prof = bottle_press.profile(d)
    _check_force(prof, bottle_press[d], bottle_press.pad.face_xy)
    assert (prof.normals[:, 2] < 0).all()  # outward from the bottle, towards the jaw


def test_uniform_cauchy_pressure_is_reproduced_exactly():
    """Nodal forces of a uniform pressure p0 on the *deformed* face (face stretched
    in-plane by s: deformed tributary areas = s² × undeformed) give p = p0 on every
    element, areas s² dx dy and F = p0 s² × face area."""
    geom = PadGeometry(0.008, 0.012, 0.002, 4, 6, 2)
    face = PadFace.of(geom, MAT)
    _, area0 = face_grid(face.face_xy)  # undeformed tributary areas
    s, p0, h = 1.1, 2.5e4, geom.thickness
    n = face.face_xy.shape[0]
    x = np.column_stack([s * face.face_xy, np.full(n, h)])
    normals = np.tile([0.0, 0.0, -1.0], (n, 1))
    u = x - np.column_stack([face.face_xy, np.full(n, h)])
    sol = ContactSolution(p0 * s**2 * area0, normals, u, x, 1, "synthetic", 0.0)
    prof = extract_profile(face, sol, Plane((0, 0, h), (0, 0, -1)))
    np.testing.assert_allclose(prof.pressures, p0, rtol=1e-12)
    np.testing.assert_allclose(prof.areas, s**2 * 0.002 * 0.002, rtol=1e-12)
    assert prof.F == pytest.approx(p0 * s**2 * geom.width * geom.length, rel=1e-12)
    np.testing.assert_allclose(prof.normal_wrench, [0, 0, prof.F, 0, 0, 0], atol=1e-12 * prof.F)


def _grid(xs, ys, drop=(), seed=0):
    """Face nodes of the grid xs × ys [m] without the nodes ``drop`` ((i, j) pairs), shuffled."""
    keep = [(i, j) for i in range(len(xs)) for j in range(len(ys)) if (i, j) not in drop]
    order = np.random.default_rng(seed).permutation(len(keep))
    ij = [keep[k] for k in order]
    return np.array([[xs[i], ys[j]] for i, j in ij]), {p: k for k, p in enumerate(ij)}


@pytest.mark.parametrize("drop", [(), ((2, 1),)])
def test_face_grid_of_a_graded_grid_against_a_cell_loop(drop):
    """Cells of 1, 2, 3 mm × 2, 3 mm with the nodes in random order (and, second case, the
    interior node (3 mm, 2 mm) missing as on a condensed patch: its four cells go).  Reference:
    a loop over the cells, each whole one a quad giving a quarter of its area to each corner;
    the quads are counter-clockwise seen from +z (shoelace area = +cell area)."""
    xs, ys = np.array([0.0, 1.0, 3.0, 6.0]) * 1e-3, np.array([0.0, 2.0, 5.0]) * 1e-3
    xy, index = _grid(xs, ys, drop)
    quads, area = face_grid(xy)
    ref_quads, ref_area = set(), np.zeros(len(xy))
    for i in range(3):
        for j in range(2):
            corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            if any(c not in index for c in corners):
                continue
            ref_quads.add(frozenset(index[c] for c in corners))
            for c in corners:
                ref_area[index[c]] += (xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) / 4
    assert {frozenset(q) for q in quads} == ref_quads and len(quads) == 6 - 4 * len(drop)
    np.testing.assert_allclose(area, ref_area, rtol=1e-12, atol=0)
    p = xy[quads]  # (m, 4, 2)
    shoelace = 0.5 * np.sum(
        p[:, :, 0] * np.roll(p[:, :, 1], -1, 1) - np.roll(p[:, :, 0], -1, 1) * p[:, :, 1], 1
    )
    np.testing.assert_allclose(shoelace, np.ptp(p[:, :, 0], 1) * np.ptp(p[:, :, 1], 1), rtol=1e-12)
    np.testing.assert_allclose(tributary_areas(quads, shoelace, len(xy)), ref_area, rtol=1e-12, atol=0)


def test_quad_vector_areas_are_the_polygon_vector_areas():
    """The vector area of a closed polygon x_0..x_3 is ½ Σ_k x_k × x_(k+1) (Stokes), for any
    non-planar quad; a 2 x 3 rectangle counter-clockwise in the xy plane has (0, 0, 6)."""
    rng = np.random.default_rng(2)
    q = rng.normal(size=(50, 4, 3))
    ref = 0.5 * sum(np.cross(q[:, k], q[:, (k + 1) % 4]) for k in range(4))
    np.testing.assert_allclose(quad_vector_areas(q), ref, rtol=1e-12, atol=1e-14)
    rect = np.array([[[0.0, 0, 1], [2, 0, 1], [2, 3, 1], [0, 3, 1]]])
    np.testing.assert_allclose(quad_vector_areas(rect), [[0.0, 0.0, 6.0]], rtol=1e-15)


def test_nodal_pressures_on_a_patch_with_rim_nodes():
    """A 3 x 3 node grid at 1 mm without nodes (1, 2) and (2, 1): only the cell at the
    origin is whole, its corners' tributary areas 0.25 mm²; the other nodes belong to no
    whole quad (area 0) and get pressure 0 whatever their force."""
    xs = np.array([0.0, 1.0, 2.0]) * 1e-3
    xy, index = _grid(xs, xs, drop=((1, 2), (2, 1)), seed=3)
    lam = np.full(len(xy), 7.0)
    cell = [index[c] for c in ((0, 0), (1, 0), (1, 1), (0, 1))]
    lam[cell] = 2.5e4 * 0.25e-6 * np.array([1.0, 2.0, 3.0, 4.0])
    ref = np.zeros(len(xy))
    ref[cell] = 2.5e4 * np.array([1.0, 2.0, 3.0, 4.0])
    np.testing.assert_allclose(nodal_pressures(SimpleNamespace(face_xy=xy), lam), ref, rtol=1e-12, atol=0)


def test_profile_of_spread_normals_by_hand():
    """A synthetic solution on a flat 6 x 8 mm face (2 mm cells, undeformed) whose node
    normals spread like a R 10 mm sphere's, random forces, the two columns x >= 1 mm unloaded.
    By hand: the 8 cells with a loaded corner are the elements (area 4 mm²); element pressure
    = mean of the corners' λ_i / A_i (A_i = 1, 2, 4 mm² at corners, edges, inside); element
    normal ∝ Σ corners (λ_i / A_i) n_i; F = Σ λ; and the normal-wrench force is within
    (1 - cos θ) Σ λ of −Σ λ_i n_i, θ the largest angle between normals of one cell."""
    geom = PadGeometry(width=0.006, length=0.008, thickness=0.002, nx=3, ny=4, nz=1)
    face = PadFace.of(geom, MAT)
    h, dx, R = geom.thickness, 0.002, 0.01
    xy = face.face_xy
    n = xy.shape[0]
    x = np.column_stack([xy, np.full(n, h)])
    normals = np.column_stack([xy, np.full(n, -R)])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    lam = np.random.default_rng(8).uniform(0.1, 1.0, n) * np.where(xy[:, 0] < 0.5e-3, 1.0, 0.0)
    sol = ContactSolution(lam, normals, np.zeros((n, 3)), x, 1, "synthetic", 0.0)
    prof = extract_profile(face, sol, Plane((0, 0, h), (0, 0, -1)))
    assert prof.centers.shape == (8, 3)
    np.testing.assert_allclose(prof.areas, dx * dx, rtol=1e-12)
    assert prof.F == pytest.approx(lam.sum(), rel=1e-12)
    edges = np.isclose(np.abs(xy[:, 0]), geom.width / 2).astype(int) + np.isclose(
        np.abs(xy[:, 1]), geom.length / 2
    ).astype(int)
    A = dx * dx / 2.0**edges
    for c, p, nrm in zip(prof.centers, prof.pressures, prof.normals, strict=True):
        corners = np.flatnonzero(np.all(np.isclose(np.abs(xy - c[:2]), dx / 2, rtol=0, atol=1e-12), axis=1))
        assert corners.size == 4 and c[2] == pytest.approx(h, rel=1e-12)
        assert p == pytest.approx(np.mean(lam[corners] / A[corners]), rel=1e-12)
        m = (lam[corners] / A[corners]) @ normals[corners]
        np.testing.assert_allclose(nrm, m / np.linalg.norm(m), rtol=0, atol=1e-12)
    near = np.all(np.abs(xy[:, None] - xy[None]) <= dx * (1 + 1e-9), axis=2)  # pairs in one cell
    cos_min = (normals @ normals.T)[near].min()
    f_sol = -(lam[:, None] * normals).sum(axis=0)
    err = np.linalg.norm(prof.normal_wrench[:3] - f_sol)
    assert 0 < err <= (1 - cos_min) * lam.sum()


def test_extract_profile_input_checks_no_contact_and_orphan_nodes(caplog):
    """A pad without face_xy or with another node count is rejected; no force gives None;
    a loaded node in no whole quad (the rim of a condensed patch) is left out with a
    warning: F = Σ λ less its force."""
    geom = PadGeometry(width=0.004, length=0.004, thickness=0.002, nx=2, ny=2, nz=1)
    face = PadFace.of(geom, MAT)
    n, h = face.face_xy.shape[0], geom.thickness
    x = np.column_stack([face.face_xy, np.full(n, h)])
    down = np.tile([0.0, 0.0, -1.0], (n, 1))
    plane = Plane((0, 0, h), (0, 0, -1))
    sol = ContactSolution(np.ones(n), down, np.zeros((n, 3)), x, 1, "synthetic", 0.0)
    with pytest.raises(ValueError, match="pad must have the face-node coordinates face_xy"):
        extract_profile(geom, sol, plane)
    other = PadFace.of(PadGeometry(width=0.004, length=0.004, thickness=0.002, nx=1, ny=2, nz=1), MAT)
    with pytest.raises(ValueError, match="the pad has 6 face nodes but the solution has 9 forces"):
        extract_profile(other, sol, plane)
    none = ContactSolution(np.zeros(n), down, np.zeros((n, 3)), x, 1, "synthetic", 0.0)
    assert extract_profile(face, none, plane) is None
    # the 3 x 3 grid without (1, 2) and (2, 1): one whole cell; node (2, 2) loaded but orphaned
    xy, index = _grid(np.array([0.0, 1.0, 2.0]) * 1e-3, np.array([0.0, 1.0, 2.0]) * 1e-3, ((1, 2), (2, 1)))
    m = len(xy)
    lam = np.zeros(m)
    lam[[index[c] for c in ((0, 0), (1, 0), (1, 1), (0, 1))]] = 1.0
    lam[index[(2, 2)]] = 0.5
    xz = np.column_stack([xy, np.full(m, h)])
    orphan = ContactSolution(
        lam, np.tile([0.0, 0.0, -1.0], (m, 1)), np.zeros((m, 3)), xz, 1, "synthetic", 0.0
    )
    with caplog.at_level(logging.WARNING, logger="workbench.fem.extract"):
        prof = extract_profile(SimpleNamespace(face_xy=xy), orphan, plane)
    assert prof.F == pytest.approx(4.0, rel=1e-12)
    assert "1 loaded nodes belong to no whole face quad; their 0.5 N (of 4.5 N)" in caplog.text

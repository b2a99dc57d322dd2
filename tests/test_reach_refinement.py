"""The refinement under REACH profiles (workbench.sources.reach._fine_faces) and the planar
model's PCA plane on large profiles (workbench.grasp.models.planar_profile).

A cylinder's side faces are slivers (80 mm × 0.6 mm on a 256-section elliptic cylinder):
halving every edge until the longest fits cut each into 4**7 pieces 4.7 µm across (a 20 × 40 mm
pad's profile had 62,527 elements), and the planar model then asked for a (n, n) matrix.
"""

import numpy as np
import pytest
import trimesh

H = 1e-3  # max_edge [m], the default of reach_profile
K, CLOSING = 2e8, 1e-3  # Winkler stiffness [Pa/m] and closing [m] of the presses below
PRESS = {"stiffness": K, "closing": CLOSING}  # the WinklerPress of the presses below


def _elliptic_cylinder():
    """trimesh's cylinder, 256 sections, scaled to semi-axes 30 × 20 mm, 80 mm high."""
    mesh = trimesh.creation.cylinder(radius=1.0, height=0.08, sections=256)
    mesh.apply_scale([0.03, 0.02, 1.0])
    return mesh


def _edges(tri):
    return np.linalg.norm(tri[:, [1, 2, 0]] - tri, axis=2)


def test_sliver_faces_are_cut_into_about_area_over_h2_pieces():
    """Every piece of a cut with edges <= h has area <= √3/4 h² (the equilateral triangle is the
    largest), and a face's longest edge ℓ alone needs ℓ/h pieces along it: no cut of a face has
    fewer than max(A/(√3/4 h²), ℓ/h) pieces.  Asserted: at most 4× the sum of the two plus one, per
    face — the strip cut's trapezoids have legs of ~h/√2 or more and are split in two.  The old
    subdivision put 16,384 pieces on each 24 mm² side face, where this bound is ~550."""
    from workbench.sources.reach import _cut_to_size

    mesh = _elliptic_cylinder()
    tri = mesh.triangles
    e = _edges(tri)
    assert e.max() > 0.079 and e.min() < 0.0006  # slivers: 80 mm sides, 0.5–0.74 mm across
    _, parent, _ = _cut_to_size(tri, H)
    count = np.bincount(parent, minlength=len(tri))
    bound = 4 * (mesh.area_faces / (np.sqrt(3) / 4 * H**2) + e.max(axis=1) / H + 1)
    assert (count <= bound).all(), (count / bound).max()
    assert (count >= mesh.area_faces / (np.sqrt(3) / 4 * H**2)).all()  # and no piece is too big


def test_a_pads_profile_on_the_sliver_cylinder_is_not_over_refined():
    """The pad (20 × 40 mm) on the flat side of the ellipse: its profile needs no more pieces than
    4× (A/(√3/4 h²) + the long edges under the pad / h), the bound above summed over the side faces
    the pad spans (each 40 mm of its length); the old refinement gave 62,527."""
    from workbench.sources.reach import WinklerPress, reach_profile

    mesh = _elliptic_cylinder()
    prof = reach_profile(
        mesh, (0.0, 0.02, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), press=WinklerPress(**PRESS)
    )
    side = np.abs(mesh.face_normals[:, 2]) < 0.5
    under = (
        side
        & (mesh.triangles[:, :, 1].min(axis=1) > 0)
        & (np.abs(mesh.triangles[:, :, 0]).min(axis=1) <= 0.01)
    )
    area = prof.areas.sum()
    bound = 4 * (area / (np.sqrt(3) / 4 * H**2) + under.sum() * 0.04 / H)
    assert 700e-6 < area < 800e-6  # 7.6 cm², the reported contact
    assert len(prof.areas) <= bound, (len(prof.areas), bound)


@pytest.mark.parametrize(
    "mesh",
    [
        _elliptic_cylinder(),
        trimesh.creation.box(extents=(0.06, 0.04, 0.08)),
        trimesh.creation.icosphere(4, radius=0.03),
    ],
    ids=["sliver-cylinder", "box", "icosphere"],
)
def test_pieces_fit_max_edge_and_tile_their_face(mesh):
    """Every sub-triangle's edges are <= max_edge; the closed-form shares of a face's area sum to
    1 (to round-off of the sum) and match each piece's area from its vertices (an independent
    reference); pieces keep their face's orientation and normal, in face order."""
    from workbench.sources.reach import _cut_to_size, _fine_faces

    tri = mesh.triangles
    sub, parent, share = _cut_to_size(tri, H)
    assert _edges(sub).max() <= H
    assert (np.diff(parent) >= 0).all()
    count = np.bincount(parent, minlength=len(tri))
    total = np.bincount(parent, share, minlength=len(tri))
    assert (np.abs(total - 1) <= 4 * np.finfo(float).eps * count).all(), np.abs(total - 1).max()
    cross = np.cross(sub[:, 1] - sub[:, 0], sub[:, 2] - sub[:, 0])
    np.testing.assert_allclose(
        0.5 * np.linalg.norm(cross, axis=1), share * mesh.area_faces[parent], rtol=1e-9
    )
    assert (np.einsum("ij,ij->i", cross, mesh.face_normals[parent]) > 0).all()

    cen, normal, area, par = _fine_faces(mesh.vertices, mesh.faces, H)
    np.testing.assert_array_equal(par, parent)
    np.testing.assert_allclose(cen, sub.mean(axis=1), rtol=0, atol=0)
    np.testing.assert_allclose(normal, mesh.face_normals[parent], atol=1e-12)
    np.testing.assert_allclose(np.bincount(par, area, len(tri)), mesh.area_faces, rtol=1e-12)


def test_slivers_degenerate_and_random_triangles_fit_max_edge():
    """Random triangles over three decades of size, needles (a vertex ~on the opposite edge) and
    zero-length edges: edges <= max_edge, shares sum to 1, a face within max_edge is kept whole."""
    from workbench.sources.reach import _cut_to_size

    rng = np.random.default_rng(7)
    tri = rng.normal(size=(60, 3, 3)) * 10 ** rng.uniform(-3.5, -1.5, size=(60, 1, 1))
    t = rng.uniform(0, 1, size=(15, 1))
    tri[:15, 2] = tri[:15, 0] + t * (tri[:15, 1] - tri[:15, 0]) + 1e-7 * rng.normal(size=(15, 3))
    tri[15:20, 2] = tri[15:20, 0]
    sub, parent, share = _cut_to_size(tri, H)
    assert _edges(sub).max() <= H
    count = np.bincount(parent, minlength=len(tri))
    assert (count >= 1).all()
    total = np.bincount(parent, share, minlength=len(tri))
    assert (np.abs(total - 1) <= 4 * np.finfo(float).eps * count).all()
    small = _edges(tri).max(axis=1) <= H
    assert small.any() and (count[small] == 1).all()
    np.testing.assert_array_equal(sub[np.isin(parent, np.flatnonzero(small))], tri[small])


def test_refining_some_faces_gives_their_rows_of_refining_all():
    """The cache contract of reach._fine_surface: a face's pieces depend on that face alone."""
    from workbench.sources.reach import _fine_faces

    mesh = _elliptic_cylinder()
    some = np.random.default_rng(3).random(len(mesh.faces)) < 0.3
    whole = _fine_faces(mesh.vertices, mesh.faces, H)
    part = _fine_faces(mesh.vertices, mesh.faces[some], H)
    rows = some[whole[3]]
    for w, p in zip(whole[:3], part[:3], strict=True):
        np.testing.assert_array_equal(w[rows], p)


def test_a_face_inside_the_pad_carries_k_closing_over_its_area():
    """Closed form: a flat 18 × 36 mm box face inside the 20 × 40 mm pad, pressed by 1 mm, carries
    the uniform pressure k·closing over its whole area, centred on it (sides parallel to the
    approach carry none)."""
    from workbench.sources.reach import WinklerPress, reach_profile

    box = trimesh.creation.box(extents=(0.05, 0.018, 0.036))
    prof = reach_profile(
        box, (0.025, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 0.0, 1.0), press=WinklerPress(**PRESS)
    )
    assert prof.F == pytest.approx(K * CLOSING * 0.018 * 0.036, rel=1e-12)
    np.testing.assert_allclose(prof.pressures, K * CLOSING, rtol=1e-12)
    np.testing.assert_allclose(prof.pressure_center, [0.025, 0.0, 0.0], atol=1e-15)


def test_a_pad_inside_a_face_carries_k_closing_over_the_pad_up_to_the_edge_cut():
    """A 20 × 40 mm pad centred on a 40 × 80 mm box face: pressure k·closing on the pieces whose
    centre is under the pad.  A piece with edges <= h lies within 2h/3 of its centre (2/3 of a
    median <= h), so the pieces kept cover the pad shrunk by 2h/3 and lie in it grown by 2h/3:
    k·closing·(20 - 4h/3)(40 - 4h/3) <= F <= k·closing·(20 + 4h/3)(40 + 4h/3).  The cut of a face
    is symmetric under the half turn about the face's centre (its two triangles swap), so the
    pressure centre is the pad's, to round-off."""
    from workbench.sources.reach import WinklerPress, reach_profile

    box = trimesh.creation.box(extents=(0.06, 0.04, 0.08))
    prof = reach_profile(
        box, (0.03, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 0.0, 1.0), press=WinklerPress(**PRESS)
    )
    g = 4 * H / 3
    assert K * CLOSING * (0.02 - g) * (0.04 - g) <= prof.F <= K * CLOSING * (0.02 + g) * (0.04 + g)
    np.testing.assert_allclose(prof.pressures, K * CLOSING, rtol=1e-12)
    np.testing.assert_allclose(prof.pressure_center, [0.03, 0.0, 0.0], atol=1e-15)


def test_a_pad_over_the_middle_third_of_a_face_is_cut_exactly():
    """A 10 mm pad centred on a 30 mm cube face: its edges run at 1/3 and 2/3 of the face, along
    lines of the cut (k a multiple of 3), so no piece's centre is on them and the pieces kept are
    exactly those under the pad: F = k·closing·(10 mm)² and the centre the face's, to round-off
    (the old subdivision, 64 parts a side, put centres on these edges and kept 96.7 mm²)."""
    from workbench.sources.reach import WinklerPress, reach_profile

    cube = trimesh.creation.box(extents=(0.03, 0.03, 0.03))
    for center, approach in (((0.015, 0.0, 0.0), (-1.0, 0.0, 0.0)), ((0.0, -0.015, 0.0), (0.0, 1.0, 0.0))):
        prof = reach_profile(
            cube, center, approach, (0.0, 0.0, 1.0), pad=(0.01, 0.01), press=WinklerPress(**PRESS)
        )
        assert prof.F == pytest.approx(K * CLOSING * 0.01**2, rel=1e-12)
        np.testing.assert_allclose(prof.pressure_center, center, atol=1e-15)


def _svd_full(monkeypatch):
    """numpy's SVD as planar_profile called it before: the full (n, n) U."""
    svd = np.linalg.svd
    monkeypatch.setattr(
        np.linalg, "svd", lambda a, full_matrices=True, **kw: svd(a, full_matrices=True, **kw)
    )


@pytest.mark.parametrize("n", [1, 2, 3, 40])
def test_planar_profile_is_the_same_without_the_full_svd(monkeypatch, n):
    """planar_profile's PCA plane from the reduced SVD equals the one from the full SVD (the old
    code, whose (n, n) U needed 29 GiB at 62,527 elements) to round-off, for 1, 2, 3 and 40
    elements (below 3 the reduced Vt would lack the plane's normal)."""
    from workbench.grasp.models import planar_profile
    from workbench.profile import ContactProfile

    rng = np.random.default_rng(n)
    normals = np.tile([0.0, 0.0, 1.0], (n, 1)) + rng.normal(scale=0.05, size=(n, 3))
    prof = ContactProfile(
        rng.normal(size=(n, 3)) * [3e-3, 2e-3, 2e-4],
        normals / np.linalg.norm(normals, axis=1)[:, None],
        rng.uniform(1e-7, 2e-7, n),
        rng.uniform(1e4, 2e4, n),
    )
    new = planar_profile(prof)
    with monkeypatch.context() as m:
        _svd_full(m)
        old = planar_profile(prof)
    for a, b in ((new.centers, old.centers), (new.normals, old.normals)):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-15)
    np.testing.assert_allclose(new.areas, old.areas, rtol=1e-14)


def test_planar_profile_of_a_large_profile_needs_no_n_by_n_matrix():
    """200,000 elements on a tilted plane (320 GB for the full SVD's U): the PCA plane is found
    and it is the tilted plane."""
    from workbench.grasp.models import planar_profile
    from workbench.profile import ContactProfile

    n = 200_000
    rng = np.random.default_rng(0)
    normal = np.array([0.0, 0.6, 0.8])
    e1, e2 = np.array([1.0, 0.0, 0.0]), np.cross(normal, [1.0, 0.0, 0.0])
    uv = rng.uniform(-0.01, 0.01, size=(n, 2))
    prof = ContactProfile(uv @ np.array([e1, e2]), np.tile(normal, (n, 1)), np.full(n, 1e-9), np.full(n, 1e5))
    flat = planar_profile(prof)
    np.testing.assert_allclose(flat.normals[0], normal, atol=1e-12)
    assert flat.F == pytest.approx(prof.F, rel=1e-12)

"""Rigid obstacles as signed-distance functions (workbench.fem.obstacles): the analytic
plane, sphere and cylinder against pointwise formulas and finite differences, triangle
meshes against exact distances (a box, a faceted sphere, a cylinder of slivers), units,
transforms, one-sided distances and careless input; the point-triangle kernels
(workbench.fem._kernels) against trimesh's closest_point (tests/naive.py), bit for bit."""

from pathlib import Path

import naive
import numpy as np
import pytest

from workbench.config import TOL
from workbench.fem._kernels import _nearest_of_candidates, _point_triangle_pairs
from workbench.fem.obstacles import Cylinder, EllipticCylinder, MeshObstacle, Plane, Sphere

MESHES = Path(__file__).resolve().parents[2] / "shared" / "data" / "deformable_objects" / "meshes"


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


def _fd_gradient(obs, x, eps=1e-7):
    return np.column_stack(
        [
            (obs.signed_distance(x + eps * e)[0] - obs.signed_distance(x - eps * e)[0]) / (2 * eps)
            for e in np.eye(3)
        ]
    )


def test_analytic_obstacles_against_pointwise_formulas():
    """Plane: d = (x - p)·n / |n| for a non-unit normal (0, 3, -4), |n| = 5.  Sphere:
    d = |x - c| - R.  Cylinder on the tilted axis a = (1, 2, 2) / 3: the distance from the
    axis line is |(x - p) × a| (a cross product, not the module's projection).  The normal
    is the gradient of d (central differences) and has unit length."""
    rng = np.random.default_rng(7)
    x = rng.uniform(-0.03, 0.03, (60, 3))
    p = np.array([0.001, -0.002, 0.004])
    cases = [
        (Plane(tuple(p), (0.0, 3.0, -4.0)), [float((xi - p) @ [0.0, 0.6, -0.8]) for xi in x]),
        (
            Sphere((0.002, 0.001, -0.003), 0.015),
            [float(np.linalg.norm(xi - [0.002, 0.001, -0.003]) - 0.015) for xi in x],
        ),
        (
            Cylinder(tuple(p), (1.0, 2.0, 2.0), 0.01),
            [float(np.linalg.norm(np.cross(xi - p, np.array([1.0, 2.0, 2.0]) / 3.0)) - 0.01) for xi in x],
        ),
    ]
    for obs, ref in cases:
        d, n = obs.signed_distance(x)
        assert d.shape == (60,) and n.shape == (60, 3)
        np.testing.assert_allclose(d, ref, rtol=0, atol=1e-15)
        np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, rtol=1e-14)
        np.testing.assert_allclose(n, _fd_gradient(obs, x), atol=1e-6)


def _box_sdf(q_local, half):
    """Exact signed distance of the box |q_i| <= half_i: |max(|q| - h, 0)| + min(max_i(|q_i| - h_i), 0)."""
    e = np.abs(q_local) - half
    return np.linalg.norm(np.maximum(e, 0.0), axis=1) + np.minimum(e.max(axis=1), 0.0)


def test_mesh_box_in_centimetres_moved_by_a_transform_is_the_exact_box_distance():
    """A box of 4 x 3 x 2 cm written in cm (units="cm": x 0.01), then rotated and moved by a
    4 x 4 transform in metres: its 12 flat triangles are the box itself, so the distance is
    the box's exact SDF in the box frame, inside and outside, to round-off; outside, the
    normal is the SDF's gradient, inside (away from the medial planes) the nearest face's."""
    import trimesh

    half = np.array([0.02, 0.015, 0.01])
    c, s = np.cos(0.5), np.sin(0.5)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.array(
        [[1.0, 0.0, 0.0], [0.0, np.cos(0.3), -np.sin(0.3)], [0.0, np.sin(0.3), np.cos(0.3)]]
    )
    t = np.array([0.1, -0.05, 0.2])
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    obs = MeshObstacle(trimesh.creation.box(extents=2 * half * 100), units="cm", transform=T)
    np.testing.assert_allclose(np.ptp(obs.mesh.vertices @ R, axis=0), 2 * half, rtol=1e-12)
    rng = np.random.default_rng(3)
    q = rng.uniform(-1.6, 1.6, (400, 3)) * half  # box frame: about half inside
    x = q @ R.T + t
    d, n = obs.signed_distance(x)
    ref = _box_sdf(q, half)
    assert (ref < 0).sum() > 50 and (ref > 0).sum() > 50
    np.testing.assert_allclose(d, ref, rtol=0, atol=1e-12)
    out = ref > 1e-6
    e = np.maximum(np.abs(q[out]) - half, 0.0) * np.sign(q[out])
    np.testing.assert_allclose(n[out], (e / np.linalg.norm(e, axis=1, keepdims=True)) @ R.T, atol=1e-9)
    gap = np.abs(q) - half  # inside: the nearest face is the largest gap
    top2 = np.sort(gap, axis=1)[:, -2:]
    inside = (ref < -1e-6) & (top2[:, 1] - top2[:, 0] > 1e-4)
    k = gap[inside].argmax(axis=1)
    face_n = np.zeros((inside.sum(), 3))
    face_n[np.arange(k.size), k] = np.sign(q[inside, k])
    np.testing.assert_allclose(n[inside], face_n @ R.T, atol=1e-9)
    # transformed(): the same obstacle built from the metres-mesh of the untransformed one
    again = MeshObstacle(trimesh.creation.box(extents=2 * half * 100), units="cm").transformed(T)
    np.testing.assert_allclose(again.signed_distance(x)[0], ref, rtol=0, atol=1e-12)


def test_one_sided_mesh_obstacle_measures_from_the_facing_wall():
    """A 0.4 mm wall (20 x 20 mm slab, 0 <= z <= 0.4 mm) and a jaw approaching along +z:
    a point pressed 0.3 mm in is 0.1 mm from the far face (two-sided: d = -0.1 mm, normal
    +z) but 0.3 mm past the face the jaw touches (facing=(0, 0, -1): d = -0.3 mm, normal -z);
    below the wall both give d = -z."""
    import trimesh

    slab = trimesh.creation.box(extents=[0.02, 0.02, 0.4e-3])
    slab.apply_translation([0.0, 0.0, 0.2e-3])
    x = np.array([[0.001, -0.002, 0.3e-3], [0.0, 0.0, -0.5e-3]])
    d2, n2 = MeshObstacle(slab).signed_distance(x)
    d1, n1 = MeshObstacle(slab, facing=(0.0, 0.0, -1.0)).signed_distance(x)
    np.testing.assert_allclose(d2, [-0.1e-3, 0.5e-3], rtol=1e-9)
    np.testing.assert_allclose(d1, [-0.3e-3, 0.5e-3], rtol=1e-9)
    np.testing.assert_allclose(n2, [[0, 0, 1], [0, 0, -1]], atol=1e-12)
    np.testing.assert_allclose(n1, [[0, 0, -1], [0, 0, -1]], atol=1e-12)


def test_mesh_obstacle_loads_a_file_path(tmp_path):
    """A path is loaded with trimesh (an STL written in mm, units="mm"): the 40 mm ball's
    distance at its centre is minus the faceted sphere's inscribed radius (the distance of its
    nearest face plane from the centre)."""
    import trimesh

    ball = trimesh.creation.icosphere(subdivisions=3, radius=20.0)
    path = tmp_path / "ball.stl"
    ball.export(path)
    stored = trimesh.load(path, force="mesh")  # STL keeps float32 coordinates
    # the closest face of a 1280-face icosphere: its plane's distance from the centre
    inscribed = np.abs(np.einsum("ij,ij->i", stored.face_normals, stored.triangles_center)).min() * 1e-3
    for source in (path, str(path)):
        d, _ = MeshObstacle(source, units="mm").signed_distance(np.zeros((1, 3)))
        assert d[0] == pytest.approx(-inscribed, rel=1e-9)


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Sphere((0, 0, 0), 0.0), "radius must be > 0"),
        (lambda: Sphere((0, 0, 0), np.nan), "radius must be > 0"),
        (lambda: Cylinder((0, 0, 0), (0, 1, 0), -0.01), "radius must be > 0"),
        (lambda: Cylinder((0, 0, 0), (0, 0, 0), 0.01), "finite non-zero 3-vector"),
        (lambda: Cylinder((0, 0, 0), (0, np.nan, 1), 0.01), "finite non-zero 3-vector"),
        (
            lambda: Cylinder((0, 0, 20), (0, 1, 0), 20.0),
            r"radius 20.0\) spans 40 m .*probably in millimetres",
        ),  # in mm
        (lambda: Plane((0, 0, 0), (0, 0, 0)).signed_distance(np.zeros((2, 3))), "finite non-zero 3-vector"),
        (lambda: MeshObstacle(np.zeros((4, 3))), "must be a trimesh.Trimesh or a path"),
        (lambda: MeshObstacle(__import__("trimesh").creation.box(), units="furlong"), "unit"),
    ],
)
def test_obstacles_reject_careless_input(make, match):
    with pytest.raises(ValueError, match=match):
        make()
    assert Cylinder((0, 0, 20), (0, 1, 0), 20.0, allow_scale=True).radius == 20.0


def test_elliptic_cylinder_distance_against_a_dense_ellipse_and_its_gradient():
    """Eberly's closest point against the distance to 400,001 points of the ellipse (their chord
    spacing s ~ 5e-7 m bounds the brute force's own error by s), signs against the implicit
    equation, the normal against the distance's finite-difference gradient (h = 1e-7 m: O(h²/ρ))."""
    from workbench.fem.obstacles import EllipticCylinder

    rng = np.random.default_rng(0)
    p0 = np.array([0.001, 0.002, 0.003])
    for a, b in ((0.03, 0.02), (0.02, 0.03)):
        e = EllipticCylinder(tuple(p0), (0, 1, 0), (0, 0, 1), a, b)
        x = rng.normal(0, 0.03, (300, 3)) + p0
        d, n = e.signed_distance(x)
        q = x - p0
        u, v = q[:, 2], q[:, 0]  # along major (z) and axis x major (y x z = x)
        th = np.linspace(0, 2 * np.pi, 400_001)
        P = np.column_stack([a * np.cos(th), b * np.sin(th)])
        brute = np.array([np.hypot(P[:, 0] - ui, P[:, 1] - vi).min() for ui, vi in zip(u, v, strict=True)])
        s = 2 * np.pi * max(a, b) / 400_000
        assert np.abs(np.abs(d) - brute).max() < s
        assert np.array_equal(d < 0, (u / a) ** 2 + (v / b) ** 2 < 1)
        h = 1e-7
        sd = e.signed_distance
        grad = np.column_stack([(sd(x + h * ek)[0] - sd(x - h * ek)[0]) / (2 * h) for ek in np.eye(3)])
        assert np.abs(grad - n).max() < 1e-6
        assert np.allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-12)


def test_a_circular_elliptic_cylinder_is_the_cylinder():
    from workbench.fem.obstacles import EllipticCylinder

    x = np.random.default_rng(1).normal(0, 0.03, (500, 3))
    c = Cylinder((0, 0, 0), (0, 1, 0), 0.02).signed_distance(x)
    e = EllipticCylinder((0, 0, 0), (0, 1, 0), (1, 0, 1), 0.02, 0.02).signed_distance(x)
    assert np.abs(c[0] - e[0]).max() < 1e-15 and np.abs(c[1] - e[1]).max() < 1e-14


def test_elliptic_cylinder_mesh_and_careless_input():
    from workbench.fem.obstacles import EllipticCylinder

    e = EllipticCylinder((0, 0, 0.05), (0, 1, 0), (0, 0, 1), 0.03, 0.02)
    m = e.to_trimesh(0.06, sections=360)
    assert m.is_watertight
    # the inscribed polygon's area and its vertices on the ellipse (distance 0 to round-off)
    assert m.volume == pytest.approx(0.06 * 360 / 2 * 0.03 * 0.02 * np.sin(2 * np.pi / 360), rel=1e-9)
    side = np.abs(m.vertices[:, 1]) < 0.03 - 1e-9  # none: every vertex is on an end ring
    assert not side.any()
    rim = np.hypot(m.vertices[:, 0], m.vertices[:, 2] - 0.05) > 0  # all but the two cap centres
    assert rim.sum() == 2 * 360 and np.abs(e.signed_distance(m.vertices[rim])[0]).max() < 1e-15
    with pytest.raises(ValueError, match="semi-axis a must be > 0"):
        EllipticCylinder(a=0.0)
    with pytest.raises(ValueError, match="parallel"):
        EllipticCylinder(axis=(0, 1, 0), major=(0, 2, 0))
    with pytest.raises(ValueError, match="metres"):
        EllipticCylinder(a=30.0, b=20.0)


@pytest.mark.parametrize(
    "make",
    [
        lambda: Sphere((0.0, float("nan"), 0.02), 0.02),
        lambda: Cylinder((0.0, 0.0, float("inf")), radius=0.02),
        lambda: EllipticCylinder(point=(float("nan"), 0.0, 0.0)),
        lambda: Plane(point=(0.0, 0.0)),
    ],
)
def test_a_point_that_is_not_a_finite_3_vector_is_refused(make):
    """A NaN centre made every distance NaN, read downstream as "no contact"."""
    with pytest.raises(ValueError, match=r"finite \(3,\) point"):
        make()


# ------------------------------------------------------------------ point-triangle kernels
def _pairs(tris, x, L):
    """The kernel's closest points and distances of the pairs (tris[k], x[k])."""
    m = len(x)
    pts, dist = np.empty((m, 3)), np.empty(m)
    tris, x = np.ascontiguousarray(tris, dtype=float), np.ascontiguousarray(x, dtype=float)
    _point_triangle_pairs(tris, x, np.arange(m), np.arange(m), L, TOL.point_triangle_zero, pts, dist)
    return pts, dist


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _region_points(rng, tris, out):
    """A point in each Voronoi region of every triangle (A, B, C) — beyond vertex A, B, C on its
    outer bisector, beyond edge AB, BC, CA, over the face — ``out`` (m,) times the triangle's
    longest edge out in its plane and as far off it (either side).  Returns the points (m, 7, 3)
    and the closest points the regions imply (m, 7, 3)."""
    m = len(tris)
    A, B, C = tris[:, 0], tris[:, 1], tris[:, 2]
    n = _unit(np.cross(B - A, C - A))
    size = np.linalg.norm(tris - np.roll(tris, 1, axis=1), axis=2).max(axis=1)
    off = (out * size)[:, None]
    up = off * rng.choice([-1.0, 1.0], (m, 1)) * n
    pts, feet = [], []
    for P, Q, R in ((A, B, C), (B, C, A), (C, A, B)):  # vertex P: (x - P)·(Q - P) < 0, (x - P)·(R - P) < 0
        pts.append(P - off * _unit(_unit(Q - P) + _unit(R - P)) + up)
        feet.append(P)
    for P, Q, R in ((A, B, C), (B, C, A), (C, A, B)):  # edge PQ, on the side away from R
        F = P + rng.uniform(0.2, 0.8, (m, 1)) * (Q - P)
        e = _unit(np.cross(Q - P, n))
        e *= np.sign(np.einsum("ij,ij->i", F - R, e))[:, None]
        pts.append(F + off * e + up)
        feet.append(F)
    w = rng.dirichlet([2.0, 2.0, 2.0], m)
    F = w[:, :1] * A + w[:, 1:2] * B + w[:, 2:] * C
    pts.append(F + up)
    feet.append(F)
    return np.stack(pts, axis=1), np.stack(feet, axis=1)


def test_point_triangle_kernel_is_trimesh_closest_point_bit_for_bit_in_every_region():
    """Random triangles with edges of 0.1 mm to 10 m (needles among them) around random centres,
    one point in each of their seven Voronoi regions from 1e-6 to 1e3 edges away: the kernel's
    closest points and distances equal trimesh's closest_point in the same query-centred,
    L-scaled frame bit for bit.  At L = 3 mm (the measured meshes' mean edges are 1.9-3.8 mm)
    each point's closest point is the one its region implies; at L = 1 m and 100 m the 0.1 mm
    triangles' dot products fall below the region tests' absolute 1e-13 and some points land in
    the wrong region (trimesh's problem with mm faces in metres, the reason for the frame) —
    the same wrong numbers from both."""
    rng = np.random.default_rng(11)
    m = 300
    size = 10.0 ** rng.uniform(-4.0, 1.0, m)
    tris = rng.normal(size=(m, 1, 3)) + rng.normal(size=(m, 3, 3)) * size[:, None, None]
    needle = rng.random(m) < 0.2  # C close to the line AB: long thin triangles
    tris[needle, 2] = 0.5 * (tris[needle, 0] + tris[needle, 1]) + 1e-3 * (tris[needle, 2] - tris[needle, 0])
    out = 10.0 ** rng.uniform(-6.0, 3.0, m)
    x, feet = _region_points(rng, tris, out)
    tri7, x7 = np.repeat(tris, 7, axis=0), x.reshape(-1, 3)
    longest = np.repeat(np.linalg.norm(tris - np.roll(tris, 1, axis=1), axis=2).max(axis=1), 7)
    for L in (3e-3, 1.0, 1e2):
        pts, dist = _pairs(tri7, x7, L)
        ref_pts, ref_dist = naive.point_triangle_closest(tri7, x7, L, TOL.point_triangle_zero)
        assert np.array_equal(pts, ref_pts) and np.array_equal(dist, ref_dist)
        if L == 3e-3:
            # every region met: the closest point is the vertex / the edge's or the face's foot, to
            # round-off of the distance (1e-10 relative on the needles' faces, 1e-3 of an edge wide)
            miss = np.linalg.norm(pts - feet.reshape(-1, 3), axis=1)
            assert (miss <= 1e-9 * (longest + np.linalg.norm(x7 - feet.reshape(-1, 3), axis=1))).all()


def _segment_distance(x, a, b):
    ab = b - a
    ll = np.einsum("ij,ij->i", ab, ab)
    t = np.einsum("ij,ij->i", x - a, ab) / np.where(ll > 0, ll, 1.0)
    return np.linalg.norm(a + np.clip(t, 0.0, 1.0)[:, None] * ab - x, axis=1)


def test_point_triangle_kernel_on_degenerate_triangles_is_trimesh_bit_for_bit():
    """Zero-area triangles: a repeated vertex (A = B, which trimesh treats as the segment AC
    first; A = C; B = C; all three) and three distinct collinear corners in every order, with
    coordinates and points on a half-integer grid (no round-off in the frame at L = 1): the same
    numbers as trimesh, and the distance to the segment they span.  Corners collinear only up to
    round-off are trimesh's too (the face test then divides by a round-off area, and both can
    miss the segment's distance by O(edge); no measured object mesh has such a face)."""
    rng = np.random.default_rng(12)
    m = 1500
    A = rng.integers(-2, 3, (m, 3)).astype(float)
    B = rng.integers(-2, 3, (m, 3)).astype(float)
    C = A + rng.choice([-1.0, 0.0, 0.5, 1.0, 2.0], (m, 1)) * (B - A)  # on the line AB
    corners = np.stack([A, B, C], axis=1)
    cases = [
        corners[np.arange(m)[:, None], rng.permuted(np.tile([0, 1, 2], (m, 1)), axis=1)],  # any order
        np.stack([A, A, B], axis=1),  # A = B
        np.stack([A, B, A], axis=1),  # A = C
        np.stack([A, B, B], axis=1),  # B = C
        np.stack([A, A, A], axis=1),  # a point
    ]
    x = rng.integers(-6, 7, (m, 3)) * 0.5
    for tris in cases:
        pts, dist = _pairs(tris, x, 1.0)
        ref_pts, ref_dist = naive.point_triangle_closest(tris, x, 1.0, TOL.point_triangle_zero)
        assert np.array_equal(pts, ref_pts) and np.array_equal(dist, ref_dist)
        a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
        hull = np.minimum(
            np.minimum(_segment_distance(x, a, b), _segment_distance(x, b, c)), _segment_distance(x, a, c)
        )
        np.testing.assert_allclose(dist, hull, rtol=0, atol=1e-14)
    # collinear up to round-off, at mixed scales: trimesh's numbers, whatever they are
    size = 10.0 ** rng.uniform(-4.0, 1.0, m)[:, None]
    A = rng.normal(size=(m, 3))
    B = A + rng.normal(size=(m, 3)) * size
    tris = np.stack([A, B, A + rng.uniform(-1.0, 2.0, (m, 1)) * (B - A)], axis=1)
    x = A + rng.normal(size=(m, 3)) * size * 10.0 ** rng.uniform(-3.0, 2.0, (m, 1))
    pts, dist = _pairs(tris, x, 3e-3)
    ref_pts, ref_dist = naive.point_triangle_closest(tris, x, 3e-3, TOL.point_triangle_zero)
    assert np.array_equal(pts, ref_pts) and np.array_equal(dist, ref_dist)


def test_nearest_candidate_kernel_picks_as_argmin():
    """Per point the nearest of its candidate triangles, the first of equal distances (repeated
    candidates) and the first NaN (a triangle with a NaN corner) as argmin picks them."""
    rng = np.random.default_rng(13)
    tris = rng.normal(size=(40, 3, 3)) * 0.01
    tris[7, 1, 2] = np.nan
    x = rng.normal(size=(50, 3)) * 0.02
    cand = rng.integers(0, 40, (50, 12))
    cand[:, 6] = cand[:, 2]  # ties: the earlier column wins
    cand[::5, 9] = 7  # NaN from column 9 on (and where 7 was drawn earlier)
    got = np.empty((50, 3)), np.empty(50), np.empty(50, dtype=np.int64)
    ref = np.empty((50, 3)), np.empty(50), np.empty(50, dtype=np.int64)
    _nearest_of_candidates(tris, x, cand, 5e-3, TOL.point_triangle_zero, *got)
    with np.errstate(invalid="ignore"):
        naive.nearest_of_candidates(tris, x, cand, 5e-3, TOL.point_triangle_zero, *ref)
    assert np.isnan(got[1][::5]).all()
    for g, r in zip(got, ref, strict=True):
        assert np.array_equal(g, r, equal_nan=True)


def _near_surface_points(rng, mesh, n, spread):
    """``n`` points about the faces of ``mesh``: a random point of a random face moved along its
    normal by N(0, spread) [m]."""
    f = rng.integers(0, len(mesh.faces), n)
    w = rng.dirichlet([1.0, 1.0, 1.0], n)
    on = np.einsum("ij,ijk->ik", w, mesh.triangles[f])
    return on + mesh.face_normals[f] * rng.normal(0.0, spread, (n, 1))


@pytest.mark.parametrize("source", ["sphere", "mustard"])
def test_mesh_obstacle_queries_are_the_trimesh_ones_bit_for_bit(source, monkeypatch):
    """MeshObstacle.closest and signed_distance (two-sided and one-sided) with the kernels
    against the same queries with trimesh's closest_point in their place (the code before the
    kernels: tests/naive.py): equal bit for bit, on a 20 mm faceted sphere and on a measured
    object's mesh, at points within ±0.3 mm (a pressed pad's face) and ±3 mm of the surface.  The
    copies the queries read are trimesh's arrays and cannot be written."""
    import trimesh

    import workbench.fem.obstacles as fo

    if source == "sphere":
        obs = MeshObstacle(trimesh.creation.icosphere(subdivisions=4, radius=20.0), units="mm")
    else:
        path = MESHES / f"{source}.obj"
        if not path.exists():
            pytest.skip(f"{path} not present (deformable_objects data)")
        obs = MeshObstacle(path)
    rng = np.random.default_rng(14)
    x = np.concatenate([_near_surface_points(rng, obs.mesh, 150, s) for s in (3e-4, 3e-3)])
    one_sided = obs.transformed(np.eye(4), facing=(1.0, 0.0, -1.0))

    def queries():
        return [q for o in (obs, one_sided) for q in (*o.closest(x), *o.signed_distance(x))]

    new = queries()
    monkeypatch.setattr(fo, "_nearest_of_candidates", naive.nearest_of_candidates)
    monkeypatch.setattr(fo, "_point_triangle_pairs", naive.point_triangle_pairs)
    old = queries()
    for a, b in zip(new, old, strict=True):
        assert np.array_equal(a, b)
    for copy, theirs in (
        (obs._triangles, obs.mesh.triangles),
        (obs._face_normals, obs.mesh.face_normals),
        (obs._corner_normals, obs.mesh.vertex_normals[obs.mesh.faces]),
    ):
        assert np.array_equal(copy, theirs) and not copy.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        obs._triangles[0, 0, 0] = 1.0

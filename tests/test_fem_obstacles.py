"""Rigid obstacles as signed-distance functions (workbench.fem.obstacles): the analytic
plane, sphere and cylinder against pointwise formulas and finite differences, triangle
meshes against exact distances (a box, a faceted sphere, a cylinder of slivers), units,
transforms, one-sided distances and careless input."""

import numpy as np
import pytest

from workbench.fem.obstacles import Cylinder, EllipticCylinder, MeshObstacle, Plane, Sphere


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
        (lambda: Cylinder((0, 0, 20), (0, 1, 0), 20.0), "20 mm = 0.02"),  # a radius in mm
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

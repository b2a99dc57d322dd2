"""Bottle family obstacles (workbench/fem/bottle.py): exact signed distance against an
independent fine triangle mesh, normals against finite differences, poses."""

import numpy as np
import pytest

from workbench.fem.bottle import Bottle, BottleParams, bottle_family, grasp_pose
from workbench.fem.pad import PadGeometry


@pytest.fixture(scope="module")
def family():
    return bottle_family(24, 8, seed=0)


def _near_wall(b, rng, n=400):
    H = b.params.height
    th, z = rng.uniform(0, 2 * np.pi, n), rng.uniform(0.2 * H, 0.8 * H, n)
    pts, nrm = b.points_normals(th, z)
    off = rng.uniform(-0.004, 0.006, n)
    return pts + off[:, None] * nrm, off


def test_family_counts_and_shapes(family):
    assert len(family) == 24 and sum(p.asymmetric for p in family) == 8
    assert not any(p.asymmetric for p in family[:16])
    again = bottle_family(24, 8, seed=0)
    assert again == family  # seeded


def test_signed_distance_is_exact(family):
    rng = np.random.default_rng(0)
    for p in (family[0], family[-1]):  # upright and leaning
        b = Bottle(p)
        x, off = _near_wall(b, rng)
        d, n = b.signed_distance(x)
        # points built at a known offset along the true normal: exact to round-off
        assert np.abs(d - off).max() < 1e-12
        # the normal is the gradient of the distance (central differences)
        eps = 1e-7
        g = np.column_stack(
            [
                (b.signed_distance(x + eps * e)[0] - b.signed_distance(x - eps * e)[0]) / (2 * eps)
                for e in np.eye(3)
            ]
        )
        assert np.abs(g - n).max() < 1e-6


def test_distance_matches_a_fine_mesh(family):
    from workbench.fem.obstacles import MeshObstacle

    b = Bottle(family[-1])
    mesh = b.to_trimesh(384, 401)
    assert mesh.is_watertight and mesh.volume > 0
    x, _ = _near_wall(b, np.random.default_rng(1), 200)
    d, _ = b.signed_distance(x)
    _, dist, _ = MeshObstacle(mesh).closest(x)  # point-triangle distances, not the SDF above
    # chord error of the mesh: sagitta c² / (8 ρ) with chords c <= 2π (70 mm) / 384 and
    # height steps ~0.5 mm, curvature radii ρ >= 8 mm: < 2.2e-5 m
    assert np.abs(dist - np.abs(d)).max() < 2.2e-5


def test_grasp_pose_touches_and_is_a_rotation(family):
    geom = PadGeometry()
    xs, ys, _ = geom.axes()
    xy = np.array(np.meshgrid(xs, ys)).reshape(2, -1).T
    face = np.column_stack([xy, np.full(len(xy), geom.thickness)])
    for p in (family[3], family[20]):
        b = Bottle(p)
        for ang in (0.0, np.pi / 2):
            pose = grasp_pose(b, 0.5 * p.height, ang, xy, geom.thickness)
            assert np.allclose(pose.R.T @ pose.R, np.eye(3), atol=1e-14) and np.isclose(
                np.linalg.det(pose.R), 1
            )
            d, n = pose.signed_distance(face)
            assert abs(d.min()) < 1e-10  # first touch at zero jaw displacement
            assert (n[d < 1e-3] @ [0, 0, -1] > 0.5).all()  # the wall faces the jaw
            assert np.isclose(pose.R[:, 1] @ [0, 0, 1], 1)  # long pad side vertical


def test_bad_parameters():
    with pytest.raises(ValueError, match="must be > 0"):
        BottleParams(a0=-0.01)
    with pytest.raises(ValueError, match="finite"):
        BottleParams(height=np.nan)
    with pytest.raises(ValueError, match="negative radius"):
        Bottle(BottleParams(s1=1.0, s2=0.01, s3=3.0))
    with pytest.raises(ValueError, match="n_asymmetric"):
        bottle_family(4, 5)

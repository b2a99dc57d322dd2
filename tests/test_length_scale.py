"""ContactProfile.length_scale (thesis §3.3.2 l_s) is invariant under rigid motion,
also for symmetric profiles whose principal axes are not unique."""

import naive
import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from workbench import ContactProfile
from workbench.profile import pca_box_longest_side


def _plain_pca_box(points):
    """The plain PCA box (the former implementation): SVD axes as they come."""
    centered = points - points.mean(axis=0)
    _, _, axes = np.linalg.svd(centered, full_matrices=False)
    extent = centered @ axes.T
    return float((extent.max(axis=0) - extent.min(axis=0)).max())


def _motions(k=8):
    rng = np.random.default_rng(5)
    for i in range(k):
        yield Rotation.random(random_state=100 + i).as_matrix(), rng.uniform(-0.5, 0.5, 3)


def _profile(points):
    n = len(points)
    return ContactProfile(points, np.tile([0.0, 0.0, 1.0], (n, 1)), np.full(n, 1e-6), np.ones(n))


def _moved(prof, R, t):
    # built afresh (not through .transformed), so nothing cached is carried over
    return ContactProfile(prof.centers @ R.T + t, prof.normals @ R.T, prof.areas, prof.pressures)


def _square(side=0.02, n=21):
    x, y = np.meshgrid(np.linspace(0, side, n), np.linspace(0, side, n))
    return np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])


def _polygon_rings(radius=0.01, n=64):
    th = 2 * np.pi * np.arange(n) / n
    rings = [r * np.column_stack([np.cos(th), np.sin(th), np.zeros(n)]) for r in (0.3, 0.6, 1.0)]
    return radius * np.vstack([np.zeros((1, 3)), *rings])


@pytest.mark.parametrize(
    "points, expect",
    [
        # a square's smallest box is the square itself
        (_square(), 0.02),
        # a regular 64-gon: the box flush with edges on both axes (64 divisible by 4), side 2 R cos(π/64)
        (_polygon_rings(), 2 * 0.01 * np.cos(np.pi / 64)),
    ],
    ids=["square", "disc"],
)
def test_symmetric_profiles_invariant_under_rigid_motion(points, expect):
    prof = _profile(points)
    assert prof.length_scale == pytest.approx(expect, rel=1e-12)
    for R, t in _motions():
        assert _moved(prof, R, t).length_scale == pytest.approx(expect, rel=1e-12)


def test_plain_pca_box_was_not_invariant():
    # the cause: equal principal variances leave the SVD axes to rounding — the square's box
    # turned between its side (0.02) and its diagonal, the disc's by ~1e-3
    values = [_plain_pca_box(_square() @ R.T + t) for R, t in _motions()]
    assert max(values) / min(values) - 1 > 0.1


def test_isotropic_point_set_uses_its_diameter():
    # all three principal variances equal (icosphere vertices): the diameter, 2 r
    pts = np.asarray(trimesh.creation.icosphere(subdivisions=2, radius=0.03).vertices)
    assert pca_box_longest_side(pts) == pytest.approx(0.06, rel=1e-12)
    for R, t in _motions(4):
        assert pca_box_longest_side(pts @ R.T + t) == pytest.approx(0.06, rel=1e-12)


def test_non_symmetric_profiles_unchanged(rng):
    # distinct principal variances: identical to the plain PCA box, to the last bit
    for _ in range(5):
        c, nrm, a, p = naive.random_profile(rng, 300)
        prof = ContactProfile(c, nrm, a, p)
        assert prof.length_scale == _plain_pca_box(c)
    rect = _square() * [1.0, 0.5, 1.0]  # 20 x 10 mm
    assert pca_box_longest_side(rect) == _plain_pca_box(rect) == pytest.approx(0.02, rel=1e-12)

"""Numerical stress: scale and frame covariance, extreme pressures, tiny slip,
near-planar and near-collinear profiles, bad twist arrays."""

import warnings

import naive
import numpy as np
import pytest

from workbench import ContactProfile, frictional_wrenches, normal_wrench, sample_twists_thesis


def _profile(rng, n=400):
    c, nrm, a, p = naive.random_profile(rng, n)
    return ContactProfile(c, nrm, a, p)


@pytest.mark.parametrize("s", [1e-6, 1e-4, 1e-2, 1.0, 1e1, 1e3])
def test_scale_covariance(rng, s):
    # lengths x s at fixed pressure => forces x s^2, torques x s^3 (CONVENTIONS.md)
    prof = _profile(rng)
    big = ContactProfile(prof.centers * s, prof.normals, prof.areas * s**2, prof.pressures, allow_scale=True)
    xi = sample_twists_thesis(100, prof, seed=9)
    xi_s = xi.copy()
    xi_s[:, :3] *= s  # v = h e + m carries a length
    w = frictional_wrenches(prof, xi, 0.8)
    ws = frictional_wrenches(big, xi_s, 0.8)
    scale = np.array([s**2] * 3 + [s**3] * 3)
    ref_scale = np.array([prof.F] * 3 + [prof.F * prof.length_scale] * 3)
    assert (np.abs(ws / scale - w) / ref_scale).max() <= 1e-9
    wn = normal_wrench(big) / scale
    assert (np.abs(wn - normal_wrench(prof)) / ref_scale).max() <= 1e-9


def test_frame_covariance(rng):
    prof = _profile(rng)
    R = np.linalg.qr(rng.standard_normal((3, 3)))[0]
    R *= np.sign(np.linalg.det(R))
    moved = prof.transformed(R, [0.3, -1.0, 1.5])  # far, within the 2 m of any object
    xi = sample_twists_thesis(100, prof, seed=10)
    xi_r = np.hstack([xi[:, :3] @ R.T, xi[:, 3:] @ R.T])  # twists about o rotate with the frame
    w = frictional_wrenches(prof, xi)
    w_r = frictional_wrenches(moved, xi_r)
    expect = np.hstack([w[:, :3] @ R.T, w[:, 3:] @ R.T])
    ref_scale = np.array([prof.F] * 3 + [prof.F * prof.length_scale] * 3)
    assert (np.abs(w_r - expect) / ref_scale).max() <= 1e-12
    wn = normal_wrench(prof)
    np.testing.assert_allclose(
        normal_wrench(moved), np.concatenate([R @ wn[:3], R @ wn[3:]]), atol=1e-12 * ref_scale.max()
    )


def test_pressures_spanning_twelve_decades(rng):
    c, nrm, a, _ = naive.random_profile(rng, 500)
    p = 10.0 ** rng.uniform(-3, 9, 500)
    prof = ContactProfile(c, nrm, a, p)
    xi = sample_twists_thesis(50, prof, seed=11)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = frictional_wrenches(prof, xi)
    ref = naive.fw_vectorized(c, nrm, a, p, xi, 1.0)
    ref_scale = np.array([prof.F] * 3 + [prof.F * prof.length_scale] * 3)
    assert np.isfinite(got).all()
    assert (np.abs(got - ref) / ref_scale).max() <= 1e-10


def test_tiny_tangential_velocity_is_finite(rng):
    # twist axis passing within 1e-15 m of element centers: |v_i| ~ 1e-15, direction still defined
    prof = _profile(rng, 200)
    o = prof.pressure_center
    xi = []
    for i in range(20):
        q = prof.centers[i] - o + 1e-15 * rng.standard_normal(3)
        e = prof.normals[i]  # rotation about the element normal: slip ~ 1e-15 at the center
        xi.append(np.concatenate([np.cross(q, e), e]))
    xi = np.array(xi)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        w = frictional_wrenches(prof, xi)
    assert np.isfinite(w).all()
    # the element's own contribution is bounded by mu p a, so the sum stays within mu F (forces)
    assert (np.linalg.norm(w[:, :3], axis=1) <= prof.F * (1 + 1e-12)).all()
    ref = naive.fw_vectorized(prof.centers, prof.normals, prof.areas, prof.pressures, xi, 1.0)
    # elements other than the near-axis one are well conditioned: agreement up to one
    # element's worth of direction noise
    assert (np.abs(w - ref)[:, :3].max(axis=1) <= 2 * prof.forces.max()).all()


def test_slip_along_normal_with_rounding_noise_is_zero():
    # normals that are unit only to rounding, velocity exactly along them: v_t is pure
    # rounding noise (~1e-17) and must be treated as sticking, not amplified to a unit direction
    rng = np.random.default_rng(0)
    n = rng.standard_normal((100, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    c = np.zeros((100, 3))
    prof = ContactProfile(c, n, np.ones(100), np.ones(100), allow_scale=True)  # l_s = sqrt(100 m²)
    for i in range(10):
        assert np.all(
            frictional_wrenches(prof.with_pressures(np.eye(100)[i] + 0.0), np.r_[n[i], 0, 0, 0])[:3] == 0
        )


def test_near_planar_and_near_collinear_profiles(rng):
    n = 300
    for jitter, width in ((1e-13, 1.0), (0.0, 1e-12)):
        x = rng.uniform(-0.01, 0.01, n)
        y = width * rng.uniform(-0.01, 0.01, n)
        z = jitter * rng.standard_normal(n)
        c = np.column_stack([x, y, z])
        nrm = np.column_stack([1e-12 * rng.standard_normal((n, 2)), np.ones(n)])
        prof = ContactProfile(c, nrm, np.full(n, 1e-6), rng.uniform(1e3, 1e5, n), normalize_normals=True)
        xi = sample_twists_thesis(100, prof, seed=12)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            got = frictional_wrenches(prof, xi)
        ref = naive.fw_vectorized(prof.centers, prof.normals, prof.areas, prof.pressures, xi, 1.0)
        ref_scale = np.array([prof.F] * 3 + [prof.F * prof.length_scale] * 3)
        assert np.isfinite(got).all()
        assert (np.abs(got - ref) / ref_scale).max() <= 1e-10


@pytest.mark.parametrize(
    "twists, match",
    [
        (np.zeros((5, 3)), r"twists must have shape \(K, 6\)"),
        (np.zeros((6, 5)), r"twists must have shape \(K, 6\)"),
        (np.zeros((2, 6, 1)), r"twists must have shape \(K, 6\)"),
        (np.array([[np.nan, 0, 0, 0, 0, 1.0]]), "twists must be finite"),
        ("abc", "twists must be a numeric"),
    ],
)
def test_bad_twists_raise(rng, twists, match):
    prof = _profile(rng, 10)
    with pytest.raises(ValueError, match=match):
        frictional_wrenches(prof, twists)


@pytest.mark.parametrize("mu", [-0.1, np.nan, "x"])
def test_bad_mu_raises(rng, mu):
    with pytest.raises(ValueError, match="mu must be"):
        frictional_wrenches(_profile(rng, 10), np.eye(6), mu)


def test_non_profile_raises():
    with pytest.raises(ValueError, match="profile must be a ContactProfile"):
        frictional_wrenches(np.zeros((3, 3)), np.eye(6))

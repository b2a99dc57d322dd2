"""The Numba 6DFW / normal-wrench kernels against the slow NumPy references."""

import naive
import numpy as np
import pytest

from workbench import (
    ContactProfile,
    canonical_twists,
    frictional_wrenches,
    mesh_profile,
    normal_wrench,
    sample_twists_6dfc,
    sample_twists_thesis,
    w_max,
)
from workbench.sources.surface_catalog import S3, S5


def _scale(profile, mu):
    """Per-component magnitude scale: mu*F for forces, mu*F*l_s for torques."""
    s = mu * profile.F
    return np.array([s] * 3 + [s * profile.length_scale] * 3)


def _assert_close(got, ref, profile, mu, rtol=1e-10):
    err = np.abs(got - ref) / _scale(profile, mu)
    assert err.max() <= rtol, f"max scaled error {err.max():.3g}"


def _arrays(p):
    return p.centers, p.normals, p.areas, p.pressures


@pytest.mark.parametrize("curved", [True, False])
def test_random_profiles_match_vectorized_reference(rng, curved):
    for n in (1, 7, 300, 1001):
        c, nrm, a, pr = naive.random_profile(rng, n, curved)
        pr[0] = max(pr[0], 1.0)  # never all-zero
        prof = ContactProfile(c, nrm, a, pr)
        xi = np.vstack(
            [
                sample_twists_thesis(50, prof, seed=1),
                sample_twists_6dfc(40, 10, prof, seed=2),
                rng.standard_normal((20, 6)),
                canonical_twists(),
            ]
        )
        mu = 0.7
        got = frictional_wrenches(prof, xi, mu)
        ref = naive.fw_vectorized(c, nrm, a, pr, xi, mu)
        _assert_close(got, ref, prof, mu)


def test_loop_reference_agrees_with_vectorized_reference(rng):
    c, nrm, a, pr = naive.random_profile(rng, 60)
    xi = sample_twists_thesis(10, 0.02, seed=3)
    loop = np.array([naive.fw_loop(c, nrm, a, pr, x, 0.5) for x in xi])
    vec = naive.fw_vectorized(c, nrm, a, pr, xi, 0.5)
    np.testing.assert_allclose(loop, vec, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("surface", [S3, S5])
def test_curved_meshes_match_reference(surface):
    mesh = mesh_profile(surface, 400)
    prof = mesh.with_pressures(np.linspace(1.0, 3.0, len(mesh)))  # non-uniform pressure
    xi = sample_twists_thesis(100, prof, seed=4)
    got = frictional_wrenches(prof, xi, 1.0)
    ref = naive.fw_vectorized(*_arrays(prof), xi, 1.0)
    _assert_close(got, ref, prof, 1.0)


def test_normal_wrench_matches_reference(rng):
    c, nrm, a, pr = naive.random_profile(rng, 500)
    prof = ContactProfile(c, nrm, a, pr)
    ref = naive.normal_wrench(c, nrm, a, pr)
    np.testing.assert_allclose(normal_wrench(prof), ref, rtol=1e-12, atol=1e-12 * prof.F * prof.length_scale)
    np.testing.assert_allclose(prof.normal_wrench, ref, rtol=1e-12, atol=1e-12 * prof.F * prof.length_scale)


def test_planar_normal_wrench_is_minus_F_along_normal():
    # flat square, uniform pressure: w_perp = [0, 0, -F, 0, 0, 0] exactly (Eq. 3.2)
    x, y = np.meshgrid(np.linspace(-1, 1, 10), np.linspace(-1, 1, 10))
    c = np.column_stack([x.ravel(), y.ravel(), np.zeros(100)]) * 0.01
    prof = ContactProfile(c, np.tile([0, 0, 1.0], (100, 1)), np.full(100, 4e-6), np.full(100, 5e4))
    np.testing.assert_allclose(prof.normal_wrench, [0, 0, -prof.F, 0, 0, 0], atol=1e-15)


def test_zero_tangential_velocity_contributes_exactly_zero():
    # flat patch, translation along the normal: no element slips -> zero wrench, no NaN
    c = np.array([[0.0, 0, 0], [0.01, 0, 0], [0, 0.01, 0]])
    n = np.tile([0.0, 0, 1], (3, 1))
    prof = ContactProfile(c, n, np.full(3, 1e-6), np.full(3, 1e5))
    w = frictional_wrenches(prof, [0, 0, 1.0, 0, 0, 0])
    assert np.all(w == 0.0)
    # pure rotation about the normal through element 0's center: element 0 sticks,
    # the others slip -> matches the reference that skips element 0 explicitly
    o = prof.pressure_center
    q = c[0] - o
    xi = np.concatenate([np.cross(q, [0, 0, 1.0]), [0, 0, 1.0]])
    got = frictional_wrenches(prof, xi)
    ref = naive.fw_loop(c, n, prof.areas, prof.pressures, xi, 1.0)
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-18)
    # the zero twist is no slip direction (its friction is undefined): refused by name, and a
    # batch with one zero row says which
    with pytest.raises(ValueError, match=r"row 0 is all zeros .*sample unit twists"):
        frictional_wrenches(prof, np.zeros(6))
    with pytest.raises(ValueError, match="row 1 is all zeros"):
        frictional_wrenches(prof, [[0, 0, 1.0, 0, 0, 0], [0.0] * 6])


def test_zero_pressure_elements_contribute_nothing(rng):
    c, nrm, a, pr = naive.random_profile(rng, 50)
    pr[::2] = 0.0
    full = ContactProfile(c, nrm, a, pr)
    sub = ContactProfile(c[1::2], nrm[1::2], a[1::2], pr[1::2])
    xi = sample_twists_thesis(20, full, seed=5)
    np.testing.assert_allclose(
        frictional_wrenches(full, xi), frictional_wrenches(sub, xi), rtol=1e-12, atol=1e-15
    )


def test_single_twist_shape_and_mu_linearity(rng):
    prof = ContactProfile(*naive.random_profile(rng, 30))
    xi = sample_twists_thesis(3, prof, seed=6)
    w1 = frictional_wrenches(prof, xi[0], 1.0)
    assert w1.shape == (6,)
    np.testing.assert_allclose(frictional_wrenches(prof, xi, 0.25)[0], 0.25 * w1, rtol=1e-14)


def test_friction_dissipates_power(rng):
    # Coulomb friction opposes slip: xi . w(xi) = -mu * sum p a |v_t| <= 0
    prof = ContactProfile(*naive.random_profile(rng, 200))
    xi = sample_twists_thesis(200, prof, seed=7)
    power = np.einsum("ij,ij->i", xi, frictional_wrenches(prof, xi, 1.0))
    assert (power < 0).all()


def test_w_max_is_support_function_upper_bound_of_samples(rng):
    prof = mesh_profile(S3, 300).normalized()
    exact = w_max(prof)
    assert (exact > 0).all()
    xi = sample_twists_thesis(3000, prof, seed=8)
    sampled = np.abs(frictional_wrenches(prof, xi)).max(axis=0)
    assert (sampled <= exact * (1 + 1e-12)).all()
    assert (sampled >= 0.9 * exact).all()  # dense sampling gets close to the support value
    # any wrench satisfies xi.w >= -h(xi) = xi.w(xi) for the maximising twist (max dissipation)
    W = frictional_wrenches(prof, xi)
    for k in range(6):
        e = np.eye(6)[k]
        assert (W @ e >= -exact[k] * (1 + 1e-12)).all()


def test_segment_kernel_matches_reference_per_segment(rng):
    # _fw_segments (used by the surface quadrature) against the reference on each segment
    from workbench import _kernels

    c, nrm, a, p = naive.random_profile(rng, 240)
    o = naive.pressure_center(c, a, p)
    xi = sample_twists_thesis(5, 0.02, seed=13)  # 10 twists
    starts = np.array([0, 17, 17, 100, 163, 240], dtype=np.int64)  # includes an empty segment
    seg_twist = np.array([3, 0, 9, 5, 1], dtype=np.int64)
    r = c - o
    out = np.empty((5, 6))
    cols = [
        np.ascontiguousarray(x) for x in (r[:, 0], r[:, 1], r[:, 2], nrm[:, 0], nrm[:, 1], nrm[:, 2], p * a)
    ]
    _kernels._fw_segments(xi, seg_twist, starts[:-1], starts[1:], *cols, 0.4, 1e-24, out)
    for j in range(5):
        sl = slice(starts[j], starts[j + 1])
        ref = np.zeros(6)
        for ci, ni, ai, pi in zip(c[sl], nrm[sl], a[sl], p[sl], strict=True):
            # naive element loop with the torque arm about the *whole* profile's center
            u = xi[seg_twist[j], :3] + np.cross(xi[seg_twist[j], 3:], ci - o)
            t = u - (u @ ni) * ni
            if np.linalg.norm(t) > naive.TANGENTIAL_RTOL * np.linalg.norm(u):
                df = -0.4 * pi * ai * t / np.linalg.norm(t)
                ref += np.concatenate([df, np.cross(ci - o, df)])
        np.testing.assert_allclose(out[j], ref, rtol=1e-10, atol=1e-10 * (p * a).sum() * 0.02)


def test_friction_directions_sum_to_the_wrench_force(rng):
    from workbench.wrench import friction_directions

    prof = ContactProfile(*naive.random_profile(rng, 300))
    for xi in sample_twists_thesis(5, prof, seed=14):
        d = friction_directions(prof, xi)
        norms = np.linalg.norm(d, axis=1)
        assert np.all((np.abs(norms - 1) < 1e-12) | (norms == 0))
        assert np.abs(np.einsum("ij,ij->i", d, prof.normals)).max() < 1e-12  # tangential
        f = (prof.forces[:, None] * d).sum(axis=0)  # f = -μ Σ p a v̂_r = μ Σ p a d  (μ = 1)
        np.testing.assert_allclose(frictional_wrenches(prof, xi)[:3], f, atol=1e-12 * prof.F)


def test_parallel_kernel_is_deterministic(rng):
    prof = ContactProfile(*naive.random_profile(rng, 1000))
    xi = sample_twists_thesis(300, prof, seed=15)
    first = frictional_wrenches(prof, xi)
    for _ in range(3):
        np.testing.assert_array_equal(frictional_wrenches(prof, xi), first)

"""MuJoCo's condim=6 elliptic cone (workbench.peers.mujoco_cone): membership and support function
against their definitions, the maximum-dissipation wrench against the 6DFW of a matched profile,
the coefficient mapping from Hertz and flat profiles, MuJoCo itself on the torsional axis (skipped
without ``mujoco``), careless input."""

from __future__ import annotations

import numpy as np
import pytest

from workbench import ContactProfile, frictional_wrenches
from workbench.peers.hertz import hertz_contact_radius, hertz_force, hertz_profile
from workbench.peers.mujoco_cone import (
    MUJOCO_MIN_MU,
    check_coefficients,
    cone_friction_wrenches,
    cone_support,
    contact_basis,
    in_cone,
    mujoco_coefficients_from_profile,
    mujoco_torsion_response,
    torsion_coefficient,
)
from workbench.wrench import normal_wrench, w_max

MU5 = np.array([0.5, 0.4, 2e-3, 1e-3, 5e-4])


def _flat_disc(a: float = 5e-3, n_r: int = 30, n_t: int = 60, uniform: bool = True) -> ContactProfile:
    """A flat disc of radius a in z = 0, normals -z (outward from the object above), polar cells."""
    edges = np.linspace(0, a, n_r + 1)
    r = np.repeat(0.5 * (edges[1:] + edges[:-1]), n_t)
    t = np.tile((np.arange(n_t) + 0.5) * 2 * np.pi / n_t, n_r)
    areas = np.repeat(np.pi * np.diff(edges**2) / n_t, n_t)
    centers = np.column_stack([r * np.cos(t), r * np.sin(t), np.zeros_like(r)])
    normals = np.tile([0.0, 0.0, -1.0], (len(r), 1))
    p = np.full(len(r), 1e4) if uniform else 1e4 * (1 - (r / a) ** 2)
    return ContactProfile(centers, normals, areas, p)


def test_membership_follows_the_documented_definition():
    # K = {f : f_1 >= 0, f_1² >= Σ f_i² / μ_{i-1}²}: f_n e_0 + μ_i f_n e_i is on the boundary
    fn = 2.0
    for i in range(5):
        f = np.zeros(6)
        f[0], f[i + 1] = fn, MU5[i] * fn
        assert in_cone(f, MU5)
        f[i + 1] *= 1 + 1e-6
        assert not in_cone(f, MU5)
    assert not in_cone([-1.0, 0, 0, 0, 0, 0], MU5)  # the contact cannot pull
    assert in_cone([0.0, 0, 0, 0, 0, 0], MU5)
    # a 0 coefficient allows no force on its axis; MJCF's (slide, torsion, roll) expands to 5
    assert not in_cone([1.0, 0, 0, 0, 1e-3, 0], [0.5, 0.5, 2e-3, 0, 0])
    assert check_coefficients([0.5, 2e-3, 1e-3]).tolist() == [0.5, 0.5, 2e-3, 1e-3, 1e-3]
    rng = np.random.default_rng(0)
    f = rng.normal(size=(1000, 6))
    q = ((f[:, 1:] / MU5) ** 2).sum(axis=1)
    assert (in_cone(f, MU5) == ((f[:, 0] >= 0) & (q <= f[:, 0] ** 2))).all()


def test_support_function_is_the_maximum_over_the_slice():
    # max d·f over f_1 = f_n, Σ (f_i/μ_i)² <= f_n²: substitute f_i = μ_i f_n g_i, |g| <= 1, so by
    # Cauchy-Schwarz the max is f_n (d_1 + |(μ_i d_i)|), attained at g ∝ (μ_i d_i)
    rng = np.random.default_rng(1)
    d = rng.normal(size=(20, 6))
    fn = 3.0
    h = cone_support(d, MU5, fn)
    g = rng.normal(size=(5000, 5))
    g /= np.linalg.norm(g, axis=1, keepdims=True)
    samples = np.column_stack([np.full(len(g), fn), fn * MU5 * g])
    assert (samples @ d.T <= h[None, :] * (1 + 1e-12)).all()
    for k in range(len(d)):
        md = MU5 * d[k, 1:]
        f = np.concatenate([[fn], fn * MU5 * md / np.linalg.norm(md)])
        assert in_cone(f, MU5, rtol=1e-9)
        assert f @ d[k] == pytest.approx(h[k], rel=1e-12)
    assert cone_support(d[0], MU5, fn) == pytest.approx(h[0])


def test_contact_basis_is_orthogonal_with_the_normal_force_first():
    n = np.array([0.3, -0.2, 0.9])
    E = contact_basis(n)
    assert np.allclose(E.T @ E, np.eye(6), atol=1e-15)
    assert np.allclose(E[:3, 0], -n / np.linalg.norm(n))  # the normal force on the object is -f_n n
    assert np.allclose(contact_basis([1.0, 0, 0]).T @ contact_basis([1.0, 0, 0]), np.eye(6), atol=1e-15)


def test_max_dissipation_wrench_matches_the_6dfw_of_a_flat_disc_on_the_axes():
    # flat uniform disc of radius a: sliding capacity μF, torsional 2μFa/3 (∫ r dA / A = 2a/3);
    # matched coefficients make the cone's maximum-dissipation wrench equal the 6DFW for pure
    # translations and the pure rotation about the normal
    a, mu = 5e-3, 0.6
    prof = _flat_disc(a)
    coef = mujoco_coefficients_from_profile(prof, mu)
    assert coef.friction[:2] == pytest.approx([mu, mu], rel=1e-12)
    assert coef.friction[2] == pytest.approx(w_max(prof, mu)[5] / prof.F, rel=1e-12)
    assert coef.friction[2] == pytest.approx(torsion_coefficient(a, mu, "uniform"), rel=2e-3)  # cells
    assert coef.f_n == pytest.approx(prof.F, rel=1e-12) and coef.friction[3:].tolist() == [0.0, 0.0]
    xi = np.array([[1.0, 0, 0, 0, 0, 0], [0, 1.0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 1.0], [0.3, -0.2, 0, 0, 0, 0]])
    cone = cone_friction_wrenches(xi, coef.normal, coef.friction, coef.f_n)
    assert np.allclose(cone, frictional_wrenches(prof, xi, mu), rtol=0, atol=1e-9 * prof.F)
    # no frictional slip (translation along the normal) gives zero, not NaN
    assert cone_friction_wrenches([0, 0, 1.0, 0, 0, 0], coef.normal, coef.friction, 1.0).tolist() == [0.0] * 6
    # every maximum-dissipation wrench lies on the cone's boundary
    rng = np.random.default_rng(2)
    w = cone_friction_wrenches(rng.normal(size=(50, 6)), coef.normal, MU5, 2.0)
    f = w @ coef.basis  # E.T w
    f[:, 0] = 2.0
    q = ((f[:, 1:] / MU5) ** 2).sum(axis=1)
    assert np.allclose(q, 4.0, rtol=1e-12)


def test_coefficients_from_a_hertz_profile():
    # Hertz: τ_max = 3π μ F a / 16, so μ_torsion = 3π μ a / 16 × F / f_n (f_n = net normal force)
    R, d, E, nu, mu = 0.02, 1e-3, 1e6, 0.45, 0.5
    prof = hertz_profile(R, d, E, nu, 12, 24)
    a, F = hertz_contact_radius(R, d), hertz_force(R, d, E, nu)
    coef = mujoco_coefficients_from_profile(prof, mu)
    assert coef.f_n == pytest.approx(normal_wrench(prof)[2], rel=1e-12)
    assert np.allclose(coef.normal, [0, 0, -1], atol=1e-12)
    assert coef.friction[2] * coef.f_n == pytest.approx(3 * np.pi * mu * F * a / 16, rel=1e-12)
    assert coef.friction[2] == pytest.approx(torsion_coefficient(a, mu, "hertz") * F / coef.f_n, rel=1e-12)
    # curved cap: sliding capacity per unit net normal force slightly above μ (F > f_n)
    assert mu < coef.friction[0] < mu * F / coef.f_n * (1 + 1e-12)
    # rolling: zero by default; from the 6DFW it is non-zero only because the cap is curved
    rolled = mujoco_coefficients_from_profile(prof, mu, rolling="profile")
    assert rolled.friction[3] > 0 and rolled.friction[3] == pytest.approx(rolled.friction[4], rel=1e-9)
    flat = mujoco_coefficients_from_profile(_flat_disc(uniform=False), mu, rolling="profile")
    assert flat.friction[3:].max() < 1e-12
    assert len(coef.mjcf_pair_friction.split()) == 5


def test_torsion_coefficient_factors():
    a, mu = 4e-3, 0.5
    assert torsion_coefficient(a, mu) == pytest.approx(3 * np.pi / 16 * mu * a)
    assert torsion_coefficient(a, mu, "foundation") == pytest.approx(8 / 15 * mu * a)
    assert torsion_coefficient(a, mu, "uniform") == pytest.approx(2 / 3 * mu * a)


def test_against_mujoco_itself_on_the_torsional_axis():
    # MuJoCo's own contact force on a sphere resting on a plane, torque about the normal: below the
    # capacity μ_torsion f_n it sticks (τ_n = the load); above, it spins with τ_n on the boundary
    pytest.importorskip("mujoco")
    prof = hertz_profile(0.02, 1e-3, 1e6, 0.45, 8, 16)
    coef = mujoco_coefficients_from_profile(prof, 0.5)
    f, used = mujoco_torsion_response(coef.friction, 0.5)
    # MuJoCo reports the coefficients it was given (its floor of 1e-5 on the zero rolling ones)
    assert np.allclose(used, np.maximum(coef.friction, MUJOCO_MIN_MU), rtol=1e-12, atol=0)
    assert in_cone(f, used, rtol=1e-9)
    assert abs(f[3]) == pytest.approx(0.5 * coef.friction[2] * 1.0, rel=5e-3)  # weight 1 N
    f, used = mujoco_torsion_response(coef.friction, 2.0)
    assert in_cone(f, used, rtol=1e-6)
    assert abs(f[3]) / (used[2] * f[0]) == pytest.approx(1.0, rel=1e-6)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: in_cone(np.zeros(6), [0.5, 0.5]), "5 coefficients"),
        (lambda: in_cone(np.zeros(6), [0.5, 0.5, -1e-3, 0, 0]), ">= 0"),
        (lambda: in_cone(np.zeros(6), [0.5, 0.5, 1.3, 0, 0]), "millimetres"),  # torsion in mm
        (lambda: in_cone(np.zeros(5), MU5), r"\(K, 6\)"),
        (lambda: in_cone([np.nan] * 6, MU5), "finite"),
        (lambda: cone_support(np.zeros(6), MU5, -1.0), ">= 0"),
        (lambda: cone_friction_wrenches([0, 0, 1.0, 0, 0, 0], [0, 0, 0], MU5), "non-zero"),  # zero normal
        (lambda: cone_friction_wrenches(np.zeros(6), [0, 0, 1], MU5), "nonzero slip"),  # zero twist
        (lambda: mujoco_coefficients_from_profile("profile", 0.5), "ContactProfile"),
        (lambda: mujoco_coefficients_from_profile(_flat_disc(), 0.0), "friction"),
        (lambda: mujoco_coefficients_from_profile(_flat_disc(), 0.5, rolling="yes"), "rolling"),
        (lambda: torsion_coefficient(4.0, 0.5), "millimetres"),  # a in mm
        (lambda: torsion_coefficient(4e-3, 0.5, "parabolic"), "pressure"),
    ],
)
def test_careless_input_raises_saying_what_and_the_fix(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_patch_coefficients_are_a_users_estimate_of_the_patch():
    from workbench.peers.mujoco_cone import patch_coefficients

    rho, delta, mu = 15e-3, 1e-3, 0.5
    a = np.sqrt(rho * delta)
    hz = patch_coefficients(mu, rho, delta, "hertz")
    assert hz.tolist()[:2] == [mu, mu] and hz.tolist()[3:] == [0.0, 0.0]  # no rolling resistance
    assert hz[2] == pytest.approx(torsion_coefficient(a, mu, "hertz"), rel=1e-15)
    assert patch_coefficients(mu, rho, delta, "diameter")[2] == pytest.approx(2 * a * mu, rel=1e-15)
    with pytest.raises(ValueError, match="torsion must be one of"):
        patch_coefficients(mu, rho, delta, "radius")
    with pytest.raises(ValueError, match="curvature radius"):
        patch_coefficients(mu, rho, 20e-3, "hertz")  # deeper than the surface is curved

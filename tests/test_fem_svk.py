"""St. Venant–Kirchhoff assembly (workbench.fem.svk, its Numba element loop in fem._kernels) against
scikit-fem's form language of the same equations (the slow reference), its derivative by central
differences, and the linear stiffness at u = 0 against scikit-fem's linear_elasticity."""

import numpy as np
import pytest
from skfem import BilinearForm, LinearForm, asm
from skfem.helpers import ddot, eye, grad, mul, trace, transpose
from skfem.models.elasticity import linear_elasticity

from workbench.fem.svk import linear_stiffness, svk_tangent
from workbench.fem.wall import PET, build_wall, circle_surface


def _svk(w_u, mu, lam):
    F = grad(w_u) + eye(np.ones_like(grad(w_u)[0, 0]), 3)
    identity = eye(np.ones_like(F[0, 0]), 3)
    E = 0.5 * (mul(transpose(F), F) - identity)
    return F, identity, lam * trace(E) * identity + 2 * mu * E


@BilinearForm
def _tangent_ref(du, v, w):
    F, identity, S = _svk(w["u"], w["mu"], w["lam"])
    dF = grad(du)
    dE = 0.5 * (mul(transpose(F), dF) + mul(transpose(dF), F))
    dS = w["lam"] * trace(dE) * identity + 2 * w["mu"] * dE
    return ddot(mul(dF, S) + mul(F, dS), grad(v))


@LinearForm
def _residual_ref(v, w):
    F, _, S = _svk(w["u"], w["mu"], w["lam"])
    return ddot(mul(F, S), grad(v))


@pytest.fixture(scope="module")
def small_wall():
    return build_wall(circle_surface(0.03), thickness=1e-3, n_theta=8, n_z=2, z_range=(0.0, 0.02))


def test_svk_assembly_matches_scikit_fem_forms(small_wall):
    b = small_wall.basis
    u = 2e-3 * np.random.default_rng(0).standard_normal(b.N)  # rotations of order 0.1-1: far from linear
    K, r = svk_tangent(b, u, PET.mu, PET.lam)
    ui = b.interpolate(u)
    K_ref = asm(_tangent_ref, b, u=ui, mu=PET.mu, lam=PET.lam)
    r_ref = asm(_residual_ref, b, u=ui, mu=PET.mu, lam=PET.lam)
    assert abs(K - K_ref).max() < 1e-12 * abs(K_ref).max()
    assert np.abs(r - r_ref).max() < 1e-12 * np.abs(r_ref).max()
    # at u = 0 the tangent is the linear stiffness and nothing is stressed
    K0, r0 = svk_tangent(b, np.zeros(b.N), PET.mu, PET.lam)
    KL = asm(linear_elasticity(PET.lam, PET.mu), b)
    assert abs(K0 - KL).max() < 1e-12 * abs(KL).max() and not r0.any()
    # the linear walls' stiffness is that tangent
    assert abs(linear_stiffness(b, PET.mu, PET.lam) - KL).max() < 1e-12 * abs(KL).max()


def test_svk_tangent_is_the_derivative_of_the_force(small_wall):
    b = small_wall.basis
    rng = np.random.default_rng(1)
    u, du = 1e-3 * rng.standard_normal(b.N), 1e-8 * rng.standard_normal(b.N)
    K, _ = svk_tangent(b, u, PET.mu, PET.lam)
    _, rp = svk_tangent(b, u + du, PET.mu, PET.lam)
    _, rm = svk_tangent(b, u - du, PET.mu, PET.lam)
    assert np.abs((rp - rm) / 2 - K @ du).max() < 1e-6 * np.abs(K @ du).max()


def test_careless_displacements_are_refused(small_wall):
    b = small_wall.basis
    with pytest.raises(ValueError, match=rf"u must be \({b.N},\) finite displacements"):
        svk_tangent(b, np.zeros(b.N - 1), PET.mu, PET.lam)
    u = np.zeros(b.N)
    u[3] = np.nan
    with pytest.raises(ValueError, match="finite displacements"):
        svk_tangent(b, u, PET.mu, PET.lam)

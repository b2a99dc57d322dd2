"""SRI linear elasticity against the Lamé thick-walled cylinder (plane strain),
the classic volumetric-locking benchmark."""

import pytest

from workbench.fem.material import Material
from workbench.fem.validation import lame_cylinder_fe


def lame_inner_displacement(material, p=1.0, a=1.0, b=2.0):  # independent reference
    E, nu = material.E, material.nu
    return (1 + nu) * p * a**2 / (E * (b**2 - a**2)) * ((1 - 2 * nu) * a + b**2 / a)


def solve_cylinder(material, scheme):
    return lame_cylinder_fe(material, scheme)


@pytest.mark.parametrize("nu", [0.3, 0.45, 0.499, 0.4999])
def test_sri_matches_lame_solution(nu):
    mat = Material(E=1.0e6, nu=nu)
    exact = lame_inner_displacement(mat)
    assert solve_cylinder(mat, "sri") == pytest.approx(exact, rel=0.02)


def test_full_integration_locks_and_sri_does_not():
    mat = Material(E=1.0e6, nu=0.4999)
    exact = lame_inner_displacement(mat)
    full = solve_cylinder(mat, "full")
    sri = solve_cylinder(mat, "sri")
    assert full < 0.8 * exact  # locked: too stiff by > 25%
    assert abs(sri / exact - 1) < 0.02


@pytest.mark.parametrize("scheme", ["sri", "full"])
def test_stiffness_has_the_six_rigid_modes_and_the_uniaxial_energy(scheme):
    """On a distorted hex block: K is symmetric, annihilates the 3 translations and 3 rotations,
    and a homogeneous uniaxial strain e_xx = eps at nu = 0 stores (E/2) eps^2 V (exact for any
    trilinear mesh: the field is linear, so every quadrature integrates it exactly)."""
    import numpy as np
    from skfem import MeshHex

    from workbench.fem.elasticity import basis, stiffness

    mesh = MeshHex.init_tensor(np.linspace(0, 0.02, 4), np.linspace(0, 0.01, 3), np.linspace(0, 0.005, 3))
    x0 = mesh.p.copy()
    x0[0] += 0.1 * x0[1] * x0[2] / 0.005  # shear the block (non-parallelepiped hexes)
    mesh = MeshHex(x0, mesh.t)
    K = stiffness(mesh, Material(2.0e6, 0.0), scheme)
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    dofs = basis(mesh).nodal_dofs  # (3, n_nodes): the x, y, z dof of each node
    x = mesh.p
    modes = [np.eye(3)[i][:, None] * np.ones_like(x) for i in range(3)]
    modes += [np.cross(np.eye(3)[i], x.T).T for i in range(3)]  # u = w x X, infinitesimal rotations
    for m in modes:
        u = np.zeros(K.shape[0])
        u[dofs] = m
        assert np.abs(K @ u).max() <= 1e-9 * abs(K).max() * np.abs(u).max()
    eps = 1e-3
    u = np.zeros(K.shape[0])
    u[dofs[0]] = eps * x[0]
    volume = 0.02 * 0.01 * 0.005  # shearing x by a function of (y, z) keeps the volume
    assert 0.5 * u @ (K @ u) == pytest.approx(0.5 * 2.0e6 * eps**2 * volume, rel=1e-10)


@pytest.mark.parametrize("scheme", ["sri", "full"])
def test_stiffness_matches_scikit_fem_forms(scheme):
    """The Numba-assembled K against scikit-fem's ``asm`` of the SRI forms written out
    (deviatoric on 2x2x2 points, volumetric on the centre point, or both on 2x2x2), on a
    distorted block with nu near 0.5 (the volumetric part dominates)."""
    import numpy as np
    from skfem import BilinearForm, MeshHex, asm
    from skfem.helpers import ddot, sym_grad, trace

    from workbench.fem.elasticity import GAUSS_1, GAUSS_2, basis, stiffness

    @BilinearForm
    def deviatoric(u, v, w):
        eu, ev = sym_grad(u), sym_grad(v)
        return 2.0 * w["mu"] * (ddot(eu, ev) - trace(eu) * trace(ev) / 3.0)

    @BilinearForm
    def volumetric(u, v, w):
        return w["kappa"] * trace(sym_grad(u)) * trace(sym_grad(v))

    mesh = MeshHex.init_tensor(np.linspace(0, 0.02, 5), np.linspace(0, 0.01, 4), np.linspace(0, 0.005, 3))
    x0 = mesh.p.copy()
    x0[2] += 0.2 * x0[0] * x0[1] / 0.02  # warp the top (non-parallelepiped hexes)
    mesh = MeshHex(x0, mesh.t)
    mat = Material(1.0e6, 0.49)
    ref = asm(deviatoric, basis(mesh, GAUSS_2), mu=mat.mu) + asm(
        volumetric, basis(mesh, GAUSS_2 if scheme == "full" else GAUSS_1), kappa=mat.bulk
    )
    K = stiffness(mesh, mat, scheme)
    assert K.shape == ref.shape == (3 * mesh.p.shape[1],) * 2
    assert abs(K - ref).max() <= 1e-12 * abs(ref).max()
    assert K.has_sorted_indices

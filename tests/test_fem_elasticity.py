"""SRI linear elasticity against the Lamé thick-walled cylinder (plane strain),
the classic volumetric-locking benchmark."""

import numpy as np
import pytest
from skfem import FacetBasis, LinearForm, MeshHex, asm, condense, solve
from skfem.helpers import dot

from fem.elasticity import ELEMENT, basis, stiffness
from fem.material import Material


def quarter_annulus(a=1.0, b=2.0, nr=8, nt=12, t=0.25):
    m = MeshHex.init_tensor(np.linspace(a, b, nr + 1), np.linspace(0, np.pi / 2, nt + 1), np.array([0.0, t]))
    r, th, z = m.p
    return MeshHex(np.array([r * np.cos(th), r * np.sin(th), z]), m.t)


def lame_inner_displacement(material, p=1.0, a=1.0, b=2.0):
    E, nu = material.E, material.nu
    return (1 + nu) * p * a**2 / (E * (b**2 - a**2)) * ((1 - 2 * nu) * a + b**2 / a)


def solve_cylinder(material, scheme, p=1.0, a=1.0, b=2.0):
    mesh = quarter_annulus(a, b)
    K = stiffness(mesh, material, scheme)
    # flat facets on the inner circle have midpoints at a cos(dθ/2) < a
    inner = mesh.facets_satisfying(lambda x: np.hypot(x[0], x[1]) < a + 0.01 * (b - a), boundaries_only=True)
    fb = FacetBasis(mesh, ELEMENT, facets=inner)

    @LinearForm
    def pressure(v, w):
        r = np.hypot(w.x[0], w.x[1])
        return p * dot(np.array([w.x[0] / r, w.x[1] / r, 0 * r]), v)

    f = asm(pressure, fb)
    nodal = basis(mesh).nodal_dofs  # (3, N): dof of each component at each node
    x, y, _ = mesh.p
    fixed = np.concatenate([nodal[0][np.isclose(x, 0)], nodal[1][np.isclose(y, 0)], nodal[2]])  # plane strain
    u = solve(*condense(K, f, D=np.unique(fixed)))
    on_inner = np.isclose(np.hypot(x, y), a)
    ur = (x * u[nodal[0]] + y * u[nodal[1]])[on_inner] / a
    return float(ur.mean())


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


@pytest.mark.parametrize(
    "E, nu", [(0.0, 0.3), (-1.0, 0.3), (1e6, 0.5), (1e6, -1.0), (1e6, 0.7), (np.nan, 0.3)]
)
def test_bad_material(E, nu):
    with pytest.raises(ValueError, match="E must be|nu must be"):
        Material(E=E, nu=nu)

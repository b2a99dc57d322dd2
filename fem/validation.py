"""Validation problems with closed-form answers (used by tests and ``fem-validation``)."""

from __future__ import annotations

import numpy as np
from skfem import FacetBasis, LinearForm, MeshHex, asm, condense, solve
from skfem.helpers import dot

from .elasticity import ELEMENT, basis, stiffness
from .material import Material


def lame_inner_displacement(material: Material, p: float = 1.0, a: float = 1.0, b: float = 2.0) -> float:
    """Lamé: inner radial displacement of a plane-strain thick cylinder under internal pressure p."""
    E, nu = material.E, material.nu
    return (1 + nu) * p * a**2 / (E * (b**2 - a**2)) * ((1 - 2 * nu) * a + b**2 / a)


def lame_cylinder_fe(
    material: Material,
    scheme: str,
    *,
    nr: int = 8,
    nt: int = 12,
    p: float = 1.0,
    a: float = 1.0,
    b: float = 2.0,
) -> float:
    """FE inner radial displacement of the same problem: a quarter cylinder of hexes with
    symmetry planes and plane strain (u_z = 0), the classic volumetric-locking benchmark."""
    m = MeshHex.init_tensor(
        np.linspace(a, b, nr + 1), np.linspace(0, np.pi / 2, nt + 1), np.array([0.0, 0.25])
    )
    r, th, z = m.p
    mesh = MeshHex(np.array([r * np.cos(th), r * np.sin(th), z]), m.t)
    K = stiffness(mesh, material, scheme)
    # flat facets on the inner circle have midpoints at a cos(dθ/2) < a
    inner = mesh.facets_satisfying(lambda x: np.hypot(x[0], x[1]) < a + 0.01 * (b - a), boundaries_only=True)

    @LinearForm
    def pressure(v, w):
        rr = np.hypot(w.x[0], w.x[1])
        return p * dot(np.array([w.x[0] / rr, w.x[1] / rr, 0 * rr]), v)

    nodal = basis(mesh).nodal_dofs  # (3, N): dof of each component at each node
    x, y, _ = mesh.p
    fixed = np.unique(np.concatenate([nodal[0][np.isclose(x, 0)], nodal[1][np.isclose(y, 0)], nodal[2]]))
    u = solve(*condense(K, asm(pressure, FacetBasis(mesh, ELEMENT, facets=inner)), D=fixed))
    on_inner = np.isclose(np.hypot(x, y), a)
    return float(((x * u[nodal[0]] + y * u[nodal[1]])[on_inner] / a).mean())

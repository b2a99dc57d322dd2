"""Linear elasticity on trilinear hexes with selective reduced integration (SRI).

Nearly incompressible silicone (nu -> 0.5) locks fully integrated trilinear
hexes.  SRI splits the energy into a deviatoric part ``2 mu dev(e):dev(e)``,
integrated with 2x2x2 Gauss points, and a volumetric part ``K tr(e)²``
integrated with one point at the element center (scikit-fem's ``intorder``
never gives one point on hexes, so the quadrature is passed explicitly).
``scheme="full"`` integrates both parts with 2x2x2 points (for comparison).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementHex1, ElementVector, MeshHex

from .material import Material

_G = 0.5 / np.sqrt(3.0)
#: 2x2x2 Gauss points on the reference hex [0, 1]^3 (exact for trilinear stiffness on parallelepipeds)
GAUSS_2 = (
    np.array(
        np.meshgrid([0.5 - _G, 0.5 + _G], [0.5 - _G, 0.5 + _G], [0.5 - _G, 0.5 + _G], indexing="ij")
    ).reshape(3, -1),
    np.full(8, 1.0 / 8.0),
)
#: one point at the element center
GAUSS_1 = (np.full((3, 1), 0.5), np.array([1.0]))

ELEMENT = ElementVector(ElementHex1())


def basis(mesh: MeshHex, quadrature=GAUSS_2) -> Basis:
    """Vector trilinear basis with an explicit quadrature rule."""
    return Basis(mesh, ELEMENT, quadrature=quadrature)


def stiffness(mesh: MeshHex, material: Material, scheme: str = "sri") -> sp.csr_matrix:
    """Global stiffness matrix (3 N × 3 N) csr of a hex mesh [N/m].

    SRI: ``∫ 2μ (ε:ε − tr ε tr ε / 3)`` on 2x2x2 points plus ``∫ κ tr ε tr ε`` on the centre
    point; each is a linear-elastic form with Lamé pair (μ, −2μ/3) and (0, κ), assembled by the
    Numba element loop of :func:`workbench.fem.svk.linear_stiffness` into one sparsity pattern
    (the same matrix as scikit-fem's ``asm`` of the two forms to rounding, ``tests/test_fem_elasticity.py``,
    and faster: docs/decisions.md).  ``scheme="full"``: both parts on 2x2x2
    points, the Lamé pair (μ, λ).
    """
    from .svk import svk_tangent

    if scheme not in ("sri", "full"):
        raise ValueError(f"scheme must be 'sri' or 'full'; got {scheme!r}")
    mu = material.mu
    c2: dict = {}
    zero = np.zeros(3 * mesh.p.shape[1])
    if scheme == "full":
        return svk_tangent(basis(mesh, GAUSS_2), zero, mu, material.lam, c2)[0]
    K, _ = svk_tangent(basis(mesh, GAUSS_2), zero, mu, -2.0 * mu / 3.0, c2)
    c1 = {k: c2[k] for k in ("slot", "indices", "indptr", "dofs")}  # same elements, same pattern
    K_vol, _ = svk_tangent(basis(mesh, GAUSS_1), zero, 0.0, material.bulk, c1)
    K.data += K_vol.data
    return K

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
from skfem import Basis, BilinearForm, ElementHex1, ElementVector, MeshHex, asm
from skfem.helpers import ddot, sym_grad, trace

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


@BilinearForm
def _deviatoric(u, v, w):
    eu, ev = sym_grad(u), sym_grad(v)
    return 2.0 * w["mu"] * (ddot(eu, ev) - trace(eu) * trace(ev) / 3.0)


@BilinearForm
def _volumetric(u, v, w):
    return w["kappa"] * trace(sym_grad(u)) * trace(sym_grad(v))


def basis(mesh: MeshHex, quadrature=GAUSS_2) -> Basis:
    """Vector trilinear basis with an explicit quadrature rule."""
    return Basis(mesh, ELEMENT, quadrature=quadrature)


def stiffness(mesh: MeshHex, material: Material, scheme: str = "sri") -> sp.csr_matrix:
    """Global stiffness matrix (3 N × 3 N) of a hex mesh [N/m]."""
    if scheme not in ("sri", "full"):
        raise ValueError(f"scheme must be 'sri' or 'full'; got {scheme!r}")
    b2 = basis(mesh, GAUSS_2)
    K_dev = asm(_deviatoric, b2, mu=material.mu)
    b_vol = b2 if scheme == "full" else basis(mesh, GAUSS_1)
    K_vol = asm(_volumetric, b_vol, kappa=material.bulk)
    return (K_dev + K_vol).tocsr()

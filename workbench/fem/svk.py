"""St. Venant–Kirchhoff internal force and tangent stiffness of a vector hex basis (total
Lagrangian), assembled by a Numba element loop (``fem._kernels._svk_element_loop``):

    E = ½ (FᵀF − I),   S = λ tr(E) I + 2μ E,   P = F S
    dP[δF] = δF S + F (λ tr(δE) I + 2μ δE),   δE = sym(Fᵀ δF)

At ``u = 0`` the tangent is the linear-elastic stiffness (:func:`linear_stiffness`, the linear
walls' ``K``, the same matrix as scikit-fem's ``linear_elasticity`` form to rounding, assembled
many times faster: ``results/benchmarks/newton.json``).
Used by :mod:`workbench.fem.wall` and :mod:`workbench.fem.wall_nonlinear`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ._kernels import _svk_element_loop
from .sparse_factor import csr_slots


def _gradients(basis) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per local dof k of a vector basis: its component ``comp`` (81,), the gradient of
    its scalar shape function ``g`` (e, q, 81, 3) and the weights × det J ``w`` (e, q)."""
    comp, g = [], []
    for k in range(basis.Nbfun):
        G = np.asarray(basis.basis[k][0].grad)  # (3, 3, e, q): row = component
        c = int(np.argmax(np.abs(G).reshape(3, -1).max(axis=1)))
        comp.append(c)
        g.append(G[c])
    return np.array(comp), np.moveaxis(np.array(g), (0, 1), (2, 3)), np.asarray(basis.dx)


def svk_tangent(
    basis, u: np.ndarray, mu: float, lam: float, cache: dict | None = None, *, tangent: bool = True
) -> tuple:
    """Tangent stiffness ``K`` (N, N) csr and internal force ``r`` (N,) of a St. Venant–
    Kirchhoff solid at displacement ``u`` (N,) (module docstring), total Lagrangian.

    basis : a scikit-fem vector basis (e.g. the wall's ``ElementVector(ElementHex2())``);
    mu, lam : Lamé parameters [Pa]; cache : a dict kept between calls on one basis
    (shape-function gradients and the sparsity pattern; a new dict may be given the pattern
    ``slot``, ``indices``, ``indptr``, ``dofs`` of another basis on the same elements);
    tangent : False for ``(None, r)``, the internal force alone.
    """
    c = {} if cache is None else cache
    if "G" not in c:
        comp, g, w = _gradients(basis)
        nn = comp.size // 3
        interleaved = np.array_equal(comp, np.tile([0, 1, 2], nn)) and np.array_equal(
            g[:, :, 0::3], g[:, :, 1::3]
        )
        if not interleaved:
            raise ValueError("svk_tangent needs a vector basis with dofs interleaved per node (x, y, z)")
        c["G"], c["w"] = np.ascontiguousarray(g[:, :, 0::3, :]), np.ascontiguousarray(w)
    if "slot" not in c:  # a pattern given by the caller (another quadrature of the same mesh) is kept
        dofs = basis.element_dofs.T  # (e, 81)
        c["dofs"] = np.ascontiguousarray(dofs, dtype=np.int64)
        # the CSR pattern once: each element-matrix entry's slot in K.data (duplicates share
        # one), so every tangent is a sum into it instead of a COO -> CSR conversion
        rows = np.repeat(dofs, dofs.shape[1], axis=1).ravel().astype(np.int64)
        cols = np.tile(dofs, (1, dofs.shape[1])).ravel()
        c["slot"], c["indices"], c["indptr"] = csr_slots(rows, cols, basis.N)
    u = np.asarray(u, dtype=float)
    if u.shape != (basis.N,) or not np.isfinite(u).all():
        raise ValueError(f"u must be ({basis.N},) finite displacements [m]; got shape {u.shape}")
    r = np.zeros(basis.N)
    data = np.zeros(c["indices"].size if tangent else 0)
    _svk_element_loop(c["G"], c["w"], c["dofs"], u, float(mu), float(lam), c["slot"], data, r, tangent)
    if not tangent:
        return None, r
    return sp.csr_matrix((data, c["indices"], c["indptr"]), shape=(basis.N, basis.N)), r


def linear_stiffness(basis, mu: float, lam: float, cache: dict | None = None) -> sp.csr_matrix:
    """Linear-elastic stiffness (N, N) csr of a vector basis with Lamé parameters ``mu``,
    ``lam`` [Pa]: the St. Venant–Kirchhoff tangent at ``u = 0`` (F = I, S = 0)."""
    K, _ = svk_tangent(basis, np.zeros(basis.N), mu, lam, cache)
    return K


__all__ = ["linear_stiffness", "svk_tangent"]

"""Frictionless contact of the condensed pad with a rigid obstacle (linear fidelity).

The jaw translates by ``delta`` along +z (towards the object).  Face node i at
``X_i`` (after the jaw motion) has gap ``d_i`` and obstacle normal ``n_i``; with
contact forces ``F_i = λ_i n_i`` on the pad, ``u = C F`` and the linearised
non-penetration ``d_i + n_iᵀ u_i >= 0`` give the LCP

    λ >= 0,  w = A λ + d >= 0,  λ·w = 0,   A = N C Nᵀ  (SPD, n_i coupled through C),

solved on candidate nodes by a primal-dual active set method (a few dense
Cholesky solves) with NNLS as the fallback, then checked on all nodes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
from scipy.optimize import nnls

from .pad import CondensedPad, PadGeometry


@dataclass(frozen=True)
class ContactSolution:
    """Nodal contact forces ``lam`` (n,) [N] along ``normals`` (n, 3), face
    displacements ``u`` (n, 3) [m], deformed face positions ``x`` (n, 3)."""

    lam: np.ndarray
    normals: np.ndarray
    u: np.ndarray
    x: np.ndarray
    iterations: int
    method: str
    max_penetration: float

    @property
    def force(self) -> float:
        """Total normal force magnitude Σ λ_i [N]."""
        return float(self.lam.sum())

    @property
    def in_contact(self) -> bool:
        return bool((self.lam > 0).any())


def solve_lcp(A: np.ndarray, d: np.ndarray, max_iter: int = 50) -> tuple[np.ndarray, int, str]:
    """LCP ``λ >= 0, Aλ + d >= 0, λ·(Aλ + d) = 0`` for SPD A; returns (λ, iterations, method)."""
    n = d.size
    scale = max(float(np.abs(d).max()), 1e-300)
    active = d < 0
    lam = np.zeros(n)
    for it in range(1, max_iter + 1):
        lam = np.zeros(n)
        if active.any():
            lam[active] = sla.cho_solve(sla.cho_factor(A[np.ix_(active, active)]), -d[active])
        w = A @ lam + d
        new = (active & (lam > 0)) | (~active & (w < -1e-12 * scale))
        if np.array_equal(new, active):
            if (lam >= 0).all():
                return lam, it, "pdas"
            break
        active = new
    # NNLS on min ½ λᵀAλ + dᵀλ = ½ ‖Lᵀλ + L⁻¹d‖² + const
    L = np.linalg.cholesky(A)
    lam, _ = nnls(L.T, -sla.solve_triangular(L, d, lower=True), maxiter=50 * n)
    return lam, max_iter, "nnls"


def face_gaps(geometry: PadGeometry, face_xy: np.ndarray, obstacle, delta: float) -> tuple:
    """Face positions after the jaw motion (n, 3), their gaps (n,) and obstacle normals (n, 3)."""
    h = geometry.thickness
    if not (np.isfinite(delta) and delta >= 0):
        raise ValueError(f"delta must be a non-negative jaw displacement [m]; got {delta}")
    X = np.column_stack([face_xy, np.full(face_xy.shape[0], h + delta)])
    d, nrm = obstacle.signed_distance(X)
    if (d < -h).any():
        raise ValueError(
            f"the obstacle penetrates {-d.min():.3g} m into the undeformed pad, deeper than the layer "
            f"(h = {h:.3g} m): the jaw would hit the object; reduce delta"
        )
    return X, d, nrm


def solve_contact(
    pad: CondensedPad, obstacle, delta: float, *, margin: float | None = None
) -> ContactSolution:
    """Press the pad by ``delta`` [m] (jaw motion along +z) into ``obstacle``."""
    h = pad.geometry.thickness
    n_nodes = pad.face_nodes.size
    X, d, nrm = face_gaps(pad.geometry, pad.face_xy, obstacle, delta)
    C = pad.compliance
    # start from the overlapping nodes; the loop below adds any node that still
    # penetrates (bulging of a nearly incompressible layer), so margin only trades
    # LCP size against loop iterations (0 was 3x faster on the default pad)
    margin = 0.0 if margin is None else margin
    cand = np.flatnonzero(d < margin)
    lam = np.zeros(n_nodes)
    iters, method = 0, "none"
    for _ in range(10):  # grow the candidate set until no node penetrates
        blocks = (3 * cand[:, None] + np.arange(3)).ravel()
        if cand.size:
            Cc = C[np.ix_(blocks, blocks)].reshape(cand.size, 3, cand.size, 3)
            A = np.einsum("ia,iajb,jb->ij", nrm[cand], Cc, nrm[cand], optimize=True)  # n_iᵀ C_ij n_j
            lam_c, iters, method = solve_lcp(A, d[cand])
            lam = np.zeros(n_nodes)
            lam[cand] = lam_c
        u = (C[:, blocks] @ (lam[cand, None] * nrm[cand]).ravel()).reshape(-1, 3)
        gap = d + np.einsum("ij,ij->i", nrm, u)
        viol = np.setdiff1d(np.flatnonzero(gap < -1e-9 * h), cand)
        if viol.size == 0:
            break
        cand = np.union1d(cand, viol)
    return ContactSolution(lam, nrm, u, X + u, iters, method, float(max(0.0, -gap.min())))


def solve_contact_full(
    geometry: PadGeometry, material, obstacle, delta: float, *, scheme: str = "sri", max_iter: int = 30
) -> ContactSolution:
    """Reference (``fidelity="linear"``): the same frictionless Signorini problem on
    the full sparse mesh, by a primal-dual active set with Lagrange multipliers
    ``[[K, Bᵀ], [B, 0]] [u; -λ] = [0; -d_S]`` — no condensation involved."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from .elasticity import basis, stiffness

    mesh = geometry.mesh()
    z = mesh.p[2]
    face = np.flatnonzero(np.isclose(z, geometry.thickness))
    X, d, nrm = face_gaps(geometry, mesh.p[:2, face].T, obstacle, delta)
    K = stiffness(mesh, material, scheme)
    nodal = basis(mesh).nodal_dofs
    free = np.ones(K.shape[0], dtype=bool)
    free[nodal[:, np.isclose(z, 0.0)].ravel()] = False
    fidx = np.flatnonzero(free)
    pos = np.full(K.shape[0], -1)
    pos[fidx] = np.arange(fidx.size)
    Kff = K[fidx][:, fidx]
    face_free = pos[nodal[:, face]].T  # (n, 3) free-dof positions of each face node
    active = d < 0
    lam = np.zeros(face.size)
    u_face = np.zeros((face.size, 3))
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 (reported)
        S = np.flatnonzero(active)
        B = sp.csr_matrix(
            (nrm[S].ravel(), face_free[S].ravel(), np.arange(0, 3 * S.size + 1, 3)), shape=(S.size, fidx.size)
        )
        Ksys = sp.bmat([[Kff, B.T], [B, None]], format="csc")
        rhs = np.concatenate([np.zeros(fidx.size), -d[S]])
        sol = spla.spsolve(Ksys, rhs)
        u = sol[: fidx.size]
        lam = np.zeros(face.size)
        lam[S] = -sol[fidx.size :]
        u_face = u[face_free]
        gap = d + np.einsum("ij,ij->i", nrm, u_face)
        new = (active & (lam > 0)) | (~active & (gap < -1e-12 * geometry.thickness))
        if np.array_equal(new, active):
            break
        active = new
    return ContactSolution(lam, nrm, u_face, X + u_face, it, "full-mesh pdas", float(max(0.0, -gap.min())))

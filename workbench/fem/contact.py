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

from workbench.kernel_launch import launch

from ._kernels import _normal_block, _normal_rows
from .obstacles import Plane
from .pad import CondensedPad, PadGeometry, top_face_nodes


@dataclass(frozen=True)
class ContactSolution:
    """Nodal contact forces ``lam`` (n,) [N] along ``normals`` (n, 3), face
    displacements ``u`` (n, 3) [m], deformed face positions ``x`` (n, 3).

    ``lam[i] >= 0`` is the magnitude of node i's contact force along the
    obstacle's outward unit normal ``normals[i]`` (outward from the object, i.e.
    towards the jaw), not along the press axis +z: the pad receives
    ``lam[i] * normals[i]``, the object the opposite.  The linear levels
    evaluate the normals at the face positions after the rigid jaw motion
    (before deformation, small sliding), the nonlinear level at the deformed ones.
    """

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
    def force_vector(self) -> np.ndarray:
        """(3,) resultant contact force on the object ``−Σ λ_i n_i`` [N] (the pad's
        normal force on the object; equals ``profile.normal_wrench[:3]`` of the
        extracted profile up to the normals' spread within an element)."""
        return -(self.lam[:, None] * self.normals).sum(axis=0)

    @property
    def in_contact(self) -> bool:
        return bool((self.lam > 0).any())


def solve_lcp(
    A: np.ndarray, d: np.ndarray, max_iter: int = 50, active: np.ndarray | None = None
) -> tuple[np.ndarray, int, str]:
    """LCP ``λ >= 0, Aλ + d >= 0, λ·(Aλ + d) = 0`` for SPD A; returns (λ, iterations, method).

    Primal-dual active set: each iteration solves ``A_SS λ_S = -d_S`` on the
    active set S.  When few candidates are inactive (R, the usual case: most
    overlapping nodes stay in contact) A is factorised once and
    ``A_SS⁻¹ = B_SS − B_SR B_RR⁻¹ B_RS`` (B = A⁻¹) is applied with the columns
    ``B e_r`` cached per node — one Cholesky instead of one per iteration.

    active : (n,) bool initial guess of the active set (default ``d < 0``).
    """
    n = d.size
    scale = max(float(np.abs(d).max()), 1e-300)
    active = d < 0 if active is None else np.asarray(active, dtype=bool).copy()
    lam = np.zeros(n)
    full = None  # Cholesky factor of A, made on first use
    cols: dict[int, np.ndarray] = {}  # cached columns of A⁻¹
    for it in range(1, max_iter + 1):
        R = np.flatnonzero(~active)
        lam = np.zeros(n)
        if R.size == n:  # nothing active: λ = 0
            pass
        elif R.size <= SCHUR_FRACTION * n:
            if full is None:
                full = sla.cho_factor(A, check_finite=False)
            v = sla.cho_solve(full, np.where(active, d, 0.0), check_finite=False)
            if R.size:
                missing = [r for r in R if r not in cols]
                if missing:
                    E = np.zeros((n, len(missing)))
                    E[missing, np.arange(len(missing))] = 1.0
                    for r, col in zip(missing, sla.cho_solve(full, E, check_finite=False).T, strict=True):
                        cols[r] = col
                BR = np.column_stack([cols[r] for r in R])
                v = v - BR @ np.linalg.solve(BR[R], v[R])
            lam = -v
            lam[R] = 0.0
        else:
            lam[active] = sla.cho_solve(
                sla.cho_factor(A[np.ix_(active, active)], check_finite=False), -d[active], check_finite=False
            )
        w = A @ lam + d
        # active-set update: a penetration below round-off of the problem's scale is contact, not noise
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


#: use the factor-once (Schur complement) active-set step while at most this
#: fraction of the candidates is inactive; beyond it a Cholesky of A_SS is cheaper
SCHUR_FRACTION = 0.3


def check_plane_faces_pad(obstacle) -> None:
    """Refuse a :class:`~.obstacles.Plane` whose solid side contains the pad: the pad's face
    looks along +z (the jaw moves that way), so the plane's outward normal must have a
    component along −z.  A flipped normal puts the pad inside the solid and its face "outside"
    by δ, and every press returns 0 N without a word — the plane counterpart of the overlap
    check of :func:`face_gaps` (an obstacle deeper than the layer), which calls this."""
    # by name too: workbench/fem/ imports as both `fem` and `workbench.fem`, two Plane classes
    if not (
        isinstance(obstacle, Plane) or (type(obstacle).__name__ == "Plane" and hasattr(obstacle, "normal"))
    ):
        return
    n = np.asarray(obstacle.normal, dtype=float)
    if n[2] < 0:
        return
    shown = "(" + ", ".join(f"{v:g}" for v in n) + ")"
    if n[2] > 0:
        flipped = "(" + ", ".join(f"{-v + 0.0:g}" for v in n) + ")"
        raise ValueError(
            f"Plane normal {shown} does not face the pad: the solid side (x - point)·normal <= 0 "
            "contains the pad, whose face looks along +z (the jaw's motion), so the pad would press "
            f"into nothing (0 N) — the normal points out of the obstacle, towards the pad: pass {flipped}"
        )
    raise ValueError(
        f"Plane normal {shown} is parallel to the press axis +z: the jaw slides along the plane and "
        "never presses into it — the normal points out of the obstacle, towards the pad (the face looks "
        "along +z): pass e.g. (0, 0, -1), or a tilted plane with normal[2] < 0"
    )


def face_gaps(geometry: PadGeometry, face_xy: np.ndarray, obstacle, delta: float) -> tuple:
    """Face positions after the jaw motion (n, 3), their gaps (n,) and obstacle normals (n, 3).

    Refuses an obstacle that overlaps the pad deeper than the layer and a :class:`~.obstacles.Plane`
    whose solid side contains the pad (its normal not facing the pad's face, −z).  The overlap's
    message says where it comes from: mostly from the obstacle's placement (it reaches into the
    pad before the jaw moves — ``Plane()``'s default point is the pad's back, z = 0, not its face,
    z = h) or from ``delta``."""
    h = geometry.thickness
    if not (np.isfinite(delta) and delta >= 0):
        raise ValueError(f"delta must be a non-negative jaw displacement [m]; got {delta}")
    if not callable(getattr(obstacle, "signed_distance", None)):
        # a name ("sphere") or a mesh where an obstacle object is expected
        raise ValueError(
            "obstacle must be an obstacle of workbench.fem.obstacles (Plane, Sphere, Cylinder, "
            f"EllipticCylinder, MeshObstacle(mesh) for a trimesh); got {type(obstacle).__name__} "
            f"{obstacle!r:.60}"
        )
    check_plane_faces_pad(obstacle)
    X = np.column_stack([face_xy, np.full(face_xy.shape[0], h + delta)])
    d, nrm = obstacle.signed_distance(X)
    if (d < -h).any():
        # how far the obstacle reaches into the pad with the jaw not yet moved (delta = 0)
        before = -float(obstacle.signed_distance(X - [0.0, 0.0, delta])[0].min())
        overlap = f"the obstacle penetrates {-d.min():.3g} m into the undeformed pad at delta = {delta:.3g} m"
        if before <= delta:
            raise ValueError(
                f"{overlap}, deeper than the layer (h = {h:.3g} m): the jaw would hit the object; "
                "reduce delta"
            )
        # a Plane facing the pad straight on (normal along -z, checked above): its point's z is its face
        plane = type(obstacle).__name__ == "Plane" and not np.any(np.asarray(obstacle.normal, float)[:2])
        example = f"Plane(point=(0, 0, {h:g}))" if plane else f"its surface at z = h = {h:g} m"
        raise ValueError(
            f"{overlap}, deeper than the layer (h = {h:.3g} m), and {before:.3g} m of it before the jaw "
            "moves (delta = 0): the obstacle is placed inside the pad, not at its face — in the pad frame "
            f"the rigid back is at z = 0 and the face at z = h = {h:g} m, and delta moves the jaw on from "
            f"there; place the obstacle touching the face (e.g. {example}), then delta is the compression"
        )
    return X, d, nrm


def solve_contact(
    pad: CondensedPad,
    obstacle,
    delta: float,
    *,
    margin: float | None = None,
    warm: ContactSolution | None = None,
) -> ContactSolution:
    """Press the pad by ``delta`` [m] (jaw motion along +z) into ``obstacle``.

    warm : the solution of the same obstacle at a smaller ``delta`` (a load
        sequence); its active set seeds the active-set iteration (fewer dense
        Cholesky factorisations; the answer does not depend on it).
    """
    h = pad.geometry.thickness
    n_nodes = pad.face_nodes.size
    X, d, nrm = face_gaps(pad.geometry, pad.face_xy, obstacle, delta)
    # work with the E = 1 compliance (C = C_1 / E): λ = E λ_1 — no 3n × 3n copy per call
    C1 = pad.compliance_unit
    # start from the overlapping nodes; the loop below adds any node that still
    # penetrates (bulging of a nearly incompressible layer), so margin only trades
    # LCP size against loop iterations (0 is the fastest on the default pad: docs/decisions.md)
    margin = 0.0 if margin is None else margin
    seed = d < 0 if warm is None else (warm.lam > 0) | (d < 0)
    cand = np.flatnonzero(seed | (d < margin))
    # G[k] = n_kᵀ C_1[k-block, :] (one row per candidate, 3n columns): reads only the
    # candidates' rows of C_1 and gives both A = G Nᵀ and u = Gᵀ λ
    G = np.empty((n_nodes, 3 * n_nodes))  # rows filled in the order of `have`
    have = np.zeros(0, dtype=np.int64)
    lam1 = np.zeros(n_nodes)
    iters, method = 0, "none"
    for _ in range(10):  # grow the candidate set until no node penetrates
        new = np.setdiff1d(cand, have)
        if new.size:
            rows = G[have.size : have.size + new.size]
            launch(_normal_rows, rows.size, C1, new, nrm, rows)
            have = np.concatenate([have, new])
        if have.size:
            A = np.empty((have.size, have.size))
            # n_iᵀ C_ij n_j
            launch(_normal_block, 3 * A.size, G[: have.size], have, nrm, A)
            # warm start: the previous solution's active set plus the new violators
            guess = (lam1[have] > 0) | np.isin(have, new) if iters else seed[have]
            lam_c, it, method = solve_lcp(0.5 * (A + A.T), d[have], active=guess)
            iters += it
            lam1 = np.zeros(n_nodes)
            lam1[have] = lam_c
            u = (lam_c @ G[: have.size]).reshape(-1, 3)
        else:
            u = np.zeros((n_nodes, 3))
        gap = d + np.einsum("ij,ij->i", nrm, u)
        # a node penetrating by more than 1e-9 of the pad thickness joins the contact set (well above the
        # solve's round-off)
        viol = np.setdiff1d(np.flatnonzero(gap < -1e-9 * h), have)
        if viol.size == 0:
            break
        cand = np.union1d(have, viol)
    lam = lam1 * pad.material.E
    return ContactSolution(lam, nrm, u, X + u, iters, method, float(max(0.0, -gap.min())))


def _pivot(dofs: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(m,) the component (0-2) each active node's constraint eliminates: the free one (dof
    >= 0) of largest |n_c| (>= 1/√3 of |n| unless components are fixed)."""
    return np.argmax(np.where(dofs >= 0, np.abs(normals), -1.0), axis=1)


def _eliminate_contacts(dofs: np.ndarray, normals: np.ndarray, gaps: np.ndarray, n: int):
    """``u = T ũ + g``: the n free dofs in terms of the kept ones when each active node's
    ``n_iᵀ u_i = -d_i`` fixes one of its components.

    dofs : (m, 3) free-dof positions of the active nodes' components (-1: fixed); normals
    (m, 3), gaps (m,).  Returns T (n, n_kept) csr, g (n,), kept (n_kept,) sorted dof
    positions, elim (m,) the eliminated dof of each node and n_e (m,) its normal component:
    ``u_e = (-d_i - Σ_{j≠e} n_ij u_j) / n_ie``.
    """
    import scipy.sparse as sp

    m = len(dofs)
    c = _pivot(dofs, normals)
    rows = np.arange(m)
    elim = dofs[rows, c]
    ne = normals[rows, c]
    if (elim < 0).any() or (np.abs(ne) <= 1e-12).any():
        raise RuntimeError(
            "an active node's obstacle normal has no component along its free displacements "
            "(e.g. a normal along y under plane_strain): the contact cannot hold it"
        )
    is_elim = np.zeros(n, dtype=bool)
    is_elim[elim] = True
    kept = np.flatnonzero(~is_elim)
    col = np.full(n, -1)
    col[kept] = np.arange(kept.size)
    # identity on the kept dofs, the constraint's coefficients on each eliminated one
    others = [(dofs[:, j], -normals[:, j] / ne) for j in range(3)]
    r = [kept] + [elim[(j != c) & (d >= 0)] for j, (d, _) in enumerate(others)]
    k = [col[kept]] + [col[d[(j != c) & (d >= 0)]] for j, (d, _) in enumerate(others)]
    v = [np.ones(kept.size)] + [w[(j != c) & (d >= 0)] for j, (d, w) in enumerate(others)]
    T = sp.csr_matrix((np.concatenate(v), (np.concatenate(r), np.concatenate(k))), shape=(n, kept.size))
    g = np.zeros(n)
    g[elim] = -gaps / ne
    return T, g, kept, elim, ne


def solve_contact_full(
    geometry: PadGeometry,
    material,
    obstacle,
    delta: float,
    *,
    scheme: str = "sri",
    max_iter: int = 30,
    plane_strain: bool = False,
) -> ContactSolution:
    """Reference (``fidelity="linear"``): the same frictionless Signorini problem on
    the full sparse mesh by a primal-dual active set, each active set solved on the whole
    mesh — no condensation involved.

    An active node i is held on the obstacle, ``n_iᵀ u_i = -d_i``: one of its free
    displacement components (the one of largest ``|n_ic|``) is eliminated by that equation
    (:func:`_eliminate_contacts`), leaving ``Tᵀ K T`` symmetric positive definite — solved by a
    nested-dissection ordered Cholesky factor (:func:`.sparse_factor.cholesky`, one ordering
    of the mesh for every active set) — and the contact force is the eliminated row's
    reaction, ``(K u)_ic = λ_i n_ic``.  The same solution as the saddle-point system
    ``[[K, Bᵀ], [B, 0]] [u; -λ] = [0; -d_S]`` (``tests/test_fem_contact.py`` solves both),
    which SuperLU's default ordering solves several times slower (docs/decisions.md).

    plane_strain : fix ``u_y`` at every node (validation of y-invariant contacts,
        e.g. a cylinder along y on a one-element-long slab: exact plane strain).
    """
    from .elasticity import basis, stiffness
    from .sparse_factor import cholesky, nested_dissection, restrict_order

    mesh = geometry.mesh()
    z = mesh.p[2]
    face = top_face_nodes(mesh.p, geometry.thickness)
    X, d, nrm = face_gaps(geometry, mesh.p[:2, face].T, obstacle, delta)
    K = stiffness(mesh, material, scheme)
    nodal = basis(mesh).nodal_dofs
    free = np.ones(K.shape[0], dtype=bool)
    free[nodal[:, np.isclose(z, 0.0)].ravel()] = False
    if plane_strain:
        free[nodal[1]] = False
    fidx = np.flatnonzero(free)
    pos = np.full(K.shape[0], -1)
    pos[fidx] = np.arange(fidx.size)
    Kff = K[fidx][:, fidx].tocsr()
    order = nested_dissection(Kff)
    face_free = pos[nodal[:, face]].T  # (n, 3) free-dof positions of each face node
    active = d < 0
    lam = np.zeros(face.size)
    u_face = np.zeros((face.size, 3))
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 (reported)
        S = np.flatnonzero(active)
        T, g, kept, elim, n_elim = _eliminate_contacts(face_free[S], nrm[S], d[S], fidx.size)
        A = (T.T @ Kff @ T).tocsr()
        u = T @ cholesky(A, restrict_order(order, kept)).solve(-(T.T @ (Kff @ g))) + g
        lam = np.zeros(face.size)
        lam[S] = (Kff @ u)[elim] / n_elim  # the reaction of the eliminated row: λ_i n_ic
        u_face = np.where(face_free >= 0, u[face_free], 0.0)
        gap = d + np.einsum("ij,ij->i", nrm, u_face)
        # as above, on the full mesh: penetration beyond round-off of the thickness
        new = (active & (lam > 0)) | (~active & (gap < -1e-12 * geometry.thickness))
        if np.array_equal(new, active):
            break
        active = new
    return ContactSolution(lam, nrm, u_face, X + u_face, it, "full-mesh pdas", float(max(0.0, -gap.min())))

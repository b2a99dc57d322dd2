"""Grasp map, grasp wrench spaces and membership (thesis §2.4.2–2.4.3, §2.5.3.1, §4.1.2.1).

* :func:`grasp_map` — ``G = [G_1 … G_N]`` (Eq. 2.79–2.81).
* :func:`gws_points` — the points whose convex hull is the GWS: ``W_L∞`` the
  Minkowski sum of the contacts' vertex sets (Eq. 4.2), ``W_L1`` their union
  (Eq. 2.88).  A contact whose force is a variable (``cone=True``) contributes
  the origin as well (zero force is allowed).
* :class:`WrenchHull` — Qhull of those points in the affine subspace they span
  (two point contacts span only 5 dimensions: no torque about the grasp axis),
  membership of ``−w_ext`` by the facet test of Eq. (2.99), and the ε-metric
  (largest origin-centred ball, torques divided by a length to share units).
* :func:`resists_lp` — the same membership **without** a hull: a linear program
  over convex-combination weights of each contact's vertices (exact for the
  V-representation; Minkowski sum = one weight simplex per contact, union = one
  simplex over all), solved by HiGHS.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog
from scipy.spatial import ConvexHull

from .contacts import ContactSet

log = logging.getLogger(__name__)

NORMS = ("linf", "l1")


def check_wrench(w, name: str = "w_ext") -> np.ndarray:
    """(6,) finite float wrench or a ValueError saying what was wrong."""
    arr = np.asarray(w, dtype=float)
    if arr.shape != (6,):
        raise ValueError(
            f"{name} must be a (6,) wrench [f_x, f_y, f_z, τ_x, τ_y, τ_z]; got shape {arr.shape}"
        )
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} must be finite; got {arr.tolist()} (NaN/inf from an upstream computation?)")
    return arr


def check_contacts(contacts) -> list[ContactSet]:
    contacts = list(contacts)
    if not contacts:
        raise ValueError("a grasp needs at least one contact; got none (the jaws touch nothing)")
    return contacts


def grasp_map(contacts) -> np.ndarray:
    """(6, 6N) grasp map ``[G_1 … G_N]`` of the contacts' frames, Eq. (2.81)."""
    return np.hstack([c.G for c in check_contacts(contacts)])


def stacked_vertices(contacts, mu: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[np.ndarray]]:
    """Object-frame vertices of all contacts stacked (n, 6), per-contact block sizes and
    starts, and the blocks themselves."""
    Vs = [c.vertices(mu) for c in contacts]
    sizes = np.array([len(v) for v in Vs])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    return np.vstack(Vs), sizes, starts, Vs


def capacity_scaling(V: np.ndarray) -> np.ndarray:
    """(6,) row scaling ``D``: forces divided by the largest vertex force, torques by the
    largest vertex torque (N vs N·m: one common scale would make torque residuals and
    feasibility tolerances invisible next to forces).  All-zero vertices (a contact
    without force) fall back to 1."""
    sf = float(np.abs(V[:, :3]).max()) or 1.0
    st = float(np.abs(V[:, 3:]).max()) or sf
    return np.r_[np.full(3, 1 / sf), np.full(3, 1 / st)]


def simplex_rows(contacts, sizes: np.ndarray, starts: np.ndarray) -> tuple[list, list]:
    """One row of ones over each contact's vertex weights: (equality rows of the
    known-force contacts, ``<= 1`` rows of the cones, whose origin is then implicit)."""
    n = int(np.sum(sizes))
    eq, ub = [], []
    for c, s, m in zip(contacts, starts, sizes, strict=True):
        row = np.zeros(n)
        row[s : s + m] = 1.0
        (ub if c.cone else eq).append(row)
    return eq, ub


def vertex_blocks(contacts, mu: float) -> list[np.ndarray]:
    """Per contact, (M_i, 6) object-frame vertices (plus the origin row for cones)."""
    blocks = []
    for c in check_contacts(contacts):
        V = c.vertices(mu)
        blocks.append(np.vstack([V, np.zeros(6)]) if c.cone else V)
    return blocks


def gws_points(contacts, mu: float, norm: str = "linf", max_points: int = 2_000_000) -> np.ndarray:
    """(P, 6) points whose hull is ``W_L∞`` (Minkowski sum) or ``W_L1`` (union)."""
    if norm not in NORMS:
        raise ValueError(f"norm must be one of {NORMS}; got {norm!r}")
    blocks = vertex_blocks(contacts, mu)
    if norm == "l1":
        return np.unique(np.vstack(blocks), axis=0)
    n = int(np.prod([len(b) for b in blocks], dtype=float))
    if n > max_points:
        raise ValueError(
            f"the Minkowski sum has {n} points (> max_points={max_points}); use resists_lp (no hull) "
            "or fewer linearisation directions M"
        )
    pts = blocks[0]
    for b in blocks[1:]:
        pts = (pts[:, None, :] + b[None, :, :]).reshape(-1, 6)
    return pts


@dataclass(frozen=True)
class WrenchHull:
    """Convex hull of wrenches in the affine subspace they span.

    center : (6,); basis : (6, r) orthonormal; equations : (K, r + 1) Qhull facets
    ``n·y + d <= 0`` inside (unit normals) in subspace coordinates ``y = basisᵀ(w − center)``;
    scale : the wrench scale used for tolerances.
    """

    center: np.ndarray
    basis: np.ndarray
    equations: np.ndarray
    scale: float

    @classmethod
    def from_points(cls, points: np.ndarray, rtol: float = 1e-9) -> WrenchHull:
        pts = np.asarray(points, float)
        center = pts.mean(axis=0)
        X = pts - center
        scale = float(np.abs(X).max()) or 1.0
        _, s, Vt = np.linalg.svd(X / scale, full_matrices=False)
        r = int((s > rtol * max(s[0], 1e-300)).sum())
        if r == 0:
            raise ValueError("all wrenches coincide: the grasp wrench space is a single point")
        basis = Vt[:r].T
        Y = X @ basis
        if r == 1:  # a segment: two "facets"
            lo, hi = Y.min(), Y.max()
            eq = np.array([[1.0, -hi], [-1.0, lo]])
        else:
            eq = ConvexHull(Y).equations
        return cls(center, basis, eq, scale)

    @property
    def dim(self) -> int:
        return self.basis.shape[1]

    def contains(self, w: np.ndarray, tol: float = 1e-9) -> np.ndarray:
        """Eq. (2.99) for wrenches (K, 6) (or (6,)): inside the span and on the
        inner side of every facet, both to ``tol`` relative to the hull's scale."""
        w = np.atleast_2d(w)
        X = w - self.center
        Y = X @ self.basis
        off = np.linalg.norm(X - Y @ self.basis.T, axis=1)
        inside = (Y @ self.equations[:, :-1].T + self.equations[:, -1] <= tol * self.scale).all(axis=1)
        return inside & (off <= tol * self.scale)

    def epsilon(self) -> float:
        """ε-metric: distance from the origin to the nearest facet if the origin is
        inside a full-dimensional (r = 6) hull, else 0 (no ball fits)."""
        if self.dim < 6 or not self.contains(np.zeros(6))[0]:
            return 0.0
        y0 = -self.center @ self.basis
        return float(-(self.equations[:, :-1] @ y0 + self.equations[:, -1]).max())


def build_gws(contacts, mu: float, norm: str = "linf", torque_length: float = 1.0) -> WrenchHull:
    """GWS hull; torques are divided by ``torque_length`` [m] first (so the ε-metric
    mixes N and N·m consistently); query with :func:`scale_torque` applied likewise."""
    pts = gws_points(contacts, mu, norm)
    return WrenchHull.from_points(scale_torque(pts, torque_length))


def scale_torque(w: np.ndarray, torque_length: float) -> np.ndarray:
    w = np.array(w, dtype=float, copy=True)
    w[..., 3:] /= torque_length
    return w


def resists_lp(contacts, w_ext, mu: float, norm: str = "linf", tol: float = 1e-9) -> bool:
    """Whether ``−w_ext`` lies in the GWS, by an LP over vertex weights (no hull).

    Minkowski sum (L∞): one weight vector per contact, ``Σ_k α_ik = 1`` (``<= 1``
    for a cone, whose zero-force origin is then implicit); union (L1): one
    simplex over all vertices.  Feasibility of ``Σ α v = −w_ext`` up to ``tol``
    relative to the wrench scale (HiGHS, primal feasibility tolerance).
    """
    w = check_wrench(w_ext)
    if norm not in NORMS:
        raise ValueError(f"norm must be one of {NORMS}; got {norm!r}")
    contacts = check_contacts(contacts)
    V, sizes, starts, _ = stacked_vertices(contacts, mu)
    D = capacity_scaling(V)
    n = len(V)
    A_eq = [V.T * D[:, None]]
    b_eq = [-w * D]
    A_ub, b_ub = [], []
    if norm == "linf":
        eq, ub = simplex_rows(contacts, sizes, starts)
        A_eq += [np.array(eq)] if eq else []
        b_eq += [np.ones(len(eq))]
        A_ub += [np.array(ub)] if ub else []
        b_ub += [np.ones(len(ub))] if ub else []
    else:
        row = np.ones((1, n))
        if any(c.cone for c in contacts):
            A_ub.append(row)
            b_ub.append([1.0])
        else:
            A_eq.append(row)
            b_eq.append([1.0])
    A_ub_m = sp.csr_matrix(np.vstack(A_ub)) if A_ub else None
    b_ub_v = np.concatenate(b_ub) if b_ub else None
    A_eq_m, b_eq_v = sp.csr_matrix(np.vstack(A_eq)), np.concatenate(b_eq)
    opts = {"primal_feasibility_tolerance": max(tol, 1e-10)}
    res = linprog(np.zeros(n), A_ub_m, b_ub_v, A_eq_m, b_eq_v, bounds=(0, None), method="highs", options=opts)
    if res.status in (0, 2):
        return res.status == 0
    # HiGHS can end a zero-objective feasibility LP with an unknown status when it is
    # infeasible by ~its tolerance (seen with 128 REACH contacts); the phase-one form —
    # minimise the L1 violation of the 6 wrench rows over slacks — is always feasible
    # and bounded, and decides by the size of the violation
    log.debug("membership LP status %s (%s); re-solving in phase-one form", res.status, res.message)
    S = sp.vstack(
        [sp.hstack([sp.eye(6), -sp.eye(6)]), sp.csr_matrix((A_eq_m.shape[0] - 6, 12))], format="csr"
    )
    res = linprog(
        np.r_[np.zeros(n), np.ones(12)],
        None if A_ub_m is None else sp.hstack([A_ub_m, sp.csr_matrix((A_ub_m.shape[0], 12))], format="csr"),
        b_ub_v,
        sp.hstack([A_eq_m, S], format="csr"),
        b_eq_v,
        bounds=(0, None),
        method="highs",
        options=opts,
    )
    if res.status != 0:
        raise RuntimeError(f"HiGHS failed on the membership LP: {res.message}")
    return bool(res.fun <= 6 * max(tol, 1e-10))


__all__ = [
    "WrenchHull",
    "build_gws",
    "capacity_scaling",
    "check_wrench",
    "grasp_map",
    "gws_points",
    "resists_lp",
    "scale_torque",
    "simplex_rows",
    "stacked_vertices",
    "vertex_blocks",
]

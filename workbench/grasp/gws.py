"""Grasp map, grasp wrench spaces and membership (thesis §2.4.2–2.4.3, §2.5.3.1, §4.1.2.1).

* :func:`grasp_map` — ``G = [G_1 … G_N]`` (Eqs. 2.79–2.81).
* :func:`gws_points` — the points whose convex hull is the GWS: ``W_L∞`` the
  Minkowski sum of the contacts' vertex sets (Eq. 4.2), ``W_L1`` their union
  (Eq. 2.88).  A contact whose force is a variable (``cone=True``) contributes
  the origin as well (zero force is allowed).
* :class:`WrenchHull` — Qhull of those points in the affine subspace they span
  (two point contacts span only 5 dimensions: no torque about the grasp axis),
  membership of ``−w_ext`` by the facet test of Eq. 2.99, and the ε-metric
  (largest origin-centred ball, torques divided by a length to share units).
* :func:`resists_lp` — the same membership **without** a hull: a linear program
  over convex-combination weights of each contact's vertices (exact for the
  V-representation; Minkowski sum = one weight simplex per contact, union = one
  simplex over all), solved by HiGHS.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial import ConvexHull

from ..wrench import check_mu  # the one rule of μ; the grasp layer imports it from here too
from .contacts import ContactSet

log = logging.getLogger(__name__)

NORMS = ("linf", "l1")


def check_wrench(w, name: str = "w_ext") -> np.ndarray:
    """(6,) finite float wrench or a ValueError saying what was wrong."""
    try:
        arr = np.asarray(w, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(
            f"{name} must be a (6,) wrench [f_x, f_y, f_z, τ_x, τ_y, τ_z] of numbers [N, N·m]; got "
            f"{type(w).__name__} {w!r} — pass an array, e.g. np.array([0, 0, -2.9, 0, 0, 0]) for 2.9 N "
            "along -z"
        ) from None
    if arr.shape != (6,):
        raise ValueError(
            f"{name} must be a (6,) wrench [f_x, f_y, f_z, τ_x, τ_y, τ_z]; got shape {arr.shape}"
        )
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} must be finite; got {arr.tolist()} (NaN/inf from an upstream computation?)")
    return arr


def check_resist_tol(tol) -> float:
    """The residual band of "resisted" (``tol`` of :func:`~.resistance.resists` and the other
    entry points): ``config.TOL.resist_rtol`` for None, else checked by that field's own rule
    (:func:`workbench.config.check_value`: a relative residual in (0, 0.1], not newtons) — the
    one rule of the band, whether set in the config or passed to a call."""
    from .. import config

    if tol is None:
        return config.TOL.resist_rtol
    return config.check_value(
        "resist_rtol",
        tol,
        "tol (the residual band of 'resisted': relative to the contacts' capacity, not in newtons)",
    )


def check_contacts(contacts) -> list[ContactSet]:
    if isinstance(contacts, ContactSet) or not hasattr(contacts, "__iter__"):
        raise ValueError(
            f"contacts must be a list of ContactSet objects; got one {type(contacts).__name__} "
            "(wrap it in a list, or build the sets with workbench.grasp.contact_sets(profile, model))"
        )
    contacts = list(contacts)
    if not contacts:
        raise ValueError("a grasp needs at least one contact; got none (the jaws touch nothing)")
    bad = [type(c).__name__ for c in contacts if not isinstance(c, ContactSet)]
    if bad:
        raise ValueError(
            f"contacts must be ContactSet objects; got {bad[:3]} (build them with "
            "workbench.grasp.contact_sets(profile, model) or the *_contact constructors)"
        )
    return contacts


def squeeze_check(contacts: list[ContactSet]) -> None:
    """Warn when the contacts' normal forces push away from their common centroid, as
    they do when a profile's normals point into the object (CONVENTIONS.md wants them
    outward).  A warning, not an error: an internal grasp (jaws opening inside a cup)
    pushes outward on purpose."""
    if len(contacts) < 2:
        return
    t = np.array([c.t for c in contacts])
    d = np.array([(c.R @ c.normal[:3]) * c.force for c in contacts])  # normal force on the object
    to_centre = t.mean(axis=0) - t
    score = float(np.einsum("ij,ij->", d, to_centre))
    if score < 0:
        import warnings

        warnings.warn(
            "the contacts' normal forces push away from the contacts' centroid: are the profiles' "
            "normals pointing into the object? (they must point out of it; fine for an internal grasp; "
            "a single jaw's curved contacts can trigger this too — a grasp needs its opposing jaw)",
            UserWarning,
            stacklevel=3,
        )


def grasp_map(contacts) -> np.ndarray:
    """(6, 6N) grasp map ``[G_1 … G_N]`` of the contacts' frames, Eq. 2.81."""
    return np.hstack([c.G for c in check_contacts(contacts)])


def capacity_scaling(V: np.ndarray, arm: float = 0.0) -> np.ndarray:
    """(6,) row scaling ``D``: forces divided by the largest vertex force, torques by the
    largest vertex torque (N vs N·m: one common scale would make torque residuals and
    feasibility tolerances invisible next to forces).  All-zero vertices (a contact
    without force) fall back to 1.

    arm : the grasp's lever arm [m] (largest distance of a contact from the origin): the
        torque scale is at least ``1e-3 · arm`` × the force scale, so contacts with no
        torque of their own (μ = 0) do not divide round-off by ~0.
    """
    sf = float(np.abs(V[:, :3]).max()) or 1.0
    st = max(float(np.abs(V[:, 3:]).max()), 1e-3 * float(arm) * sf) or sf
    return np.r_[np.full(3, 1 / sf), np.full(3, 1 / st)]


def vertex_blocks(contacts, mu: float, max_points: int = 2_000_000) -> list[np.ndarray]:
    """Per contact, the object-frame points whose hull is its wrench set: the vertices at
    both ends of its force interval (:meth:`ContactSet.force_bounds`: the origin row for
    a cone, the vertices at ``F (1 − r)`` as well for a known force), so the hull means
    what :func:`~workbench.grasp.resistance.resists` means.  The contacts of one force
    ``group`` (a REACH jaw) are one block: the Minkowski sum of their vertex sets at full
    force and its ``(1 − r)`` copy (one reading scales them together)."""
    contacts = check_contacts(contacts)
    blocks, members = [], {}
    for c in contacts:
        if c.group is not None:
            members.setdefault(c.group, []).append(c)
            continue
        V = c.vertices(mu)
        lo, hi = c.force_bounds()
        if c.cone:
            blocks.append(np.vstack([V, np.zeros(6)]))
        elif lo < hi:
            blocks.append(np.vstack([V, V * (lo / hi)]))
        else:
            blocks.append(V)
    for g, cs in members.items():
        n = 2 * float(np.prod([len(c.friction) for c in cs], dtype=float))
        if n > max_points:
            raise ValueError(
                f"force group {g!r}: the Minkowski sum of its {len(cs)} contacts has {n:.3g} points "
                f"(> max_points={max_points}); use resists (no hull), or fewer REACH elements"
            )
        V = cs[0].vertices(mu)
        for c in cs[1:]:
            V = (V[:, None, :] + c.vertices(mu)[None, :, :]).reshape(-1, 6)
        blocks.append(np.vstack([V, V * (1.0 - cs[0].rtol)]) if cs[0].rtol > 0 else V)
    return blocks


def gws_points(contacts, mu: float, norm: str = "linf", max_points: int = 2_000_000) -> np.ndarray:
    """(P, 6) points whose hull is ``W_L∞`` (Minkowski sum) or ``W_L1`` (union)."""
    if norm not in NORMS:
        raise ValueError(f"norm must be one of {NORMS}; got {norm!r}")
    check_mu(mu)
    blocks = vertex_blocks(contacts, mu, max_points)
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
    # rtol: singular values below 1e-9 of the largest are round-off: the points' affine hull is flatter
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

    # tol: relative to the hull's offsets; a point on a facet tests inside whatever its last bits
    def contains(self, w: np.ndarray, tol: float = 1e-9) -> np.ndarray:
        """Eq. 2.99 for wrenches (K, 6) (or (6,)): inside the span and on the
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


def check_torque_length(torque_length: Any) -> float:
    """``torque_length`` [m] as a float if it is a positive, finite, plausible length, else
    ``ValueError``: judged as a ``"lever"`` of :data:`workbench.plausible.RANGES` (hard range
    only: the default 1 m, "no scaling", is no slip), so 30 given for 30 mm is named
    "probably in millimetres — pass 0.03" and 0 (every torque divided by zero) is refused."""
    from ..plausible import check

    try:
        return check("lever", torque_length, "torque_length", warn=False)
    except ValueError as exc:
        raise ValueError(
            f"{exc} — torques are divided by it to share units with forces: pass the grasp's size in "
            "metres (e.g. its largest contact distance from the origin), or 1.0 for no scaling"
        ) from None


def build_gws(contacts, mu: float, norm: str = "linf", torque_length: float = 1.0) -> WrenchHull:
    """GWS hull; torques are divided by ``torque_length`` [m] first (so the ε-metric
    mixes N and N·m consistently); query with :func:`scale_torque` applied likewise.
    torque_length : a positive length in metres (:func:`check_torque_length`)."""
    length = check_torque_length(torque_length)
    pts = gws_points(contacts, mu, norm)
    return WrenchHull.from_points(scale_torque(pts, length))


def scale_torque(w: np.ndarray, torque_length: float) -> np.ndarray:
    """Copy of wrenches ``w`` (..., 6) with the torques divided by ``torque_length`` [m]
    (:func:`check_torque_length`)."""
    length = check_torque_length(torque_length)
    w = np.array(w, dtype=float, copy=True)
    w[..., 3:] /= length
    return w


__all__ = [
    "WrenchHull",
    "build_gws",
    "capacity_scaling",
    "check_contacts",
    "check_mu",
    "check_torque_length",
    "check_wrench",
    "grasp_map",
    "gws_points",
    "scale_torque",
    "vertex_blocks",
]

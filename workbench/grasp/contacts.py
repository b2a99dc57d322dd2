"""Contact models as polytopes of contact wrenches (thesis §2.3.5, §3.4, §4.1.2).

Every model — hard point (Eqs. 2.44, 2.47), soft point (Eq. 2.50), planar and
nonplanar 3DLS, raw 6DFW, REACH triangles, 6DLS and 6DFC — is reduced to one
representation, :class:`ContactSet`:

* in its local contact frame C (rotation ``R``, origin ``t`` in the object
  frame), the frictional wrench vertices **at unit normal force and μ = 1**,
  ``friction`` (M, 6), and the normal wrench at unit force, ``normal`` (6,);
* a contact wrench at friction coefficient μ is then ``F (μ s + ŵ⊥)`` — all
  these models scale linearly with the normal force and with μ (Eqs. 3.20,
  3.25–3.27), which is what lets the robust metric perturb μ without refitting;
* ``cone=False``: the force ``F = force`` is known (a force-sensor reading,
  §4.1.3.2): the set is ``conv{F (μ s_m + ŵ⊥)}`` (6DLS, 6DFW, 3DLS, REACH);
  ``cone=True``: the normal force is a variable in ``[0, force]`` (hard and soft
  point with ``f⊥ <= f_max``, the 6DFC of Eq. 3.30): ``conv({0} ∪ {f_max (μ s_m + ŵ⊥)})``.

The contact map ``G_n = [[R, 0], [t̂ R, R]]`` (Eqs. 2.79, 4.1) takes local wrenches
to the object frame (origin at the object's COM by convention, §4.1.3.1).
Wrench order ``[f, τ]``; normals point out of the object, so a jaw pushes the
object along ``−n`` (CONVENTIONS.md).
"""

from __future__ import annotations

import uuid
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from .. import config
from ..limit_surface.base import LimitSurfaceModel
from ..limit_surface.contact_wrench import ContactWrenchModel
from ..profile import ContactProfile


def _split_pairs(A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Masks (inequality rows, one row of each ``a s <= 0, −a s <= 0`` pair)."""
    eq = np.zeros(len(A), dtype=bool)
    ineq = np.ones(len(A), dtype=bool)
    Z = np.flatnonzero(b == 0)
    if Z.size >= 2:
        dots = A[Z] @ A[Z].T
        sq = np.diag(dots)
        # ± row pairs are exact negatives written by the models: equal to round-off
        pair = np.isclose(dots, -np.sqrt(np.outer(sq, sq)), rtol=1e-12, atol=0) & (sq[:, None] > 0)
        for r, c in zip(*np.nonzero(np.triu(pair, 1)), strict=True):
            if ineq[Z[r]] and ineq[Z[c]]:
                eq[Z[r]] = True
                ineq[Z[r]] = ineq[Z[c]] = False
    return ineq, eq


def skew(t: np.ndarray) -> np.ndarray:
    """(3, 3) cross-product matrix ``t̂`` with ``t̂ x = t × x``."""
    return np.array([[0.0, -t[2], t[1]], [t[2], 0.0, -t[0]], [-t[1], t[0], 0.0]])


def contact_map(R: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(6, 6) ``G_n = [[R, 0], [t̂ R, R]]``, Eq. 2.79 with the identity wrench basis."""
    G = np.zeros((6, 6))
    G[:3, :3] = R
    G[3:, 3:] = R
    G[3:, :3] = skew(t) @ R
    return G


def normal_frame(normal_out: np.ndarray) -> np.ndarray:
    """(3, 3) rotation whose z axis is the *inward* normal ``−n`` (thesis §2.3.5.1)."""
    z = -np.asarray(normal_out, float)
    z = z / np.linalg.norm(z)
    a = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = np.cross(a, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


@dataclass(frozen=True)
class ContactSet:
    """One contact's wrench set (see module docstring).

    friction : (M, 6) frictional wrench vertices, unit normal force, μ = 1, frame C;
    normal : (6,) normal wrench at unit normal force, frame C;
    R : (3, 3), t : (3,) pose of C in the object frame [m];
    force : known normal force (``cone=False``) or its upper bound ``f_max`` [N].
    """

    name: str
    friction: np.ndarray
    normal: np.ndarray
    R: np.ndarray
    t: np.ndarray
    force: float
    cone: bool
    #: outer H-representation of the frictional set (μ = 1, unit force): ``A s <= b``
    #: (m, 6), (m,) in frame C — the QP's constraints (Eqs. 3.28, 3.30); None: use vertices
    A: np.ndarray | None = None
    b: np.ndarray | None = None
    #: the limit-surface model itself (6DLS/6DFC/3DLS contacts; frame C, μ = 1, unit
    #: force): what "resisted" means for this contact unless a caller asks for a
    #: linearisation (``representation="inner"|"outer"``)
    model: LimitSurfaceModel | None = field(default=None, compare=False)
    #: relative accuracy of a known force (``cone=False``): the force lies in
    #: ``[F(1 − r), F]``; None reads ``config.TOL.known_force_rtol`` at use
    force_rtol: float | None = None
    #: force group (``cone=False`` only): the contacts of one group share one sensor
    #: reading, so their known forces scale *together* by one factor σ in
    #: ``[1 − r, 1]`` instead of each moving in its own interval — the elements of one
    #: REACH jaw (their split of the jaw force is the model's, not a measurement).
    #: None: the contact is its own group.  Any hashable token, unique per jaw.
    group: str | None = None

    def __post_init__(self) -> None:
        if self.friction.ndim != 2 or self.friction.shape[1] != 6 or len(self.friction) == 0:
            raise ValueError(f"{self.name}: friction must be (M, 6) with M >= 1; got {self.friction.shape}")
        if not (np.isfinite(self.force) and self.force >= 0):
            raise ValueError(f"{self.name}: the normal force must be finite and >= 0; got {self.force}")
        if self.force_rtol is not None:  # the rule of config.TOL.known_force_rtol
            config.check_value("known_force_rtol", self.force_rtol, f"{self.name}: force_rtol")
        if self.group is not None and self.cone:
            raise ValueError(
                f"{self.name}: a force group shares one known force reading; a cone contact "
                "(cone=True, force a bound) cannot be in one (set group=None)"
            )

    @property
    def rtol(self) -> float:
        """Relative accuracy r of a known force (``force_rtol`` or the config's, read now)."""
        return config.TOL.known_force_rtol if self.force_rtol is None else self.force_rtol

    def force_bounds(self) -> tuple[float, float]:
        """``(f_lo, f_hi)`` [N]: ``(0, f_max)`` for a cone (6DFC, point contacts), the
        sensor interval ``(F (1 − r), F)`` for a known force (thesis §4.1.3.2; see
        ``Tolerances.known_force_rtol`` for why an interval and why F bounds it).  The
        contacts of one force ``group`` each stay in their interval and move together,
        ``f_i = σ F_i`` with one σ per group."""
        if self.cone:
            return 0.0, self.force
        return self.force * (1.0 - self.rtol), self.force

    @cached_property
    def halfspaces(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
        """``(A_in N, b_in, N, (2, d) force and torque norms of N's columns)``: the
        frictional set ``A s <= b`` on its affine hull.  The
        ``a s = 0`` rows given as ± pairs (flat or point-like sets: a point contact's
        f_z, τ_x, τ_y, τ_z) confine ``s`` to the span of the orthonormal basis
        ``N`` (6, d), so ``s = N z`` with ``z`` (d,) free and only the other rows,
        ``A_in N z <= b_in``, remain (active-set QP solvers also reject degenerate ±
        pairs).  None without half-spaces.  Derived from immutable fields only (a
        cache, not state)."""
        if self.A is None:
            return None
        ineq, eq = _split_pairs(self.A, self.b)
        N = np.eye(6)
        if eq.any():
            _, sv, Vt = np.linalg.svd(self.A[eq])
            # numerical rank of ± pairs built from unit rows: singular values are 1-ish or round-off
            rank = int((sv > 1e-12 * sv[0]).sum())
            N = Vt[rank:].T
        return self.A[ineq] @ N, self.b[ineq], N, np.linalg.norm(N.reshape(2, 3, -1), axis=1)

    @cached_property
    def G(self) -> np.ndarray:
        """(6, 6) contact map of this contact's frame, Eq. 2.79."""
        return contact_map(self.R, self.t)

    def local_vertices(self, mu: float) -> np.ndarray:
        """(M, 6) contact wrench vertices in C at friction coefficient ``mu``."""
        return self.force * (mu * self.friction + self.normal)

    def vertices(self, mu: float) -> np.ndarray:
        """(M, 6) contact wrench vertices in the object frame, Eq. 4.1."""
        return self.local_vertices(mu) @ self.G.T

    def moved(self, R: np.ndarray, t: np.ndarray, *, group: str | None | object = ...) -> ContactSet:
        """The same contact under a rigid motion ``x -> R x + t`` of the gripper, in
        the same force ``group`` — or in ``group=`` when the copy is *another* jaw
        (a mirrored jaw built from this one reads its own sensor: give it a new group,
        or None)."""
        kw = {} if group is ... else {"group": group}
        return self._keep_split(replace(self, R=R @ self.R, t=R @ self.t + t, **kw))

    def with_force(self, force: float) -> ContactSet:
        """The same contact with normal force (or bound) ``force`` [N] (same group)."""
        other = self._keep_split(replace(self, force=float(force)))
        other.__dict__["G"] = self.G  # same pose: the contact map is shared, not recomputed
        return other

    def _keep_split(self, other: ContactSet) -> ContactSet:
        # the half-space split depends on A, b and normal only, which a moved or
        # re-forced copy shares: hand the computed value over instead of recomputing
        # it per copy (a sweep makes thousands of copies)
        if self.A is not None:
            other.__dict__["halfspaces"] = self.halfspaces  # computed once, on the source
        return other


def _vector(v, name: str, what: str) -> np.ndarray:
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {what}, (3,) numbers; got {v!r}") from None
    if a.shape != (3,) or not np.isfinite(a).all():
        raise ValueError(f"{name} must be {what}, (3,) finite numbers; got {v!r}")
    return a


def check_object_point(v, name: str, what: str) -> np.ndarray:
    """(3,) a point of the object in its frame [m] — a contact point, a centre of mass — as a
    float array, refused when it is not three finite numbers or lies farther from the object
    origin than ``config.TOL.max_object_extent_m`` (the largest object: farther is a point in
    millimetres).  The one rule of such a point: :func:`point_contact`,
    :func:`soft_point_contact` and :func:`~.robust.gravity_wrench` call it (``what`` names the
    point in the message)."""
    a = _vector(v, name, what)
    limit = config.TOL.max_object_extent_m
    dist = float(np.linalg.norm(a))
    if dist > limit * (1 + config.TOL.extent_limit_rtol):
        raise ValueError(
            f"{name} must be in metres, in the object's frame; got {a.tolist()}, {dist:.3g} m from the "
            f"origin, beyond the largest object (config.TOL.max_object_extent_m = {limit:g} m) — in "
            f"millimetres? pass {np.round(a / 1e3, 12).tolist()}"
        )
    return a


def _point_like(
    point, normal_out, f_max: float, n_edges: int, kind: str, name: str, torsion_length: float | None
) -> ContactSet:
    """Friction cone linearised by an n-gon (Eq. 2.47) — ``kind`` "inner" (vertices on the
    circle) or "outer" (circumscribed) — and, for a soft contact, ``|τ_z| <= torsion_length``
    at μ = 1, unit force; as vertices and as half-spaces (``s_j = 0`` rows as ± pairs)."""
    if n_edges < 3:
        raise ValueError(f"n_edges must be >= 3; got {n_edges}")
    point, normal_out = (
        check_object_point(point, "point", "the contact point [m]"),
        _vector(normal_out, "normal_out", "the outward surface normal"),
    )
    if not np.linalg.norm(normal_out) > 0:
        raise ValueError(
            "normal_out must be the outward surface normal at the contact, a nonzero (3,) vector; "
            "got [0, 0, 0] — pass the surface's normal there (e.g. mesh.face_normals[face])"
        )
    f_max = float(np.asarray(f_max, dtype=float))
    if not (np.isfinite(f_max) and f_max >= 0):
        raise ValueError(f"f_max must be a finite normal force >= 0 [N]; got {f_max}")
    if torsion_length is not None:
        from workbench.plausible import check

        # a torsion length is a lever on the contact (the patch's radius scale: 1-10 mm);
        # 13.3 given in mm is 13.3 m and resists N·m of torsion from a 10 N grip
        # (refused only: a small patch's sub-millimetre length is real, not unusual)
        torsion_length = (
            0.0
            if torsion_length == 0
            else check(
                "lever",
                torsion_length,
                "torsion_length",
                warn=False,
                examples="a pad patch's torsion length (2/3 of a disc's radius) 1-20 mm",
                named="torsion length",
            )
        )
    if kind not in ("inner", "outer"):
        raise ValueError(f"kind must be 'inner' or 'outer'; got {kind!r}")
    r = 1.0 if kind == "inner" else 1.0 / np.cos(np.pi / n_edges)
    th = 2 * np.pi * np.arange(n_edges) / n_edges
    poly = np.zeros((n_edges, 6))
    poly[:, 0], poly[:, 1] = r * np.cos(th), r * np.sin(th)
    edge = th + np.pi / n_edges  # outward normals of the polygon's edges
    A = [np.column_stack([np.cos(edge), np.sin(edge), np.zeros((n_edges, 4))])]
    b = [np.full(n_edges, r * np.cos(np.pi / n_edges))]
    eye = np.eye(6)
    for j in range(2, 6):  # f_z, τ_x, τ_y (and τ_z for a hard contact) are zero
        if j == 5 and torsion_length is not None:
            continue
        A.append(np.array([eye[j], -eye[j]]))
        b.append(np.zeros(2))
    fr = poly
    if torsion_length is not None:
        if not (np.isfinite(torsion_length) and torsion_length >= 0):
            raise ValueError(f"torsion_length must be >= 0 [m]; got {torsion_length}")
        fr = np.vstack([poly, poly])
        fr[:n_edges, 5], fr[n_edges:, 5] = torsion_length, -torsion_length
        A.append(np.array([eye[5], -eye[5]]))
        b.append(np.full(2, float(torsion_length)))
    return ContactSet(
        name,
        fr,
        eye[2].copy(),  # unit normal force along the local z (the inward normal)
        normal_frame(normal_out),
        point,
        f_max,
        True,
        np.vstack(A),
        np.concatenate(b),
    )


def point_contact(
    point, normal_out, f_max: float, *, n_edges: int = 8, kind: str = "inner", name: str = "point"
) -> ContactSet:
    """Hard point contact: the linearised friction cone (Eqs. 2.44, 2.47) with ``f⊥ <= f_max``."""
    return _point_like(point, normal_out, f_max, n_edges, kind, name, None)


def soft_point_contact(
    point,
    normal_out,
    f_max: float,
    torsion_length: float,
    *,
    n_edges: int = 8,
    kind: str = "inner",
    name: str = "soft point",
) -> ContactSet:
    """Soft point contact (Eq. 2.50): ``‖f_t‖ <= μ f⊥`` and ``|τ_z| <= γ f⊥`` with
    ``γ = μ · torsion_length`` (torsional friction scales with μ like the rest)."""
    return _point_like(point, normal_out, f_max, n_edges, kind, name, torsion_length)


def limit_surface_contact(
    model: ContactWrenchModel,
    origin,
    force: float,
    *,
    M: int = 200,
    cone: bool = False,
    name: str = "6DLS",
    seed: int = 0,
    R: np.ndarray | None = None,
) -> ContactSet:
    """6DLS (``cone=False``, force known) or 6DFC (``cone=True``, ``f_C <= force``)
    from a contact-wrench model fitted at μ = 1 on the normalised profile.

    The model's wrenches are about the profile's pressure centre ``origin`` (3,) [m]
    with object-frame axes (CONVENTIONS.md), so ``R = I``, ``t = origin`` — or, for a
    model fitted on the profile expressed in a frame turned by ``R`` (3, 3) (the planar
    model's plane frame), with that frame's axes: ``object = R @ local``.  The inner
    linearisation (Eqs. 3.19–3.21, 3.27) gives the vertices (GWS, LP), the outer
    tangent half-spaces at the same points (Eqs. 3.22–3.24, 3.28, 3.30) the QP's constraints.
    """
    ls = model.limit_surface
    outer = ls.linearize(M, "outer", seed=seed)  # its vertices are the inner ones (same directions)
    return ContactSet(
        name,
        outer.vertices,
        np.asarray(model.normal_wrench, float),
        np.eye(3) if R is None else np.array(R, dtype=float),
        np.asarray(origin, float),
        float(force),
        cone,
        outer.A,
        outer.b,
        model=ls,
    )


def wrench_hull_contact(
    profile: ContactProfile, wrenches_unit_mu: np.ndarray, *, name: str = "6DFW"
) -> ContactSet:
    """Raw 6DFW: the sampled frictional wrenches themselves (μ = 1, profile force F),
    no limit-surface model — their convex hull is the contact's frictional set."""
    W = np.asarray(wrenches_unit_mu, float) / profile.F
    return ContactSet(
        name,
        W,
        profile.normal_wrench / profile.F,
        np.eye(3),
        profile.pressure_center.copy(),
        profile.F,
        False,
    )


def _merge_elements(c: np.ndarray, n: np.ndarray, f: np.ndarray, groups) -> tuple:
    """One contact per group of elements (centres (n, 3), unit outward normals (n, 3),
    forces (n,)) with the group's exact normal wrench: the force vector ``Σ f_k n_k``,
    applied on its line of action nearest the force-weighted centre, and the rest of
    the moment ``Σ c_k × f_k n_k`` — a torsion about that line, κ per newton — carried
    by the merged contact's normal wrench.  Summing scalar forces along an averaged
    normal instead inflated a curved jaw's net force by ~1 % and left a moment that no
    contact could balance.  Returns centres, normals, forces, torsions κ [m]."""
    cs, ns, fs, ks = [], [], [], []
    for g in groups:
        Fv = (f[g, None] * n[g]).sum(axis=0)
        F2 = float(Fv @ Fv)
        F = np.sqrt(F2)
        cbar = np.average(c[g], axis=0, weights=f[g])
        m = np.cross(c[g] - cbar, f[g, None] * n[g]).sum(axis=0)  # moment about cbar
        cs.append(cbar + np.cross(Fv, m) / F2)
        ns.append(Fv / F)
        fs.append(F)
        ks.append(float(m @ Fv) / F2)  # the moment's part along the force, per newton
    return np.array(cs), np.array(ns), np.array(fs), np.array(ks)


def reach_contacts(
    profile: ContactProfile, *, torsion_length: float = 0.0, max_triangles: int = 16, n_edges: int = 8
) -> list[ContactSet]:
    """The REACH *contact model* of a profile (thesis §2.3.1.3; the ``"reach"`` model of
    :func:`~.models.contact_sets`): each element a soft point contact with its own known
    normal force ``p a``; elements are merged (pressure-weighted, by k-means on the
    centres) down to ``max_triangles`` to bound the cost.  The elements share one force
    ``group``: a force-sensor's accuracy scales the jaw's elements together.  Any profile works — not only
    one made by :func:`~workbench.sources.reach.reach_profile`, which is a *profile source* (pad ∩ mesh).

    torsion_length : torsional friction per newton at μ = 1 of each element [m]; the
        default 0 makes every element a hard point contact (REACH's elements are points).
    max_triangles : element clusters per jaw (the defaults match ``contact_sets(p, "reach")``).
    n_edges : sides of each element's friction polygon, inscribed (conservative: the
        capacity in a direction between two vertices is cos(π/n_edges) of the circle's).
    A merged cluster presses with ``|Σ p a n|`` (slightly less than ``Σ p a`` on a
    curved jaw) so that the jaw's normal wrench is kept exactly."""
    from scipy.cluster.vq import kmeans2

    if int(max_triangles) < 1 or int(n_edges) < 3:
        raise ValueError(
            f"max_triangles must be >= 1 and n_edges >= 3; got {max_triangles}, {n_edges} "
            "(16 clusters of 8-sided polygons are the defaults)"
        )
    c, n, f = profile.centers, profile.normals, profile.forces
    keep = f > 0
    c, n, f = c[keep], n[keep], f[keep]
    if len(f) == 0:
        return []
    if len(f) > max_triangles:
        _, lab = kmeans2(c, c[np.linspace(0, len(c) - 1, max_triangles).astype(int)], minit="matrix", seed=0)
        groups = [np.flatnonzero(lab == k) for k in range(max_triangles)]
        groups = [g for g in groups if g.size]
        c, n, f, kappa = _merge_elements(c, n, f, groups)
    else:
        kappa = np.zeros(len(f))
    # each element presses with its own known force, a soft point contact with
    # cone=False; the jaw's sensor reads their sum, so the elements form one force
    # group (one reading's accuracy scales them together; ContactSet.group)
    group = f"reach-{uuid.uuid4().hex[:12]}"
    out = []
    for ci, ni, fi, ki in zip(c, n, f, kappa, strict=True):
        sp = soft_point_contact(ci, ni, fi, torsion_length, n_edges=n_edges)
        normal = sp.normal.copy()
        # the merged elements' torsion about the force (object torque −κ f n, and
        # local z = −n)
        normal[5] = ki
        out.append(replace(sp, name="REACH", cone=False, group=group, normal=normal))
    return out

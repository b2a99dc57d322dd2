"""Thin-walled deformable objects: wall stiffness ``s = f / Δ`` under a parallel-jaw squeeze.

Thesis §4.3.3.1 measures, per grasp location, ``s_i = f_⊥ / (l_s − l_e)`` — the
jaw force over the closing of the gripper from first touch — and the minimal-work
metric uses it in Eq. 4.5, ``d_i = f_⊥i / s_i + ε``.  Here the same quantity
is simulated: the object's side wall (plastic bottle or cup) is a linear-elastic
solid shell, one triquadratic hex (27 nodes, 3×3×3 Gauss points) through the
thickness — quadratic elements because trilinear hexes shear-lock in bending at
these aspect ratios — clamped at its bottom rim (the base is far stiffer than
the wall); two rigid flat jaws close symmetrically along the grasp axis with
frictionless unilateral contact on the outer surface.  The wall's normal
compliance at the candidate nodes is condensed by solves with one sparse LU per
object (nested-dissection ordered, :mod:`workbench.fem.sparse_factor`), so each location
is a small LCP (:func:`workbench.fem.contact.solve_lcp`), and the
jaw closing ``Δ`` at the target force (default 10 N, as in the thesis) is found
by a secant iteration.  ``s`` is the secant stiffness ``f / Δ`` there.

Validated against the thin ring under diametral line loads (Roark):
the perpendicular diameter grows by ``(4 − π)/(2π) · P' R³ / D``,
``D = E t³ / (12 (1 − ν²))`` (:func:`ring_pinch`), and two jaws closing on it by
``(π/4 − 2/π) · P' R³ / D`` (:func:`ring_validation`, both with mesh refinement).

Assumptions stated, not hidden: small strains (no buckling or snap-through of a
squeezed bottle), rigid jaws (the pad's own compliance is in series and not
included), empty object, open top rim.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from skfem import Basis, ElementHex2, ElementVector, MeshHex

from workbench import config as _config

from ..groups import checked_group
from .contact import solve_lcp
from .material import Material
from .sparse_factor import factor_spd
from .svk import linear_stiffness

log = logging.getLogger(__name__)

_X3 = np.array([0.5 - 0.5 * np.sqrt(0.6), 0.5, 0.5 + 0.5 * np.sqrt(0.6)])
_W3 = np.array([5.0, 8.0, 5.0]) / 18.0
#: 3×3×3 Gauss points on [0, 1]³ — exact for the triquadratic stiffness of a parallelepiped
#: (scikit-fem's default for ElementHex2 uses 343 points)
GAUSS_3 = (
    np.array(np.meshgrid(_X3, _X3, _X3, indexing="ij")).reshape(3, -1),
    np.einsum("i,j,k->ijk", _W3, _W3, _W3).ravel(),
)

#: PET-like default for plastic bottles (E ≈ 2–4 GPa, ν ≈ 0.37–0.44)
PET = Material(2.5e9, 0.4)


def wall_mesh(
    surface, thickness: float | Callable, n_theta: int, n_z: int, z_range: tuple[float, float]
) -> tuple:
    """Closed tube of hexes, one element through the wall.

    surface : callable ``(theta (N,), z (N,)) -> (points (N, 3), outward normals (N, 3))``
        of the *outer* wall surface (e.g. :meth:`workbench.fem.bottle.Bottle.points_normals`);
        the wall extends ``thickness`` [m] inwards along the normal — a number, or a
        callable ``z (N,) -> (N,)`` for a wall whose thickness varies with height
        (e.g. a rolled lip, :meth:`workbench.fem.object_wall.WallGeometry.thickness_at`),
        applied at the vertices.
    Returns ``(mesh, outer, bottom, top)``: (n_vertices,) bool masks of the outer-surface,
    the bottom-rim and the top-rim vertices.
    """
    if not callable(thickness) and not (np.isfinite(thickness) and thickness > 0):
        raise ValueError(f"thickness must be a positive wall thickness [m]; got {thickness}")
    if n_theta < 8 or n_z < 1:
        raise ValueError(f"need n_theta >= 8 and n_z >= 1; got {n_theta}, {n_z}")
    ref = MeshHex.init_tensor(np.arange(n_theta + 1.0), np.arange(n_z + 1.0), np.array([0.0, 1.0]))
    i, j, k = np.rint(ref.p).astype(int)
    i = i % n_theta  # close the tube: θ = 2π is θ = 0
    key = (k * (n_z + 1) + j) * n_theta + i
    uniq, first, inv = np.unique(key, return_index=True, return_inverse=True)
    ii, jj, kk = i[first], j[first], k[first]
    theta = 2 * np.pi * ii / n_theta
    z = z_range[0] + (z_range[1] - z_range[0]) * jj / n_z
    pts, nrm = surface(theta, z)
    t = np.broadcast_to(thickness(z) if callable(thickness) else thickness, z.shape)
    if not (np.isfinite(t).all() and (t > 0).all()):
        raise ValueError(f"thickness must be positive everywhere [m]; got {np.min(t)} at some height")
    p = pts - (t * kk)[:, None] * nrm
    mesh = MeshHex(np.ascontiguousarray(p.T), inv[ref.t])
    return mesh, kk == 0, jj == 0, jj == n_z


@dataclass
class Wall:
    """A meshed wall with its factorised stiffness (built once per object and material).

    The linear stiffness is assembled and factorised on first use of :attr:`lu` (seconds
    per wall): the geometrically nonlinear solver (:mod:`workbench.fem.wall_nonlinear`)
    needs only the mesh, basis and dofs, and assembles its own tangents."""

    mesh: MeshHex
    basis: Basis
    material: Material
    free: np.ndarray  # (n_free,) free dof indices
    outer_xyz: np.ndarray  # (m, 3) outer-surface node locations
    outer_dofs: np.ndarray  # (m, 3) their x, y, z dofs
    mesh_seconds: float  # meshing, basis and dofs [s]

    @cached_property
    def lu(self):
        """Sparse factor of ``K_ff`` (:class:`workbench.fem.sparse_factor.SPDFactor`): ``.solve(b)``."""
        t0 = time.perf_counter()
        K = linear_stiffness(self.basis, self.material.mu, self.material.lam)  # the element kernel
        # the contact solve loads dozens of nodes at once: the blocked solves
        lu = factor_spd(K[self.free][:, self.free], blocked=True)
        self._stiffness_seconds = time.perf_counter() - t0
        return lu

    @property
    def seconds(self) -> float:
        """Build time [s]: meshing plus the stiffness's assembly and factorisation (done now
        if not yet)."""
        self.lu  # noqa: B018 - the factor's build is part of the wall's
        return self.mesh_seconds + self._stiffness_seconds

    @cached_property
    def free_position(self) -> np.ndarray:
        """(N,) index of each dof among the free ones, −1 for a fixed dof."""
        pos = np.full(self.basis.N, -1)
        pos[self.free] = np.arange(self.free.size)
        return pos

    def compliance(
        self,
        nodes: np.ndarray,
        directions: np.ndarray,
        at: np.ndarray | None = None,
        at_directions: np.ndarray | None = None,
    ) -> np.ndarray:
        """Normal compliance ``A_ij = a_iᵀ u_i(unit load n_j at node j)`` [m/N].

        nodes : (c,) indices into ``outer_xyz`` loaded along directions (c, 3) (unit);
        at, at_directions : (r,) nodes and (r, 3) directions where the displacement is
        read (default the loaded ones: then A is (c, c), symmetrised).  Returns (r, c).
        One sparse solve per loaded node, so callers load few nodes and read many.
        """
        rows = self.free_position[self.outer_dofs[nodes]]  # (c, 3); -1 marks a fixed component
        if (rows < 0).all(axis=1).any():
            raise ValueError(
                "the jaw footprint reaches the clamped base rim (a fully fixed node); grasp higher"
            )
        dirs = np.where(rows >= 0, directions, 0.0)  # a fixed component neither loads nor moves
        rhs = np.zeros((self.free.size, nodes.size))
        for c in range(3):
            ok = rows[:, c] >= 0
            rhs[rows[ok, c], np.flatnonzero(ok)] = dirs[ok, c]
        U = np.vstack([self.lu.solve(rhs), np.zeros((1, nodes.size))])  # row -1: fixed, zero
        if at is None:
            A = np.einsum("icj,ic->ij", U[rows], dirs)  # U[rows] : (c, 3, c)
            return 0.5 * (A + A.T)
        at_rows = self.free_position[self.outer_dofs[at]]
        return np.einsum("icj,ic->ij", U[at_rows], np.where(at_rows >= 0, at_directions, 0.0))

    def displacement(self, nodes: np.ndarray, forces: np.ndarray) -> np.ndarray:
        """Outer-surface displacements (m, 3) [m] under forces (c, 3) [N] at outer nodes."""
        f = np.zeros(self.basis.N)
        np.add.at(f, self.outer_dofs[nodes].ravel(), forces.ravel())
        u = np.zeros(self.basis.N)
        u[self.free] = self.lu.solve(f[self.free])
        return u[self.outer_dofs]


def build_wall(
    surface,
    material: Material = PET,
    *,
    thickness: float | Callable = 0.5e-3,
    n_theta: int = 48,
    n_z: int = 24,
    z_range: tuple[float, float] = (0.0, 0.1),
    clamp_top: bool = False,
) -> Wall:
    """Mesh the wall (see module docstring), clamped at its bottom rim; its stiffness is
    assembled and factorised on first use (:attr:`Wall.lu`).

    surface, thickness : as :func:`wall_mesh`; ``n_theta × n_z`` hexes around × along the
    heights ``z_range`` (lo, hi) [m];
    clamp_top : also clamp the top rim (a wall closed by a stiff shoulder, neck or cap);
        default free (an open cup).
    The plane-strain slab of Roark's ring is :func:`ring_wall`.
    """
    return _build_wall(surface, material, thickness, (n_theta, n_z, z_range), _Supports(top=clamp_top))


@dataclass(frozen=True)
class _Supports:
    """The fixed dofs of a wall (:func:`_build_wall`): ``bottom`` / ``top`` clamp that rim;
    ``plane_strain`` fixes ``u_z`` everywhere (a slab of a long tube, for :func:`ring_pinch`),
    and then the rigid-body modes in the plane are removed by the symmetry conditions
    ``u_y = 0`` at θ = 0, π and ``u_x = 0`` at θ = ±π/2 (n_theta % 4 == 0)."""

    bottom: bool = True
    top: bool = False
    plane_strain: bool = False


def _build_wall(
    surface, material: Material, thickness: float | Callable, grid: tuple, supports: _Supports
) -> Wall:
    """:func:`build_wall` with ``grid`` = (n_theta, n_z, z_range) and any ``supports``."""
    from workbench.plausible import check

    check("wall_modulus", material.E, "material.E (the wall's Young's modulus [Pa])")
    if not callable(thickness):
        check("wall_thickness", thickness, "thickness")
    t0 = time.perf_counter()
    mesh, outer, bottom, top = wall_mesh(surface, thickness, *grid)
    basis = Basis(mesh, ElementVector(ElementHex2()), quadrature=GAUSS_3)
    fixed = np.zeros(basis.N, dtype=bool)
    if supports.bottom:
        fixed[basis.get_dofs(facets=_facets_within(mesh, bottom)).all()] = True
    if supports.top:
        fixed[basis.get_dofs(facets=_facets_within(mesh, top)).all()] = True
    if supports.plane_strain:
        comp = components(basis)
        fixed[comp == 2] = True
        ang = np.arctan2(basis.doflocs[1], basis.doflocs[0])
        # symmetry planes: dof angles equal to 0, ±π/2, π up to round-off of arctan2
        tol = 1e-9
        on_x = (np.abs(np.sin(ang)) < tol) & (comp == 1)  # u_y dofs at θ = 0, π
        on_y = (np.abs(np.cos(ang)) < tol) & (comp == 0)  # u_x dofs at θ = ±π/2
        fixed |= on_x | on_y
    free = np.flatnonzero(~fixed)
    # outer-surface dofs: the facets whose 4 vertices are all on the outer surface
    view = basis.get_dofs(facets=_facets_within(mesh, outer))
    comp = [view.all(f"u^{c + 1}") for c in range(3)]
    xyz = basis.doflocs[:, comp[0]].T
    assert all(np.allclose(basis.doflocs[:, c].T, xyz) for c in comp[1:])  # same node order
    return Wall(mesh, basis, material, free, xyz, np.column_stack(comp), time.perf_counter() - t0)


def _facets_within(mesh: MeshHex, vertices: np.ndarray) -> np.ndarray:
    """Boundary facets whose 4 vertices all lie in the vertex mask."""
    facets = mesh.boundary_facets()
    return facets[vertices[mesh.facets[:, facets]].all(axis=0)]


def components(basis: Basis) -> np.ndarray:
    """(N,) the displacement component (0, 1, 2) of each dof of a vector basis.

    From the basis's dof tables (row c = component c for every node, edge, facet and
    interior dof) — not from ``get_dofs``, which only sees boundary facets and would
    leave interior facet and bubble dofs unassigned."""
    comp = np.full(basis.N, -1)
    for table in (basis.nodal_dofs, basis.edge_dofs, basis.facet_dofs, basis.interior_dofs):
        if table.size:
            for c in range(3):
                comp[table[c::3] if table.shape[0] > 3 else table[c]] = c
    if (comp < 0).any():
        raise RuntimeError("a dof of the vector basis has no component")  # not expected
    return comp


def circle_surface(radius: float):
    """Outer surface ``(θ, z) -> (points, outward normals)`` of a circular tube of ``radius``."""

    def surface(th, z):
        n = np.column_stack([np.cos(th), np.sin(th), np.zeros_like(th)])
        return np.column_stack([radius * n[:, :2], z]), n

    return surface


def turned_surface(surface, angle: float):
    """The outer-surface callable ``(θ, z) -> (points, normals)`` of ``surface`` turned by
    ``-angle`` [rad] about the z axis: a direction at ``angle`` in the plane becomes +x."""
    R = turn_matrix(angle)

    def turned(theta, z):
        p, n = surface(theta, z)
        return p @ R.T, n @ R.T

    return turned


def turn_matrix(angle: float) -> np.ndarray:
    """(3, 3) rotation by ``-angle`` [rad] about z (takes the direction at ``angle`` to +x)."""
    c, s = np.cos(-angle), np.sin(-angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _check_ring(radius, thickness) -> None:
    """ValueError unless ``radius`` [m] is a plausible object radius (35 for 0.035 is refused) and
    the ring's ``thickness`` [m] a plausible wall thinner than it."""
    from workbench.plausible import check

    check(
        "lever",
        radius,
        "radius (the ring's mid-surface radius [m])",
        examples="bottles and cups 20-50 mm in radius",
        named="ring radius",
    )
    check("wall_thickness", thickness, "thickness")
    if thickness >= radius:
        raise ValueError(f"thickness {thickness!r} m must be below the radius {radius!r} m: a thin ring")


def ring_wall(radius: float, thickness: float, material: Material = PET, n_theta: int = 64) -> Wall:
    """A plane-strain slab (one element, ``thickness`` long) of a tube with mid-surface
    ``radius`` — the thin ring of Roark's formulas."""
    _check_ring(radius, thickness)
    return _build_wall(
        circle_surface(radius + thickness / 2),
        material,
        thickness,
        (n_theta, 1, (0.0, thickness)),
        _Supports(bottom=False, plane_strain=True),
    )


def ring_pinch(
    radius: float = 0.035, thickness: float = 0.5e-3, material: Material = PET, n_theta: int = 64
) -> dict:
    """Diametral line loads ``P'`` on a long tube (plane strain): FE vs the thin-ring formula.

    The loads act along ∓x at θ = 0, π on the mid-surface (through-thickness nodes);
    the measured quantity is the growth of the perpendicular (y) mid-surface
    diameter, away from the load points.  ``radius`` is the mid-surface radius.
    """
    _check_ring(radius, thickness)
    slab = thickness
    wall = ring_wall(radius, thickness, material, n_theta)
    b = wall.basis
    x, y = b.doflocs[0], b.doflocs[1]
    r = np.hypot(x, y)
    P = 1.0  # N per metre of tube
    f = np.zeros(b.N)
    comp = components(b)
    for sgn in (1, -1):
        # nodes on the x axis (y = 0 to round-off; coordinates in metres)
        sel = (comp == 0) & (np.abs(y) < 1e-9) & (np.sign(x) == sgn)
        # consistent load of a line force on the quadratic element's faces: Simpson weights
        # over the slab length (z = 0, slab/2, slab) and over the thickness (inner, mid, outer)
        wz = np.where(np.isclose(b.doflocs[2], slab / 2), 4.0, 1.0) / 6.0
        # mid-surface nodes (Simpson weight 4/6): radius equal to round-off of the mesh's trigonometry
        wr = np.where(np.isclose(r, radius, rtol=1e-6), 4.0, 1.0) / 6.0
        f[sel] = -sgn * P * slab * (wz * wr)[sel]
    u = np.zeros(b.N)
    u[wall.free] = wall.lu.solve(f[wall.free])
    mid_y = (comp == 1) & np.isclose(r, radius, rtol=1e-6) & (np.abs(x) < 1e-9)
    grow = float(np.mean(np.abs(u[mid_y]))) * 2  # both sides move out by the same amount
    D = material.E * thickness**3 / (12 * (1 - material.nu**2))
    exact = (4 - np.pi) / (2 * np.pi) * P * radius**3 / D
    return {"fe": grow, "exact": exact, "rel_err": grow / exact - 1, "dofs": b.N}


def ring_validation(
    material: Material, thickness: float, meshes: Sequence[int], radius: float = 0.035
) -> list[dict]:
    """The thin ring (mid-surface ``radius`` [m], wall ``thickness`` [m]) under diametral line
    loads against Roark, two ways, on a plane-strain slab of each ``n_theta`` of ``meshes``:

    * ``perpendicular_rel_err``: the growth of the perpendicular diameter (:func:`ring_pinch`);
    * ``load_line_rel_err``: the closing of two rigid jaws (:func:`squeeze`, the contact solve
      itself) at ``P = 1e-3`` N on the slab (``P' = P / t``), against
      ``(π/4 − 2/π) P' R³ / D`` with ``D = E t³ / 12 (1 − ν²)``.

    Returns one row per mesh: ``{"n_theta", "perpendicular_rel_err", "load_line_rel_err", "dofs"}``.
    """
    import warnings

    from workbench.plausible import ImplausibleWarning

    t, R = thickness, radius
    D = material.E * t**3 / (12 * (1 - material.nu**2))
    rows = []
    for n in meshes:
        perp = ring_pinch(R, t, material, n_theta=n)
        wall = ring_wall(R, t, material, n)
        P = 1e-3  # N on a slab of length t: P' = 2 N/m, linear anyway
        with warnings.catch_warnings():  # a probe load of Roark's ring, not a gripper's: no warning
            warnings.simplefilter("ignore", ImplausibleWarning)
            sq = squeeze(wall, np.array([0.0, 0.0, t / 2]), np.array([1.0, 0.0, 0.0]), force=P)
        exact = (np.pi / 4 - 2 / np.pi) * (P / t) * R**3 / D
        rows.append(
            {
                "n_theta": n,
                "perpendicular_rel_err": perp["rel_err"],
                "load_line_rel_err": sq.delta / exact - 1,
                "dofs": int(perp["dofs"]),
            }
        )
    return rows


def check_wall(wall: Any, usage: str = "squeeze(wall, centre, axis)") -> Wall:
    """``wall`` if it is a :class:`Wall`, else a ValueError naming what to pass — the one rule of
    every function that takes a wall (``usage``: how that function is called with it, quoted in
    the fix).  The wall is built from the object: :func:`build_wall` on a surface, or
    ``geo, wall = object_wall(mesh)`` (:func:`workbench.fem.object_wall.object_wall`) from a mesh;
    the mesh itself, that ``(geometry, wall)`` pair or the geometry alone is not one."""
    # by name too: workbench/fem/ imports as both `fem` and `workbench.fem`, two Wall classes
    if isinstance(wall, Wall) or (type(wall).__name__ == "Wall" and hasattr(wall, "outer_xyz")):
        return wall
    name = type(wall).__name__
    build = "geo, wall = object_wall(mesh)"
    hint = {
        "Trimesh": f"a mesh is the object's surface, not its wall: {build}; {usage}",
        "tuple": f"object_wall returns the pair (geometry, wall): {build}; {usage}",
        "WallGeometry": f"{build}; {usage} (or wall = geo.build(material))",
    }.get(name, f"{build} (or build_wall(surface, material)); {usage}")
    raise ValueError(
        f"wall must be the Wall built on the surface (build_wall, or object_wall's second value); "
        f"got {name} — {hint}"
    )


@dataclass(frozen=True)
class SqueezeControls:
    """How :func:`squeeze` solves the contact (its defaults are every experiment's).

    The contact set is grown from the footprint nodes within ``margin`` [m] of first touch
    (at most ``max_start`` per jaw, spread over the footprint) by at most ``max_add`` nodes
    per round that pass through a jaw, for at most ``max_rounds`` rounds; each round closes
    the jaws by at most ``max_iter`` Newton steps on their travels.  ``margin`` is a length
    judged as a closing (``[0, 0.1]`` m: 0.2 is taken for millimetres) or ``math.inf``: every
    footprint node starts in the set."""

    margin: float = 0.2e-3
    max_iter: int = 20
    max_start: int = 24
    max_add: int = 48
    max_rounds: int = 30

    def __post_init__(self) -> None:
        number = isinstance(self.margin, int | float | np.integer | np.floating)
        if isinstance(self.margin, bool) or not (number and not np.isnan(self.margin) and self.margin >= 0):
            raise ValueError(
                f"margin must be a distance >= 0 [m] from first touch, or math.inf (every footprint "
                f"node); got {self.margin!r}"
            )
        from workbench.plausible import check

        # a finite margin is a closing past first touch: 0.2 (200 mm) is a millimetre slip
        if not np.isinf(self.margin):
            check(
                "closing",
                self.margin,
                "SqueezeControls.margin (from first touch [m])",
                warn=False,
                examples="0.1-1 mm of a footprint near first touch (the default 0.2 mm)",
                named="contact-set margin",
            )
        for name in ("max_iter", "max_start", "max_add", "max_rounds"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
                raise ValueError(f"{name} must be an integer >= 1; got {value!r}")


def _read_only(values, dtype=float) -> np.ndarray:
    """A read-only copy of ``values`` as an array of ``dtype``."""
    out = np.array(values, dtype=dtype)
    out.flags.writeable = False
    return out


@dataclass(frozen=True)
class Squeeze:
    """The answer of :func:`squeeze`: the same fields on every path, arrays read-only.

    status : ``"solved"`` (the contact was solved; ``converged`` says whether to the target
        force and with no footprint node through a jaw) or ``"clamped"`` (a jaw first touches
        a clamped node of its footprint: it cannot close, no contact solve ran);
    reason : None for a converged solve, else why not (the clamp, or the unmet limit);
    stiffness : force / delta [N/m] (inf when clamped);
    delta : the jaw closing [m], sum of both jaws' travel (0 when clamped);
    width : the object's width [m] between the two jaws' first touches;
    implausible : ``delta >= width``: the jaws would meet inside the object — an impossible
        result of the linear model, flagged, not a stiffness (False when clamped);
    on_clamp : a jaw rests on a clamped node of its footprint (the base): the grasp is as
        stiff as the clamp, rigid (always when clamped);
    clamp_gap : [m] that jaw's travel from its first touch to the clamped node (when not
        on_clamp: the smaller jaw's, inf when no clamped node is under a jaw);
    jaw_travel : (2,) [m] each jaw's travel from first touch (zeros when clamped);
    jaw_forces : (2,) [N] both jaws' forces (NaN when clamped);
    contact_points : (2, 3) [m] the first touches of the grasp axis with the wall;
    contact_nodes : nodes in contact at the end; lcp_solves, candidate_rounds,
    compliance_solves : the LCP solves, rounds of the contact set and sparse solves
    (0 when clamped); converged : bool (True when clamped: nothing to solve).
    """

    status: str
    reason: str | None
    stiffness: float
    delta: float
    width: float
    implausible: bool
    on_clamp: bool
    clamp_gap: float
    jaw_travel: np.ndarray
    jaw_forces: np.ndarray
    contact_points: np.ndarray
    contact_nodes: int
    lcp_solves: int
    candidate_rounds: int
    converged: bool
    compliance_solves: int

    def __post_init__(self) -> None:
        for name in ("jaw_travel", "jaw_forces", "contact_points"):
            object.__setattr__(self, name, _read_only(getattr(self, name)))


def squeeze(
    wall: Wall,
    centre: np.ndarray,
    axis: np.ndarray,
    *,
    jaw: tuple[float, float] = (0.02, 0.04),
    force: float = 10.0,
    controls: SqueezeControls | None = None,
) -> Squeeze:
    """Squeeze the wall between two rigid flat jaws closing along ``axis`` through ``centre``.

    centre : (3,) a point on the grasp axis [m]; axis : (3,) horizontal grasp axis;
    jaw : (width, length) [m] of the jaw faces (length vertical);
    force : target jaw force [N] (thesis: 10 N);
    controls : the contact solve's settings (:class:`SqueezeControls`; default its defaults).
    The jaws press with equal forces (the object is free between them; the wall's
    clamps stand for its stiff base and shoulder, so they carry no net force), each
    travelling its own distance from first touch.  Returns a :class:`Squeeze`: the stiffness
    ``force / Δ`` [N/m], the closing ``Δ`` [m], the object's width between the first touches,
    the ``implausible`` flag (``Δ >= width``), ``on_clamp`` when a jaw would travel past a
    clamped node of its footprint (``clamp_gap`` [m] from that jaw's first touch: the jaw then
    rests on the clamped edge, the base, and the grasp is as stiff as the clamp — rigid), the
    forces and travels of both jaws, the contact points and the solver's counts.

    The contact set grows from a few near-touching nodes (:class:`SqueezeControls`);
    ``converged`` says both jaw forces are the target and no footprint node passes
    through a jaw at the end (else a warning is logged).

    Discretisation: the footprint is the nodes inside the jaw face, so ``stiffness`` steps
    when a jaw edge crosses a row of nodes — an error of the order of the row spacing over the
    jaw length, not a solver tolerance.  Around the wall the same holds for the node columns a
    flat jaw bears on (the axis on a vertex column or on a mid-side one).  Both shrink as
    ``n_z`` and ``n_theta`` grow (the measurements: docs/decisions.md).
    """
    from workbench.sources.jaws import check_jaw_force

    check_wall(wall)
    check_jaw_force(force)
    from workbench.sources.jaws import check_pad

    check_pad(jaw)  # (width, length) [m]: (20, 40) for 0.02 m is refused
    controls = checked_group(
        controls, SqueezeControls, "controls", hint="pass SqueezeControls(margin=..., max_iter=...)"
    )
    axis = _grasp_axis(axis)
    fp = _footprint(wall, centre, axis, jaw)
    if (fp.stop <= 0).any() or not ((fp.owner == 0).any() and (fp.owner == 1).any()):
        # a jaw first touches the clamped edge: it cannot close at all
        return _clamped_result(fp)
    state = _grow_contact(wall, fp, force, controls)
    delta = float(state.travel.sum())
    width = float(np.linalg.norm(fp.touch[0] - fp.touch[1]))
    _warn_closing(delta, force, width)
    travel, stop = state.travel, fp.stop
    return Squeeze(
        status="solved",
        reason=state.reason,
        stiffness=force / delta,
        delta=delta,
        width=width,
        implausible=bool(delta >= width),
        on_clamp=bool((travel > stop).any()),
        clamp_gap=float(stop[np.argmax(travel > stop)]) if (travel > stop).any() else float(stop.min()),
        jaw_travel=travel,
        jaw_forces=state.f,
        contact_points=np.array(fp.touch),
        contact_nodes=int((state.lam > 0).sum()),
        lcp_solves=state.solves,
        candidate_rounds=state.rounds,
        converged=state.converged,
        compliance_solves=int(state.have.sum()),
    )


def _grasp_axis(axis: np.ndarray) -> np.ndarray:
    """The unit (3,) grasp ``axis`` of :func:`squeeze`, or a ValueError unless it is a non-zero
    horizontal (3,) vector."""
    axis = np.asarray(axis, float)
    if axis.shape != (3,) or not np.isfinite(axis).all() or not np.linalg.norm(axis) > 0:
        raise ValueError(f"axis must be a non-zero (3,) grasp axis; got {axis.tolist()}")
    if abs(axis[2]) > 0.05 * np.linalg.norm(axis):  # > ~3 deg: the jaws' faces are vertical
        raise ValueError(
            f"axis {axis.tolist()} is not horizontal: the squeeze's jaws close along a horizontal axis "
            "(their faces vertical, their length along z)"
        )
    return axis / np.linalg.norm(axis)


@dataclass
class _Footprint:
    """The outer-surface nodes under the two jaws of :func:`squeeze` (clamped ones removed)."""

    nodes: np.ndarray  # (k,) indices into Wall.outer_xyz
    dirs: np.ndarray  # (k, 3) each node's closing direction (towards the other jaw)
    gaps: np.ndarray  # (k,) gap to its jaw at first touch [m]
    owner: np.ndarray  # (k,) the jaw (0: on the +axis side, 1) over each node
    lat: np.ndarray  # (k,) lateral coordinate in the jaw face [m]
    vert: np.ndarray  # (k,) vertical coordinate in the jaw face [m]
    stop: np.ndarray  # (2,) each jaw's travel to a clamped node of its footprint [m] (inf: none)
    touch: list  # the two jaws' first-touch points, (3,) each [m]


def _footprint(wall: Wall, centre: np.ndarray, axis: np.ndarray, jaw: tuple[float, float]) -> _Footprint:
    """Each jaw's footprint nodes, their gaps at first touch and the jaws' travel to a clamp."""
    up = np.array([0.0, 0.0, 1.0])
    side = np.cross(up, axis)
    rel = wall.outer_xyz - centre
    along, lat, vert = rel @ axis, rel @ side, rel @ up
    in_print = (np.abs(lat) <= jaw[0] / 2) & (np.abs(vert) <= jaw[1] / 2)
    nodes, dirs, gaps, owner = [], [], [], []
    touch = []
    for jaw_id, s in enumerate((1.0, -1.0)):  # the jaw on the +axis side moves along -axis
        cand = np.flatnonzero(in_print & (s * along > 0))
        if cand.size == 0:
            raise ValueError("no wall under a jaw: the grasp axis misses the object")
        reach = s * along[cand]
        nodes.append(cand)
        gaps.append(reach.max() - reach)  # first touch at the outermost node
        dirs.append(np.tile(-s * axis, (cand.size, 1)))
        owner.append(np.full(cand.size, jaw_id))
        touch.append(centre + s * reach.max() * axis)
    nodes, dirs, gaps, owner = map(np.concatenate, (nodes, dirs, gaps, owner))
    lat, vert = lat[nodes], vert[nodes]
    # a clamped node under a jaw (the base or top edge) does not move: it stops that jaw
    # once the jaw has travelled its gap; the rest of the footprint is the LCP's
    pinned = (wall.free_position[wall.outer_dofs[nodes]] < 0).all(axis=1)
    stop = np.array(
        [gaps[pinned & (owner == c)].min() if (pinned & (owner == c)).any() else np.inf for c in (0, 1)]
    )
    keep = ~pinned
    return _Footprint(nodes[keep], dirs[keep], gaps[keep], owner[keep], lat[keep], vert[keep], stop, touch)


def _clamped_result(fp: _Footprint) -> Squeeze:
    """:func:`squeeze`'s answer when a jaw first touches the clamped edge (it cannot close)."""
    return Squeeze(
        status="clamped",
        reason="a jaw first touches a clamped node of its footprint (the clamped edge): it cannot close",
        stiffness=np.inf,
        delta=0.0,
        width=float(np.linalg.norm(fp.touch[0] - fp.touch[1])),
        implausible=False,
        on_clamp=True,
        clamp_gap=max(float(fp.stop.min()), 0.0),
        jaw_travel=np.zeros(2),
        jaw_forces=np.full(2, np.nan),
        contact_points=np.array(fp.touch),
        contact_nodes=0,
        lcp_solves=0,
        candidate_rounds=0,
        converged=True,
        compliance_solves=0,
    )


@dataclass
class _Contact:
    """The state of :func:`squeeze`'s contact solve."""

    cols: np.ndarray  # (k, k) column j: displacement along dirs under a unit load at node j
    have: np.ndarray  # (k,) bool: column computed
    travel: np.ndarray  # (2,) each jaw's travel [m]
    f: np.ndarray  # (2,) the jaw forces [N]
    lam: np.ndarray | None = None  # (|active|,) the contact forces of the last LCP [N]
    solves: int = 0  # LCP solves
    rounds: int = 0  # candidate rounds
    converged: bool = False
    reason: str | None = None  # why not converged (None when it did)


def _grow_contact(wall: Wall, fp: _Footprint, force: float, controls: SqueezeControls) -> _Contact:
    """Condense only a few near-touching nodes and add the footprint nodes the wall pushes
    through a jaw, round by round: a rigid jaw on a convex wall touches a handful of nodes,
    and on a flat face (a box) the contact gathers at the jaw's edges, so the contact set is
    small even when the whole footprint starts within ``controls.margin``.  Each compliance
    column (one sparse solve) is read at every footprint node and kept, so a round costs only
    its new nodes' solves and the check costs none."""
    active = _spread(
        np.flatnonzero(fp.gaps < controls.margin), fp.gaps, fp.owner, fp.lat, fp.vert, controls.max_start
    )
    k = fp.nodes.size
    st = _Contact(np.zeros((k, k)), np.zeros(k, dtype=bool), np.full(2, 0.5e-3), np.zeros(2))
    while True:
        st.rounds += 1
        new = active[~st.have[active]]
        if new.size:
            st.cols[:, new] = wall.compliance(fp.nodes[new], fp.dirs[new], fp.nodes, fp.dirs)
            st.have[new] = True
        A = st.cols[np.ix_(active, active)]
        A = 0.5 * (A + A.T)
        force_ok = _close_jaws(st, A, fp.gaps[active], fp.owner[active], force, controls.max_iter)
        gap_all = fp.gaps - st.travel[fp.owner] + st.cols[:, active] @ st.lam
        # a node penetrating beyond 1e-9 of the jaws' travel joins the contact set (above the solve's
        # round-off)
        viol = np.setdiff1d(np.flatnonzero(gap_all < -1e-9 * st.travel.sum()), active)
        if viol.size == 0:
            st.converged = force_ok
            if not force_ok:
                log.warning("squeeze: jaw forces %s N, target %.6g N", st.f, force)
                st.reason = f"the jaw forces {st.f.tolist()} N missed the target {force:.6g} N"
            return st
        if st.rounds >= controls.max_rounds:
            log.warning(
                "squeeze: %d footprint nodes still pass through a jaw after %d rounds", viol.size, st.rounds
            )
            st.reason = f"{viol.size} footprint nodes still pass through a jaw after {st.rounds} rounds"
            return st
        # the deepest violators first, at most max_add per round (a flat face's whole footprint
        # would otherwise come in at once)
        viol = viol[np.argsort(gap_all[viol])][: controls.max_add]
        active = np.union1d(active, viol)


def _close_jaws(
    st: _Contact, A: np.ndarray, gaps: np.ndarray, own: np.ndarray, force: float, max_iter: int
) -> bool:
    """Equal and opposite jaw forces on the contact set with compliance ``A`` (a free object
    between the jaws; the clamps only stand for its stiff base and shoulder, so they carry no
    net force): Newton on the two jaws' travels, exact while the contact set holds
    (f = Mᵀ A_SS⁻¹ (M t − g)).  Updates ``st`` (travel, forces, contact forces, solves);
    True when both jaw forces reached ``force``."""
    for _ in range(max_iter):
        lam, _, _ = solve_lcp(A, gaps - st.travel[own])
        st.lam = lam
        st.solves += 1
        st.f = np.array([lam[own == c].sum() for c in (0, 1)])
        # both jaws' forces at the target to 1e-9: the secant update has converged
        if np.all(np.abs(st.f / force - 1) < 1e-9):
            return True
        S = lam > 0
        touching = np.array([(S & (own == c)).any() for c in (0, 1)])
        if not touching.all():  # a jaw off the wall: move it in
            st.travel = np.where(touching, st.travel, 2 * st.travel)
            continue
        M = (own[S, None] == np.arange(2)).astype(float)  # (|S|, 2) jaw of each contact node
        J = M.T @ np.linalg.solve(A[np.ix_(S, S)], M)
        st.travel = np.maximum(st.travel + np.linalg.solve(J, force - st.f), 0.5 * st.travel)
    return False


def _warn_closing(delta: float, force: float, width: float) -> None:
    """Log a warning when the closing ``delta`` [m] at ``force`` [N] is impossible (the jaws
    would meet inside the object's ``width`` [m]) or beyond the linear model's small strains."""
    if delta >= width:  # impossible: the jaws would meet inside the object
        log.warning(
            "squeeze: the jaws close by %.4g m at %g N, more than the object's %.4g m width along the "
            "grasp axis — the linear wall model does not hold there (a modulus in another unit?)",
            delta,
            force,
            width,
        )
    elif delta > _config.TOL.linear_closing_max_fraction * width:  # possible, but not small strain
        log.warning(
            "squeeze: the jaws close by %.3g mm at %g N, %.0f%% of the object's %.3g mm width: beyond "
            "the small deflections of the linear wall model (workbench.fem.wall_nonlinear follows them)",
            delta * 1e3,
            force,
            100 * delta / width,
            width * 1e3,
        )


def _spread(
    near: np.ndarray,
    gaps: np.ndarray,
    owner: np.ndarray,
    lat: np.ndarray,
    vert: np.ndarray,
    k: int,
) -> np.ndarray:
    """At most ``k`` of the ``near`` candidates per jaw, spread over the jaw face:
    farthest-point sampling in the face's (lateral, vertical) coordinates from the
    closest node — the footprint's corners and edges come first, where a flat jaw on a
    flat face bears.  All of them when a jaw has at most ``k``."""
    keep = []
    for jaw in (0, 1):
        cand = near[owner[near] == jaw]
        if cand.size <= k:
            keep.append(cand)
            continue
        xy = np.column_stack([lat[cand], vert[cand]])
        pick = [int(np.argmin(gaps[cand]))]
        d = np.linalg.norm(xy - xy[pick[0]], axis=1)
        while len(pick) < k:
            pick.append(int(np.argmax(d)))
            d = np.minimum(d, np.linalg.norm(xy - xy[pick[-1]], axis=1))
        keep.append(cand[pick])
    return np.unique(np.concatenate(keep))

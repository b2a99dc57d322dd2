"""The wall of a hollow object from its mesh, with the edges that make it stiff.

:func:`workbench.fem.mesh_wall.radial_surface` gives the side wall, the band of heights whose
sections are star-shaped.  What ends that band decides how stiff the wall is near
its top, so :func:`object_wall` models it instead of leaving a free edge:

* a **rolled lip** (an open cup): the mesh continues less than ``LIP_MAX_HEIGHT``
  above the side wall and bulges out there (:func:`find_lip`).  The lip is modelled
  as a ring: the wall's top element row widens, outwards, to the lip's radial width
  measured on the mesh (outermost minus innermost hit), so it is a solid ring of the
  lip's size.  A real rolled lip is a hollow bead — softer than the solid ring of its
  size by about 2× in bending — so this is an upper bound on the lip's stiffening;
* a **shoulder, neck or cap** (a bottle; a solid mesh): the object is closed above
  the side wall; its top is clamped (a closed shoulder is far stiffer than the wall);
* nothing above (an open cylinder), or an opening the side wall runs up to (the
  mustard bottle's star-shaped band climbs over its shoulder to the nozzle, so the
  shoulder is in the model and only the nozzle's small ring is free): a free edge.

Open or closed is read off the mesh (:func:`is_closed_top`): a closed object
continues more than ``LIP_MAX_HEIGHT`` above its side wall, or a ray down the axis
from above meets it within that of its top.

The base always clamps the bottom of the side wall.  Grasps on the lip are on the
modelled wall; grasps above it (caps, necks) are rigid (:mod:`workbench.fem.wall_grasps`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np

from workbench.units import closed_mesh

from .material import Material
from .mesh_wall import RadialSurface, _ray_hits, radial_surface
from .wall import PET, Wall, build_wall, turned_surface

log = logging.getLogger(__name__)

#: a band above the side wall shorter than this [m] is a lip (an open cup's rim); taller: a shoulder
LIP_MAX_HEIGHT = 6e-3
#: a lip bulges at least this far [m] beyond the side wall's outer surface
LIP_MIN_BULGE = 0.5e-3
TOPS = ("auto", "lip", "clamped", "free")


@dataclass(frozen=True)
class Lip:
    """A rolled rim above the side wall: heights ``z0``..``z1`` [m], radial ``width`` [m]
    (outermost minus innermost mesh hit) and how far it bulges beyond the wall, ``bulge`` [m]."""

    z0: float
    z1: float
    width: float
    bulge: float


def find_lip(mesh: Any, surface: RadialSurface, *, n_theta: int = 36, dz: float = 0.25e-3) -> Lip | None:
    """The lip of an open cup (module docstring), or None (a taller band above: a shoulder;
    no bulge: a plain edge).  ``mesh`` in metres, ``surface`` its side wall."""
    z_hi = surface.z_range[1]
    top = float(surface.bounds[1, 2])
    if top - z_hi > LIP_MAX_HEIGHT or top - z_hi < dz:
        return None
    zs = np.arange(z_hi + dz, top - 0.1 * dz, dz)
    th = 2 * np.pi * np.arange(n_theta) / n_theta
    T, Z = np.meshgrid(th, zs, indexing="ij")
    dirs = np.column_stack([np.cos(T.ravel()), np.sin(T.ravel()), np.zeros(T.size)])
    c = surface.centre
    origins = np.column_stack([np.full(T.size, c[0]), np.full(T.size, c[1]), Z.ravel()])
    counts, dists = _ray_hits(mesh, origins, dirs)
    outer = np.array([d[-1] if len(d) else np.nan for d in dists]).reshape(T.shape)
    inner = np.array([d[0] if len(d) >= 2 else np.nan for d in dists]).reshape(T.shape)
    wall = surface.radius(T.ravel(), np.full(T.size, z_hi)).reshape(T.shape)
    bulge = np.nanmedian(outer - wall, axis=0)  # per height
    rows = np.flatnonzero(bulge > LIP_MIN_BULGE)
    if rows.size == 0:
        return None
    width = float(np.nanmedian((outer - inner)[:, rows]))
    lip = Lip(float(zs[rows[0]]), top, width, float(np.median(bulge[rows])))
    log.info(
        "find_lip: lip z = %.4g..%.4g m, width %.2f mm, bulge %.2f mm",
        lip.z0,
        top,
        width * 1e3,
        lip.bulge * 1e3,
    )
    return lip


def is_closed_top(mesh: Any, surface: RadialSurface) -> bool:
    """Whether the object is closed above its side wall: the mesh continues more than
    ``LIP_MAX_HEIGHT`` above it (a bottle's shoulder, neck and cap), or a ray down the
    axis from above meets the mesh within ``LIP_MAX_HEIGHT`` of its top (a flush cap, a
    solid mesh).  An open cup ends just above its side wall, and that ray meets its base."""
    top = float(surface.bounds[1, 2])
    if top - surface.z_range[1] > LIP_MAX_HEIGHT:
        return True
    c = surface.centre
    counts, dists = _ray_hits(mesh, np.array([[c[0], c[1], top + 1e-3]]), np.array([[0.0, 0.0, -1.0]]))
    return bool(counts[0] and dists[0][0] - 1e-3 < LIP_MAX_HEIGHT)


@dataclass(frozen=True)
class WallGeometry:
    """The modelled wall: ``surface`` (side wall), ``lip`` (or None), wall ``thickness`` [m],
    heights ``z_range`` [m] of the modelled wall (side wall plus lip), ``clamp_top``, and
    ``n_z`` element rows (chosen so one row spans the lip)."""

    surface: RadialSurface
    lip: Lip | None
    thickness: float
    z_range: tuple[float, float]
    clamp_top: bool
    n_z: int

    def outer(self, theta: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Outer points (N, 3) and normals (N, 3) at θ (N,), z (N,): the side wall, moved
        out on the lip so its outer face is the lip's (the ``surface`` of :func:`build_wall`)."""
        z = np.asarray(z, float)
        lo, hi = self.surface.z_range
        p, n = self.surface(theta, np.clip(z, lo, hi))
        p = p.copy()
        p[:, 2] = z
        if self.lip is not None:
            on = z >= self.lip.z0
            p[on] += (self.lip.width - self.thickness) * n[on]
        return p, n

    def thickness_at(self, z: np.ndarray) -> np.ndarray:
        """(N,) wall thickness [m] at heights z (N,): the lip's width on the lip."""
        z = np.asarray(z, float)
        if self.lip is None:
            return np.full(z.shape, self.thickness)
        return np.where(z >= self.lip.z0, self.lip.width, self.thickness)

    def build(self, material: Material = PET, *, n_theta: int = 48, turn: float = 0.0) -> Wall:
        """The wall assembled and factorised (:func:`workbench.fem.wall.build_wall`), ``n_theta``
        elements around and ``n_z`` along; ``turn`` [rad]: built turned by ``-turn`` about
        z (:func:`workbench.fem.wall.turned_surface`: a grasp axis at ``turn`` becomes +x)."""
        return build_wall(
            turned_surface(self.outer, turn) if turn else self.outer,
            material,
            thickness=self.thickness_at,
            n_theta=n_theta,
            n_z=self.n_z,
            z_range=self.z_range,
            clamp_top=self.clamp_top,
        )


def check_wall_options(thickness: Any, top: Any) -> None:
    """``ValueError`` unless ``thickness`` is a finite wall thickness > 0 [m] and ``top`` one
    of ``TOPS`` (:func:`wall_geometry`'s options, checkable before any mesh is read)."""
    from workbench.plausible import check

    if isinstance(thickness, np.number):
        thickness = thickness.item()
    check("wall_thickness", thickness, "thickness")
    if top not in TOPS:
        raise ValueError(
            f"top must be one of {TOPS} (the wall's top edge; module workbench.fem.object_wall); got {top!r}"
        )


def wall_geometry(
    mesh: Any,
    *,
    thickness: float = 0.5e-3,
    n_z: int = 24,
    top: str = "auto",
    units: str | float | None = None,
) -> WallGeometry:
    """The modelled wall of a hollow object's watertight mesh (metres), before assembly:
    the side wall by ray casting, its top edge (module docstring) and ``n_z`` rows
    (at least one per lip height).  Cheap next to :meth:`WallGeometry.build`, so
    locations can be checked against ``.surface`` before any FEM work.

    thickness : wall thickness [m] (> 0); n_z : elements along the height;
    top : "auto" (clamped if the object is closed above its side wall,
    :func:`is_closed_top`; an open one gets its lip if :func:`find_lip` finds one,
    else a free edge), "lip", "clamped" or "free".
    Raises ``ValueError`` for careless meshes (:func:`workbench.fem.mesh_wall.radial_surface`), a
    thickness <= 0, an unknown ``top`` or ``top="lip"`` on an object without one.
    """
    check_wall_options(thickness, top)
    mesh = closed_mesh(mesh, "the object mesh", units=units, override=None)
    # the axis is the box's vertical centre line and the heights are found, not given, so the
    # only fix a caller has is another object
    surface = radial_surface(
        mesh,
        remedy="the wall is built about the vertical line through the mesh box's centre, so every "
        "horizontal section of the side wall must be star-shaped about it: one body, no handle",
    )
    closed = is_closed_top(mesh, surface)
    lip = find_lip(mesh, surface) if top == "lip" or (top == "auto" and not closed) else None
    if top == "lip" and lip is None:
        raise ValueError("top='lip' but the mesh has no lip above its side wall; use top='auto'")
    # a shell: the wall is thin next to the section (0.5 given for 0.5 mm reads as 0.5 m)
    r_min = float(
        np.min(
            surface.radius(
                np.linspace(0, 2 * np.pi, 72, endpoint=False), np.full(72, np.mean(surface.z_range))
            )
        )
    )
    if thickness > 0.2 * r_min:
        raise ValueError(
            f"thickness {thickness!r} m is more than a fifth of the section's smallest radius "
            f"({r_min:.3g} m): a thin-walled object's wall is given in metres, e.g. 0.5e-3 for 0.5 mm"
        )
    lo, hi = surface.z_range
    clamp_top = top == "clamped" or (top == "auto" and closed)
    if lip is not None:
        hi = lip.z1
        n_z = max(n_z, int(np.ceil((hi - lo) / (lip.z1 - lip.z0))))
    log.info(
        "wall_geometry: z = %.4g..%.4g m, top %s, %d element rows",
        lo,
        hi,
        "lip" if lip else ("clamped" if clamp_top else "free"),
        n_z,
    )
    return WallGeometry(surface, lip, float(thickness), (lo, hi), bool(clamp_top), int(n_z))


def object_wall(
    mesh: Any,
    material: Material = PET,
    *,
    thickness: float = 0.5e-3,
    n_theta: int = 48,
    n_z: int = 24,
    top: str = "auto",
    units: str | float | None = None,
) -> tuple[WallGeometry, Wall]:
    """:func:`wall_geometry` and its wall assembled and factorised
    (:meth:`WallGeometry.build` with ``n_theta`` elements around)."""
    geo = wall_geometry(mesh, thickness=thickness, n_z=n_z, top=top, units=units)
    return geo, geo.build(material, n_theta=n_theta)


__all__ = [
    "LIP_MAX_HEIGHT",
    "Lip",
    "WallGeometry",
    "check_wall_options",
    "find_lip",
    "is_closed_top",
    "object_wall",
    "wall_geometry",
]

"""A closed triangle mesh standing on its base as an object the FEM pad grasps from the side —
the thesis's 24 objects of §3.5.2 (Fig 3.11(b)) given as meshes — with the interface of
:class:`workbench.fem.bottle.Bottle` that :func:`workbench.fem.bottle.grasp_pose` and fem-fitting
read: ``params.height`` and ``params.asymmetric``, the horizontal cross-section at a height as
an equivalent ellipse (:meth:`MeshObject.section`), the signed distance and the mesh.

The object stands along +z (its base at its lowest z).  A cross-section is the mesh cut by the
plane z = const; its equivalent ellipse has the cut region's area centroid and second moments of
area (Green's theorem over the cut's edges, each oriented by its face's outward normal — no
loops need tracing), which an ellipse's own section returns exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..cachedir import array_digest
from .obstacles import MeshObstacle

__all__ = ["MeshObject", "MeshParams", "edges_ellipse", "polygon_ellipse"]


@dataclass(frozen=True)
class MeshParams:
    """What fem-fitting reads of an object's parameters: ``height`` [m] (its z extent) and
    ``asymmetric`` (its mirror image about the y–z plane through its base's centre is not
    itself: the thesis's "eight objects are asymmetric")."""

    height: float
    asymmetric: bool


def polygon_ellipse(xy: np.ndarray) -> tuple[np.ndarray, float, float, float]:
    """The ellipse with the area, centroid and second moments of area of the closed polygon
    ``xy`` (n, 2) [m] (vertices in order, either sense, not repeated): ``(centre (2,), A, B,
    φ)``, semi-axes A ≥ B [m] and the major axis's angle φ [rad] from +x, in (−π/2, π/2].
    Raises ``ValueError`` for a polygon of no area."""
    p = np.asarray(xy, dtype=float)
    return edges_ellipse(p, np.roll(p, -1, axis=0))


def edges_ellipse(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, float, float, float]:
    """:func:`polygon_ellipse` of the region bounded by the directed edges ``a[i] → b[i]``
    ((n, 2) each, [m]): Green's theorem summed over the edges, so any set of closed loops, each
    oriented with the region on its left (holes clockwise), in any order — the region of either
    sense when all loops turn alike.  Raises ``ValueError`` for a region of no area."""
    x, y = a[:, 0], a[:, 1]
    xn, yn = b[:, 0], b[:, 1]
    c = x * yn - xn * y
    area = c.sum() / 2.0
    if not abs(area) > 0:
        raise ValueError("the section polygon has no area")
    cx = ((x + xn) * c).sum() / (6.0 * area)
    cy = ((y + yn) * c).sum() / (6.0 * area)
    # second moments about the origin, then about the centroid (sign-free: divided by area)
    ixx = ((y * y + y * yn + yn * yn) * c).sum() / 12.0 / area - cy * cy  # ∫ y² dA / A
    iyy = ((x * x + x * xn + xn * xn) * c).sum() / 12.0 / area - cx * cx  # ∫ x² dA / A
    ixy = ((x * yn + 2 * x * y + 2 * xn * yn + xn * y) * c).sum() / 24.0 / area - cx * cy
    # an ellipse of semi-axes A, B has ∫ u² dA / area = A² / 4 along its major axis
    evals, evecs = np.linalg.eigh(np.array([[iyy, ixy], [ixy, ixx]]))
    B, A = (2.0 * np.sqrt(np.clip(evals, 0.0, None))).tolist()
    major = evecs[:, 1]
    phi = float(np.arctan2(major[1], major[0]))
    if phi <= -np.pi / 2:
        phi += np.pi
    elif phi > np.pi / 2:
        phi -= np.pi
    return np.array([cx, cy]), A, B, phi


class MeshObject:
    """A closed mesh as a graspable object (the module docstring says what it offers).

    mesh : a ``trimesh.Trimesh`` or a path to one, closed (:class:`MeshObstacle` refuses an
        open one); units : its length unit (``"m"``, ``"mm"``, …; :class:`MeshObstacle`);
    name : what tables call it (default: the file's stem, else ``"mesh"``);
    asymmetry_tol : the mirror test's tolerance [m] — the object is ``asymmetric`` when, at
        one of five heights, its section's centroid is further than this from the midpoint of
        its x extent.
    """

    def __init__(
        self,
        mesh,
        *,
        units: str | float | None = "m",
        name: str | None = None,
        asymmetry_tol: float = 1e-3,
    ) -> None:
        if name is None:
            name = Path(mesh).stem if isinstance(mesh, (str, Path)) else "mesh"
        self.name = str(name)
        self.obstacle = MeshObstacle(mesh, units=units)
        self._sides: dict[tuple, MeshObstacle] = {}  # one-sided views, per direction
        m = self.obstacle.mesh
        #: SHA-256 of the mesh in metres (vertices and faces): what a cache of its results is keyed by
        self.digest = array_digest(
            [np.ascontiguousarray(m.vertices, float), np.ascontiguousarray(m.faces, np.int64)], "mesh"
        )
        lo, hi = self.obstacle.mesh.bounds
        self.z0 = float(lo[2])
        height = float(hi[2] - lo[2])
        # a mirror-symmetric object's sections are centred on its x extent's midpoint at every
        # height: check at five
        mid_x = 0.5 * float(lo[0] + hi[0])
        offsets = [abs(self.section(self.z0 + f * height)[0][0] - mid_x) for f in (0.2, 0.35, 0.5, 0.65, 0.8)]
        asym = max(offsets) > asymmetry_tol
        self.params = MeshParams(height=height, asymmetric=bool(asym))

    def section(self, z: float) -> tuple[np.ndarray, float, float, float]:
        """Centre (2,), semi-axes A ≥ B [m] and major-axis angle φ [rad] of the equivalent
        ellipse (:func:`edges_ellipse`) of the object's cut at height ``z`` [m] (absolute, as
        the mesh's own z): the material region — every loop of the cut, each edge oriented by
        its face's outward normal, so a hollow's inner wall subtracts.  Raises ``ValueError``
        where the plane misses the object."""
        import trimesh

        mesh = self.obstacle.mesh
        segs, faces = trimesh.intersections.mesh_plane(
            mesh, plane_normal=[0.0, 0.0, 1.0], plane_origin=[0.0, 0.0, float(z)], return_faces=True
        )
        if len(segs) < 3:
            raise ValueError(
                f"{self.name}: the plane z = {z:.4g} m misses the object (z from {self.z0:.4g} m)"
            )
        a, b = segs[:, 0, :2], segs[:, 1, :2]
        d = b - a
        # the region on the left of each edge: its outward normal (d_y, −d_x) along the face's
        flip = (d[:, 1] * mesh.face_normals[faces, 0] - d[:, 0] * mesh.face_normals[faces, 1]) < 0
        a, b = np.where(flip[:, None], b, a), np.where(flip[:, None], a, b)
        return edges_ellipse(a, b)

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N,) signed distances [m] and (N, 3) outward normals of points ``x`` (N, 3) [m]
        (:meth:`MeshObstacle.signed_distance`)."""
        return self.obstacle.signed_distance(x)

    def one_sided(self, direction) -> MeshObstacle:
        """The obstacle of the faces whose outward normal has a positive component along
        ``direction`` (3,) — what a jaw coming from that side can touch.  A thin shell (the
        thesis's meshes are ~0.5 mm walls) pressed deeper than half its wall is otherwise nearer
        its inner surface, and the contact's normals flip.  Kept per direction (to 1e-6)."""
        d = np.asarray(direction, dtype=float)
        d = d / np.linalg.norm(d)
        key = tuple(np.round(d, 6).tolist())
        if key not in self._sides:
            self._sides[key] = MeshObstacle(self.obstacle.mesh, facing=key)
        return self._sides[key]

    def to_trimesh(self):
        """The mesh [m] (for renders)."""
        return self.obstacle.mesh

    def __repr__(self) -> str:
        p = self.params
        return f"MeshObject({self.name!r}, height={p.height:.4g} m, asymmetric={p.asymmetric})"

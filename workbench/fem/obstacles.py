"""Rigid obstacles as signed-distance functions (positive outside the obstacle).

``signed_distance(points)`` returns ``(d, n)``: the signed distance (N,) and
the obstacle's outward unit normal (N, 3) at the closest surface point — which
is the "outward from the object" normal of a contact profile.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._kernels import _nearest_of_candidates, _point_triangle_pairs


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v)
    if not np.isfinite(n) or n == 0:
        raise ValueError(f"direction must be a finite non-zero 3-vector; got {v}")
    return v / n


def _frozen(a, dtype) -> np.ndarray:
    """A C-contiguous copy of ``a`` that cannot be written."""
    out = np.array(a, dtype=dtype, order="C")
    out.flags.writeable = False
    return out


def _point(name: str, p, allow_scale: bool = False) -> None:
    """Refuse a point that is not a finite 3-vector (a NaN would silently mean "no contact")."""
    v = np.asarray(p, dtype=float)
    if v.shape != (3,) or not np.isfinite(v).all():
        raise ValueError(f"{name} must be a finite (3,) point [m]; got {p!r}")
    if np.linalg.norm(v) > 0 and not allow_scale:  # within reach of the pad (25 for 0.025 is a slip)
        from workbench.plausible import check

        check("lever", float(np.linalg.norm(v)), f"{name}'s distance from the pad [m]", warn=False)


def _length(name: str, value) -> float:
    """``value`` as a float if it is a finite number > 0 (a 0-d array too; not a bool or a
    string), else a ValueError naming ``name``."""
    ok = not isinstance(value, (bool, np.bool_, str, bytes)) and np.ndim(value) == 0
    try:
        x = float(value) if ok else np.nan
    except (TypeError, ValueError):
        x = np.nan
    if not (np.isfinite(x) and x > 0):
        raise ValueError(f"{name} must be > 0, a length in metres; got {value!r}")
    return x


def _radius(obstacle, where: str) -> None:
    """Refuse ``obstacle.radius`` [m] unless it is a number > 0 and, unless ``allow_scale``, a
    plausible object size by the mesh extent rule (:func:`workbench.units.check_extent` on the
    diameter, as :class:`MeshObstacle`: a radius of 20 reads as 20 m, "probably millimetres").
    ``where``: the obstacle's position field, named in the fix."""
    r = _length("radius", obstacle.radius)
    if not obstacle.allow_scale:
        from workbench.units import check_extent

        check_extent(
            2.0 * float(r),
            f"{type(obstacle).__name__}'s diameter (2 × radius {obstacle.radius})",
            fix=f"give the radius and the {where} in metres (scale both by {{factor:g}}: 20 mm = 0.02)",
        )


@dataclass(frozen=True)
class Plane:
    """Half-space ``(x - point)·normal <= 0``; ``normal`` points out of the obstacle.

    Pressed by a pad (:func:`workbench.fem.press`; the pad's face looks along +z), the normal
    must face the pad, ``normal[2] < 0`` (default ``(0, 0, -1)``): a flipped one puts the pad
    inside the solid and is refused there (:func:`workbench.fem.contact.face_gaps`).  The pad's
    frame has its rigid back at z = 0 and its face at z = h (the layer thickness), so a plane
    pressed from first touch is ``Plane(point=(0, 0, h))``; the default point, the origin, lies at
    the back and is refused there as an obstacle placed inside the layer."""

    point: tuple = (0.0, 0.0, 0.0)
    normal: tuple = (0.0, 0.0, -1.0)

    def __post_init__(self) -> None:
        _point("point", self.point)
        _unit(self.normal)

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = _unit(self.normal)
        d = (x - np.asarray(self.point, float)) @ n
        return d, np.broadcast_to(n, x.shape).copy()


@dataclass(frozen=True)
class Sphere:
    center: tuple = (0.0, 0.0, 0.0)
    radius: float = 0.02
    allow_scale: bool = False  # accept a radius outside the plausible object sizes

    def __post_init__(self) -> None:
        # the size first: a sphere given in millimetres is named by its radius, not by a centre
        # "too far from the pad" that follows from the same slip
        _radius(self, "center")
        _point("center", self.center, self.allow_scale)

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r = x - np.asarray(self.center, float)
        dist = np.linalg.norm(r, axis=1)
        return dist - self.radius, r / np.where(dist > 0, dist, 1.0)[:, None]


@dataclass(frozen=True)
class Cylinder:
    """Infinite circular cylinder with axis through ``point`` along ``axis``."""

    point: tuple = (0.0, 0.0, 0.0)
    axis: tuple = (0.0, 1.0, 0.0)
    radius: float = 0.02
    allow_scale: bool = False  # accept a radius outside the plausible object sizes
    _a: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _radius(self, "point")  # the size first, as Sphere
        _point("point", self.point, self.allow_scale)
        object.__setattr__(self, "_a", _unit(self.axis))

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r = x - np.asarray(self.point, float)
        radial = r - (r @ self._a)[:, None] * self._a
        dist = np.linalg.norm(radial, axis=1)
        return dist - self.radius, radial / np.where(dist > 0, dist, 1.0)[:, None]


@dataclass(frozen=True)
class EllipticCylinder:
    """Infinite elliptic cylinder: axis through ``point`` along ``axis``, semi-axis ``a`` along
    ``major`` (made orthogonal to the axis) and ``b`` along ``axis × major`` [m].

    The exact signed distance to the elliptic section (Eberly, "Distance from a point to an
    ellipse", 2013): the closest point ``x_i = e_i² y_i / (t + e_i²)`` with ``t`` the root of
    ``Σ (e_i y_i / (t + e_i²))² = 1`` in its bracket, found by bisection to round-off (inside and
    outside alike); the normal is the ellipse's outward normal at that point.
    """

    point: tuple = (0.0, 0.0, 0.0)
    axis: tuple = (0.0, 1.0, 0.0)
    major: tuple = (0.0, 0.0, 1.0)
    a: float = 0.03
    b: float = 0.02
    allow_scale: bool = False  # accept semi-axes outside the plausible object sizes
    _frame: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("a", "b"):  # the size first, as Sphere
            _length(f"semi-axis {name}", getattr(self, name))
        if not self.allow_scale:
            from workbench.units import check_extent

            check_extent(
                2.0 * max(self.a, self.b),
                f"{type(self).__name__} of semi-axes {self.a}, {self.b} (largest diameter)",
                fix="give the semi-axes and the point in metres (scale them by {factor:g}: 20 mm = 0.02)",
            )
        _point("point", self.point, self.allow_scale)
        ax = _unit(self.axis)
        u = _unit(self.major)
        u = u - (u @ ax) * ax
        if np.linalg.norm(u) < 1e-9:
            raise ValueError(f"major {self.major} is parallel to axis {self.axis}: give one across it")
        u /= np.linalg.norm(u)
        object.__setattr__(self, "_frame", np.stack([u, np.cross(ax, u), ax]))

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        q = (np.asarray(x, float) - np.asarray(self.point, float)) @ self._frame.T  # (N, 3): u, v, axis
        swap = self.a < self.b  # the algorithm wants e0 >= e1
        e0, e1 = (self.b, self.a) if swap else (self.a, self.b)
        y = np.abs(q[:, [1, 0]] if swap else q[:, :2])
        y0, y1 = y[:, 0], y[:, 1]
        c0, c1 = np.empty_like(y0), np.empty_like(y1)
        on_axis = y1 <= 0.0
        # y1 > 0: bisection on t in [-e1² + e1 y1, -e1² + |(e0 y0, e1 y1)|]
        g = ~on_axis
        z0, z1 = y0[g], y1[g]
        lo = -e1 * e1 + e1 * z1
        hi = -e1 * e1 + np.hypot(e0 * z0, e1 * z1)
        for _ in range(200):  # halves the bracket to round-off (< 200 halvings of a double)
            t = 0.5 * (lo + hi)
            f = (e0 * z0 / (t + e0 * e0)) ** 2 + (e1 * z1 / (t + e1 * e1)) ** 2 - 1.0
            lo, hi = np.where(f > 0, t, lo), np.where(f > 0, hi, t)
            if np.all(hi - lo <= 4 * np.finfo(float).eps * np.maximum(np.abs(lo), np.abs(hi))):
                break
        t = 0.5 * (lo + hi)
        c0[g] = e0 * e0 * z0 / (t + e0 * e0)
        c1[g] = e1 * e1 * z1 / (t + e1 * e1)
        # y1 = 0 (on the major axis): the closest point is the vertex, or off-axis when y0 is
        # inside the evolute's cusp
        z0 = y0[on_axis]
        spread = e0 * e0 - e1 * e1  # 0 for a circle: no cusp, every on-axis point goes to the vertex
        inner = z0 < spread / e0
        x0 = np.where(inner, e0 * e0 * z0 / spread, e0) if spread > 0 else np.full_like(z0, e0)
        c0[on_axis] = x0
        c1[on_axis] = np.where(inner, e1 * np.sqrt(np.clip(1.0 - (x0 / e0) ** 2, 0.0, None)), 0.0)
        inside = (y0 / e0) ** 2 + (y1 / e1) ** 2 < 1.0
        d = np.hypot(y0 - c0, y1 - c1) * np.where(inside, -1.0, 1.0)
        n2 = np.column_stack([c0 / (e0 * e0), c1 / (e1 * e1)])
        n2 *= np.sign(np.where(q[:, [1, 0]] if swap else q[:, :2], q[:, [1, 0]] if swap else q[:, :2], 1.0))
        n2 /= np.linalg.norm(n2, axis=1, keepdims=True)
        if swap:
            n2 = n2[:, [1, 0]]
        n = n2 @ self._frame[:2]
        return d, n

    def to_trimesh(self, length: float, sections: int = 720):
        """A closed triangle mesh of the cylinder, ``length`` [m] long, centred on ``point``,
        ``sections`` facets around (for peers that need a mesh, e.g. Drake)."""
        import trimesh

        cyl = trimesh.creation.cylinder(radius=1.0, height=float(length), sections=int(sections))
        cyl.apply_transform(np.diag([self.a, self.b, 1.0, 1.0]))
        T = np.eye(4)
        T[:3, :3] = self._frame.T  # local (u, v, axis) -> world
        T[:3, 3] = np.asarray(self.point, float)
        cyl.apply_transform(T)
        return cyl


class MeshObstacle:
    """A rigid watertight triangle mesh (trimesh) as an obstacle.

    The signed distance uses the closest surface point ``c``; its sign is that
    of ``(x - c)·n_s`` with ``n_s`` the vertex normals interpolated at ``c``
    (a face-normal test fails when ``c`` lies on an edge, ray-cast ``contains``
    misclassified points near the surface), and the normal is the distance
    gradient ``±(x - c)/|x - c|``; within 1e-6 edge lengths of the surface both
    come from the closest face.
    A non-watertight mesh is rejected.

    units : the mesh's length unit (``"m"``, ``"cm"``, ``"mm"``, ``"um"`` or metres per
        unit; ``None``: metres).  The size is checked after the conversion
        (:func:`workbench.units.check_extent`): a mesh whose largest bounding-box side
        is above ``TOL.max_object_extent_m`` (2 m) or below ``TOL.min_object_extent_m``
        (0.1 mm) raises ``ValueError`` naming the likely unit (a 150 mm bottle exported
        in mm reads as 150 m: pass ``units="mm"``); ``allow_scale=True`` accepts any size.
    transform : 4×4 rigid transform applied after the unit conversion (metres).
    facing : keep only faces whose normal has a positive component along it (one-sided).

    The obstacle is fixed when made: its search trees and the arrays its queries read
    (corners, face normals, vertex normals at each face's corners) are read-only copies of
    ``mesh`` taken then — a query does not go through trimesh's cached properties, which
    re-hash the mesh at every access — so edit no ``mesh`` in place; :meth:`transformed`
    makes a moved obstacle.
    """

    def __init__(
        self,
        mesh,
        *,
        units: str | float | None = None,
        transform: np.ndarray | None = None,
        facing=None,
        allow_scale: bool = False,
    ) -> None:
        import trimesh

        from workbench.units import check_closed, check_extent, length_factor

        if isinstance(mesh, (str, bytes)) or hasattr(mesh, "__fspath__"):
            mesh = trimesh.load(mesh, force="mesh")
        if not isinstance(mesh, trimesh.Trimesh):
            raise ValueError(f"mesh must be a trimesh.Trimesh or a path to one; got {type(mesh).__name__}")
        check_closed(mesh, "mesh passed to MeshObstacle")  # watertight and outward, or refused
        # rebuild from vertices/faces: vertex normals then come from the faces, not
        # from the file (some thesis OBJs carry inward vertex normals)
        mesh = trimesh.Trimesh(np.array(mesh.vertices), np.array(mesh.faces), process=False)
        factor = length_factor("m" if units is None else units)
        check_extent(
            float(np.ptp(mesh.vertices, axis=0).max()) * factor,
            "mesh passed to MeshObstacle (largest bounding-box side)",
            units=units,
            allow_scale=allow_scale,
        )
        mesh.apply_scale(factor)
        if transform is not None:
            from workbench.units import check_rigid

            mesh.apply_transform(check_rigid(transform, "transform (a rigid 4×4 in metres)"))
        self.mesh = mesh
        self.facing = None if facing is None else _unit(facing)
        # what the queries read, as plain read-only arrays (the same numbers as trimesh's)
        self._triangles = _frozen(mesh.triangles, float)  # (F, 3, 3) corners
        self._face_normals = _frozen(mesh.face_normals, float)  # (F, 3)
        self._corner_normals = _frozen(mesh.vertex_normals[mesh.faces], float)  # (F, 3, 3)
        from scipy.spatial import cKDTree

        # thin walls (0.4 mm on some thesis bottles): a point pressed past half the
        # wall is nearer the inner surface; facing=(0, 0, -1) keeps only the faces a
        # jaw approaching along +z can touch (a one-sided distance)
        keep = (
            np.arange(len(mesh.faces))
            if self.facing is None
            else np.flatnonzero(self._face_normals @ self.facing > 0)
        )
        self._faces = keep
        centers = mesh.triangles_center[keep]
        self._tree = cKDTree(centers)
        self._edge = float(mesh.edges_unique_length.mean())
        # centroid-to-corner distance: a face whose closest point lies within d of x has its
        # centroid within d + this of x, which certifies the nearest-centroid candidates.
        # Faces far above the median (a cylinder's full-height sides, a cap's spokes) are
        # searched in a tree of their own, so they do not widen every other point's search.
        reach = np.linalg.norm(self._triangles[keep] - centers[:, None, :], axis=2).max(axis=1)
        big = reach > 2.0 * np.median(reach)
        self._reach = float(reach[~big].max()) if (~big).any() else 0.0
        self._big = keep[big]
        self._big_reach = float(reach[big].max()) if big.any() else 0.0
        self._big_tree = cKDTree(centers[big]) if big.any() else None

    #: candidate triangles (nearest centroids) searched exactly per query point
    CANDIDATES = 24

    def closest(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Closest surface points (N, 3), distances (N,) and triangle ids (N,).

        Point-triangle distances over the nearest-centroid candidates, evaluated
        in a frame centered at the query point and scaled by the mean edge
        length: trimesh's routine uses absolute tolerances and, with mm-sized
        triangles in metres, returned distances 5x too large (measured on a
        20k-face sphere of radius 20 mm; O(1) triangles fix it).  The distances are
        that routine's (Ericson's region tests, tolerance ``TOL.point_triangle_zero`` =
        trimesh's ``tol.zero``) bit for bit, computed pair by pair by
        ``fem._kernels._closest_on_triangle`` in that frame.  The candidates
        are certified: where a face outside them could still be closer (its
        centroid within the found distance plus the largest centroid-to-corner
        distance — long or sliver faces, e.g. a cylinder's full-height sides), every
        face whose centroid lies in that ball is searched as well.
        """
        from workbench.config import TOL

        x = np.ascontiguousarray(x, dtype=float)
        k = min(self.CANDIDATES, len(self._faces))
        r_cand, cand = self._tree.query(x, k=k)
        cand = self._faces[cand.reshape(len(x), k)]
        # the nearest candidate of each point (the first of equal distances, as argmin)
        best_p, best_d = np.empty((len(x), 3)), np.empty(len(x))
        best_t = np.empty(len(x), dtype=cand.dtype)
        _nearest_of_candidates(
            self._triangles, x, cand, self._edge, TOL.point_triangle_zero, best_p, best_d, best_t
        )
        if k < len(self._faces):
            searches = [(self._tree, self._faces, self._reach, np.asarray(r_cand).reshape(len(x), k)[:, -1])]
            if self._big_tree is not None:  # r = 0: always searched (few faces)
                searches.append((self._big_tree, self._big, self._big_reach, np.zeros(len(x))))
            for tree, faces, reach, r_k in searches:
                radius = best_d + reach
                unsure = np.flatnonzero(r_k < radius)
                if unsure.size == 0:
                    continue
                balls = tree.query_ball_point(x[unsure], radius[unsure])
                owner = np.repeat(unsure, [len(b) for b in balls])
                if owner.size == 0:
                    continue
                tri = faces[np.concatenate([np.asarray(b, dtype=np.int64) for b in balls])]
                p2, d2 = self._point_triangle(x, owner, tri)
                order = np.lexsort((d2, owner))  # per query point, nearest first
                first = order[np.r_[True, owner[order][1:] != owner[order][:-1]]]
                i = owner[first]
                closer = d2[first] < best_d[i]
                i, first = i[closer], first[closer]
                best_p[i], best_d[i], best_t[i] = p2[first], d2[first], tri[first]
        return best_p, best_d, best_t

    def _point_triangle(
        self, x: np.ndarray, owner: np.ndarray, tri: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Closest points (m, 3) on triangles ``tri`` (m,) to points ``x[owner]`` (``x`` (n, 3)
        C-contiguous, ``owner`` (m,)), and the distances, in the query-centred, edge-scaled frame
        (see :meth:`closest`): trimesh's ``closest_point`` pair by pair, the same numbers
        (``fem._kernels._closest_on_triangle``)."""
        from workbench.config import TOL

        owner = np.asarray(owner, dtype=np.int64)
        tri = np.asarray(tri, dtype=np.int64)
        pts, dist = np.empty((tri.size, 3)), np.empty(tri.size)
        _point_triangle_pairs(self._triangles, x, owner, tri, self._edge, TOL.point_triangle_zero, pts, dist)
        return pts, dist

    def transformed(self, transform: np.ndarray, facing=None) -> MeshObstacle:
        """Copy moved by a 4×4 homogeneous transform (metres), optionally one-sided."""
        # already in metres and checked (or accepted with allow_scale) when this one was made
        return MeshObstacle(self.mesh, allow_scale=True, transform=transform, facing=facing)

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        from trimesh.triangles import points_to_barycentric

        x = np.asarray(x, dtype=float)
        closest, dist, tri = self.closest(x)
        fn = self._face_normals[tri]
        # vertex normals interpolated at c (barycentric coordinates in the query-centered,
        # edge-scaled frame, for the same tolerance reason as in closest())
        local = (self._triangles[tri] - x[:, None, :]) / self._edge
        bary = points_to_barycentric(local, (closest - x) / self._edge)
        n_s = np.einsum("ij,ijk->ik", bary, self._corner_normals[tri])
        n_s /= np.linalg.norm(n_s, axis=1, keepdims=True)
        # within 1e-6 edge lengths of a face (e.g. the center of a contact element whose
        # corners lie on a curved surface) x - c is rounding-scale: use the face instead
        tiny = dist <= 1e-6 * self._edge
        side = np.einsum("ij,ij->i", x - closest, np.where(tiny[:, None], fn, n_s))
        sign = np.where(side >= 0, 1.0, -1.0)
        grad = np.where(tiny[:, None], fn, sign[:, None] * (x - closest) / np.where(tiny, 1.0, dist)[:, None])
        return sign * dist, grad

"""The outer wall of a hollow object from its triangle mesh, as a radial surface ``r(θ, z)``.

:func:`workbench.fem.wall.build_wall` meshes a wall from any outer surface ``(θ, z) ->
(points, outward normals)``.  For a scanned or CAD object the surface is a
triangle mesh; :func:`radial_surface` turns it into that callable by casting
horizontal rays from a vertical axis on a (θ, z) grid and keeping the outermost
hit — the wall's outer side, also when the mesh is a solid wall with an inner
side (four of the five objects in ``deformable_objects/`` are) — then
interpolating ``r(θ, z)`` with a periodic-in-θ bicubic spline, whose derivatives
give the normals.

It works for objects whose horizontal sections are star-shaped about the axis
(every ray from the axis leaves the outer surface once): bottles, cups, boxes
with rounded corners.  Where a ray hits the mesh more than twice (a handle, a
fold, two bodies) or misses it, the section is not star-shaped about that axis
or the height is outside the object, and :func:`radial_surface` refuses it,
naming the height and angle.  A mesh with an inner side also yields the wall
thickness ``r_outer − r_inner`` per ray (:attr:`RadialSurface.thickness`) — only
as good as the mesh: the meshes here give 0.5 mm for the cup but 3–7 mm for the
bottles, which are modelling solids, not their real ~0.5 mm walls.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.interpolate import RectBivariateSpline

from workbench.units import closed_mesh

log = logging.getLogger(__name__)

#: rays per 2π and height step of the sampling grid (defaults; arguments override)
N_THETA = 180
DZ = 1.0e-3
#: samples beyond 2π on each side so the spline is periodic to its 3rd derivative
_PAD = 4


@dataclass(frozen=True)
class RadialSurface:
    """Outer surface ``(cx + r cos θ, cy + r sin θ, z)`` of a mesh (module docstring).

    centre : (2,) the axis's (x, y) [m]; theta : (n_θ,) ray angles; z : (n_z,) heights;
    r : (n_θ, n_z) outer radius per ray; r_inner : (n_θ, n_z) inner radius (NaN where a
    ray hits the mesh once, i.e. the mesh is a solid outer surface there);
    bounds : (2, 3) the mesh's box, including what lies outside the side wall.
    """

    centre: np.ndarray
    theta: np.ndarray
    z: np.ndarray
    r: np.ndarray
    r_inner: np.ndarray
    bounds: np.ndarray  # (2, 3) the whole mesh's axis-aligned box [m]
    _spline: Any = field(repr=False, compare=False)

    @property
    def z_range(self) -> tuple[float, float]:
        """Heights [m] between which the surface is defined (every ray hit the mesh)."""
        return float(self.z[0]), float(self.z[-1])

    @property
    def thickness(self) -> np.ndarray:
        """(n_θ, n_z) wall thickness ``r − r_inner`` [m] seen by the rays (NaN: one hit)."""
        return self.r - self.r_inner

    def radius(self, theta: np.ndarray, z: np.ndarray, dtheta: int = 0, dz: int = 0) -> np.ndarray:
        """(N,) ``r`` (or a derivative) at parameters θ (N,) [rad] and z (N,) [m]."""
        th = np.mod(np.asarray(theta, float), 2 * np.pi)
        return self._spline(th, np.asarray(z, float), dx=dtheta, dy=dz, grid=False)

    def __call__(self, theta: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points (N, 3) and outward unit normals (N, 3) at θ (N,), z (N,) — the
        ``surface`` callable of :func:`workbench.fem.wall.build_wall`."""
        theta = np.asarray(theta, float)
        z = np.asarray(z, float)
        r = self.radius(theta, z)
        r_t = self.radius(theta, z, dtheta=1)
        r_z = self.radius(theta, z, dz=1)
        c, s = np.cos(theta), np.sin(theta)
        pts = np.column_stack([self.centre[0] + r * c, self.centre[1] + r * s, z])
        # P_θ × P_z with P_θ = (r_θ c − r s, r_θ s + r c, 0), P_z = (r_z c, r_z s, 1)
        n = np.column_stack([r_t * s + r * c, -r_t * c + r * s, -r * r_z])
        return pts, n / np.linalg.norm(n, axis=1, keepdims=True)

    def parameters(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(θ, z, radial offset) of points (N, 3) [m]: the offset is the point's radius minus
        the surface's at its (θ, z) — about its distance off the surface where the wall is
        near vertical (positive outside)."""
        p = np.asarray(points, float)
        if p.ndim != 2 or p.shape[1] != 3:
            raise ValueError(f"points must have shape (N, 3); got {p.shape}")
        d = p[:, :2] - self.centre
        th = np.mod(np.arctan2(d[:, 1], d[:, 0]), 2 * np.pi)
        return th, p[:, 2], np.hypot(d[:, 0], d[:, 1]) - self.radius(th, p[:, 2])


def _ray_hits(mesh, origins: np.ndarray, dirs: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
    """(hit count per ray, list of each ray's sorted hit distances), from the disk cache
    (:func:`_rays_cache_path`) when these rays were cast on this mesh before."""
    # a few rays cast faster than the mesh hashes
    from workbench.atomic_io import read_cache_npz, write_cache_npz

    path = _rays_cache_path(mesh, origins, dirs) if len(origins) >= 64 else None

    def check(d: dict) -> None:
        counts, dist = d["counts"], d["dist"]
        if counts.shape != (len(origins),) or dist.shape != (int(counts.sum()),):
            raise ValueError(f"{counts.shape} counts, {dist.shape} distances for {len(origins)} rays")

    cached = read_cache_npz(path, check, "ray cache", "casting again")
    if cached is not None:
        counts, dist = cached["counts"], cached["dist"]
        return counts, np.split(dist, np.cumsum(counts)[:-1])
    locs, ray_idx, _ = mesh.ray.intersects_location(origins, dirs, multiple_hits=True)
    # no hit at all comes back as a (0,) array, not (0, 3)
    locs, ray_idx = np.asarray(locs, float).reshape(-1, 3), np.asarray(ray_idx, int)
    dist = np.einsum("ij,ij->i", locs - origins[ray_idx], dirs[ray_idx])
    order = np.lexsort((dist, ray_idx))
    ray_idx, dist = ray_idx[order], dist[order]
    counts = np.bincount(ray_idx, minlength=len(origins))
    if path is not None:
        write_cache_npz(path, counts=counts, dist=dist)
    return counts, np.split(dist, np.cumsum(counts)[:-1])


def _rays_cache_path(mesh, origins: np.ndarray, dirs: np.ndarray):
    """``<cache>/rays-<sha256>.npz`` for these rays on this mesh, or ``None`` with the cache off
    (:func:`workbench.cachedir.cache_dir`: ``$WORKBENCH_CACHE_DIR``, the folder the pads use).
    Casting is trimesh's pure-NumPy intersector here (seconds a wall, and every process of every
    run paid it — driver and each Dask worker of minimal-work, the
    wall-nonlinear runs), so the hits are kept by the content hash of the mesh's vertices and
    faces, the rays, the intersector's class, trimesh's version and the code of
    :func:`_ray_hits` (its normalised syntax: a comment edit keeps the cache)."""
    import trimesh

    from workbench.cachedir import array_digest, cache_dir

    folder = cache_dir()
    if folder is None:
        return None
    arrays = (
        np.ascontiguousarray(mesh.vertices, dtype=np.float64),
        np.ascontiguousarray(mesh.faces, dtype=np.int64),
        np.ascontiguousarray(origins, dtype=np.float64),
        np.ascontiguousarray(dirs, dtype=np.float64),
    )
    from workbench.code_key import normalized_function

    code = normalized_function(_ray_hits)[:16]
    tag = f"{type(mesh.ray).__module__};trimesh={trimesh.__version__};code={code}"
    return folder / f"rays-{array_digest(arrays, tag)}.npz"


def radial_surface(
    mesh: Any,
    *,
    units: str | float | None = None,
    centre: Any = None,
    z_range: tuple[float, float] | None = None,
    n_theta: int = N_THETA,
    dz: float = DZ,
    margin: float = 2e-3,
    remedy: str | None = None,
) -> RadialSurface:
    """The outer surface ``r(θ, z)`` of a watertight mesh with a vertical (z) axis.

    mesh : ``trimesh.Trimesh``, watertight, in metres (``units="mm"`` converts a copy).
    centre : (2,) axis position (x, y) [m]; default the centre of the mesh's xy box.
    z_range : heights [m] to sample, every section star-shaped; default the longest band
        of star-shaped sections within the mesh's z extent less ``margin`` at both ends
        (a rolled rim, cap, neck or base ends it; logged) — at least half that extent.
    n_theta, dz : ray count per turn and height step of the sampling grid.
    remedy : the fix the not-star-shaped error suggests (default: this function's own
        ``centre`` and ``z_range``; a caller that does not pass them on says its own).
    Raises ``ValueError`` for an open mesh, a mesh in millimetres, or a section that is
    not star-shaped about the axis (rays with more than two hits, or none).
    """
    mesh = closed_mesh(mesh, "the object mesh", units=units, override=None)
    if not (isinstance(n_theta, int) and n_theta >= 16):
        raise ValueError(f"n_theta must be an integer >= 16; got {n_theta!r}")
    lo, hi = mesh.bounds
    c = (lo[:2] + hi[:2]) / 2 if centre is None else np.asarray(centre, float)
    if c.shape != (2,) or not np.isfinite(c).all():
        raise ValueError(f"centre must be the axis's (x, y) [m]; got {centre!r}")
    z0, z1 = (lo[2] + margin, hi[2] - margin) if z_range is None else map(float, z_range)
    if not (np.isfinite(dz) and 0 < dz < (z1 - z0) / 3):
        raise ValueError(f"need z_range with room for >= 4 heights of dz = {dz}; got ({z0}, {z1})")
    if not (lo[2] <= z0 < z1 <= hi[2]):
        raise ValueError(
            f"z_range ({z0:.4g}, {z1:.4g}) m must lie within the mesh's heights ({lo[2]:.4g}, {hi[2]:.4g}) m"
        )
    theta = 2 * np.pi * np.arange(n_theta) / n_theta
    zs = np.linspace(z0, z1, int(np.ceil((z1 - z0) / dz)) + 1)
    T, Z = np.meshgrid(theta, zs, indexing="ij")
    dirs = np.column_stack([np.cos(T.ravel()), np.sin(T.ravel()), np.zeros(T.size)])
    origins = np.column_stack([np.full(T.size, c[0]), np.full(T.size, c[1]), Z.ravel()])
    counts, dists = _ray_hits(mesh, origins, dirs)
    ok_row = ((counts >= 1) & (counts <= 2)).reshape(T.shape).all(axis=0)
    if z_range is None and not ok_row.all():
        # keep the longest band of heights whose sections are star-shaped: caps, rolled
        # rims, necks and bases end the side wall (logged, so nothing is cut silently)
        runs = np.flatnonzero(np.diff(np.r_[0, ok_row.astype(int), 0]))
        starts, ends = runs[::2], runs[1::2]
        best = int(np.argmax(ends - starts)) if len(starts) else None
        if best is not None and ends[best] - starts[best] >= max(4, ok_row.size // 2):
            keep = slice(starts[best], ends[best])
            log.info(
                "radial_surface: side wall z = %.4g..%.4g m of %.4g..%.4g m (sections outside are "
                "not star-shaped about the axis: a rim, cap, neck or base)",
                zs[keep][0],
                zs[keep][-1],
                z0,
                z1,
            )
            idx = np.arange(counts.size).reshape(T.shape)[:, keep].ravel()
            counts, dists = counts[idx], [dists[i] for i in idx]
            zs, T, Z = zs[keep], T[:, keep], Z[:, keep]
    bad = np.flatnonzero((counts == 0) | (counts > 2))
    if bad.size:
        k = bad[0]
        what = "misses the mesh" if counts[k] == 0 else f"hits it {counts[k]} times"
        raise ValueError(
            f"the section is not star-shaped about the axis at ({c[0]:.4g}, {c[1]:.4g}) m: the ray at "
            f"z = {Z.ravel()[k]:.4g} m, θ = {np.degrees(T.ravel()[k]):.0f}° {what} ({bad.size} of "
            f"{counts.size} rays) — "
            + (
                remedy
                or "pass a centre inside every section, a narrower z_range, or an object whose "
                "horizontal sections are star-shaped (no handle)"
            )
        )
    r = np.array([d[-1] for d in dists]).reshape(T.shape)
    r_in = np.array([d[0] if len(d) == 2 else np.nan for d in dists]).reshape(T.shape)
    # periodic in θ: pad the grid on both sides before an interpolating bicubic spline
    th_pad = np.r_[theta[-_PAD:] - 2 * np.pi, theta, theta[:_PAD] + 2 * np.pi]
    r_pad = np.vstack([r[-_PAD:], r, r[:_PAD]])
    spline = RectBivariateSpline(th_pad, zs, r_pad, kx=3, ky=3, s=0)
    return RadialSurface(c, theta, zs, r, r_in, np.array(mesh.bounds, float), spline)


__all__ = ["RadialSurface", "radial_surface"]

"""The object as MuJoCo collides it: convex pieces.

MuJoCo collides a mesh geom as its convex hull.  A convex object is its own hull; a bottle's
waist, a cup's foot or a mustard bottle's flat sides are not, and a pad pressed there would touch
a surface the object does not have (millimetres away).  A non-convex object is therefore cut into
slabs across gravity, each slab's hull one geom: the union follows the object to within the slab
thickness times the wall's slope along gravity, exactly where a cross-section is convex (bottles,
cups, boxes), and a concave cross-section keeps its hull.
"""

from __future__ import annotations

import logging

import numpy as np

log = logging.getLogger(__name__)

__all__ = ["collision_pieces", "convex_slabs"]

#: the smallest volume [m³] of a slab's hull kept as a geom (a flat sliver has no inside for
#: MuJoCo's collision and its hull computation fails on coplanar points)
MIN_PIECE_VOLUME = 1e-12


def _plane_points(v: np.ndarray, edges: np.ndarray, s: np.ndarray, level: float) -> np.ndarray:
    """(k, 3) where the mesh's edges cross the plane ``s = level`` (``s`` (n,): each vertex's
    height along the slab axis)."""
    sa, sb = s[edges[:, 0]] - level, s[edges[:, 1]] - level
    x = sa * sb < 0
    t = sa[x] / (sa[x] - sb[x])
    a, b = v[edges[x, 0]], v[edges[x, 1]]
    return a + t[:, None] * (b - a)


def convex_slabs(mesh, axis, thickness: float) -> list:
    """The convex hulls (``trimesh.Trimesh``) of ``mesh`` cut into slabs of at most
    ``thickness`` [m] along ``axis`` (3,): each hull spans the slab's vertices and the points
    where the surface crosses its two planes; hulls of less than :data:`MIN_PIECE_VOLUME` are
    dropped."""
    import trimesh
    from scipy.spatial import QhullError

    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    v = np.asarray(mesh.vertices, float)
    edges = np.asarray(mesh.edges_unique, int)
    s = v @ axis
    lo, hi = float(s.min()), float(s.max())
    n = max(1, int(np.ceil((hi - lo) / thickness - 1e-9)))
    levels = np.linspace(lo, hi, n + 1)
    cuts = [_plane_points(v, edges, s, z) for z in levels]
    pieces = []
    for k in range(n):
        inside = v[(s >= levels[k]) & (s <= levels[k + 1])]
        pts = np.vstack([inside, cuts[k], cuts[k + 1]])
        if len(pts) < 4:
            continue
        try:
            hull = trimesh.convex.convex_hull(pts)
        except QhullError:  # coplanar points even after trimesh's joggle: no volume to collide
            continue
        if hull.volume > MIN_PIECE_VOLUME:
            pieces.append(hull)
    return pieces


def collision_pieces(mesh, down, slab: float) -> list:
    """The convex pieces the object collides as: its hull when it is convex or ``slab`` is 0,
    else :func:`convex_slabs` of ``slab`` [m] along gravity ``down`` (3,)."""
    if slab == 0 or mesh.is_convex:
        return [mesh.convex_hull]
    pieces = convex_slabs(mesh, -np.asarray(down, float), slab)
    log.info("engine object: not convex, collides as %d convex slabs of %.3g mm", len(pieces), slab * 1e3)
    return pieces

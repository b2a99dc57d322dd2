"""How far the surface the engine collides lies from the object's at given points.

The engine collides the object as convex pieces (:func:`.collision.collision_pieces`): its hull,
or slabs across gravity.  Where the pieces bridge a concavity, a point of the mesh's surface (a
grasp's contact point) lies inside them, and a pad pressed there touches a surface the object
does not have.  A module of its own: the trials do not import it, so the code keys of what they
do import stay as they are.
"""

from __future__ import annotations

import numpy as np

from .collision import collision_pieces

__all__ = ["surface_gap"]


def surface_gap(mesh, points, down, slab: float) -> np.ndarray:
    """How deep [m] each of ``points`` (..., 3) [m] lies inside the object as the engine collides
    it (:func:`~.collision.collision_pieces` of ``mesh`` with gravity ``down`` (3,) and ``slab``
    [m]): its largest signed distance into any one piece, 0 outside every piece; shape (...).

    A point of the mesh's surface is at 0 where the pieces follow the mesh, and as deep as the
    pieces stand off the mesh there where they bridge a concavity (a hull over a waist)."""
    import trimesh

    pts = np.asarray(points, float)
    if pts.ndim < 1 or pts.shape[-1] != 3:
        raise ValueError(f"points must be (..., 3) positions [m]; got shape {pts.shape}")
    pieces = collision_pieces(mesh, down, slab)
    depth = np.max([trimesh.proximity.signed_distance(p, pts.reshape(-1, 3)) for p in pieces], axis=0)
    return np.maximum(depth, 0.0).reshape(pts.shape[:-1])  # signed distance > 0 inside

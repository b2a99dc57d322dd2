"""How an object rests on the table of a top-grasp planner (thesis §4.2.1): standing as its mesh
is given, or lying on its broad side, moved onto the table z = 0; and how flat it then is.

"Lying" turns the object so its oriented bounding box's longest side is along x and its shortest
vertical: a flat object on its broad face.  It is a pose of the box, not a computed stable pose
(trimesh's stable poses need networkx): for a curved face the object touches the table at its
lowest point only, and nothing here lets it roll.
"""

from __future__ import annotations

import numpy as np

__all__ = ["flatness", "rest_on_table"]


def _check_mesh(mesh, what: str):
    import trimesh

    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ValueError(f"{what} must be a trimesh.Trimesh with faces; got {type(mesh).__name__}")
    if not np.isfinite(mesh.vertices).all():
        raise ValueError(f"{what} has non-finite vertices")
    return mesh


def rest_on_table(mesh, lying: bool = False):
    """A copy of ``mesh`` (metres) resting on the table z = 0 and the (4, 4) transform from the
    mesh's frame to the resting one: upright as given (only moved down or up), or (``lying``)
    turned first so its oriented box's sides run longest along x, shortest along z."""
    mesh = _check_mesh(mesh, "mesh").copy()
    if not isinstance(lying, bool):
        raise ValueError(f"lying must be True or False; got {lying!r}")
    T = np.eye(4)
    if lying:
        obb = mesh.bounding_box_oriented
        to_box = np.linalg.inv(obb.primitive.transform)
        order = np.argsort(obb.primitive.extents)[::-1]  # longest along x, shortest along z
        P = np.eye(4)
        P[:3, :3] = np.eye(3)[order]
        if np.linalg.det(P[:3, :3]) < 0:  # a turn, not a mirror
            P[1] *= -1
        T = P @ to_box
    mesh.apply_transform(T)
    lift = np.eye(4)
    lift[2, 3] = -mesh.bounds[0, 2]
    mesh.apply_transform(lift)
    return mesh, lift @ T


def flatness(mesh) -> float:
    """Height over the largest horizontal extent of ``mesh`` as it rests (0: flat; a box of
    80 × 50 × 20 mm on its broad face: 0.25)."""
    ext = _check_mesh(mesh, "mesh").extents
    return float(ext[2] / max(ext[0], ext[1]))

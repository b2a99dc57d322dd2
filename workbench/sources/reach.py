"""REACH-style contact profiles from triangle meshes (thesis §2.3.1.3, §4.1.4.1;
Danielczuk et al.): the compliant pad, extruded from the jaw face along the
approach direction, is intersected with the rigid object; each object triangle
the pad overlaps carries a pressure proportional to the local pad compression
(a Winkler foundation, ``p = k d`` with ``k = M / h``, M the pad's confined modulus).

Geometry by projection, no booleans: the object is refined near the jaw to
``max_edge``, triangles facing the jaw inside the pad footprint are binned on a
grid over the footprint and only the front-most surface of each bin counts
(what the pad can reach first); the jaw closes by ``closing`` from first touch.

:func:`reach_profile` is one jaw's profile; :func:`jaw_profiles` both jaws' of a grasp,
scaled to the force-sensor reading (the FEM counterpart: :mod:`workbench.sources.fem_jaw`).
"""

from __future__ import annotations

import numpy as np

from ..profile import ContactProfile
from .jaws import check_grasp, check_jaw_force, check_pad, checked_jaw_profile, jaw_frame

__all__ = ["jaw_profiles", "reach_profile"]


def reach_profile(
    mesh,
    center,
    approach,
    up=(0.0, 0.0, 1.0),
    *,
    pad: tuple[float, float] = (0.02, 0.04),
    closing: float = 1e-3,
    stiffness: float = 1.0e6 / 0.005,
    max_edge: float = 1e-3,
    depth_window: float = 0.01,
    units: str | float | None = None,
    allow_scale: bool = False,
) -> ContactProfile:
    """A *profile source*: the REACH-style contact profile (pad ∩ mesh, Winkler pressure)
    of a jaw approaching ``center`` (on or near the object) along
    ``approach`` (into the object), pad ``(width, length)`` [m], closing ``closing`` [m]
    past first touch, pressure ``stiffness · compression`` [Pa/m].

    ``units`` is the unit of ``mesh.vertices`` only (``None``: metres; "mm" scales a
    copy by 1e-3): ``center`` and every other length are in metres, as returned by
    ``antipodal_grasps(mesh, ..., units=...)``.

    Raises ``ValueError`` for a non-watertight mesh, when the pad touches nothing, or
    for a mesh spanning more than ``TOL.max_object_extent_m`` or less than
    ``TOL.min_object_extent_m`` (a likely unit mistake; ``allow_scale=True`` accepts it).
    """
    import trimesh

    from ..units import closed_mesh

    check_pad(pad)
    mesh = closed_mesh(mesh, "mesh passed to reach_profile", units=units, allow_scale=allow_scale)
    if not (closing > 0 and stiffness > 0 and max_edge > 0):
        raise ValueError("closing, stiffness and max_edge must be > 0")
    a, e1, e2 = jaw_frame(approach, up)
    c = np.asarray(center, float)
    rel = mesh.vertices - c
    u, v, z = rel @ e1, rel @ e2, rel @ a
    # faces whose bounding box (in the jaw frame) overlaps the footprint and the depth
    # window: a large face can cover the pad with no vertex inside it (a box's side, a
    # coarse cylinder), so vertices alone would miss it
    fu, fv, fz = u[mesh.faces], v[mesh.faces], z[mesh.faces]  # (m, 3) each
    hu, hv = pad[0] / 2 + 2 * max_edge, pad[1] / 2 + 2 * max_edge
    near = (fu.min(1) <= hu) & (fu.max(1) >= -hu) & (fv.min(1) <= hv) & (fv.max(1) >= -hv)
    near &= (fz.min(1) <= depth_window) & (fz.max(1) >= -depth_window)
    faces = mesh.faces[near]
    if len(faces) == 0:
        raise ValueError(
            f"the pad footprint {pad} m around {np.round(c, 4).tolist()} covers no part of the object "
            f"within ±{depth_window} m along the approach {np.round(a, 3).tolist()}: check center, "
            "approach (into the object) and units"
        )
    sub_v, sub_f = trimesh.remesh.subdivide_to_size(mesh.vertices, faces, max_edge=max_edge)
    tri = sub_v[sub_f]
    cen = tri.mean(axis=1)
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = 0.5 * np.linalg.norm(cross, axis=1)
    normal = cross / np.maximum(2 * area, 1e-300)[:, None]
    rel = cen - c
    u, v, z = rel @ e1, rel @ e2, rel @ a
    # faces (nearly) parallel to the approach have no area under the pad: a Winkler
    # foundation along the approach puts no pressure on them (a box's side walls)
    from .. import config

    facing = normal @ a < -config.DEFAULTS.reach_min_facing
    keep = (np.abs(u) <= pad[0] / 2) & (np.abs(v) <= pad[1] / 2) & facing & (area > 0)
    if not keep.any():
        raise ValueError(
            f"no object surface faces the jaw inside the pad footprint (approach {np.round(a, 3).tolist()} "
            "must point into the object, from the jaw towards the surface)"
        )
    idx = np.flatnonzero(keep)
    # front-most surface per footprint bin (the pad cannot reach behind the first surface)
    iu = np.floor((u[idx] + pad[0] / 2) / max_edge).astype(int)
    iv = np.floor((v[idx] + pad[1] / 2) / max_edge).astype(int)
    bins = iu * (int(pad[1] / max_edge) + 2) + iv
    order = np.lexsort((z[idx], bins))
    first = np.r_[True, bins[order][1:] != bins[order][:-1]]
    front_z = np.repeat(z[idx][order][first], np.diff(np.r_[np.flatnonzero(first), len(order)]))
    visible = np.zeros(len(cen), dtype=bool)
    visible[idx[order]] = z[idx][order] <= front_z + 2 * max_edge
    z0 = z[visible].min()  # first touch
    depth = np.where(visible, z0 + closing - z, 0.0)
    sel = depth > 0
    return ContactProfile(cen[sel], normal[sel], area[sel], stiffness * depth[sel])


def jaw_profiles(
    mesh,
    grasp: dict,
    force: float,
    *,
    up=(0.0, 0.0, 1.0),
    pad: tuple[float, float] = (0.02, 0.04),
    closing: float = 1e-3,
    units: str | None = None,
    allow_scale: bool = False,
) -> list[ContactProfile]:
    """The two jaws' REACH profiles (:func:`reach_profile`) of an antipodal
    ``grasp`` (a dict of :func:`~workbench.grasp.sampling.antipodal_grasps`: ``p1``, ``p2`` [m],
    ``axis`` from jaw 1 into the object), each scaled to the reading ``force`` [N] along the
    grasp axis (:func:`~.jaws.checked_jaw_profile`).  ``units`` is the unit of
    ``mesh.vertices`` only; the grasp is in metres.  Raises ValueError when a jaw would
    pull the object."""
    p1, p2, axis = check_grasp(grasp)
    check_jaw_force(force)
    check_pad(pad)
    out = []
    for point, approach in ((p1, axis), (p2, -axis)):
        prof = reach_profile(
            mesh, point, approach, up, pad=pad, closing=closing, units=units, allow_scale=allow_scale
        )
        out.append(checked_jaw_profile(prof, point, approach, force, pad))
    return out

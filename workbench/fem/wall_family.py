"""Walls of the thesis bottle family squeezed at antipodal grasps (thesis §4.3.3.1, the s_i of
Eq. 4.5): the grasp axis at a height and angle, a bottle's wall built once per process, and the
stiffness's mesh convergence at one location.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .bottle import Bottle, bottle_family
from .material import Material
from .wall import build_wall, squeeze

__all__ = ["bottle_wall", "grasp_axis", "mesh_convergence"]


def grasp_axis(bottle: Bottle, z: float, angle: float) -> tuple[np.ndarray, np.ndarray]:
    """The grasp at height ``z`` [m] whose horizontal axis makes ``angle`` [rad] with the major axis
    of the bottle's section there: ``(point (3,), unit axis (3,))``, the point the section's centre."""
    centre, _, _, phi = bottle.section(z)
    return np.r_[centre, z], np.array([np.cos(phi + angle), np.sin(phi + angle), 0.0])


@lru_cache(maxsize=2)
def bottle_wall(seed: int, i: int, E: float, nu: float, thickness: float, nt: int, nz: int):
    """Bottle ``i`` of ``bottle_family(seed)`` and its linear wall (:func:`workbench.fem.wall.build_wall`:
    modulus ``E`` [Pa], ratio ``nu``, ``thickness`` [m], ``nt × nz`` hexes around × along its height),
    assembled and factorised once per process (driver or worker; the sparse factor does not pickle,
    so it is never sent).  Up to two walls stay cached."""
    b = Bottle(bottle_family(seed=seed)[i])
    wall = build_wall(
        b.points_normals,
        Material(E, nu),
        thickness=thickness,
        n_theta=nt,
        n_z=nz,
        z_range=(0, b.params.height),
    )
    return b, wall


def mesh_convergence(
    bottle: Bottle, material: Material, thickness: float, meshes: list, force: float, jaw: tuple
) -> list[dict]:
    """The bottle's stiffness at mid-height, along the section's major and minor axes, squeezed by
    ``force`` [N] between jaws ``jaw`` (width, length) [m] on walls of each ``[n_theta, n_z]`` of
    ``meshes``: rows ``{"mesh", "angle", "stiffness_N_per_m", "build_s", "rel_to_finest"}``, the
    last relative to the last mesh's stiffness at the same angle."""
    H = bottle.params.height
    conv = []
    for nt, nz in meshes:
        wall = build_wall(
            bottle.points_normals, material, thickness=thickness, n_theta=nt, n_z=nz, z_range=(0, H)
        )
        for ang in (0.0, np.pi / 2):
            r = squeeze(wall, *grasp_axis(bottle, 0.5 * H, ang), force=force, jaw=jaw)
            conv.append(
                {
                    "mesh": f"{nt}x{nz}",
                    "angle": ang,
                    "stiffness_N_per_m": r.stiffness,
                    "build_s": wall.seconds,
                }
            )
    for r in conv:
        ref = next(c for c in conv[::-1] if c["angle"] == r["angle"])
        r["rel_to_finest"] = r["stiffness_N_per_m"] / ref["stiffness_N_per_m"] - 1
    return conv

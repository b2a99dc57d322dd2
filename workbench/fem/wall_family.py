"""Walls of the thesis bottle family squeezed at antipodal grasps (thesis §4.3.3.1, the s_i of
Eq. 4.5): the grasp axis at a height and angle, a bottle's wall built once per process, a
bottle's stiffness map over heights × angles from its grasps' rows, the stiffness's mesh
convergence at one location, and what the shoulder-convergence benchmark measured of a mesh's
discretisation error.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from functools import lru_cache
from pathlib import Path

import numpy as np

from .bottle import Bottle, bottle_family
from .material import Material
from .wall import build_wall, squeeze

__all__ = ["bottle_wall", "grasp_axis", "mesh_convergence", "mesh_error", "stiffness_map"]


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


def stiffness_map(
    rows: Sequence[Mapping],
    bottle: int,
    height_fractions: Sequence[float],
    angles: np.ndarray,
    *,
    asymmetric: bool,
) -> dict:
    """Bottle ``bottle``'s stiffness map over ``height_fractions`` (h,) × ``angles`` (a,) [rad]
    from its grasps' ``rows`` (each ``bottle``, ``height_fraction``, ``angle`` [rad] and
    ``stiffness_N_per_m``, None where the closing was implausible).  Returns
    ``{"asymmetric", "height_fractions", "angles_rad", "stiffness_N_per_m": (h, a) nested lists
    (None: implausible), "n_implausible", "min", "max"}`` (min and max [N/m] over the plausible
    grasps, None when there are none)."""
    grid = np.array(
        [
            [
                next(
                    r
                    for r in rows
                    # the row's angle is this linspace value (exact through the JSON checkpoint);
                    # 1e-9 rad only absorbs last-bit differences of a recomputed one
                    if r["bottle"] == bottle and r["height_fraction"] == hf and abs(r["angle"] - a) < 1e-9
                )["stiffness_N_per_m"]
                for a in angles
            ]
            for hf in height_fractions
        ],
        dtype=float,  # None (an implausible closing) -> NaN
    )
    return {
        "asymmetric": asymmetric,
        "height_fractions": height_fractions,
        "angles_rad": np.asarray(angles).tolist(),
        "stiffness_N_per_m": [[None if np.isnan(v) else v for v in row] for row in grid.tolist()],
        "n_implausible": int(np.isnan(grid).sum()),
        "min": None if np.isnan(grid).all() else float(np.nanmin(grid)),
        "max": None if np.isnan(grid).all() else float(np.nanmax(grid)),
    }


def mesh_error(mesh: Sequence[int], path: str | Path) -> dict:
    """What is known of the stiffness error of wall ``mesh`` [around, along]: per region (body,
    below a shoulder, on a shoulder) the number of grasps and the min, median and max of its
    stiffness relative to the finest mesh measured at the same grasps, read from the convergence
    benchmark's JSON at ``path`` (``results/benchmarks/shoulder_convergence.json`` of
    ``benchmarks/bench_shoulder_convergence.py``: ``locations``, each with a ``region``, the
    ``finest`` mesh and ``rel_to_finest`` {``"<around>x<along>"``: relative error}).

    Returns ``{"measured": True, "reference_mesh", "rel_to_reference": {region: {"n", "min",
    "median", "max"}}, "note"}``, or ``{"measured": False, "note"}`` saying that this mesh was
    not measured or that the file is absent or unreadable (e.g. in an installed wheel)."""
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return {
            "measured": False,
            "note": f"no convergence measurement at {path} (make bench-shoulder writes it)",
        }
    key = "x".join(str(int(v)) for v in mesh)
    by_region: dict[str, list[float]] = {}
    for loc in data.get("locations", []):
        rel = loc.get("rel_to_finest", {}).get(key)
        if rel is not None:
            by_region.setdefault(loc["region"], []).append(float(rel))
    measured = sorted({k for loc in data.get("locations", []) for k in loc.get("rel_to_finest", {})})
    if not by_region:
        return {"measured": False, "note": f"mesh {list(mesh)} not measured (measured: {measured}; {path})"}
    finest = data["locations"][0]["finest"]
    regions = {
        name: {"n": len(v), "min": min(v), "median": float(np.median(v)), "max": max(v)}
        for name, v in by_region.items()
    }
    text = "; ".join(
        f"{name.replace('_', ' ')} {r['min']:+.0%}..{r['max']:+.0%} "
        f"(median {r['median']:+.0%}, {r['n']} grasps)"
        for name, r in regions.items()
    )
    return {
        "measured": True,
        "reference_mesh": finest,
        "rel_to_reference": regions,
        "note": f"stiffness of mesh {list(mesh)} vs {finest} on the benchmark's bottles: {text}; a jaw "
        "edge on a shoulder is not converged even on the finest meshes "
        "(results/benchmarks/shoulder_convergence.json)",
    }

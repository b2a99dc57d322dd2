"""The contacts the peers are compared on: one silicone pad pressed by a rigid sphere, a circular
cylinder, an elliptic cylinder or a thesis bottle, and the neo-Hookean reference solve of each.

A case is set up from a settings dict (the ``peers`` experiment's config: ``pad_mm``, ``pad_cells``,
``E``, ``nu``, ``radius_mm``, ``ellipse_mm``, ``bottle``, ``seed``, ``deltas_mm``,
``reference_stabilization``; lengths in millimetres there, metres here).  Every contact is in the
pad frame of :func:`workbench.fem.press` (pad face ``z = h``, the object above it).
"""

from __future__ import annotations

import time

import numpy as np

from ..fem.extract import extract_profile
from ..fem.material import Material
from ..fem.obstacles import Cylinder, EllipticCylinder, MeshObstacle, Sphere
from ..fem.pad import PadGeometry

__all__ = ["CASES", "bottle_mesh", "drake_pad", "reference_case", "setup_case"]

#: the contacts, in the order the comparison runs them
CASES = ("sphere", "cylinder", "elliptic_cylinder", "bottle")


def setup_case(
    case: str, config: dict, cells: list | None = None
) -> tuple[PadGeometry, Material, object, np.ndarray, float]:
    """The pad, material, obstacle, the object's centre (3,) [m] and the surface's curvature
    radius at the contact [m] of one ``case`` of :data:`CASES` (pad frame: face ``z = h``);
    ``cells``: the pad's ``[nx, ny, nz]`` hexes (default ``config["pad_cells"]``)."""
    w, ln, h = (v * 1e-3 for v in config["pad_mm"])
    nx, ny, nz = cells or config["pad_cells"]
    geom = PadGeometry(w, ln, h, int(nx), int(ny), int(nz))
    mat = Material(config["E"], config["nu"])
    R = config["radius_mm"] * 1e-3
    if case == "sphere":
        c = np.array([0.0, 0.0, h + R])
        return geom, mat, Sphere(tuple(c), R), c, R
    if case == "cylinder":
        c = np.array([0.0, 0.0, h + R])
        return geom, mat, Cylinder(tuple(c), (0.0, 1.0, 0.0), R), c, R
    if case == "bottle":
        return (geom, mat, *_bottle(geom, mat, config))
    a, b = (v * 1e-3 for v in config["ellipse_mm"])
    c = np.array([0.0, 0.0, h + a])
    return geom, mat, EllipticCylinder(tuple(c), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), a, b), c, b * b / a


def _bottle(geom: PadGeometry, mat: Material, config: dict) -> tuple[object, np.ndarray, float]:
    """The thesis bottle seen from the pad (:func:`workbench.fem.bottle.grasp_pose`: touching at
    δ = 0, the pad's y axis up), its section centre in the pad frame [m] and the section's
    curvature radius at the contact, B²/A at the major axis's end [m]."""
    from ..fem.bottle import Bottle, bottle_family, grasp_pose
    from ..fem.pad import PadFace

    spec = config["bottle"]
    bottle = Bottle(bottle_family(24, 8, config["seed"])[spec["index"]])
    z = spec["height"] * bottle.params.height
    pose = grasp_pose(bottle, z, 0.0, PadFace.of(geom, mat).face_xy, geom.thickness)
    centre, A, B, _ = bottle.section(z)
    c = pose.R.T @ (np.r_[centre, z] - pose.t)
    return pose, c, B * B / A


def bottle_mesh(pose, mesh: list | tuple) -> MeshObstacle:
    """The posed bottle (a :func:`workbench.fem.bottle.grasp_pose`) as a watertight mesh of
    ``mesh = [n_theta, n_z]`` vertices in the pad frame (for Drake)."""
    import trimesh

    n_theta, n_z = mesh
    m = pose.obstacle.to_trimesh(n_theta, n_z)
    return MeshObstacle(trimesh.Trimesh((np.asarray(m.vertices) - pose.t) @ pose.R, m.faces, process=False))


def drake_pad(case: str, obs, geom: PadGeometry, config: dict, resolution_over_R: float):
    """``(pad, "")``: a :class:`~workbench.peers.drake_hydro.DrakeHydroPad` of the case (its rigid
    tessellation hint ``resolution_over_R`` × the radius; the elliptic cylinder as a mesh of
    ``ellipse_sections`` facets around, the bottle as :func:`bottle_mesh`), or ``(None, reason)``
    without Drake."""
    try:
        from .drake_hydro import DrakeHydroPad, Meshing, hydroelastic_modulus
    except ImportError as exc:  # pragma: no cover - the module itself imports without Drake
        return None, str(exc)
    e_hydro = hydroelastic_modulus(config["E"], geom.thickness, geom.width, geom.length)
    res = None if case in ("elliptic_cylinder", "bottle") else resolution_over_R * config["radius_mm"] * 1e-3
    if case == "elliptic_cylinder":  # Drake takes it as a mesh of ellipse_sections facets around
        obs = MeshObstacle(obs.to_trimesh(3.0 * geom.length, config["ellipse_sections"]))
    elif case == "bottle":
        obs = bottle_mesh(obs, config["bottle"]["mesh"])
    try:
        # the cylinders and the bottle's wall span the pad: cut there on purpose
        edge = "warn" if case == "sphere" else "cut"
        pad = DrakeHydroPad(
            obs,
            geom.thickness,
            e_hydro,
            width=geom.width,
            length=geom.length,
            meshing=Meshing(res),
            edge=edge,
        )
        return pad, ""
    except ImportError as exc:
        return None, f"Drake not installed ({exc}): pip install -e '.[peers]'"


def reference_case(case: str, config: dict) -> dict:
    """The neo-Hookean reference (:class:`workbench.fem.nonlinear.NonlinearPad`) of one case at
    every δ of ``deltas_mm`` (the load stepping takes the longest: one task per case):
    ``{"case", "rows": {δ [m]: {"force" [N], "profile", "p_node" (n_face,) [Pa], "area" [m²]}},
    "face_xy" (n_face, 2) [m], "seconds" per δ}``; the area and nodal pressure are the deformed face's."""
    from ..fem.nonlinear import NonlinearPad

    geom, mat, obs, _, _ = setup_case(case, config)
    deltas = [d * 1e-3 for d in config["deltas_mm"]]
    nl = NonlinearPad(geom, mat, stabilization=config["reference_stabilization"])
    t0 = time.perf_counter()
    sols = nl.solve(obs, deltas)
    seconds = (time.perf_counter() - t0) / len(deltas)
    out = {}
    for d in deltas:
        r = sols[d]
        a_def = nl.deformed_areas(r)
        out[d] = {
            "force": float(r.force),
            "profile": extract_profile(nl, r, obs),
            "p_node": np.divide(r.lam, a_def, out=np.zeros_like(r.lam), where=a_def > 0),
            "area": float(a_def[r.lam > 0].sum()),
        }
    return {"case": case, "rows": out, "face_xy": np.asarray(nl.face_xy), "seconds": seconds}

"""A silicone pad as a MuJoCo deformable body: a 3D flex grid whose back layer is pinned to
its jaw, with its contacts carried by small spheres on the face's vertices."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from .settings import EngineSettings


def pad_rotation(approach: np.ndarray, up: np.ndarray) -> np.ndarray:
    """(3, 3) rotation of the pad's grid frame: local −z along ``approach`` (its face looks
    at the object), local y along the part of ``up`` ⟂ approach (the pad's length), x = y × z."""
    a = np.asarray(approach, float) / np.linalg.norm(approach)
    z = -a
    y = np.asarray(up, float) - (np.asarray(up, float) @ a) * a
    if not np.linalg.norm(y) > 1e-9:
        raise ValueError(
            f"up {np.asarray(up).tolist()} is parallel to the jaw's approach {a.round(4).tolist()}: "
            "give the pad's length direction, any vector not along the grasp axis"
        )
    y /= np.linalg.norm(y)
    return np.column_stack([np.cross(y, z), y, z])


def _quat(R: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(R).as_quat()
    return np.array([w, x, y, z])


def flexcomp_xml(
    name: str,
    size: tuple[float, float, float],
    E: float,
    nu: float,
    face_center: np.ndarray,
    approach: np.ndarray,
    up: np.ndarray,
    settings: EngineSettings,
) -> str:
    """MJCF ``<flexcomp>`` of one pad (in its jaw body's frame [m]): ``size`` = (width, length,
    thickness) [m], Young's modulus ``E`` [Pa], Poisson ratio ``nu``; the face's centre at
    ``face_center`` (3,), pressing along ``approach`` (3,), its length along ``up`` (3,)."""
    w, ln, h = size
    nx, ny, nz = settings.pad_grid
    R = pad_rotation(approach, up)
    a = -R[:, 2]
    # grid centred on pos; its face (local z = -h/2) lies at face_center
    pos = np.asarray(face_center, float) - 0.5 * h * a
    q = _quat(R)
    p = " ".join(f"{v:.9g}" for v in pos)
    qs = " ".join(f"{v:.12g}" for v in q)
    return (
        f'<flexcomp name="{name}" type="grid" dim="3" count="{nx} {ny} {nz}" '
        f'spacing="{w / (nx - 1):.9g} {ln / (ny - 1):.9g} {h / (nz - 1):.9g}" pos="{p}" quat="{qs}" '
        f'radius="0" mass="{settings.pad_mass:g}">'
        f'<elasticity young="{E:g}" poisson="{nu:g}"/>'
        '<contact selfcollide="none" contype="0" conaffinity="0"/>'
        f'<pin gridrange="0 0 {nz - 1} {nx - 1} {ny - 1} {nz - 1}"/>'
        "</flexcomp>"
    )


def add_tips(spec: Any, name: str, approach: np.ndarray, mu: float, settings: EngineSettings) -> int:
    """Give the face vertices of pad ``name`` (the flex bodies nearest the object along
    ``approach``) a sphere of ``settings.tip_radius`` that carries their contacts (contype 2,
    touching only geoms of conaffinity 2), and gravity compensation to every vertex body (the
    engine's pad mass is a numerical choice, its weight must not act).  Returns the tips' count."""
    mujoco = __import__("mujoco")
    a = np.asarray(approach, float) / np.linalg.norm(approach)
    bodies = [b for b in spec.bodies if b.name.startswith(f"{name}_")]
    along = np.array([np.asarray(b.pos, float) @ a for b in bodies])
    r = settings.tip_radius
    n = 0
    for b, s in zip(bodies, along, strict=True):
        b.gravcomp = 1.0
        if s < along.max() - 1e-9:
            continue
        g = b.add_geom()
        g.type = mujoco.mjtGeom.mjGEOM_SPHERE
        g.size = [r, 0.0, 0.0]
        g.pos = list(-r * a)  # the sphere's outermost point at the vertex
        g.mass = 0.0
        g.friction = [mu, 0.0, 0.0]
        g.condim = 3
        g.contype, g.conaffinity = 2, 0
        g.solref = list(settings.contact_solref)
        g.solimp = list(settings.contact_solimp)
        n += 1
    return n


def compile_spec(spec: Any) -> Any:
    """``spec.compile()`` without MuJoCo's "flex ... has no equality constraints or passive
    forces" warning, which it gives for every elastic 3D flex (its elasticity is active: a pad
    with ``young=0`` collapses by its whole thickness, with 1 MPa it does not)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=r"flex '.*' is not rigid and has no equality")
        return spec.compile()

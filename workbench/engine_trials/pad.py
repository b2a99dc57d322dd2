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
    from ..sources.jaws import check_direction

    # a zero vector first, by its own name: it would otherwise read as "up parallel to the approach"
    check_direction(approach, "approach", "the jaw's closing direction, the grasp axis")
    check_direction(up, "up", "the pad's length direction, across the grasp axis")
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


def pad_bodies(spec: Any, name: str, approach: np.ndarray) -> tuple[list, np.ndarray, np.ndarray]:
    """(bodies, along, face) of pad ``name`` in an uncompiled spec: its vertex bodies (the
    pinned back layer has none), each one's position along ``approach`` (N,) [m], and which
    are on the face — the layer nearest the object (N,) bool."""
    a = np.asarray(approach, float) / np.linalg.norm(approach)
    bodies = [b for b in spec.bodies if b.name.startswith(f"{name}_")]
    along = np.array([np.asarray(b.pos, float) @ a for b in bodies])
    return bodies, along, along >= along.max() - 1e-9


def conform_pad(spec: Any, name: str, approach: np.ndarray, thickness: float, mesh: Any, gap: float) -> float:
    """Mould pad ``name`` (uncompiled, flat, of ``thickness`` [m]) to ``mesh``: each face vertex
    moves along ``approach`` (3,) until it is ``gap`` [m] from the mesh's surface (a ray along
    the approach), its column's inner vertices by the same shift times their height above the
    pinned back (0 at the back, 1 at the face) — a jaw shaped to the object at rest, as the
    thesis's fin-ray jaws are by a grasp force above 20 N (§4.1.3.2).  A face vertex whose ray
    misses the mesh takes the shift of the nearest one that hits.  Returns the largest shift
    [m]; raises ValueError when no ray hits or a shift would leave < 1/4 of the thickness."""
    a = np.asarray(approach, float) / np.linalg.norm(approach)
    bodies, along, face = pad_bodies(spec, name, a)
    pos = np.array([np.asarray(b.pos, float) for b in bodies])
    lateral = pos - np.outer(along, a)
    fpos = pos[face]
    # rays start a body-length behind the face so a surface already past it is found too
    back_off = float(np.ptp(np.asarray(mesh.vertices, float) @ a)) + thickness
    hits, idx, _ = mesh.ray.intersects_location(fpos - back_off * a, np.tile(a, (len(fpos), 1)))
    dist = np.full(len(fpos), np.inf)
    for h, i in zip(hits, idx, strict=True):
        dist[i] = min(dist[i], float((h - fpos[i]) @ a))  # the first surface along the ray
    ok = np.isfinite(dist)
    if not ok.any():
        raise ValueError(
            f"no face vertex of {name} looks at the mesh along the approach: nothing to mould it to"
        )
    flat = lateral[face]
    if not ok.all():
        near = np.argmin(np.linalg.norm(flat[~ok][:, None] - flat[ok][None], axis=2), axis=1)
        dist[~ok] = dist[ok][near]
    shift_face = dist - gap
    if shift_face.min() < -0.75 * thickness:
        raise ValueError(
            f"moulding {name} to the mesh would compress it by {-shift_face.min() * 1e3:.3g} mm of its "
            f"{thickness * 1e3:.3g} mm: the grasp point is not the surface's nearest point to the jaw"
        )
    # each vertex's column: the face vertex with the same lateral position
    col = np.argmin(np.linalg.norm(lateral[:, None] - flat[None], axis=2), axis=1)
    back = along[face].max() - thickness
    height = (along - back) / thickness
    for b, p, c, t in zip(bodies, pos, col, height, strict=True):
        b.pos = list(p + shift_face[c] * t * a)
    return float(np.abs(shift_face).max())


def add_tips(
    spec: Any, name: str, approach: np.ndarray, mu: float, settings: EngineSettings, face=None
) -> int:
    """Give the face vertices of pad ``name`` (the flex bodies nearest the object along
    ``approach``, or the mask ``face`` from :func:`pad_bodies` taken before moulding) a sphere
    of ``settings.tip_radius`` that carries their contacts (contype 2, touching only geoms of
    conaffinity 2), and gravity compensation to every vertex body (the engine's pad mass is a
    numerical choice, its weight must not act).  Returns the tips' count."""
    mujoco = __import__("mujoco")
    a = np.asarray(approach, float) / np.linalg.norm(approach)
    bodies, _, on_face = pad_bodies(spec, name, a)
    on_face = on_face if face is None else face
    r = settings.tip_radius
    n = 0
    for b, f in zip(bodies, on_face, strict=True):
        b.gravcomp = 1.0
        if not f:
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


def pad_spec(xml: str) -> Any:
    """The ``mujoco.MjSpec`` of a scene's MJCF ``xml`` with every flex's own element contacts
    off: its pads touch through the tips :func:`add_tips` gives their face vertices."""
    mujoco = __import__("mujoco")
    spec = mujoco.MjSpec.from_string(xml)
    for f in spec.flexes:
        f.contype, f.conaffinity = 0, 0
    return spec


def compile_spec(spec: Any) -> Any:
    """``spec.compile()`` without MuJoCo's "flex ... has no equality constraints or passive
    forces" warning, which it gives for every elastic 3D flex (its elasticity is active: a pad
    with ``young=0`` collapses by its whole thickness, with 1 MPa it does not)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=r"flex '.*' is not rigid and has no equality")
        return spec.compile()

"""Antipodal grasp sampling on triangle meshes (Dex-Net style; thesis §4.1.4.2, §4.3.3.3).

Sample a surface point ``p1`` with outward normal ``n1``; draw a grasp axis
inside the friction cone around ``−n1`` (half-angle ``atan μ``); cast a ray from
``p1`` along the axis and take the last point where it leaves the object,
``p2`` — the outer surface on the far side, so a thin-walled (hollow) object is
grasped across, not through its 0.4 mm wall; keep the grasp if ``n2`` is also
within the friction cone of the axis (antipodal), the jaw opening ``|p2 − p1|``
fits, and both contacts clear the table by ``clearance``.  Seeded; returns as
many grasps as found (up to ``n``).
"""

from __future__ import annotations

import logging

import numpy as np

log = logging.getLogger(__name__)


def _cone_directions(rng: np.random.Generator, axes: np.ndarray, half_angle: float) -> np.ndarray:
    """Unit vectors uniformly within a cone of ``half_angle`` around each axis (n, 3)."""
    n = len(axes)
    cos_t = rng.uniform(np.cos(half_angle), 1.0, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    helper = np.where(np.abs(axes[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    x = np.cross(axes, helper)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    y = np.cross(axes, x)
    sin_t = np.sqrt(1 - cos_t**2)
    return cos_t[:, None] * axes + sin_t[:, None] * (np.cos(phi)[:, None] * x + np.sin(phi)[:, None] * y)


def antipodal_grasps(
    mesh,
    n: int,
    mu: float,
    *,
    max_width: float = 0.1,
    min_width: float = 0.005,
    table_z: float | None = None,
    clearance: float = 0.01,
    seed: int = 0,
    max_samples: int | None = None,
    units: str | float | None = None,
    allow_scale: bool = False,
    pad: tuple[float, float] | None = (0.02, 0.04),
    up=(0.0, 0.0, 1.0),
    edge_depth: float = 1e-3,
) -> list[dict]:
    """Up to ``n`` antipodal grasps ``{p1, p2, n1, n2, axis, center, width}`` [m].

    ``units`` is the unit of ``mesh.vertices`` (``None``: metres; "mm" scales a
    copy by 1e-3); every other length argument and every result is in metres.  A
    mesh spanning more than ``TOL.max_object_extent_m`` or less than
    ``TOL.min_object_extent_m`` raises ``ValueError`` naming the likely unit
    (``allow_scale=True`` accepts it): a millimetre mesh read as metres would
    otherwise yield no grasp at all, every width exceeding ``max_width``.

    pad, up, edge_depth : grasps whose flat jaws (``pad = (width, length)`` [m], length
        axis along ``up``) would first meet the surface at a pad edge more than
        ``edge_depth`` [m] before the contact point are dropped (counted in the log; see
        :func:`edge_touch`); ``pad=None`` keeps every antipodal pair.
    """
    import trimesh

    from ..units import mesh_in_metres
    from .gws import check_mu

    if not isinstance(mesh, trimesh.Trimesh) or not mesh.is_watertight:
        raise ValueError("antipodal sampling needs a watertight trimesh.Trimesh")
    mesh = mesh_in_metres(mesh, "mesh passed to antipodal_grasps", units=units, allow_scale=allow_scale)
    check_mu(mu)
    rng = np.random.default_rng(seed)
    half = np.arctan(mu)
    m = max_samples or 20 * n
    pts, fid = trimesh.sample.sample_surface(mesh, m, seed=int(rng.integers(2**31)))
    n1 = mesh.face_normals[fid]
    axes = _cone_directions(rng, -n1, half)
    # ray start offset off the surface: far above round-off of the mesh scale, far below any wall
    eps = 1e-6 * mesh.scale
    locs, ray_idx, tri_idx = mesh.ray.intersects_location(pts + eps * axes, axes, multiple_hits=True)
    out = []
    n_edge = 0
    for k in range(m):
        hits = np.flatnonzero(ray_idx == k)
        if hits.size == 0:
            continue
        dist = (locs[hits] - pts[k]) @ axes[k]
        exits = hits[(mesh.face_normals[tri_idx[hits]] @ axes[k] > 0) & (dist > eps)]
        if exits.size == 0:
            continue
        j = exits[np.argmax((locs[exits] - pts[k]) @ axes[k])]
        p2, n2 = locs[j], mesh.face_normals[tri_idx[j]]
        width = float(np.linalg.norm(p2 - pts[k]))
        if not min_width <= width <= max_width or np.arccos(np.clip(n2 @ axes[k], -1, 1)) > half:
            continue
        if table_z is not None and min(pts[k][2], p2[2]) < table_z + clearance:
            continue
        if pad is not None and (
            edge_touch(mesh, pts[k], axes[k], up, pad, edge_depth)
            or edge_touch(mesh, p2, -axes[k], up, pad, edge_depth)
        ):
            n_edge += 1
            continue
        out.append(
            {
                "p1": pts[k],
                "p2": p2,
                "n1": n1[k],
                "n2": n2,
                "axis": axes[k],
                "center": 0.5 * (pts[k] + p2),
                "width": width,
            }
        )
        if len(out) == n:
            break
    if n_edge:
        log.info("antipodal_grasps: dropped %d grasps whose jaws meet the surface at a pad edge", n_edge)
    return out


def edge_touch(mesh, p: np.ndarray, approach, up, pad, depth: float, rim: float = 0.75) -> bool:
    """Whether a flat jaw ``pad = (width, length)`` [m] centred on ``p`` and closing along
    ``approach`` meets the surface of ``mesh`` only near the edge of its face: after
    closing ``depth`` past first touch (:func:`~workbench.sources.reach.reach_profile`, faces refined to
    1 mm under the footprint), the patch's pressure centre lies in the outer
    ``1 − rim`` of the face (or nothing faces the jaw).  The jaw then presses with its
    edge, far from the planned contact, and face-contact models do not describe what it
    transmits.  A patch that merely spans the face (a cylinder along the pad) is not
    an edge contact: its pressure centre stays inside."""
    from ..sources.jaws import jaw_frame
    from ..sources.reach import reach_profile

    a = np.asarray(approach, float) / np.linalg.norm(approach)
    up = np.asarray(up, float)
    if abs(a @ up) > 0.99 * np.linalg.norm(up):  # jaw length axis undefined: any perpendicular
        up = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    try:
        prof = reach_profile(mesh, p, a, up, pad=pad, closing=depth, allow_scale=True)
    except ValueError:  # the pad touches nothing facing it: no face contact at all
        return True
    _, e1, e2 = jaw_frame(a, up)
    rel = prof.pressure_center - p
    return bool(abs(rel @ e1) >= rim * pad[0] / 2 or abs(rel @ e2) >= rim * pad[1] / 2)


def horizontal_grasps(
    mesh,
    heights,
    n_angles: int,
    mu: float,
    *,
    centre=None,
    pad: tuple[float, float] | None = (0.02, 0.04),
    edge_depth: float = 1e-3,
    units: str | float | None = None,
) -> list[dict]:
    """Antipodal grasps with horizontal axes through a vertical axis, on a grid of
    ``heights`` (k,) [m] × ``n_angles`` axis angles in [0, π) — the layout of the measured
    stiffness maps (thesis §4.3.3.1) and of a parallel-jaw gripper grasping an upright
    object from the side.  Same dicts as :func:`antipodal_grasps` (``p1``, ``p2`` the
    outermost hits of the line, ``axis`` from jaw 1 into the object), kept when both
    surface normals lie within the friction cone (half-angle ``arctan μ``) of the axis
    and, with ``pad``, neither jaw first meets the surface at a pad edge (:func:`edge_touch`).

    centre : (2,) the vertical axis's (x, y) [m] (default the mesh box's centre).
    """
    from ..units import closed_mesh
    from .gws import check_mu

    mesh = closed_mesh(mesh, "mesh passed to horizontal_grasps", units=units)
    check_mu(mu)
    if isinstance(n_angles, bool) or not isinstance(n_angles, (int, np.integer)) or n_angles < 1:
        raise ValueError(f"n_angles must be an integer >= 1; got {n_angles!r}")
    z = np.atleast_1d(np.asarray(heights, float))
    lo, hi = mesh.bounds
    if z.ndim != 1 or not np.isfinite(z).all() or ((z <= lo[2]) | (z >= hi[2])).any():
        raise ValueError(f"heights must be finite and inside the mesh z extent ({lo[2]:.4g}, {hi[2]:.4g}) m")
    c = (lo[:2] + hi[:2]) / 2 if centre is None else np.asarray(centre, float)
    half = np.arctan(mu)
    phis = np.pi * np.arange(n_angles) / n_angles
    Z, P = np.meshgrid(z, phis, indexing="ij")
    d = np.column_stack([np.cos(P.ravel()), np.sin(P.ravel()), np.zeros(P.size)])
    far = float(np.linalg.norm(hi - lo))
    origins = np.column_stack([c[0] - far * d[:, 0], c[1] - far * d[:, 1], Z.ravel()])
    locs, ray_idx, tri_idx = mesh.ray.intersects_location(origins, d, multiple_hits=True)
    out, n_cone, n_edge = [], 0, 0
    for k in range(len(d)):
        hits = np.flatnonzero(ray_idx == k)
        if hits.size < 2:
            continue
        t = (locs[hits] - origins[k]) @ d[k]
        i1, i2 = hits[np.argmin(t)], hits[np.argmax(t)]
        p1, p2 = locs[i1], locs[i2]
        n1, n2 = mesh.face_normals[tri_idx[i1]], mesh.face_normals[tri_idx[i2]]
        if np.arccos(np.clip(-n1 @ d[k], -1, 1)) > half or np.arccos(np.clip(n2 @ d[k], -1, 1)) > half:
            n_cone += 1
            continue
        if pad is not None and (
            edge_touch(mesh, p1, d[k], (0.0, 0.0, 1.0), pad, edge_depth)
            or edge_touch(mesh, p2, -d[k], (0.0, 0.0, 1.0), pad, edge_depth)
        ):
            n_edge += 1
            continue
        out.append(
            {
                "p1": p1,
                "p2": p2,
                "n1": n1,
                "n2": n2,
                "axis": d[k].copy(),
                "center": 0.5 * (p1 + p2),
                "width": float(np.linalg.norm(p2 - p1)),
            }
        )
    log.info(
        "horizontal_grasps: %d of %d kept (%d outside the friction cone, %d meet a pad edge)",
        len(out),
        len(d),
        n_cone,
        n_edge,
    )
    return out

"""Wall stiffness at given grasp locations (thesis §4.3.3.1).

The measured stiffness maps (``deformable_objects/stiffness_maps/*.json``) list
``2n`` contact points: point ``i`` and point ``i + n`` are the two jaws of grasp
``i``.  :func:`grasp_pairs` checks such a list against the object's outer surface
(:class:`workbench.fem.mesh_wall.RadialSurface`); :func:`stiffness_at` squeezes the wall at
each grasp (the grasp axis through both points, its midpoint as the centre,
:func:`workbench.fem.wall.squeeze`) and reports ``s = f / Δ``.

Grasps the wall model cannot squeeze are not errors of the whole run; each is
flagged with its reason:

* ``rigid``: a jaw point outside the modelled wall's heights (a cap, a neck or the
  base, which :func:`workbench.fem.mesh_wall.radial_surface` leaves out), a jaw that would
  travel onto a clamped edge of the wall (the base: it stops there), or a closing
  below ``rigid_closing`` (what the gripper cannot resolve) —
  reported as ``RIGID_STIFFNESS`` like the measured maps' 8e10 (the computed value
  is kept as ``fem_stiffness``);
* ``failed`` (and ``implausible``): the jaws would close by more than the object's width at
  the target force — an impossible closing of the linear model (a modulus in another unit);
* ``failed``: the squeeze raised (e.g. no wall under a jaw), the grasp axis is
  not horizontal (the squeeze's jaws are vertical), or it points out of the wall at a
  jaw point (more than 90° from the outward normal: the jaw would press from inside) —
  ``NaN`` with the reason.

A grasp is squeezed but flagged ``non_antipodal`` (and logged) when its axis is more
than ``config.TOL.antipodal_max_deg`` from the surface normal at either jaw point —
a pair of points that is not a parallel-jaw grasp (e.g. two points on one side); each
row carries that angle as ``axis_normal_deg``.
"""

from __future__ import annotations

import logging
import time
from typing import Any

import numpy as np

from .mesh_wall import RadialSurface
from .wall import Squeeze, Wall, check_wall, squeeze

log = logging.getLogger(__name__)

#: stiffness reported for a rigid location [N/m] (the measured maps use 8e10)
RIGID_STIFFNESS = 8.0e10


def _as_locations(locations: Any, what: str) -> np.ndarray:
    """``locations`` as a finite (2n, 3) float array, n >= 1, or a ``ValueError`` naming ``what``."""
    try:
        L = np.asarray(locations, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(
            f"{what} must be a finite (2n, 3) array [m], one [x, y, z] of numbers per point; got "
            f"{str(locations)[:80]} — give every point three numbers"
        ) from None
    if L.ndim != 2 or L.shape[1] != 3 or not np.isfinite(L).all():
        got = f"shape {L.shape}" if L.ndim != 2 or L.shape[1] != 3 else "non-finite values (NaN or inf)"
        raise ValueError(f"{what} must be a finite (2n, 3) array [m], one [x, y, z] per point; got {got}")
    if len(L) == 0 or len(L) % 2:
        raise ValueError(
            f"{what} must hold 2n points (point i and i + n are one grasp's two jaws); got {len(L)} — "
            "every grasp needs both jaw points: add the missing one or drop the unpaired one"
        )
    return L


def grasp_pairs(
    locations: Any, surface: RadialSurface, *, max_offset: float = 1e-3, mesh: Any = None
) -> tuple[np.ndarray, np.ndarray]:
    """(n, 3) first and (n, 3) second jaw points of ``locations`` (2n, 3) [m].

    surface : a :class:`RadialSurface` or a :class:`~workbench.fem.object_wall.WallGeometry`
    (its ``surface``).  Raises ``ValueError`` for a malformed or odd-length array, a point outside the
    mesh's box, or more than ``max_offset`` [m] off the surface (radially) where the
    surface is defined — the mark of another object, frame or unit.  With ``mesh`` (the
    object's, in metres) points at other heights (a lip, cap, neck or base, which the
    side wall leaves out) must lie within ``max_offset`` of it too.
    """
    L = _as_locations(locations, "locations")
    surface = _surface_of(surface)[0]  # a WallGeometry's side wall, or a ValueError
    fix = "the locations must lie on this mesh, in its frame and in metres"
    beyond = np.maximum(surface.bounds[0] - L, L - surface.bounds[1]).max(axis=1)
    if (beyond > max_offset).any():
        k = int(np.argmax(beyond))
        # in millimetres: far larger than the object, and inside its box once divided by 1000
        mm = np.maximum(surface.bounds[0] - L / 1e3, L / 1e3 - surface.bounds[1]).max(axis=1)
        huge = np.abs(L).max() > 100 * np.abs(surface.bounds).max()
        hint = (
            " — they are probably in millimetres: divide them by 1000"
            if huge and (mm <= max_offset).all()
            else ""
        )
        raise ValueError(
            f"{_which(beyond > max_offset)} outside the object's box {surface.bounds.tolist()} m; the "
            f"farthest, location {k} {L[k].tolist()}, {beyond[k] * 1e3:.2f} mm beyond it (at most "
            f"{max_offset * 1e3:g} mm): {fix}{hint}"
        )
    _, z, off = surface.parameters(L)
    lo, hi = surface.z_range
    on_wall = (z >= lo) & (z <= hi)
    far = on_wall & (np.abs(off) > max_offset)
    if far.any():
        k = int(np.argmax(np.where(far, np.abs(off), 0)))
        raise ValueError(
            f"{_which(far)} off the object's surface; the farthest, location {k} {L[k].tolist()}, is "
            f"{off[k] * 1e3:.2f} mm off it (radially, + outside; at most {max_offset * 1e3:g} mm): {fix}"
        )
    if mesh is not None and not on_wall.all():
        from trimesh.proximity import closest_point

        idx = np.flatnonzero(~on_wall)
        _, dist, _ = closest_point(mesh, L[idx])
        if (dist > max_offset).any():
            k = int(idx[np.argmax(dist)])
            bad = np.zeros(len(L), dtype=bool)
            bad[idx[dist > max_offset]] = True
            raise ValueError(
                f"{_which(bad)} off the object's mesh; the farthest, location {k} {L[k].tolist()}, is "
                f"{dist.max() * 1e3:.2f} mm from it "
                f"(at most {max_offset * 1e3:g} mm; it lies above or below the side wall, "
                f"z = {lo:.4g}..{hi:.4g} m): {fix}"
            )
    n = len(L) // 2
    return L[:n], L[n:]


def _which(mask: np.ndarray, show: int = 8) -> str:
    """The words "locations 0, 3, 5 (3 of 12) lie": every offending index (the first ``show``)."""
    idx = np.flatnonzero(mask)
    more = f", … ({idx.size - show} more)" if idx.size > show else ""
    name, verb = ("location", "lies") if idx.size == 1 else ("locations", "lie")
    return f"{name} {', '.join(map(str, idx[:show]))}{more} ({idx.size} of {mask.size}) {verb}"


def axis_normal_angles(surface: RadialSurface, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(n,) larger angle [deg] between the grasp axis and the wall's outward normal at
    the two jaw points: the axis ``b − a`` against ``−n(a)`` and against ``n(b)``.

    a, b : (n, 3) first and second jaw points [m] (:func:`grasp_pairs`).  0° is an
    ideal antipodal pair; > 90° means the axis leaves the object at a jaw point.  The
    normal is the radial surface's at the point's (θ, z) (outside the side wall's
    heights its spline's extrapolation: a rough value)."""
    a, b = np.atleast_2d(np.asarray(a, float)), np.atleast_2d(np.asarray(b, float))
    axis = b - a
    norm = np.linalg.norm(axis, axis=1, keepdims=True)
    axis = np.divide(axis, norm, out=np.zeros_like(axis), where=norm > 0)  # coincident points: 90°
    out = []
    for p, sign in ((a, -1.0), (b, 1.0)):
        th, z, _ = surface.parameters(p)
        _, n = surface(th, z)
        out.append(np.degrees(np.arccos(np.clip(sign * np.einsum("ij,ij->i", n, axis), -1.0, 1.0))))
    return np.maximum(*out)


def _surface_of(geometry: Any) -> tuple[RadialSurface, tuple[float, float]]:
    """The outer surface and the modelled heights (lo, hi) [m] of ``geometry``: a
    :class:`RadialSurface` (its own heights), or a :class:`~workbench.fem.object_wall.WallGeometry`
    (its ``surface``; its heights, side wall plus lip); ``ValueError`` else."""
    from .object_wall import WallGeometry

    if isinstance(geometry, WallGeometry):
        surface = geometry.surface
        heights = geometry.z_range
    elif isinstance(geometry, RadialSurface):
        surface, heights = geometry, geometry.z_range
    else:
        raise ValueError(
            "surface must be the object's outer surface, a RadialSurface (radial_surface(mesh)) or the "
            f"WallGeometry that object_wall / wall_geometry return; got {type(geometry).__name__} — "
            "pass geo (or geo.surface) from geo, wall = object_wall(mesh)"
        )
    return surface, (float(heights[0]), float(heights[1]))


def stiffness_at(
    wall: Wall,
    surface: RadialSurface | Any,
    locations: Any,
    *,
    force: float = 10.0,
    jaw: tuple[float, float] = (0.02, 0.04),
    max_offset: float = 1e-3,
    rigid_closing: float = 0.0,
    grasp_ids: Any = None,
) -> list[dict]:
    """One dict per grasp of ``locations`` (2n, 3): ``stiffness`` [N/m], ``delta`` [m],
    ``rigid``, ``failed`` and ``non_antipodal`` flags and ``axis_normal_deg`` (module
    docstring), ``reason``, ``fem_stiffness``
    (the squeeze's value, also for a grasp flagged rigid by its closing), ``seconds``.

    wall : the wall built on ``surface`` (:func:`workbench.fem.wall.build_wall`);
    surface : the object's outer surface, a :class:`RadialSurface` (the modelled heights are
    its ``z_range``, the side wall's), or the :class:`workbench.fem.object_wall.WallGeometry`
    that ``object_wall`` returns with the wall (``geo, wall = object_wall(mesh)``: its
    ``surface`` is used, and its ``z_range`` — side wall plus lip — is the modelled heights);
    anything else is a ``ValueError``;
    force : jaw force [N] (thesis: 10 N); jaw : (width, length) of the jaw faces [m];
    rigid_closing : closings [m] below this are reported rigid (0: never);
    grasp_ids : (n,) the grasps' numbers in the caller's list, used in log messages
    (default 0 … n − 1).
    """
    if not (np.isfinite(rigid_closing) and rigid_closing >= 0):
        raise ValueError(f"rigid_closing must be a closing >= 0 [m]; got {rigid_closing}")
    from workbench.config import TOL

    check_wall(wall, "stiffness_at(wall, geo, locations)")
    surface, (lo, hi) = _surface_of(surface)
    p1, p2 = grasp_pairs(locations, surface, max_offset=max_offset)
    angles = axis_normal_angles(surface, p1, p2)
    limit = TOL.antipodal_max_deg  # read at call time
    ids = np.arange(len(p1)) if grasp_ids is None else np.asarray(grasp_ids)
    if ids.shape != (len(p1),):
        raise ValueError(f"grasp_ids must hold one number per grasp ({len(p1)}); got shape {ids.shape}")
    out = []
    for k, (a, b) in enumerate(zip(p1, p2, strict=True)):
        ang = float(angles[k])
        t0 = time.perf_counter()
        coincide = np.linalg.norm(b - a) < 1e-6  # < 1 µm apart: no grasp axis
        row = _new_row(ang, limit, coincide, int(ids[k]))
        skip = _not_squeezed(a, b, ang, coincide, (lo, hi))
        if skip is not None:
            row.update(skip)
        else:
            try:
                res = squeeze(wall, (a + b) / 2, b - a, jaw=jaw, force=force)
                s = float(res.stiffness)
                row.update(stiffness=s, fem_stiffness=s, delta=float(res.delta))
                row.update(_squeeze_flags(res, rigid_closing))
            except ValueError as exc:
                row.update(failed=True, reason=str(exc))
        row["seconds"] = time.perf_counter() - t0
        out.append(row)
    return out


def _new_row(ang: float, limit: float, coincide: bool, grasp_id: int) -> dict:
    """A grasp's row of :func:`stiffness_at` before its squeeze: ``ang`` [deg] its axis–normal
    angle against the antipodal ``limit`` [deg] (a warning logged beyond it), ``coincide``
    its jaw points (no axis, no angle)."""
    row = {
        "stiffness": np.nan,
        "fem_stiffness": np.nan,
        "delta": np.nan,
        "rigid": False,
        "failed": False,
        "implausible": False,
        "non_antipodal": bool(ang > limit),
        "axis_normal_deg": ang,
        "reason": None,
    }
    if coincide:
        row.update(non_antipodal=False, axis_normal_deg=float("nan"))
    if row["non_antipodal"]:
        log.warning(
            "grasp %d is not antipodal: its axis is %.0f° from the surface normal at a jaw point "
            "(at most %g°, config.TOL.antipodal_max_deg) — check that points i and i + n are the "
            "two jaws of one grasp",
            grasp_id,
            ang,
            limit,
        )
    return row


def _not_squeezed(
    a: np.ndarray, b: np.ndarray, ang: float, coincide: bool, heights: tuple[float, float]
) -> dict | None:
    """The flags and reason of a grasp from jaw point ``a`` to ``b`` (3,) [m] that is not
    squeezed (module docstring: rigid or failed), or None to squeeze it; ``heights`` (lo, hi) [m]
    of the modelled wall."""
    lo, hi = heights
    axis = b - a
    if coincide:
        return {
            "failed": True,
            "reason": "the two jaw points coincide (no grasp axis); points i and i + n must be the two jaws",
        }
    if not all(lo <= p[2] <= hi for p in (a, b)):
        return {"stiffness": RIGID_STIFFNESS, "delta": 0.0, "rigid": True, "reason": "outside the side wall"}
    if abs(axis[2]) > 0.05 * np.linalg.norm(axis):  # > ~3°: squeeze's jaws are vertical
        return {"failed": True, "reason": "grasp axis not horizontal (the wall squeeze assumes it is)"}
    if ang > 90.0:
        return {
            "failed": True,
            "reason": f"the grasp axis leaves the wall at a jaw point ({ang:.0f}° from its outward "
            "normal): a jaw would press from inside; points i and i + n must face each other",
        }
    return None


def _squeeze_flags(res: Squeeze, rigid_closing: float) -> dict:
    """The flags and reason of a squeezed grasp (:func:`workbench.fem.wall.squeeze`'s ``res``):
    implausible (failed), on the clamped edge or closing below ``rigid_closing`` [m] (rigid),
    or none."""
    if res.implausible:
        return {
            "stiffness": np.nan,
            "failed": True,
            "implausible": True,
            "reason": f"impossible: the jaws close by {res.delta:.4g} m at the target force, "
            f"more than the object's {res.width * 1e3:.3g} mm width (the linear wall model "
            "does not hold; a modulus or thickness in another unit?)",
        }
    if res.on_clamp:
        return {
            "stiffness": RIGID_STIFFNESS,
            "rigid": True,
            "reason": (
                "a jaw rests on the clamped edge after "
                f"{res.clamp_gap * 1e3:.3g} mm of its own travel from first touch "
                f"(closing of both jaws {res.delta * 1e3:.3g} mm at the target force)"
            ),
        }
    if res.delta < rigid_closing:
        return {
            "stiffness": RIGID_STIFFNESS,
            "rigid": True,
            "reason": f"closing {res.delta * 1e3:.3f} mm below {rigid_closing * 1e3:g} mm",
        }
    return {}


def read_locations(path: Any) -> tuple[np.ndarray, np.ndarray | None]:
    """``stiffness_locations`` (2n, 3) [m] of a JSON file in the measured maps' format,
    and its ``stiffness_map`` as (n,) [N/m] (one value per grasp) when present, else None.

    Raises ``ValueError`` when the file is not JSON, lacks ``stiffness_locations``, holds
    anything but 2n finite points [x, y, z], or the map's length does not match (entries
    i and i + n must be equal: one grasp)."""
    import json
    from pathlib import Path

    fmt = (
        "a JSON object with 'stiffness_locations' (2n points [m], i and i + n one grasp) as in "
        "deformable_objects/stiffness_maps/*.json"
    )
    try:
        data = json.loads(Path(path).read_text())
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: expected {fmt}; got text that is not JSON ({exc})") from None
    if not isinstance(data, dict) or "stiffness_locations" not in data:
        got = f"keys {sorted(data)}" if isinstance(data, dict) else f"a JSON {type(data).__name__}"
        raise ValueError(f"{path}: expected {fmt}; got {got}")
    L = _as_locations(data["stiffness_locations"], f"{path}: 'stiffness_locations'")
    if "stiffness_map" not in data:
        return L, None
    want = f"{path}: 'stiffness_map' must hold one value [N/m] per location, equal for points i and i + n"
    try:
        S = np.asarray(data["stiffness_map"], dtype=float).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"{want}; got {str(data['stiffness_map'])[:80]} (not all numbers)") from None
    n = len(L) // 2
    if S.shape != (len(L),):
        raise ValueError(f"{want}; got {S.size} values for {len(L)} locations")
    # a map's two jaw points of one grasp carry one stiffness written twice (equal to 1e-9 after JSON)
    differ = ~np.isclose(S[:n], S[n:], rtol=1e-9)
    if differ.any():
        k = int(np.argmax(differ))
        raise ValueError(f"{want}; got {S[k]:g} and {S[k + n]:g} for points {k} and {k + n}")
    from workbench.grasp.stiffness_map import check_stiffness

    try:  # > 0, and not in N/mm (the same check as every stiffness input)
        check_stiffness(S[:n], n, "grasp", fix="one value per grasp")
    except ValueError as exc:
        raise ValueError(f"{path}: 'stiffness_map': {exc}") from None
    return L, S[:n]


__all__ = ["RIGID_STIFFNESS", "axis_normal_angles", "grasp_pairs", "read_locations", "stiffness_at"]

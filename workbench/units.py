"""Length units and a guard against meshes and profiles given in the wrong unit.

The library works in metres (CONVENTIONS.md "Units and scale"); readers convert
explicitly with ``units="mm"`` and nothing guesses silently.  What *can* be
checked is plausibility: a graspable object or a contact patch spanning more
than ``TOL.max_object_extent_m`` (2 m) or less than ``TOL.min_object_extent_m``
(0.1 mm) was almost certainly given in another unit — a 150 mm bottle exported
in millimetres reads as 150 m.  :func:`check_extent` raises a ``ValueError``
naming the likely unit and the fix; ``allow_scale=True`` accepts an unusual
size on purpose.  :func:`closed_mesh` is the one gate of every mesh input (finite,
watertight, not flat, outward, a plausible size); :func:`far_from_object` says when a
point given with a mesh lies too far from it to be on it (a point in millimetres).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import config as _config

_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6}
_UNIT_NAMES = {"m": "metres", "cm": "centimetres", "mm": "millimetres", "um": "micrometres"}


def length_factor(units: str | float) -> float:
    """Metres per unit for ``units`` ("m", "cm", "mm", "um" or a positive float)."""
    if isinstance(units, str):
        if units not in _UNITS:
            raise ValueError(f"units must be one of {sorted(_UNITS)} or a positive float; got {units!r}")
        return _UNITS[units]
    factor = float(units)
    if not np.isfinite(factor) or factor <= 0:
        raise ValueError(f"units scale must be a positive finite float; got {units!r}")
    return factor


def _likely_unit(raw: float, factor: float, larger: bool) -> str | None:
    """The common unit (other than the declared one, of ``factor`` m) in which the
    caller's number ``raw`` is a plausible size; ``larger``: look at units larger
    than the declared one (the object came out too small)."""
    units = _likely_units(raw, factor, larger)
    return units[0] if units else None


def _likely_units(raw: float, factor: float, larger: bool) -> list[str]:
    """Every common unit (other than the declared one, of ``factor`` m) in which ``raw`` is a
    plausible size, in the order of ``_likely_unit``'s search: a mesh 20 units long is 2 cm in
    millimetres and 20 cm in centimetres, and only its maker knows which, so both are named.
    Micrometres are named only when neither millimetres nor centimetres fit."""
    tol = _config.TOL
    order = ("m", "cm", "mm") if larger else ("mm", "cm", "um")
    fits = [
        u
        for u in order
        if (_UNITS[u] > factor if larger else _UNITS[u] < factor)
        and tol.min_object_extent_m <= raw * _UNITS[u] <= tol.max_object_extent_m
    ]
    if "um" in fits and len(fits) > 1:
        fits.remove("um")
    return fits


def check_extent(
    extent_m: float,
    what: str,
    *,
    units: str | float | None = None,
    allow_scale: bool = False,
    check_lower: bool = True,
    fix: str = "pass units={units!r} (or scale it by {factor:g}, e.g. mesh.apply_scale({factor:g}))",
    override: str | None = "allow_scale=True",
) -> float:
    """Return ``extent_m`` [m] if it is a plausible object size, else raise ``ValueError``.

    extent_m : the size of ``what`` in metres *after* ``units`` was applied
        (e.g. the longest side of its bounding box).
    what : how to name the thing in the message ("mesh passed to antipodal_grasps").
    units : the unit the caller declared (``None`` = metres); used to name the fix.
    allow_scale : accept any finite size >= 0 (a deliberately huge or tiny model).
    check_lower : also apply the lower limit (off for contact patches, which can
        legitimately be far smaller than the objects they lie on).
    fix : the remedy named in the message, a format string: ``{units}`` is the
        likely unit, ``{factor}`` the length factor to apply, ``{area_factor}`` its square.
    override : how the caller accepts an unusual size, named in the message; None where
        it cannot (the message then names only the fix).

    The limits ``TOL.max_object_extent_m`` / ``TOL.min_object_extent_m`` are read
    at call time, so a changed ``workbench.config.TOL`` applies at once.  A size
    at a limit passes, within ``TOL.extent_limit_rtol`` (the thesis's surfaces
    S1-S6 are 2 m long up to rounding).  An extent of exactly 0 is not judged here.
    """
    tol = _config.TOL
    extent = float(extent_m)
    if not np.isfinite(extent) or extent < 0:
        raise ValueError(f"{what}: extent must be a finite length >= 0 [m]; got {extent_m!r}")
    if allow_scale:
        return extent
    lo, hi, slack = tol.min_object_extent_m, tol.max_object_extent_m, tol.extent_limit_rtol
    escape = "" if override is None else f", or {override} if the size is intended"
    factor = 1.0 if units is None else length_factor(units)
    declared = "metres" if units is None else _UNIT_NAMES.get(str(units), f"units of {factor:g} m")
    raw = extent / factor  # the size in the caller's own numbers
    if extent > hi * (1 + slack):
        units = _likely_units(raw, factor, larger=False)
        if not units:
            likely = "no common unit makes it a graspable size: check how it was made"
        else:
            readings = []
            for i, u in enumerate(units):
                k = _UNITS[u] / factor
                remedy = fix.format(units=u, factor=k, area_factor=k * k)
                size = "" if i == 0 else f" (then {raw * _UNITS[u]:.3g} m across)"
                readings.append(f"{_UNIT_NAMES[u]}{size}: {remedy}")
            likely = "it is probably in " + "; or in ".join(readings)
        raise ValueError(
            f"{what} spans {extent:.4g} m (read as {declared}), more than "
            f"TOL.max_object_extent_m = {hi:g} m; {likely}{escape}"
        )
    if check_lower and 0 < extent < lo * (1 - slack):
        u = _likely_unit(raw, factor, larger=True)
        if u is None:
            likely = "was it converted to metres twice (e.g. scaled by 1e-3 a second time)?"
        else:
            likely = f"it is probably in {_UNIT_NAMES[u]}: pass units={u!r} instead of units={units!r}"
        raise ValueError(
            f"{what} spans {extent:.4g} m (read as {declared}), less than "
            f"TOL.min_object_extent_m = {lo:g} m; {likely}{escape}"
        )
    return extent


def mesh_in_metres(
    mesh: Any,
    what: str,
    *,
    units: str | float | None = None,
    allow_scale: bool = False,
    fix: str | None = None,
    override: str | None = "allow_scale=True",
) -> Any:
    """``mesh`` (a ``trimesh.Trimesh``) in metres, after :func:`check_closed` and
    :func:`check_extent` on the longest side of its axis-aligned bounding box (``fix``: its
    remedy text, when the caller cannot pass ``units``, e.g. a CLI reading a file).

    ``units`` is the unit of ``mesh.vertices`` (``None`` or "m": metres); any other
    unit is applied to a *copy*, the caller's mesh is never modified.  The same gate as
    :func:`closed_mesh` (the name its callers read best): no mesh is taken in metres without
    being checked finite, closed and outward — an inside-out mesh given to a sampler is refused
    by name, not found to have "no far side" on every candidate.
    """
    return closed_mesh(mesh, what, units=units, allow_scale=allow_scale, fix=fix, override=override)


#: the remedy of a mesh in another unit, for the functions that take a mesh in metres only
#: (``closed_mesh(..., fix=MESH_UNIT_FIX)``: ``units`` and ``factor`` are filled in)
MESH_UNIT_FIX = (
    "convert it first: workbench.units.mesh_in_metres(mesh, 'object', units={units!r}) "
    "(or scale it by {factor:g}, e.g. mesh.apply_scale({factor:g}))"
)


def vertex_extents(vertices: Any) -> np.ndarray:
    """(3,) the sides of the axis-aligned box of ``vertices`` (n, 3): ``np.ptp(vertices, axis=0)``,
    reduced along contiguous rows (a reduction across 3 columns is an order of magnitude slower)."""
    return np.ptp(np.ascontiguousarray(np.asarray(vertices, dtype=np.float64).T), axis=1)


def closed_mesh(
    mesh: Any,
    what: str,
    *,
    units: str | float | None = None,
    allow_scale: bool = False,
    fix: str | None = None,
    override: str | None = "allow_scale=True",
) -> Any:
    """A watertight ``trimesh.Trimesh`` in metres, or a ``ValueError`` that says which
    and how to fix it — the one gate of every mesh input (``what`` names the caller's
    argument in the message): :func:`check_closed`, then :func:`check_extent` on the longest
    side of its bounding box (``fix``: the remedy text of a unit slip, when the caller cannot
    pass ``units``).  ``units`` is applied to a copy."""
    check_closed(mesh, what)
    factor = 1.0 if units is None else length_factor(units)
    extents = vertex_extents(mesh.vertices)
    opts = {} if fix is None else {"fix": fix}
    check_extent(
        float(extents.max()) * factor, what, units=units, allow_scale=allow_scale, override=override, **opts
    )
    if factor == 1.0:
        return mesh
    scaled = mesh.copy()
    scaled.apply_scale(factor)
    return scaled


def check_closed(mesh: Any, what: str) -> None:
    """Refuse ``mesh`` unless it is a ``trimesh.Trimesh`` with finite vertices that is closed
    (watertight) and outward-facing (a positive signed volume): the topology half of
    :func:`closed_mesh`, for callers that convert units themselves (``MeshObstacle``).

    Finiteness comes first: a NaN vertex makes the volume NaN, which would read as "inside out"
    and send the user to ``mesh.invert()``, a fix that cannot work.

    An inside-out mesh (every face wound the other way, ``mesh.invert()``) is watertight
    too, but its "outside" is the object's inside: a pad pressed on it finds no surface
    (0 N) and REACH finds no face towards the jaw, so it is refused here by name.
    """
    import trimesh

    if not isinstance(mesh, trimesh.Trimesh):
        raise ValueError(f"{what} must be a trimesh.Trimesh; got {type(mesh).__name__}")
    if len(mesh.faces) == 0:
        raise ValueError(f"{what} must be a closed triangle mesh; got one without faces")
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    bad = np.flatnonzero(~np.isfinite(vertices).all(axis=1)) if not np.isfinite(vertices).all() else []
    if len(bad):
        raise ValueError(
            f"{what} must have finite vertex coordinates; got {bad.size} of {len(vertices)} vertices with "
            f"NaN/inf (first: vertex {bad[0]}, {vertices[bad[0]].tolist()}) — fix the export or the "
            "computation that made them (a transform or scale with NaN?) before passing the mesh"
        )
    from . import config

    # flatness first: a solid squashed onto a plane (one axis scaled by 0) also fails the
    # watertight test through its degenerate faces, which would hide the cause
    ext = vertex_extents(vertices)
    if ext.max() > 0 and ext.min() < config.TOL.min_mesh_aspect * ext.max():
        raise ValueError(
            f"{what} is flat: its bounding box is {ext.tolist()} (its units), the thinnest side "
            f"{ext.min() / ext.max():.2g} of the longest (below config.TOL.min_mesh_aspect = "
            f"{config.TOL.min_mesh_aspect:g}) — an object a gripper holds has a volume; check the "
            "export (a surface instead of a solid?) or the scale of one axis"
        )
    if not mesh.is_watertight:
        open_edges = len(trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1))
        got = (
            f"{open_edges} open edges (a hole or a missing face)"
            if open_edges
            else "edges shared by more than two faces (non-manifold)"
        )
        raise ValueError(
            f"{what} is not watertight: it must be closed (inside and outside defined) but has "
            f"{got} — repair it first (trimesh.repair.fill_holes / fix_normals) or pass a closed mesh"
        )
    volume = float(mesh.volume)  # signed: negative when the faces are wound inwards
    if not volume > 0:
        raise ValueError(
            f"{what} is inside out: its faces are wound so that their normals point into the "
            f"object (signed volume {volume:.4g} in its units^3, not positive) — flip it with "
            "mesh.invert() (or trimesh.repair.fix_normals(mesh)) before passing it"
        )


def far_from_object(point: Any, bounds: Any) -> str | None:
    """Why ``point`` (3,) [m] cannot be a point on or near the object whose axis-aligned
    bounding box is ``bounds`` (2, 3) [m] — it lies farther outside that box, along some axis,
    than the object's own size (the box's longest side; a contact point in millimetres reads
    as metres and lands there) — or None when it is within that reach.

    The sentence names the distance and, when the point lies more than ten sizes off and a common
    unit turns it into one on or near the box (a millimetre point scaled by 1e-3), that unit and
    the point in metres.  Callers refuse with it (an FEM jaw's point,
    :func:`workbench.sources.fem_jaw.check_jaw_reaches`) or append it to the message of what
    failed (a REACH pad that covers no part of the object).
    """
    p = np.asarray(point, dtype=np.float64)
    lo, hi = (np.asarray(b, dtype=np.float64) for b in bounds)
    size = float((hi - lo).max())
    if p.shape != (3,) or not np.isfinite(p).all():
        return None

    def outside(q: np.ndarray) -> float:  # how far q lies outside the box (0 inside), per axis max
        return max(float(np.max(np.maximum(lo - q, q - hi))), 0.0)

    off = outside(p)
    if not off > size:
        return None
    box = f"{np.round(lo, 4).tolist()}–{np.round(hi, 4).tolist()} m"
    where = (
        f"{np.round(p, 4).tolist()} lies {off:.4g} m outside the object's bounding box {box}, "
        f"farther than the object's own size ({size:.3g} m)"
    )
    # a point on the object read in centimetres or millimetres lands tens to thousands of its sizes
    # away; only then is a unit named (a point 1-10 sizes off is more likely another object's)
    for u in ("mm", "cm") if off > 10 * size else ():
        q = p * _UNITS[u]
        if outside(q) <= size:
            return (
                f"{where}: it is probably in {_UNIT_NAMES[u]} — pass metres "
                f"(× {_UNITS[u]:g}: {np.round(q, 6).tolist()}, which lies on or near the object)"
            )
    return f"{where}: is it in another unit than the mesh (metres), or another object's point?"


# no gripper is 5 m from the object it holds (the physical inputs' ranges: workbench.plausible)
_MAX_TRANSLATION_M = 5.0
# |RᵀR − I| allowed in a rigid transform: 6-digit rotations (REACH's) are off by ~4e-7
_RIGID_ATOL = 1e-5


def check_rigid(T, what: str, *, atol: float = _RIGID_ATOL) -> np.ndarray:
    """``T`` as a (4, 4) float array if it is a rigid transform [m], else ValueError naming the fault.

    Checks the shape, finiteness, the bottom row ``[0, 0, 0, 1]``, a translation under 5 m (else
    "millimetres?"), ``max |RᵀR − I| <= atol`` (else "scaled" or "sheared") and ``det R = +1``.
    """
    try:
        T = np.array(T, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be a 4×4 homogeneous transform of numbers; got {T!r}") from None
    if T.shape != (4, 4):
        raise ValueError(f"{what} must be a 4×4 homogeneous transform; got shape {T.shape}")
    if not np.isfinite(T).all():
        raise ValueError(f"{what} has non-finite entries: {T.tolist()}")
    if not np.allclose(T[3], [0, 0, 0, 1], atol=1e-9):
        hint = " (transposed? pass T.T)" if np.allclose(T[:, 3], [0, 0, 0, 1], atol=1e-9) else ""
        raise ValueError(f"{what} must have the bottom row [0, 0, 0, 1]; got {T[3].tolist()}{hint}")
    dist = float(np.linalg.norm(T[:3, 3]))
    if dist > _MAX_TRANSLATION_M:
        raise ValueError(
            f"{what} translates by {dist:.4g} m (more than {_MAX_TRANSLATION_M:g} m): given in "
            "millimetres? transforms are in metres: divide the translation by 1000"
        )
    R = T[:3, :3]
    err = float(np.abs(R.T @ R - np.eye(3)).max())
    if err > atol:
        s = np.linalg.svd(R, compute_uv=False)
        kind = (
            f"a rotation scaled by {s.mean():.4g} (a unit conversion applied to the whole matrix?)"
            if s.max() - s.min() <= atol * s.mean()
            else "sheared or rounded"
        )
        raise ValueError(
            f"{what} is not rigid: its rotation is not orthonormal (max |RᵀR − I| = {err:.3g} > "
            f"{atol:g}), {kind}; pass a rotation (e.g. orthonormalise it with "
            "scipy.spatial.transform.Rotation.from_matrix(R).as_matrix())"
        )
    if np.linalg.det(R) < 0:
        raise ValueError(
            f"{what} is a reflection (det R = -1), not a rotation: a left-handed frame; flip one axis"
        )
    return T


def check_turn_limit(value, what: str) -> None:
    """A trial's turn limit ``value`` [deg], in [1, 90]: below one degree the verdict would judge
    the pads' own compliance (a held object turns by 0.3-3 degrees with them), and the value was
    most likely given in radians (the thesis's 5° is 0.0873 rad)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (0 < value <= 90):
        raise ValueError(f"{what} must be an angle in [1, 90] degrees; got {value!r}")
    if value < 1.0:
        raise ValueError(
            f"{what} = {value!r} deg is below one degree, where the pads' own compliance turns a held "
            f"object: probably in radians — pass {np.degrees(value):.3g} [deg] (the thesis's limit is 5 deg)"
        )

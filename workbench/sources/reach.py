"""REACH-style contact profiles from triangle meshes (thesis §2.3.1.3, §4.1.4.1;
Danielczuk et al.): the compliant pad, extruded from the jaw face along the
approach direction, is intersected with the rigid object; each object triangle
the pad overlaps carries a pressure proportional to the local pad compression
(a Winkler foundation, ``p = k d`` with ``k = M / h``, M the pad's confined modulus).

Geometry by projection, no booleans: the object is refined near the jaw to
``max_edge``, triangles facing the jaw inside the pad footprint are binned on a
grid over the footprint and only the front-most surface of each bin counts
(what the pad can reach first); the jaw closes by ``closing`` from first touch.

:func:`reach_profile` is one jaw's profile (a centred rectangle or any polygon pad);
:func:`jaw_profiles` both jaws' of a grasp, scaled to the force-sensor reading (the FEM
counterpart: :mod:`workbench.sources.fem_jaw`); :func:`pad_profile` the jaw of a
:class:`~.gripper.Gripper` closing from its open tooltip, None when it misses.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .. import config
from .._row_kernels import _rows_minus
from ..groups import checked_group
from ..plausible import check
from ..profile import ContactProfile
from ._kernels import _elements_may_touch, _faces_may_overlap, _front_most
from .gripper import Jaw, as_polygon, points_in_polygon
from .jaws import check_direction as _check_direction
from .jaws import check_grasp, check_jaw_force, check_pad, jaw_frame, placed_jaw_profile
from .pad_patch import PadPatch, pressed_profile
from .surface_index import SurfaceIndex, concat_runs

__all__ = ["WinklerPress", "fine_surface", "jaw_profiles", "pad_profile", "reach_profile"]

log = logging.getLogger(__name__)


def check_press_closing(closing, what: str = "closing") -> float:
    """``closing`` [m] past first touch as a float if it is a plausible compression of a pad
    (:mod:`workbench.plausible` ``"compression"``: no pad layer is 20 mm deep, so a 30 mm press is
    refused) and > 0 (a pad pressed by 0 carries no pressure), else ValueError — the rule of every
    REACH press (:func:`reach_profile`, :func:`pad_profile`, :func:`jaw_profiles`, the samplers'
    pad-edge check)."""
    c = check("compression", closing, f"{what} (past first touch [m])")
    if c <= 0:
        raise ValueError(f"{what} must be a closing > 0 [m] past first touch, e.g. 1e-3; got {closing!r}")
    return c


def check_press_pad(stiffness, max_edge) -> bool:
    """True if a press's pad ``stiffness`` [Pa/m] (modulus / layer thickness) and refinement length
    ``max_edge`` [m] are plausible (:mod:`workbench.plausible`: 200 for 2e8 Pa/m, or 1.0 for 1e-3 m,
    is refused), else ValueError."""
    check("winkler_stiffness", stiffness, "stiffness (the pad's Winkler modulus [Pa/m])")
    check("element_size", max_edge, "max_edge (the refinement length [m])")
    return True


@dataclass(frozen=True)
class WinklerPress:
    """How :func:`reach_profile`'s Winkler pad presses and where it looks for the surface.

    closing : how far the jaw closes past first touch [m] (:func:`check_press_closing`).
    stiffness : the pad's Winkler modulus [Pa/m], its confined modulus over its layer thickness
        (default 1 MPa / 5 mm); the pressure is ``stiffness · compression``.
    max_edge : the object's faces are refined to sub-triangles of edges <= ``max_edge`` [m]
        (:func:`check_press_pad` checks both).
    window : ``(lo, hi)`` [m] or None — the range along the approach, relative to the jaw's
        ``center``, searched for surface: faces reaching into it, and of those the sub-triangles
        whose centre lies in it (a jaw open at ``center`` with ``stroke`` of travel:
        ``(0, stroke)``).  None: faces reaching into ``±depth_window``, with no sub-triangle filter.
    depth_window : the half-range [m] searched when ``window`` is None.

    Checked when made, with the messages these had as keywords of :func:`reach_profile`.
    """

    closing: float = 1e-3
    stiffness: float = 1.0e6 / 0.005
    max_edge: float = 1e-3
    window: tuple[float, float] | None = None
    depth_window: float = 0.01

    def __post_init__(self) -> None:
        _check_window(self.window, self.depth_window)
        if not (check_press_closing(self.closing) > 0 and check_press_pad(self.stiffness, self.max_edge)):
            raise ValueError(
                "closing, stiffness and max_edge must be > 0; got "
                f"{self.closing!r}, {self.stiffness!r}, {self.max_edge!r}"
            )


def reach_profile(
    mesh,
    center,
    approach,
    up=(0.0, 0.0, 1.0),
    *,
    pad: tuple[float, float] = (0.02, 0.04),
    outline=None,
    press: WinklerPress | None = None,
    allow_scale: bool = False,
) -> ContactProfile:
    """A *profile source*: the REACH-style contact profile (pad ∩ mesh, Winkler pressure)
    of a jaw approaching ``center`` (on or near the object) along
    ``approach`` (into the object), pad ``(width, length)`` [m], pressed as ``press`` says
    (a :class:`WinklerPress`; None: its defaults): closing ``press.closing`` [m] past first
    touch, pressure ``press.stiffness · compression`` [Pa/m], searched within ``press.window``.

    outline : (k, 2) [m] or None — the pad's footprint as a polygon in the jaw frame's
        ``(e1, e2)`` coordinates about ``center`` (:func:`~.jaws.jaw_frame`: e2 the part of
        ``up`` ⟂ approach, e1 = e2 × approach; :attr:`~.gripper.Jaw.outline`), in place of the
        centred ``pad`` rectangle (then ignored).

    ``mesh`` is a watertight trimesh in metres, as ``center`` and every other length; a mesh in
    another unit is converted first: ``workbench.units.mesh_in_metres(mesh, "object", units="mm")``.

    Raises ``ValueError`` for a zero or non-finite ``approach`` or ``up`` (before anything is
    divided by its length), an ``up`` parallel to ``approach``, a non-watertight mesh, when the
    pad touches nothing, or for a mesh spanning more than ``TOL.max_object_extent_m`` or less than
    ``TOL.min_object_extent_m`` (a likely unit mistake; ``allow_scale=True`` accepts it).
    """
    from ..units import MESH_UNIT_FIX, closed_mesh

    a = _check_direction(
        approach, "approach", "the jaw's closing direction, into the object, e.g. (0, 0, -1)"
    )
    u = _check_direction(up, "up", "the pad's length direction, not parallel to approach, e.g. (0, 0, 1)")
    c = np.asarray(center, float) if np.ndim(center) == 1 else np.full(3, np.nan)
    if c.shape != (3,) or not np.isfinite(c).all():
        raise ValueError(f"center must be a finite (3,) point [m], where the jaw approaches; got {center!r}")
    poly = None if outline is None else as_polygon(outline, "outline (the pad in jaw coordinates e1, e2)")
    if poly is None:
        check_pad(pad)
    checked = _checked_press(pad, poly, press)
    mesh = closed_mesh(mesh, "mesh passed to reach_profile", allow_scale=allow_scale, fix=MESH_UNIT_FIX)
    _check_across(a, u, approach, up)
    frame = jaw_frame(approach, up)
    return _profile(mesh, c, frame, checked, _fine_surface(mesh, checked.max_edge, build=False))


def _checked_press(pad, poly, press: WinklerPress | None) -> _Press:
    """The :class:`_Press` of ``press`` (None: a :class:`WinklerPress` of defaults; else checked
    to be one) with the footprint ``pad`` (``poly`` None) or ``poly``, both checked already."""
    press = checked_group(press, WinklerPress, "press")
    win = _check_window(press.window, press.depth_window)
    return _Press(pad, poly, win, press.window is not None, press.closing, press.stiffness, press.max_edge)


def _profile(mesh, center, frame, press: _Press, fine) -> ContactProfile:
    """:func:`_reach`'s profile on checked input, or ValueError saying why the pad touches nothing."""
    out = _reach(mesh, center, frame, press, fine)
    if isinstance(out, str):
        raise ValueError(out)
    return out


def _check_across(a: np.ndarray, u: np.ndarray, approach, up) -> None:
    """ValueError unless the unit ``up`` ``u`` (3,) crosses the unit ``approach`` ``a`` (3,)
    (``approach`` and ``up`` as the caller gave them, for the message); an
    :class:`~workbench.plausible.ImplausibleWarning` when it is within
    ``config.TOL.jaw_up_warn_deg`` (read now) of it."""
    sine = float(np.linalg.norm(np.cross(a, u)))
    across = tuple(int(k == np.argmin(np.abs(a))) for k in range(3))  # the axis least along a
    if sine < 1e-9:
        raise ValueError(
            f"up must not be parallel to the approach direction (it sets the pad's length axis e2, the "
            f"part of up normal to approach); got up {np.asarray(up, float).tolist()} and approach "
            f"{np.asarray(approach, float).tolist()} — pass an up across the approach, e.g. {across}"
        )
    limit = config.TOL.jaw_up_warn_deg
    if sine < np.sin(np.radians(limit)):
        import warnings

        from ..plausible import ImplausibleWarning

        warnings.warn(
            f"up {np.asarray(up, float).tolist()} is {np.degrees(np.arcsin(sine)):.3g} deg from the approach "
            f"{np.round(np.asarray(approach, float), 6).tolist()} (config.TOL.jaw_up_warn_deg = {limit:g}): "
            "the pad's length axis is up's small part across the approach, so a slight change of either "
            f"turns the pad far — pass an up across the approach, e.g. {across}",
            ImplausibleWarning,
            stacklevel=3,
        )


def pad_profile(
    mesh,
    jaw: Jaw,
    *,
    closing: float | None = None,
    force: float | None = None,
    stiffness: float | None = None,
    max_edge: float = 1e-3,
):
    """The REACH profile (:func:`reach_profile`) of a gripper's jaw (:meth:`~.gripper.Gripper.jaws`)
    closing on ``mesh`` [m] from its open tooltip: the pad polygon ``jaw.outline`` at ``jaw.origin``
    moves along ``jaw.closing`` to the first surface within its ``jaw.stroke``, then on by
    ``closing`` [m], or until its normal force along ``jaw.closing`` is ``force`` [N] (give one of
    the two); pressure ``stiffness`` [Pa/m] (default ``jaw.stiffness``) times the compression.

    Returns a :class:`ContactProfile`, or None when the pad touches nothing within its stroke (a
    physical miss, logged at DEBUG).  Raises ValueError for bad input (a mesh that is not
    watertight or not in metres, closing, stiffness or max_edge not > 0, a force no jaw has,
    both or neither of closing and force).
    """
    if (closing is None) == (force is None):
        raise ValueError(
            f"give one of closing (the press past first touch [m]) and force (the jaw's force [N]); "
            f"got closing={closing!r}, force={force!r}"
        )
    if closing is not None:
        check_press_closing(closing)
    else:
        force = check_jaw_force(force)
    patch = pad_patch(mesh, jaw, stiffness=stiffness, max_edge=max_edge)
    if patch is None:
        return None
    return patch.profile(closing if force is None else patch.depth_for_force(force))


def pad_patch(mesh, jaw: Jaw, *, stiffness: float | None = None, max_edge: float = 1e-3) -> PadPatch | None:
    """The surface ``jaw``'s pad can reach on ``mesh`` [m] (:class:`~.pad_patch.PadPatch`; the
    geometry of :func:`pad_profile`, pressed by the caller to a depth or a force), or None when it
    touches nothing within its stroke (logged at DEBUG).  ``stiffness`` [Pa/m] defaults to
    ``jaw.stiffness``; ``mesh`` is subdivided to ``max_edge`` [m] once and cached."""
    if not isinstance(jaw, Jaw):
        raise ValueError(f"jaw must be a Jaw (Gripper.jaws(pose)); got {type(jaw).__name__}")
    k = jaw.stiffness if stiffness is None else stiffness
    if not (check_press_pad(k, max_edge) and k > 0 and max_edge > 0):
        raise ValueError(f"stiffness and max_edge must be > 0; got {k!r}, {max_edge!r}")
    fine = _fine_surface(mesh, float(max_edge))
    # the object slides along the closing axis ahead of a jaw whose open tooltip already reaches
    # past its surface (the other jaw closes too): the search starts a stroke behind the tooltip
    # (approach collisions are not modelled)
    lo, hi = -jaw.stroke, jaw.stroke
    frame = (jaw.closing, jaw.e1, jaw.e2)
    (u_lo, v_lo), (u_hi, v_hi) = jaw.outline.min(axis=0), jaw.outline.max(axis=0)
    box = (u_lo - max_edge, u_hi + max_edge, v_lo - max_edge, v_hi + max_edge, lo, hi)
    cand = fine[4].within(jaw.origin, frame, box)
    # every element _patch keeps lies inside the outline (so inside box) and within the stroke
    out = _patch(
        fine[0],
        fine[1],
        fine[2],
        jaw.origin,
        frame,
        _Press(None, jaw.outline, (lo, hi), True, 0.0, k, max_edge),
        cand,
    )
    if isinstance(out, str):
        rel = fine[0][cand] - jaw.origin
        u, v, z = rel @ jaw.e1, rel @ jaw.e2, rel @ jaw.closing
        near = (u >= box[0]) & (u <= box[1]) & (v >= box[2]) & (v <= box[3]) & (z >= lo) & (z <= hi)
        why = "the pad outline covers no part of the object within its stroke" if not near.any() else out
        log.debug("pad_patch: a miss: %s", why)
        return None
    return out


#: the fine surfaces of the last meshes pressed by pad_profile, or made by fine_surface for many
#: reach_profile presses, by content hash (a pose-robustness run or an antipodal sampler presses
#: one mesh hundreds of times; the subdivision does not depend on the pose)
_FINE: dict[str, tuple] = {}
_FINE_KEEP = 4


def fine_surface(mesh, max_edge: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The whole mesh subdivided to ``max_edge`` (centres, normals, areas; read-only), cached by a
    hash of its vertices, faces and ``max_edge``; the mesh is checked once (watertight, metres).

    While it is cached, :func:`reach_profile` with this ``max_edge`` takes its sub-triangles
    from it instead of subdividing the faces near the pad again (the same profile, faster when
    one mesh is pressed many times: call this first)."""
    return _fine_surface(mesh, max_edge)[:3]


def _fine_surface(mesh, max_edge: float, build: bool = True):
    """:func:`fine_surface`, the index (m,) of each sub-triangle's face in ``mesh.faces``, a
    :class:`~.surface_index.SurfaceIndex` of the centres (cells of
    ``config.DEFAULTS.surface_index_cells`` × ``max_edge``) and each face's first sub-triangle
    (F + 1,); None when it is not cached and ``build`` is False."""
    import xxhash

    from ..units import closed_mesh

    v = np.ascontiguousarray(getattr(mesh, "vertices", np.empty((0, 3))), dtype=float)
    f = np.ascontiguousarray(getattr(mesh, "faces", np.empty((0, 3))), dtype=np.int64)
    h = xxhash.xxh3_128()
    for part in (v, f, np.float64(max_edge)):
        h.update(part.tobytes())
    key = h.hexdigest()
    if key not in _FINE:
        if not build:
            return None
        mesh = closed_mesh(mesh, "mesh passed to pad_profile")
        arrays = _fine_faces(np.asarray(mesh.vertices, float), np.asarray(mesh.faces), max_edge)
        for arr in arrays:
            arr.flags.writeable = False
        # each face's run of sub-triangles (they are in face order): a face's are starts[f]:starts[f + 1]
        starts = np.searchsorted(arrays[3], np.arange(len(mesh.faces) + 1)).astype(np.int64)
        starts.flags.writeable = False
        index = SurfaceIndex.build(arrays[0], config.DEFAULTS.surface_index_cells * max_edge)
        arrays = (*arrays, index, starts)
        while len(_FINE) >= _FINE_KEEP:
            _FINE.pop(next(iter(_FINE)))
        _FINE[key] = arrays
    return _FINE[key]


def _check_window(window, depth_window) -> tuple[float, float]:
    """The (lo, hi) [m] searched along the approach: ``window``, or ``±depth_window`` when it is
    None; each judged as a gripper's travel (:mod:`workbench.plausible` ``"opening"``: a 20 m
    window is a millimetre slip), else ValueError naming the field."""
    if window is None:
        d = check("opening", depth_window, "WinklerPress.depth_window (half-range searched [m])", warn=False)
        return -d, d
    try:
        lo, hi = (float(w) for w in window)
    except (TypeError, ValueError):
        raise ValueError(
            f"WinklerPress.window must be (lo, hi) [m] along the approach; got {window!r}"
        ) from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
        raise ValueError(
            f"WinklerPress.window must be (lo, hi) [m], finite with lo < hi, e.g. (0, stroke); got {window!r}"
        )
    for name, v in (("lo", lo), ("hi", hi), ("hi - lo", hi - lo)):
        if v != 0:
            check("opening", abs(v), f"WinklerPress.window {window!r}: |{name}| [m]", warn=False)
    return lo, hi


class _Press(NamedTuple):
    """A checked press of the Winkler pad (:func:`_reach`, :func:`_press`).

    The footprint is the ``pad`` rectangle (``poly`` None) or the polygon ``poly`` (k, 2) in
    (e1, e2); ``window`` the (lo, hi) [m] searched along the approach; ``filter_window`` also
    drops sub-triangles whose centre is outside it; the pad closes ``closing`` [m] past first
    touch with pressure ``stiffness`` [Pa/m] times the compression, on sub-triangles of edges
    <= ``max_edge`` [m].
    """

    pad: tuple[float, float] | None
    poly: np.ndarray | None
    window: tuple[float, float]
    filter_window: bool
    closing: float
    stiffness: float
    max_edge: float


def _reach(mesh, c, frame, press: _Press, fine):
    """The profile of :func:`reach_profile` on checked input: the jaw at ``c`` (3,) [m] with
    ``frame`` (a, e1, e2) (:func:`~.jaws.jaw_frame`), the pad ``press``, and the mesh's cached
    :func:`_fine_surface` ``fine`` (None: the faces near the pad are refined here); or why the
    pad touches nothing (str)."""
    pad, poly, window, max_edge = press.pad, press.poly, press.window, press.max_edge
    a, e1, e2 = frame
    if poly is None:
        (u_lo, v_lo), (u_hi, v_hi) = (-pad[0] / 2, -pad[1] / 2), (pad[0] / 2, pad[1] / 2)
    else:
        (u_lo, v_lo), (u_hi, v_hi) = poly.min(axis=0), poly.max(axis=0)
    lo, hi = window
    V, F = np.asarray(mesh.vertices, float), np.asarray(mesh.faces, np.int64)
    # faces whose bounding box (in the jaw frame) overlaps the footprint's and the depth
    # window: a large face can cover the pad with no vertex inside it (a box's side, a
    # coarse cylinder), so vertices alone would miss it.  The compiled pass keeps a superset
    # and marks the faces inside by more than its margin (far more than round-off), which pass
    # the exact test below; that test judges the rest
    m2 = 2 * max_edge
    box = np.array([u_lo - m2, u_hi + m2, v_lo - m2, v_hi + m2, lo, hi])
    cand, sure = _faces_may_overlap(V, F, c, np.array([a, e1, e2]), box, config.TOL.prefilter_margin_m)
    near = sure.copy()
    edge = np.flatnonzero(~sure)
    if len(edge):
        rel = V[F[cand[edge]].ravel()] - c
        fu, fv, fz = ((rel @ e).reshape(-1, 3) for e in (e1, e2, a))  # (k, 3) each
        ok = (fu.min(1) <= box[1]) & (fu.max(1) >= box[0])
        ok &= (fv.min(1) <= box[3]) & (fv.max(1) >= box[2])
        ok &= (fz.min(1) <= hi) & (fz.max(1) >= lo)
        near[edge] = ok
    near_faces = cand[near]
    what = f"the pad footprint {pad} m" if poly is None else "the pad outline"
    if len(near_faces) == 0:
        from ..units import far_from_object

        far = far_from_object(c, mesh.bounds)
        return (
            f"{what} around {np.round(c, 4).tolist()} covers no part of the object "
            f"within [{lo:.4g}, {hi:.4g}] m along the approach {np.round(a, 3).tolist()}: "
            + ("check center, approach (into the object) and units" if far is None else f"center {far}")
        )
    if fine is None:
        cen, normal, area, _ = _fine_faces(V, F[near_faces], max_edge)
        rows = None
    else:
        # the near faces' sub-triangles from the cached whole-mesh subdivision: the same triangles
        # in the same order as refining the near faces alone (_fine_faces cuts each face on its
        # own, in face order), so the profile is the same
        cen, normal, area = fine[0], fine[1], fine[2]
        rows = concat_runs(fine[5][near_faces], fine[5][near_faces + 1])
    return _press(cen, normal, area, c, (a, e1, e2), press, rows)


def _fine_faces(vertices: np.ndarray, faces: np.ndarray, max_edge: float):
    """Centres (m, 3), unit normals (m, 3) and areas (m,) of ``faces`` cut into sub-triangles
    with no edge longer than ``max_edge`` (:func:`_cut_to_size`), and the index (m,) of each
    sub-triangle's face in ``faces`` (non-decreasing).

    A sub-triangle has its face's normal and its exact share of the face's area (closed form),
    so the areas of a face's sub-triangles sum to the face's to round-off.  A face's
    sub-triangles depend on that face alone, in a fixed order: refining a subset of the faces
    gives the subset's rows of refining them all (the cache of :func:`_fine_surface`).
    """
    tri0 = np.asarray(vertices, float)[np.asarray(faces, dtype=np.int64).reshape(-1, 3)]
    cross = np.cross(tri0[:, 1] - tri0[:, 0], tri0[:, 2] - tri0[:, 0])
    face_area = 0.5 * np.linalg.norm(cross, axis=1)
    face_normal = cross / np.maximum(2 * face_area, 1e-300)[:, None]
    tri, parent, share = _cut_to_size(tri0, max_edge)
    return tri.mean(axis=1), face_normal[parent], face_area[parent] * share, parent


def _cut_to_size(tri: np.ndarray, max_edge: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Triangles ``tri`` (k, 3, 3) cut into sub-triangles whose edges are all ``<= max_edge``:
    ``(sub (m, 3, 3), parent (m,), share (m,))`` — ``parent`` the row of ``tri`` each lies in
    (non-decreasing), ``share`` its exact fraction of the parent's area; each keeps the parent's
    orientation.  A triangle with no edge over ``max_edge`` is returned as it is.

    Each triangle ``(A, B, C)``, ``BC`` its shortest edge (length ``w``, the longest ``ell``),
    is cut one of two ways, whichever gives fewer pieces:

    * *similar*: ``k >= ell / max_edge`` equal parts along every edge, ``k²`` triangles
      similar to it (a well-shaped triangle);
    * *strips* (a sliver, ``w`` well below ``ell``): lines parallel to ``BC`` cut it into ``n``
      strips of equal height, strip ``i`` of ``n`` into ``ceil((i+1) q / n)`` equal trapezoids
      (``q`` in the last) and each trapezoid along its shorter diagonal into two triangles.  A
      trapezoid's legs are ``<= ell / n`` and its parallel sides ``<= w / q``, so its shorter
      diagonal is ``<= sqrt(leg² + side²)``: ``n >= ell / sqrt(max_edge² - (w/q)²)``.  A
      sliver narrower than ``max_edge`` is cut across only (``q = 1``).

    ``k`` and ``n`` are multiples of 3 (``k = 1`` for a triangle that fits): the centres of a cut
    triangle's pieces then lie at ``(3i+1)/(3k)`` or ``(3i+2)/(3k)`` of the way across it (the
    strip cut: from ``A`` to ``BC``), never at a fraction ``p/r`` with ``r`` not a multiple of 9 —
    1/2, 1/3, 1/4, 2/5 …  A pad edge at such a round place (a 10 mm pad centred on a 30 mm face)
    would otherwise pass through pieces' centres and leave round-off to decide, unevenly, which
    side they are on (the pad's area and centre off by a row of pieces).

    An 80 mm × 0.6 mm cylinder side at 1 mm becomes ~200 triangles (102 strips ~0.8 mm long),
    where halving every edge until the longest fits (``trimesh.remesh.subdivide_to_size``) made
    4**7 pieces 4.7 µm across, as the similar cut or longest-edge bisection (it keeps a
    sliver's shape) would.  The pieces do not conform across faces (hanging vertices), which
    nothing here needs: only centres, normals, areas and parents are used.
    """
    tri = np.asarray(tri, float)
    # a budget shrunk by 1e-9 so that round-off cannot push an edge past max_edge
    h = float(max_edge) * (1.0 - 1e-9)
    edge = np.linalg.norm(tri[:, [1, 2, 0]] - tri, axis=2)  # edge j from vertex j to j+1
    rows = np.arange(len(tri))
    jw = edge.argmin(axis=1)
    A, B, C = tri[rows, (jw + 2) % 3], tri[rows, jw], tri[rows, (jw + 1) % 3]  # a cyclic shift
    w, ell = edge[rows, jw], edge.max(axis=1)
    # parts along the edges: multiples of 3 (the docstring says why)
    k = np.where(ell <= h, 1, 3 * np.ceil(ell / (3 * h)))
    # strips: q from a few candidates — the fewest with w/q < h, one more, about w/q = h/√2 —
    # by the pieces they give, ~ q (n + 1) + n - 1
    q0 = np.floor(w / h) + 1
    qb = np.maximum(q0, np.ceil(np.sqrt(2) * w / h))
    qs = np.stack([q0, q0 + 1, qb, qb + 1])
    ns = 3 * np.ceil(ell / (3 * h * np.sqrt(1.0 - (w / (qs * h)) ** 2)))
    cost = qs * (ns + 1) + ns - 1
    pick = cost.argmin(axis=0)
    strips = cost[pick, rows] < k * k
    pieces = float(np.where(strips, cost[pick, rows], k * k).sum())
    _check_pieces(pieces, len(tri), float(edge.max()) if len(tri) else 0.0, max_edge)
    whole, u, s = np.flatnonzero(k == 1), np.flatnonzero((k > 1) & ~strips), np.flatnonzero(strips)
    n, q = ns[pick, rows][s].astype(np.int64), qs[pick, rows][s].astype(np.int64)
    parts = [
        (tri[whole], np.arange(len(whole)), np.ones(len(whole))),  # as they are, vertices and all
        _similar_cut(A[u], B[u], C[u], k[u].astype(np.int64)),
        _strip_cut(A[s], B[s], C[s], n, q),
    ]
    sub = np.concatenate([p[0] for p in parts])
    parent = np.concatenate([idx[p[1]] for idx, p in zip((whole, u, s), parts, strict=True)])
    share = np.concatenate([p[2] for p in parts])
    order = np.argsort(parent, kind="stable")
    return sub[order], parent[order], share[order]


def _check_pieces(pieces: float, n: int, longest: float, max_edge: float) -> None:
    """ValueError when cutting ``n`` triangles (longest edge ``longest`` [m]) to edges <=
    ``max_edge`` [m] would make ``pieces`` sub-triangles, more than ``config.TOL.max_sub_triangles``
    (read now): a mesh far larger than an object, most likely in millimetres taken for metres."""
    limit = config.TOL.max_sub_triangles
    if pieces > limit:
        raise ValueError(
            f"cutting {n} faces (the longest edge {longest:.4g} m) into sub-triangles of edges <= "
            f"{max_edge:g} m would make ~{pieces:.3g} of them, more than config.TOL.max_sub_triangles = "
            f"{limit:.3g} (~{pieces * 200 / 1e9:.3g} GB while they are made): a mesh in millimetres taken "
            "for metres? pass units='mm' (or mesh.apply_scale(1e-3)); or press with a larger max_edge"
        )


def _strip_rows(n: np.ndarray, per_strip) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For triangles cut into ``n`` (t,) strips each: ``(triangle, strip i, piece j, count)`` per
    piece, strip ``i`` of a triangle holding ``count = per_strip(i, triangle)`` pieces."""
    f = np.repeat(np.arange(len(n)), n)
    i = np.arange(len(f)) - np.repeat(np.cumsum(n) - n, n)
    count = per_strip(i, f)
    piece = np.repeat(np.arange(len(f)), count)
    j = np.arange(len(piece)) - np.repeat(np.cumsum(count) - count, count)
    return f[piece], i[piece], j, count[piece]


def _similar_cut(A, B, C, k):
    """``k²`` similar triangles of each ``(A, B, C)`` (t, 3): strip ``i`` of ``k`` holds
    ``2i + 1``, alternately pointing away from and towards ``A``; lattice point
    ``P(i, j) = A + (i/k)(B - A) + (j/k)(C - B)``."""
    f, i, r, _ = _strip_rows(k, lambda i, f: 2 * i + 1)
    j, down = r // 2, (r % 2 == 1)[:, None]
    kf = k[f][:, None]
    a, ab, bc = A[f], (B - A)[f], (C - B)[f]

    def P(ii, jj):
        return a + (ii[:, None] / kf) * ab + (jj[:, None] / kf) * bc

    p_ij, p_i1j1 = P(i, j), P(i + 1, j + 1)
    # away from A: (P(i,j), P(i+1,j), P(i+1,j+1)); towards A: (P(i,j), P(i+1,j+1), P(i,j+1))
    sub = np.stack([p_ij, np.where(down, p_i1j1, P(i + 1, j)), np.where(down, P(i, j + 1), p_i1j1)], axis=1)
    return sub, f, 1.0 / (k[f].astype(float) ** 2)


def _strip_cut(A, B, C, n, q):
    """Each ``(A, B, C)`` (t, 3) cut into ``n`` strips parallel to ``BC`` of ``ceil((i+1) q / n)``
    trapezoids each, every trapezoid into two triangles along its shorter diagonal (the first
    strip's are triangles already); ``X(t, s) = A + t (B - A) + t s (C - B)``."""
    f, i, j, m = _strip_rows(n, lambda i, f: -(-(i + 1) * q[f] // n[f]))
    nf = n[f]
    t0, t1 = (i / nf)[:, None], ((i + 1) / nf)[:, None]
    s0, s1 = (j / m)[:, None], ((j + 1) / m)[:, None]
    a, ab, bc = A[f], (B - A)[f], (C - B)[f]
    p00, p01 = a + t0 * (ab + s0 * bc), a + t0 * (ab + s1 * bc)
    p10, p11 = a + t1 * (ab + s0 * bc), a + t1 * (ab + s1 * bc)
    short = (np.linalg.norm(p11 - p00, axis=1) <= np.linalg.norm(p10 - p01, axis=1))[:, None, None]
    # the triangle with its base on the side away from A, then the one with its base on the
    # side towards A (empty in the first strip, whose side towards A is A); both turn like
    # (A, B, C), and their areas are t1 and t0 parts of the trapezoid's (t1² - t0²)
    outer = np.where(short, np.stack([p00, p10, p11], axis=1), np.stack([p01, p10, p11], axis=1))
    inner = np.where(short, np.stack([p00, p11, p01], axis=1), np.stack([p00, p10, p01], axis=1))
    dt_ds = 1.0 / (nf * m)
    sub = np.stack([outer, inner], axis=1).reshape(-1, 3, 3)
    share = np.column_stack([dt_ds * t1[:, 0], dt_ds * t0[:, 0]]).ravel()
    keep = np.column_stack([np.ones(len(i), dtype=bool), i > 0]).ravel()
    return sub[keep], np.repeat(f, 2)[keep], share[keep]


def _press(cen, normal, area, c, frame, press: _Press, rows: np.ndarray | None = None):
    """The Winkler pad ``press`` pressed on the fine faces (``cen``, ``normal``, ``area``; their
    ``rows`` only, :func:`_patch`) from ``c`` (3,) along ``frame[0]`` to ``press.closing`` past
    first touch: the rest of :func:`_reach`; or why it touches nothing (str).

    ``PadPatch(...).profile(press.closing)`` of :func:`_patch`'s patch, its elements taken once."""
    seen = _visible(cen, normal, area, c, frame, press, rows)
    if isinstance(seen, str):
        return seen
    cen, normal, area, z, vis, z0 = seen
    return pressed_profile(cen, normal, area, z, z0, press.stiffness, press.closing, among=vis)


def _patch(cen, normal, area, c, frame, press: _Press, rows: np.ndarray | None = None) -> PadPatch | str:
    """The :class:`~.pad_patch.PadPatch` the pad ``press`` reaches on the fine faces (``cen``,
    ``normal``, ``area``; of those the ascending indices ``rows`` (m,) only, None: all) from
    ``c`` (3,) along ``frame[0]`` — the front-most surface facing it inside its footprint — or
    why there is none (str)."""
    seen = _visible(cen, normal, area, c, frame, press, rows)
    if isinstance(seen, str):
        return seen
    cen, normal, area, z, vis, z0 = seen
    return PadPatch(cen[vis], normal[vis], area[vis], z[vis], z0, frame[0], press.stiffness)


def _visible(cen, normal, area, c, frame, press: _Press, rows: np.ndarray | None):
    """What :func:`_patch` reaches: ``(cen, normal, area, z, vis, z0)`` — the candidate elements'
    arrays (k, 3), (k, 3), (k,), their distance ``z`` (k,) [m] along ``frame[0]`` from ``c``, the
    ascending indices ``vis`` into them of the front-most surface facing the pad inside its
    footprint, and its first touch ``z0`` [m] (the least ``z[vis]``) — or why there is none (str)."""
    pad, poly, window, filter_window, _, _, max_edge = press
    a, e1, e2 = frame
    if poly is None:
        (u_lo, v_lo), (u_hi, v_hi) = (-pad[0] / 2, -pad[1] / 2), (pad[0] / 2, pad[1] / 2)
    else:
        (u_lo, v_lo), (u_hi, v_hi) = poly.min(axis=0), poly.max(axis=0)
    lo, hi = window
    what = f"the pad footprint {pad} m" if poly is None else "the pad outline"
    # faces (nearly) parallel to the approach have no area under the pad: a Winkler
    # foundation along the approach puts no pressure on them (a box's side walls)
    min_facing = config.DEFAULTS.reach_min_facing
    # the compiled pass keeps a superset of the elements the exact tests below keep, which then
    # run on it alone
    box = np.array([u_lo, u_hi, v_lo, v_hi, *((lo, hi) if filter_window else (-np.inf, np.inf))])
    rows = np.arange(len(cen), dtype=np.int64) if rows is None else np.asarray(rows, np.int64)
    pre = _elements_may_touch(
        cen, normal, area, rows, c, np.array([a, e1, e2]), box, -min_facing, config.TOL.prefilter_margin_m
    )
    # take: the rows' copies, as indexing gives them, without its per-call cost on (m, 3)
    cen, normal, area = cen.take(pre, axis=0), normal.take(pre, axis=0), area.take(pre)
    rel = _rows_minus(cen, np.asarray(c, float))  # cen - c, in one pass
    u, v, z = rel @ e1, rel @ e2, rel @ a
    facing = normal @ a < -min_facing
    if poly is None:
        inside = (np.abs(u) <= pad[0] / 2) & (np.abs(v) <= pad[1] / 2)
    else:
        inside = points_in_polygon(np.column_stack([u, v]), poly)
    keep = inside & facing & (area > 0)
    if filter_window:
        keep &= (z >= lo) & (z <= hi)
    if not keep.any():
        return (
            f"no object surface faces the jaw inside {what} (approach {np.round(a, 3).tolist()} "
            "must point into the object, from the jaw towards the surface)"
        )
    idx = np.flatnonzero(keep)
    # front-most surface per footprint bin (the pad cannot reach behind the first surface);
    # the bins tile the footprint's bounding box
    visible = _front_most(u, v, z, idx, u_lo, v_lo, max_edge, int((v_hi - v_lo) / max_edge) + 2, 2 * max_edge)
    vis = np.flatnonzero(visible)
    return cen, normal, area, z, vis, float(z[vis].min())  # z0: the first touch


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
    pull the object.

    Many grasps of one mesh: call :func:`fine_surface` ``(mesh, 1e-3)`` once first — each press
    then reads the cached refinement instead of refining the faces under its pad again (the same
    profiles; refining a large face, a box's side, costs far more than pressing it)."""
    from ..units import closed_mesh

    p1, p2, axis = check_grasp(grasp)
    check_jaw_force(force)
    check_pad(pad)
    mesh = closed_mesh(mesh, "mesh passed to reach_profile", units=units, allow_scale=allow_scale)
    checked = _checked_press(pad, None, WinklerPress(closing=closing))
    u = _check_direction(up, "up", "the pad's length direction, not parallel to approach, e.g. (0, 0, 1)")
    _check_across(axis, u, axis, up)
    # what reach_profile and checked_jaw_profile would check again for each jaw is checked once
    # above (the grasp's points are finite, its axis a unit vector), and the mesh looked up once
    fine = _fine_surface(mesh, checked.max_edge, build=False)
    a, e1, e2 = jaw_frame(axis, up)
    # jaw 2's frame, jaw_frame(-axis, up), is jaw 1's with the approach and e1 negated: negation
    # is exact in every product and sum of jaw_frame, so these are its very numbers
    return [
        placed_jaw_profile(_profile(mesh, point, frame, checked, fine), point, approach, force, pad)
        for point, approach, frame in ((p1, axis, (a, e1, e2)), (p2, -axis, (-a, -e1, e2)))
    ]

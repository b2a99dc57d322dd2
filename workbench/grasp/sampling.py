"""Antipodal grasp sampling on triangle meshes (Dex-Net style; thesis §4.1.4.2, §4.3.3.3).

Sample a surface point ``p1`` with outward normal ``n1``; draw a grasp axis
inside the friction cone around ``−n1`` (half-angle ``atan μ``); cast a ray from
``p1`` along the axis and take the last point where it leaves the object,
``p2`` — the outer surface on the far side, so a thin-walled (hollow) object is
grasped across, not through its 0.4 mm wall; keep the grasp if ``n2`` is also
within the friction cone of the axis (antipodal), the jaw opening ``|p2 − p1|``
fits, both contacts clear the table by ``clearance`` and neither flat jaw first meets
the surface at its pad edge.  Seeded; returns as many grasps as found (up to ``n``)
as :class:`Grasps`, a list that also counts the candidates dropped per reason
(:data:`DROP_REASONS`).

Both samplers show a progress bar (tqdm, on stderr) when asked to (``progress=True``) or,
by default, when stderr is a terminal and the call has run a few seconds: the pad-edge
check presses each surviving candidate's two jaws (:func:`edge_touch`).
"""

from __future__ import annotations

import logging
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from .inputs import Jaws

log = logging.getLogger(__name__)

#: why a candidate is not kept, in the order the samplers test it: reason -> (what happened,
#: what usually gets more grasps).  Every reason is a key of :attr:`Grasps.dropped`.
DROP_REASONS: dict[str, tuple[str, str]] = {
    "no_far_side": (
        "the line along the axis finds no far side to grasp",
        "check that the mesh is closed and its normals point outward",
    ),
    "too_narrow": ("the object is narrower across the grasp than min_width", "a smaller min_width"),
    "too_wide": (
        "the object is wider across the grasp than max_width",
        "a larger max_width if the gripper opens that far",
    ),
    "outside_cone": (
        "a contact normal lies outside the friction cone of the axis",
        "more candidates (max_samples), or a larger mu only if the materials' friction allows it",
    ),
    "near_table": ("a contact is within clearance of the table", "a smaller clearance or a lower table_z"),
    "pad_edge": (
        "a flat jaw first meets the surface at its pad edge (edge_touch)",
        "a smaller Jaws(pad=(width, length)), a larger GraspSampling(edge_depth=...), or jaws=None to "
        "keep every antipodal pair",
    ),
}

# the pad-edge check's fine surface [m]: the mesh refined to 1 mm under the pad (edge_touch);
# the samplers have the whole mesh subdivided to it once, for all their presses
_EDGE_MAX_EDGE = 1e-3

#: the jaws :func:`antipodal_grasps` checks for pad-edge contact unless told: ``Jaws()``, a
#: 20 × 40 mm pad with its length axis along +z
_JAWS = Jaws()


class Grasps(list):
    """The grasps a sampler returns: a plain ``list`` of grasp dicts — iterate, index and
    ``len`` it as before — that also says what became of the candidates it tried.

    dropped : dict[str, int]
        Candidates not kept, per reason: every key of :data:`DROP_REASONS`, zeros included.
    n_candidates : int
        Candidates tried, ``len(self) + sum(self.dropped.values())``; a sampler that stops at
        ``n`` grasps may try fewer than it drew.

    The list is an ordinary mutable list; ``dropped`` and ``n_candidates`` describe the call
    that made it and do not follow later changes to the list (a slice, ``list(grasps)`` or
    ``grasps + other`` is a plain list).
    """

    def __init__(self, grasps=(), *, dropped: dict[str, int] | None = None) -> None:
        super().__init__(grasps)
        self.dropped: dict[str, int] = dict.fromkeys(DROP_REASONS, 0)
        for reason, count in (dropped or {}).items():
            if reason not in DROP_REASONS:
                raise ValueError(
                    f"dropped reasons must be keys of DROP_REASONS {list(DROP_REASONS)}; got {reason!r}"
                )
            self.dropped[reason] = int(count)
        self.n_candidates: int = len(self) + sum(self.dropped.values())

    def summary(self) -> str:
        """One line: kept of tried, and the non-zero drop counts per reason."""
        parts = [f"{c} {r}" for r, c in self.dropped.items() if c]
        return f"{len(self)} kept of {self.n_candidates} candidates" + (
            f"; dropped {', '.join(parts)}" if parts else ""
        )


def _progress_bar(progress: bool | None, total: int, desc: str) -> Any:
    """A tqdm bar of ``total`` candidates on stderr, or None: ``progress`` True shows it,
    False never, None only when stderr is a terminal and after ``config.RUN.progress_delay_s``."""
    if progress is not None and not isinstance(progress, bool):
        raise ValueError(
            f"progress must be True (show a bar), False (never) or None (on a terminal, for long calls); "
            f"got {progress!r}"
        )
    if progress is False or (
        progress is None and not (hasattr(sys.stderr, "isatty") and sys.stderr.isatty())
    ):
        return None
    from tqdm import tqdm

    from .. import config

    delay = config.RUN.progress_delay_s if progress is None else 0.0
    return tqdm(total=total, desc=desc, unit="candidate", file=sys.stderr, delay=delay)


def check_edge_args(pad, edge_depth) -> None:
    """ValueError unless ``pad`` is a jaw face ``(width, length)`` [m] and ``edge_depth`` a
    closing > 0 [m] (the rules of :func:`~workbench.sources.jaws.check_pad` and of a closing,
    :mod:`workbench.plausible`): the pad-edge check would otherwise call every grasp an edge
    touch, as a jaw that touches nothing is one (:func:`edge_touch`)."""
    from ..sources.jaws import check_pad
    from ..sources.reach import check_press_closing

    check_pad(pad)
    check_press_closing(edge_depth, "edge_depth")


def _check_sampler_args(min_width, max_width, clearance=0.0) -> None:
    """ValueError for arguments that would make every candidate fail and blame the geometry:
    widths that are not a gripper's opening (:mod:`workbench.plausible`, e.g. 100 for 0.1 m) or
    out of order, a clearance that is no height above a table."""
    from ..plausible import check

    lo = check("opening", min_width, "min_width (the narrowest jaw opening [m])") if min_width else 0.0
    hi = check("opening", max_width, "max_width (the gripper's opening [m])")
    if not lo < hi:
        raise ValueError(f"min_width must be < max_width; got {min_width!r} >= {max_width!r}")
    check(
        "closing",
        clearance,
        "clearance (the contacts' height above the table [m])",
        warn=False,
        examples="a contact 5-20 mm above the table (Dex-Net's table_offset: 5 mm); 0: on it",
        named="height above the table",
    )


def _check_table(mesh, table_z) -> None:
    """ValueError for a table above the object or far below it (another unit than the mesh?)."""
    if table_z is not None:
        z_lo, z_hi = mesh.bounds[:, 2]
        if not np.isfinite(table_z) or table_z >= z_hi or table_z < z_lo - (z_hi - z_lo):
            raise ValueError(
                f"table_z = {table_z!r} m is above the object's top ({z_hi:.4g} m) or farther below its "
                f"bottom than its height: the table is under the object, usually at its bottom z = "
                f"{z_lo:.4g} m (None: no table; another unit than the mesh?)"
            )


def _check_count(name: str, value) -> None:
    """ValueError unless ``value`` is an integer >= 1 (``name`` names it)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1; got {value!r}")


@dataclass(frozen=True)
class GraspSampling:
    """Which candidates :func:`antipodal_grasps` draws and which it keeps (lengths in metres).

    max_width, min_width : the jaw opening's range [m], each a gripper's opening
        (:mod:`workbench.plausible`; ``min_width`` 0: no lower bound), ``min_width < max_width``.
    table_z : the height [m] of the table under the object, or None (no table); checked against
        the mesh by the sampler (under the object, not farther below it than its height).
    clearance : how far above the table both contacts must lie [m].
    max_samples : the candidates drawn, an integer >= 1 (None: ``20 n``).
    edge_depth : how far past first touch a jaw is pressed by the pad-edge check [m], a
        closing > 0 (:func:`edge_touch`); used when the sampler is given jaws.

    Checked when made: a careless value (a width in millimetres, widths out of order) is
    refused here with the message it had as a keyword of the sampler.
    """

    max_width: float = 0.1
    min_width: float = 0.005
    table_z: float | None = None
    clearance: float = 0.01
    max_samples: int | None = None
    edge_depth: float = 1e-3

    def __post_init__(self) -> None:
        from ..sources.reach import check_press_closing

        _check_count("max_samples", 1 if self.max_samples is None else self.max_samples)
        check_press_closing(self.edge_depth, "edge_depth")
        _check_sampler_args(self.min_width, self.max_width, self.clearance)


class _Cast(NamedTuple):
    """The rays of one sampler call: the mesh, every hit ``locs`` (h, 3) [m] and its triangle
    ``tri_idx`` (h,), the friction cone's half-angle ``half`` [rad] and the pad-edge check
    ``edge`` — ``(pad, up, edge_depth)`` of :func:`edge_touch` — or None (no check)."""

    mesh: Any
    locs: np.ndarray
    tri_idx: np.ndarray
    half: float
    edge: tuple | None


def _subdivide_once(mesh, presses: int, pad) -> None:
    """Cache the whole mesh refined for the pad-edge check (:func:`~workbench.sources.reach.fine_surface`)
    so that each :func:`edge_touch` takes the faces under its pad from it instead of refining
    them again — when that pays: when the mesh's area is at most the ``presses`` expected times
    the pad's (a large finely meshed object pressed a few times keeps refining only the faces
    under each pad).  A mesh the cache refuses (one accepted with ``allow_scale``) is logged."""
    from ..sources.reach import fine_surface

    if mesh.area > presses * pad[0] * pad[1]:
        return
    try:
        fine_surface(mesh, _EDGE_MAX_EDGE)
    except ValueError as exc:
        log.info("pad-edge checks refine the faces under each pad, press by press: %s", exc)


def _edge_pair(mesh, p1, p2, axis, edge: tuple) -> bool:
    """Whether either jaw of the grasp (jaw 1 at ``p1`` along ``axis``, jaw 2 at ``p2`` against
    it) first meets the surface at its pad edge (:func:`edge_touch`; ``edge = (pad, up, edge_depth)``)."""
    pad, up, edge_depth = edge
    return edge_touch(mesh, p1, axis, up, pad, edge_depth) or edge_touch(mesh, p2, -axis, up, pad, edge_depth)


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
    sampling: GraspSampling | None = None,
    *,
    jaws: Jaws | None = _JAWS,
    seed: int | np.random.Generator = 0,
    progress: bool | None = None,
) -> Grasps:
    """Up to ``n`` antipodal grasps ``{p1, p2, n1, n2, axis, center, width}`` [m], as
    :class:`Grasps`: a list of those dicts whose ``dropped`` counts the candidates not kept
    per reason (:data:`DROP_REASONS`) and ``n_candidates`` those tried.

    sampling : a :class:`GraspSampling` (None: its defaults) — the jaw opening's range, the
        table and the contacts' clearance above it, the candidates drawn and the pad-edge
        check's depth.  ``sampling.max_samples`` candidates (default ``20 n``) are drawn and
        tried in turn until ``n`` grasps are kept; fewer than ``n`` logs a WARNING with the
        counts per reason and what usually helps.  The draws depend on ``n`` through that
        default: the same seed with another ``n`` gives other grasps (fix ``max_samples`` to
        make the first grasps of a larger ``n`` those of a smaller one).

    mesh : a watertight trimesh in metres; every length argument and every result is in metres.
        A mesh in another unit is converted first:
        ``workbench.units.mesh_in_metres(mesh, "object", units="mm")``.  A mesh spanning more than
        ``TOL.max_object_extent_m`` or less than ``TOL.min_object_extent_m`` raises ``ValueError``
        naming the likely unit and that conversion: a millimetre mesh read as metres would
        otherwise yield no grasp at all, every width exceeding ``max_width``.

    jaws : the flat jaws (:class:`~.inputs.Jaws`; ``pad = (width, length)`` [m], length axis
        along ``up``; its ``force`` is not used here): grasps whose jaws would first meet the
        surface at a pad edge more than ``sampling.edge_depth`` [m] before the contact point are
        dropped (reason ``"pad_edge"``; see :func:`edge_touch`); default ``Jaws()`` (a
        20 × 40 mm pad, length along +z); ``jaws=None`` keeps every antipodal pair.
    A hollow mesh (a thin-walled bottle or bowl, such as the thesis's objects) is grasped across:
    the far contact is the axis's last exit from the mesh.  Axes that cross only a wall (a rim,
    a bowl's side from inside) are narrower than ``min_width`` and dropped as "too_narrow", often
    the most common reason on such meshes.

    progress : True shows a progress bar of the candidates on stderr, False never, None
        (default) when stderr is a terminal and the call runs longer than a few seconds.
    seed : an int >= 0 or a ``numpy.random.Generator`` (:func:`workbench.seeds.check_seed`).
    """
    import trimesh

    from ..seeds import check_seed

    mesh, sampling, jaws = _checked_antipodal(mesh, n, mu, sampling, jaws)
    rng = np.random.default_rng(check_seed(seed))
    half = np.arctan(mu)
    m = sampling.max_samples or 20 * n
    bar = _progress_bar(progress, m, "antipodal_grasps")
    if jaws is not None:
        _subdivide_once(mesh, m, jaws.pad)
    pts, fid = trimesh.sample.sample_surface(mesh, m, seed=int(rng.integers(2**31)))
    n1 = mesh.face_normals[fid]
    axes = _cone_directions(rng, -n1, half)
    # ray start offset off the surface: far above round-off of the mesh scale, far below any wall
    eps = 1e-6 * mesh.scale
    locs, ray_idx, tri_idx = mesh.ray.intersects_location(pts + eps * axes, axes, multiple_hits=True)
    # the hits of ray k are order[starts[k]:starts[k + 1]], in the order the intersector gave them
    order = np.argsort(ray_idx, kind="stable")
    starts = np.searchsorted(ray_idx[order], np.arange(m + 1))
    edge = None if jaws is None else (jaws.pad, jaws.up, sampling.edge_depth)
    cast = _Cast(mesh, locs, tri_idx, half, edge)
    result = _collect(
        (
            _antipodal_candidate(
                cast, eps, sampling, pts[k], n1[k], axes[k], order[starts[k] : starts[k + 1]]
            )
            for k in range(m)
        ),
        bar,
        n,
    )
    log.info("antipodal_grasps: %s", result.summary())
    if len(result) < n:
        hints = "; ".join(
            f"{c} {r} ({DROP_REASONS[r][0]}: {DROP_REASONS[r][1]})" for r, c in result.dropped.items() if c
        )
        log.warning(
            "antipodal_grasps: %d of %d grasps found among %d candidates; dropped %s; or draw more "
            "candidates (max_samples=%d now)",
            len(result),
            n,
            result.n_candidates,
            hints or "none",
            m,
        )
    return result


def _checked_antipodal(mesh, n, mu, sampling, jaws) -> tuple:
    """The inputs of :func:`antipodal_grasps` checked before any work: (the mesh — closed,
    outward, of a graspable size in metres —, the :class:`GraspSampling`, the jaws or None)."""
    import trimesh

    from ..groups import checked_group
    from ..units import MESH_UNIT_FIX, closed_mesh
    from .gws import check_mu

    if not isinstance(mesh, trimesh.Trimesh) or not mesh.is_watertight:
        raise ValueError("antipodal sampling needs a watertight trimesh.Trimesh")
    mesh = closed_mesh(mesh, "mesh passed to antipodal_grasps", fix=MESH_UNIT_FIX, override=None)
    check_mu(mu)
    _check_count("n", n)
    sampling = checked_group(sampling, GraspSampling, "sampling")
    if jaws is not None:
        jaws = checked_group(jaws, Jaws, "jaws")
    _check_table(mesh, sampling.table_z)
    return mesh, sampling, jaws


def _collect(candidates: Iterator[dict | str], bar: Any, n: int | None = None) -> Grasps:
    """The grasps among ``candidates`` (each a grasp dict or the :data:`DROP_REASONS` key it was
    dropped for), at most ``n`` (None: all), the drops counted; ``bar`` (or None) advanced per
    candidate and closed at the end."""
    out, dropped = [], dict.fromkeys(DROP_REASONS, 0)
    try:
        for grasp in candidates:
            if isinstance(grasp, str):
                dropped[grasp] += 1
            else:
                out.append(grasp)
            if bar is not None:
                bar.update(1)
                bar.set_postfix(kept=len(out), refresh=False)
            if n is not None and len(out) == n:
                break
    finally:
        if bar is not None:
            bar.close()
    return Grasps(out, dropped=dropped)


def _antipodal_candidate(cast: _Cast, eps: float, sampling: GraspSampling, p1, n1, axis, hits) -> dict | str:
    """The grasp of one candidate of :func:`antipodal_grasps` (jaw 1 at ``p1`` (3,) with
    normal ``n1`` closing along ``axis``; ``hits`` its ray's rows of ``cast.locs`` /
    ``cast.tri_idx``; exits nearer than ``eps`` [m] are its own start), or the key of
    :data:`DROP_REASONS` saying why it is not kept."""
    mesh, locs, tri_idx, half, edge = cast
    if hits.size == 0:
        return "no_far_side"
    dist = (locs[hits] - p1) @ axis
    exits = hits[(mesh.face_normals[tri_idx[hits]] @ axis > 0) & (dist > eps)]
    if exits.size == 0:
        return "no_far_side"
    j = exits[np.argmax((locs[exits] - p1) @ axis)]
    p2, n2 = locs[j], mesh.face_normals[tri_idx[j]]
    width = float(np.linalg.norm(p2 - p1))
    if width < sampling.min_width:
        return "too_narrow"
    if width > sampling.max_width:
        return "too_wide"
    if np.arccos(np.clip(n2 @ axis, -1, 1)) > half:
        return "outside_cone"
    if sampling.table_z is not None and min(p1[2], p2[2]) < sampling.table_z + sampling.clearance:
        return "near_table"
    if edge is not None and _edge_pair(mesh, p1, p2, axis, edge):
        return "pad_edge"
    return {"p1": p1, "p2": p2, "n1": n1, "n2": n2, "axis": axis, "center": 0.5 * (p1 + p2), "width": width}


def edge_touch(mesh, p: np.ndarray, approach, up, pad, depth: float, rim: float = 0.75) -> bool:
    """Whether a flat jaw ``pad = (width, length)`` [m] centred on ``p`` and closing along
    ``approach`` meets the surface of ``mesh`` only near the edge of its face: after
    closing ``depth`` past first touch (:func:`~workbench.sources.reach.reach_profile`, faces refined to
    1 mm under the footprint), the patch's pressure centre lies in the outer
    ``1 − rim`` of the face (or nothing faces the jaw).  The jaw then presses with its
    edge, far from the planned contact, and face-contact models do not describe what it
    transmits.  A patch that merely spans the face (a cylinder along the pad) is not
    an edge contact: its pressure centre stays inside.

    Raises ValueError for a bad ``pad`` or ``depth`` (rather than calling every grasp an edge touch).
    """
    from ..sources.jaws import jaw_frame
    from ..sources.reach import WinklerPress, reach_profile

    check_edge_args(pad, depth)
    a = np.asarray(approach, float) / np.linalg.norm(approach)
    up = np.asarray(up, float)
    if abs(a @ up) > 0.99 * np.linalg.norm(up):  # jaw length axis undefined: any perpendicular
        up = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    press = WinklerPress(closing=depth, max_edge=_EDGE_MAX_EDGE)
    try:
        prof = reach_profile(mesh, p, a, up, pad=pad, press=press, allow_scale=True)
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
    progress: bool | None = None,
) -> Grasps:
    """Antipodal grasps with horizontal axes through a vertical axis, on a grid of
    ``heights`` (k,) [m] × ``n_angles`` axis angles in [0, π) — the layout of the measured
    stiffness maps (thesis §4.3.3.1) and of a parallel-jaw gripper grasping an upright
    object from the side.  Same dicts as :func:`antipodal_grasps` (``p1``, ``p2`` the
    outermost hits of the line, ``axis`` from jaw 1 into the object), kept when both
    surface normals lie within the friction cone (half-angle ``arctan μ``) of the axis
    and, with ``pad``, neither jaw first meets the surface at a pad edge (:func:`edge_touch`).
    Returned as :class:`Grasps` (the grid's lines are the candidates, in height-major order;
    ``dropped`` counts ``no_far_side`` (the line meets the mesh less than twice),
    ``outside_cone`` and ``pad_edge``).

    mesh : a closed trimesh in metres (one in another unit is converted first:
        ``workbench.units.mesh_in_metres(mesh, "object", units="mm")``).
    centre : (2,) the vertical axis's (x, y) [m] (default the mesh box's centre).
    progress : as :func:`antipodal_grasps`.
    """
    from ..units import MESH_UNIT_FIX, closed_mesh
    from .gws import check_mu

    mesh = closed_mesh(mesh, "mesh passed to horizontal_grasps", fix=MESH_UNIT_FIX, override=None)
    check_mu(mu)
    _check_count("n_angles", n_angles)
    if pad is not None:
        check_edge_args(pad, edge_depth)
    z = np.atleast_1d(np.asarray(heights, float))
    lo, hi = mesh.bounds
    if z.size == 0 or z.ndim != 1 or not np.isfinite(z).all() or ((z <= lo[2]) | (z >= hi[2])).any():
        raise ValueError(
            f"heights must be at least one height [m], finite and inside the mesh z extent "
            f"({lo[2]:.4g}, {hi[2]:.4g}) m; got {np.asarray(heights).tolist()}"
        )
    c = (lo[:2] + hi[:2]) / 2 if centre is None else np.asarray(centre, float)
    if c.shape != (2,) or not np.isfinite(c).all() or ((c < lo[:2]) | (c > hi[:2])).any():
        raise ValueError(
            f"centre must be the vertical axis's (x, y) [m] inside the mesh's box {lo[:2].tolist()}–"
            f"{hi[:2].tolist()}; got {np.asarray(centre).tolist()} (in another unit than the mesh?)"
        )
    half = np.arctan(mu)
    phis = np.pi * np.arange(n_angles) / n_angles
    Z, P = np.meshgrid(z, phis, indexing="ij")
    d = np.column_stack([np.cos(P.ravel()), np.sin(P.ravel()), np.zeros(P.size)])
    bar = _progress_bar(progress, len(d), "horizontal_grasps")
    far = float(np.linalg.norm(hi - lo))
    origins = np.column_stack([c[0] - far * d[:, 0], c[1] - far * d[:, 1], Z.ravel()])
    locs, ray_idx, tri_idx = mesh.ray.intersects_location(origins, d, multiple_hits=True)
    if pad is not None:
        _subdivide_once(mesh, 2 * len(d), pad)
    order = np.argsort(ray_idx, kind="stable")
    starts = np.searchsorted(ray_idx[order], np.arange(len(d) + 1))
    cast = _Cast(mesh, locs, tri_idx, half, None if pad is None else (pad, (0.0, 0.0, 1.0), edge_depth))
    result = _collect(
        (
            _horizontal_candidate(cast, origins[k], d[k], order[starts[k] : starts[k + 1]])
            for k in range(len(d))
        ),
        bar,
    )
    log.log(logging.WARNING if not result else logging.INFO, "horizontal_grasps: %s", result.summary())
    return result


def _horizontal_candidate(cast: _Cast, origin, d, hits) -> dict | str:
    """The grasp on the line from ``origin`` along ``d`` of :func:`horizontal_grasps`
    (``hits`` its rows of ``cast.locs`` / ``cast.tri_idx``), or the key of :data:`DROP_REASONS`
    saying why it is not kept."""
    mesh, locs, tri_idx, half, edge = cast
    if hits.size < 2:
        return "no_far_side"
    t = (locs[hits] - origin) @ d
    i1, i2 = hits[np.argmin(t)], hits[np.argmax(t)]
    p1, p2 = locs[i1], locs[i2]
    n1, n2 = mesh.face_normals[tri_idx[i1]], mesh.face_normals[tri_idx[i2]]
    if np.arccos(np.clip(-n1 @ d, -1, 1)) > half or np.arccos(np.clip(n2 @ d, -1, 1)) > half:
        return "outside_cone"
    if edge is not None and _edge_pair(mesh, p1, p2, d, edge):
        return "pad_edge"
    return {
        "p1": p1,
        "p2": p2,
        "n1": n1,
        "n2": n2,
        "axis": d.copy(),
        "center": 0.5 * (p1 + p2),
        "width": float(np.linalg.norm(p2 - p1)),
    }

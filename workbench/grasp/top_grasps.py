"""Top grasps of an object resting on a table (thesis §4.2.1–4.2.2, Fig 4.8).

The planner of §4.2 grasps only from the top: the gripper approaches the object from above.
Candidates come from the friction-cone sampler of Mahler et al. (:func:`~.sampling.antipodal_grasps`);
a candidate is kept if the gripper can reach it — its axis nearly horizontal, no jaw below the
table, no finger in the object on the way down.

Fig 4.8 is about where the grasp axis sits on the jaws: between the jaws' *centres*, a flat
object's grasps put the lower half of each jaw under the table; between the jaws' *bottoms*
(``axis_at="jaw_bottom"``, the thesis's definition) the jaws end at the axis and more grasps of a
flat object are kept.

Frames follow :mod:`workbench.sources.gripper`: the gripper's x is the jaw axis, z the approach;
here the approach is straight down as far as the axis allows (world −z made ⟂ to the axis).
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..groups import checked_group
from ..plausible import ImplausibleWarning, check
from ..quiet_log import quieted
from ..seeds import check_seed
from ..sources.gripper import Gripper, check_gripper
from .sampling import GraspSampling, antipodal_grasps

log = logging.getLogger(__name__)

__all__ = [
    "AXIS_AT",
    "TOP_DROP_REASONS",
    "TopGraspSpec",
    "TopGrasps",
    "finger_boxes",
    "sample_top_grasps",
    "top_grasp_pose",
    "top_grasps",
]

#: where the grasp axis meets the pads: Fig 4.8(a) the pads' centres, (b) their bottom edge
AXIS_AT = ("jaw_bottom", "centre")

#: why a sampled antipodal grasp is not a top grasp: (what happened, what usually helps)
TOP_DROP_REASONS = {
    "tilted": ("the grasp axis is tilted more than max_tilt_deg from the table", "a larger max_tilt_deg"),
    "table": (
        "a jaw would reach below the table (plus table_clearance)",
        'axis_at="jaw_bottom" (Fig 4.8(d)), or a smaller table_clearance',
    ),
    "finger": (
        "a finger meets the object while the gripper comes down or at the open grasp",
        "a thinner or shorter finger, if the gripper's is",
    ),
    "pad": (
        "a pad finds no surface facing it inside its outline (the grasp point at the pad's edge, "
        "e.g. just below a rim: the pad would close past the object)",
        'axis_at="centre", or a longer pad',
    ),
}


_CLEARANCE = "Dex-Net's table_offset 5 mm; 0: the jaws may touch the table"
_APPROACH = "Dex-Net's approach_dist 0.1 m: the gripper comes down from 10 cm above its grasp"
_FINGER = "parallel-jaw fingers 5-20 mm thick and 20-100 mm long"


@dataclass(frozen=True)
class TopGraspSpec:
    """Which top grasps are kept (lengths in metres).

    axis_at : ``"jaw_bottom"`` (the thesis's axis, Fig 4.8(d)) or ``"centre"`` (Fig 4.8(c)).
    max_tilt_deg : the largest angle [deg] between the grasp axis and the table, in [0, 90]
        (Dex-Net's ``max_approach_table_angle``: 10).
    table_clearance : how far above the table every jaw must stay [m], >= 0 (Dex-Net's
        ``table_offset``: 5 mm).
    approach_dist : how far above its grasp the gripper starts coming down [m] (Dex-Net's
        ``approach_dist``: 0.1); the fingers sweep that far.
    finger : ``(thickness, length)`` [m] of each finger behind its pad: a box as wide as the
        pad, ``thickness`` deep behind the pad's layer and ``length`` up from the pad's bottom.
    """

    axis_at: str = "jaw_bottom"
    max_tilt_deg: float = 10.0
    table_clearance: float = 0.005
    approach_dist: float = 0.1
    finger: tuple[float, float] = field(default=(0.01, 0.06))

    def __post_init__(self) -> None:
        if self.axis_at not in AXIS_AT:
            raise ValueError(f"axis_at must be one of {AXIS_AT}; got {self.axis_at!r}")
        t = self.max_tilt_deg
        if isinstance(t, bool) or not isinstance(t, int | float) or not 0 <= t <= 90:
            raise ValueError(
                f"max_tilt_deg must be an angle in [0, 90] degrees between the axis and the table; got {t!r}"
            )
        if 0 < t < 1:  # 10 degrees typed in radians is 0.17: every grasp but a level one dropped
            warnings.warn(
                f"TopGraspSpec.max_tilt_deg = {t:g} degrees keeps only nearly level axes: is it in radians "
                f"({t:g} rad = {np.degrees(t):.3g} deg)? Dex-Net's limit is 10 degrees",
                ImplausibleWarning,
                stacklevel=3,
            )
        for key, value, what, named, examples in (
            ("closing", self.table_clearance, "table_clearance", "clearance above the table", _CLEARANCE),
            ("opening", self.approach_dist, "approach_dist", "approach distance", _APPROACH),
        ):
            check(key, value, f"TopGraspSpec.{what} [m]", warn=False, named=named, examples=examples)
        if not (isinstance(self.finger, tuple) and len(self.finger) == 2):
            raise ValueError(f"finger must be (thickness, length) [m]; got {self.finger!r}")
        for value, what in zip(self.finger, ("thickness", "length"), strict=True):
            named = f"finger {what}"
            check("pad_size", value, f"TopGraspSpec.{named} [m]", warn=False, named=named, examples=_FINGER)


def _pad_reference(gripper: Gripper, axis_at: str) -> np.ndarray:
    """(3,) the point of the gripper frame the grasp axis passes through: the mean of the two
    pads' reference points — each pad's bottom edge (its largest tooltip x, the fingertip end,
    at the outline's area centroid across) or its area centroid — on their contact faces."""
    outline = gripper.pad.outline
    cx, cy = _area_centroid(outline)
    x_ref = outline[:, 0].max() if axis_at == "jaw_bottom" else cx
    points = [T[:3, :3] @ np.array([x_ref, cy, 0.0]) + T[:3, 3] for T in gripper.tooltips]
    return np.mean(points, axis=0)


def _area_centroid(poly: np.ndarray) -> tuple[float, float]:
    """The area centroid (x, y) of a simple polygon (k, 2) (the shoelace formula)."""
    x, y = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    return float(((x + xn) * cross).sum() / (6 * area)), float(((y + yn) * cross).sum() / (6 * area))


def _finger_extent(gripper: Gripper, spec: TopGraspSpec) -> tuple[float, float, float, float, float]:
    """(x_top, x_bottom, y_lo, y_hi, depth) [m] of a jaw's swept finger box in its tooltip frame:
    the pad's width, from its bottom edge up the finger's length and the approach, and from the
    contact face back through the pad's layer and the finger's thickness."""
    outline = gripper.pad.outline
    bottom = float(outline[:, 0].max())
    return (
        bottom - spec.finger[1] - spec.approach_dist,
        bottom,
        float(outline[:, 1].min()),
        float(outline[:, 1].max()),
        gripper.pad.thickness + spec.finger[0],
    )


def top_grasp_pose(p1, p2, gripper: Gripper, axis_at: str = "jaw_bottom") -> np.ndarray:
    """(4, 4) the gripper pose [m] in the object frame that grasps across ``p1`` → ``p2`` (3,)
    from the top: gripper x along ``p2 − p1``, z (the approach) world −z made ⟂ to it, and the
    pads' reference point (``axis_at``: their bottom edge, or their centres) on the segment's
    midpoint.  A vertical axis has no top grasp: ValueError."""
    if axis_at not in AXIS_AT:
        raise ValueError(f"axis_at must be one of {AXIS_AT}; got {axis_at!r}")
    a, b = np.asarray(p1, float), np.asarray(p2, float)
    x = b - a
    if x.shape != (3,) or not np.isfinite(x).all() or np.linalg.norm(x) == 0:
        raise ValueError(f"p1 and p2 must be two distinct finite (3,) points [m]; got {p1!r}, {p2!r}")
    x /= np.linalg.norm(x)
    down = np.array([0.0, 0.0, -1.0])
    z = down - (down @ x) * x  # world down, its part along the axis removed
    if np.linalg.norm(z) < 1e-9:
        raise ValueError("the grasp axis is vertical: a gripper coming from the top cannot close along it")
    z /= np.linalg.norm(z)
    R = np.column_stack([x, np.cross(z, x), z])
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = 0.5 * (a + b) - R @ _pad_reference(gripper, axis_at)
    return T


def finger_boxes(gripper: Gripper, pose: np.ndarray, spec: TopGraspSpec) -> np.ndarray:
    """(2, 8, 3) the corners [m] of each jaw's swept finger box at the open gripper ``pose``
    (4, 4), in the object frame: as wide as the pad, from the pad's contact face back through its
    layer and the finger's ``thickness``, and from the pad's bottom edge up the finger's
    ``length`` plus ``approach_dist`` (the way the gripper came down)."""
    top, bottom, ylo, yhi, depth = _finger_extent(gripper, spec)
    local = np.array([[x, y, z] for x in (top, bottom) for y in (ylo, yhi) for z in (0.0, -depth)])
    out = np.empty((2, 8, 3))
    for k, T in enumerate(gripper.tooltips):
        world = pose @ T
        out[k] = local @ world[:3, :3].T + world[:3, 3]
    return out


def _in_boxes(points: np.ndarray, gripper: Gripper, pose: np.ndarray, spec: TopGraspSpec) -> bool:
    """Whether any of ``points`` (n, 3) [m] lies inside a finger box (:func:`finger_boxes`)."""
    top, bottom, ylo, yhi, depth = _finger_extent(gripper, spec)
    for T in gripper.tooltips:
        world = pose @ T
        q = (points - world[:3, 3]) @ world[:3, :3]  # the points in the tooltip frame
        inside = (
            (q[:, 0] >= top) & (q[:, 0] <= bottom) & (q[:, 1] >= ylo) & (q[:, 1] <= yhi)
            & (q[:, 2] <= 0.0) & (q[:, 2] >= -depth)
        )  # fmt: skip
        if inside.any():
            return True
    return False


#: how far [m] a mesh's lowest point may lie from the table z = 0 to be resting on it
_REST_TOL = 1e-3


class TopGrasps(list):
    """Top grasps: a list of ``(grasp dict, pose (4, 4))`` pairs, with ``dropped`` (every reason
    of :data:`~.sampling.DROP_REASONS` and :data:`TOP_DROP_REASONS`, zeros included) and
    ``n_candidates`` (the antipodal candidates tried)."""

    dropped: dict[str, int]
    n_candidates: int


def top_grasps(
    grasps,
    gripper: Gripper,
    spec: TopGraspSpec | None = None,
    *,
    surface=None,
    table_z: float = 0.0,
    mesh=None,
) -> TopGrasps:
    """The antipodal ``grasps`` (dicts with ``p1``, ``p2``) a gripper can take from the top, each
    with its pose (:func:`top_grasp_pose`), tested in order: the axis tilted more than
    ``spec.max_tilt_deg`` ("tilted"); a pad point below ``table_z + spec.table_clearance``
    ("table"); a point of ``surface`` (n, 3) [m] — the object's surface, sampled finer than a
    finger; None: no finger check — inside a finger box (:func:`finger_boxes`; "finger"); a pad
    that finds no surface of ``mesh`` facing it inside its outline
    (:func:`~workbench.sources.reach.pad_patch`; None: no check; "pad")."""
    from ..sources.reach import pad_patch

    gripper = check_gripper(gripper)
    spec = checked_group(spec, TopGraspSpec, "spec")
    if isinstance(table_z, bool) or not isinstance(table_z, int | float) or not np.isfinite(table_z):
        raise ValueError(f"table_z must be the table's height [m], a finite number; got {table_z!r}")
    pts = None if surface is None else np.asarray(surface, float)
    if pts is not None and (pts.ndim != 2 or pts.shape[1] != 3 or not np.isfinite(pts).all()):
        raise ValueError(
            f"surface must be the object's surface points, (n, 3) finite [m]; got shape {np.shape(surface)}"
        )
    kept = TopGrasps()
    kept.dropped = {**getattr(grasps, "dropped", {}), **dict.fromkeys(TOP_DROP_REASONS, 0)}
    kept.n_candidates = getattr(grasps, "n_candidates", len(grasps))
    max_tilt = np.sin(np.radians(spec.max_tilt_deg))
    for g in grasps:
        axis = np.asarray(g["p2"], float) - np.asarray(g["p1"], float)
        if abs(axis[2]) / np.linalg.norm(axis) > max_tilt + 1e-12:
            kept.dropped["tilted"] += 1
            continue
        pose = top_grasp_pose(g["p1"], g["p2"], gripper, spec.axis_at)
        lowest = min(j.outline_points[:, 2].min() for j in gripper.jaws(pose))
        if lowest < table_z + spec.table_clearance:
            kept.dropped["table"] += 1
            continue
        if pts is not None and _in_boxes(pts, gripper, pose, spec):
            kept.dropped["finger"] += 1
            continue
        if mesh is not None and any(pad_patch(mesh, j) is None for j in gripper.jaws(pose)):
            kept.dropped["pad"] += 1
            continue
        kept.append((g, pose))
    return kept


def sample_top_grasps(
    mesh,
    n: int,
    mu: float,
    gripper: Gripper,
    spec: TopGraspSpec | None = None,
    *,
    seed: int = 0,
    block: int = 2000,
    max_blocks: int = 20,
) -> TopGrasps:
    """Up to ``n`` top grasps of ``mesh`` (watertight, metres, resting on the table z = 0 of its
    frame): blocks of ``block`` antipodal candidates (friction cone ``mu``, widths up to the
    gripper's opening; block ``b`` seeded ``[seed, b]``) filtered by :func:`top_grasps` against
    the surface's vertices and face centres and the pads' reach on ``mesh``, until ``n`` are kept
    or ``max_blocks`` are drawn.  The first ``k`` grasps of a larger ``n`` are those of ``n = k``
    (a run can grow)."""
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
        raise ValueError(f"n must be an integer >= 1 (top grasps wanted); got {n!r}")
    for name, v in (("block", block), ("max_blocks", max_blocks)):
        if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 1:
            raise ValueError(f"{name} must be an integer >= 1; got {v!r}")
    gripper = check_gripper(gripper)
    spec = checked_group(spec, TopGraspSpec, "spec")
    seed = check_seed(seed, generator=False)
    bottom = float(np.asarray(mesh.vertices)[:, 2].min())
    if abs(bottom) > _REST_TOL:
        raise ValueError(
            f"the mesh must rest on the table z = 0 of its frame; its lowest point is at z = {bottom:.4g} m "
            f"— move it first: mesh.apply_translation((0, 0, {-bottom:.4g}))"
        )
    surface = np.vstack([mesh.vertices, mesh.triangles_center])
    sampling = GraspSampling(max_width=gripper.opening, max_samples=block)
    out = TopGrasps()
    out.dropped, out.n_candidates = {}, 0
    sampler_log = logging.getLogger(antipodal_grasps.__module__)
    for b in range(max_blocks):
        rng = np.random.default_rng([seed, b])
        # a block keeps fewer than it draws by design (its counts go into dropped): the
        # sampler's shortfall warning is for a caller who asked for n, not for a block
        with quieted(sampler_log):
            drawn = antipodal_grasps(mesh, block, mu, sampling, jaws=None, seed=rng, progress=False)
        kept = top_grasps(drawn, gripper, spec, surface=surface, mesh=mesh)
        out.extend(kept[: n - len(out)])
        for k, v in kept.dropped.items():
            out.dropped[k] = out.dropped.get(k, 0) + v
        out.n_candidates += kept.n_candidates
        if len(out) >= n:
            break
    if len(out) < n:
        log.warning(
            "%d of %d top grasps after %d candidates: dropped %s", len(out), n, out.n_candidates, out.dropped
        )
    return out

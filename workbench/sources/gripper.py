"""Parallel-jaw grippers as users describe them: two tooltip frames, a pad polygon, a force.

Frames (the REACH / Dex-Net convention of ``yumi_metal_spline.yaml``, checked on the data):

- the **gripper** frame has x the jaw (closing) axis and z the approach;
- each **tooltip** frame sits on its pad's contact face, with z the direction its jaw closes
  (towards the other jaw), x the gripper's approach (the pad's length axis) and y completing it;
- the pad outline is a polygon in the tooltip's (x, y) plane; the pad is the prism from that
  face back to ``z = -thickness`` (``round_pad.obj``: z ∈ [-3, 0] mm, the rounded end at +x,
  towards the fingertip).

:meth:`Gripper.jaws` places both tooltips at a gripper pose in the object frame and returns one
:class:`Jaw` each, in the jaw frame of :func:`~.jaws.jaw_frame`: ``closing`` (tooltip z),
``e2`` (tooltip x) and ``e1 = e2 × closing = −(tooltip y)``, so a tooltip point ``(x, y)`` has
jaw coordinates ``(e1, e2) = (−y, x)`` — a rotation by +90°, which keeps a counter-clockwise
outline counter-clockwise.  :func:`~.reach.pad_profile` turns a jaw into a contact profile.

``force`` is the closing force of **each** jaw (a force-sensor reading, thesis §4.1.3.2), not
the sum of both: :meth:`Gripper.with_total_force` halves a total.
"""

from __future__ import annotations

import dataclasses
import logging
import numbers
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..plausible import RANGES, check
from ..units import check_rigid
from .jaws import check_jaw_force, jaw_frame

__all__ = [
    "DATA_DIR",
    "Gripper",
    "Jaw",
    "PadShape",
    "SILICONE_MODULUS_PA",
    "as_polygon",
    "check_gripper",
    "gripper_from_yaml",
    "parallel_jaw",
    "points_in_polygon",
    "polygon_area",
    "polygon_centroid",
    "yumi",
]

log = logging.getLogger(__name__)

#: the packaged REACH data (MIT; LICENSE and NOTICE.md in the folder)
DATA_DIR = Path(__file__).resolve().parents[1] / "data" / "reach_trials"

#: Young's modulus of a soft silicone pad [Pa].  The REACH data gives the pad's depth (3 mm) but
#: not its material; 1 MPa is Gent's Shore-A relation at ~30 Shore A (E ≈ 1.1 MPa; A. N. Gent,
#: Trans. Inst. Rubber Ind. 34, 46, 1958), the modulus of workbench/fem/material.py's default silicone.
#: An assumption: the Winkler pressure's *shape* does not depend on it, only the compression a
#: force needs (pressures are rescaled to the force reading).
SILICONE_MODULUS_PA = 1.0e6


def check_pad_mu(mu) -> float:
    """``mu`` as a float if it is a pad's friction coefficient, in (0, 2] (rubber on plastic
    ~0.3–1.5); else ValueError naming the likely slip (30 for 0.3: a percentage; 0: no friction,
    no parallel-jaw grasp holds anything).  The one rule of a gripper's μ: :class:`Gripper` and
    :func:`~workbench.grasp.gripper_eval.check_task` call it."""
    from workbench.wrench import check_mu

    mu_f = check_mu(mu)
    if mu_f == 0:
        raise ValueError(
            "mu must be a friction coefficient > 0 (rubber on plastic ~0.3-1.5); got 0: without "
            "friction a parallel-jaw grasp holds nothing"
        )
    return mu_f


# ---------------------------------------------------------------- rigid transforms


# ---------------------------------------------------------------- polygons


def polygon_area(polygon) -> float:
    """Signed area [m²] of a polygon (k, 2) (shoelace formula; > 0 when counter-clockwise)."""
    p = np.asarray(polygon, float)
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def polygon_centroid(polygon) -> np.ndarray:
    """Area centroid (2,) [m] of a simple polygon (k, 2) (shoelace formula, either orientation)."""
    p = np.asarray(polygon, float)
    # about the first vertex: the same centroid with less cancellation for a far-off polygon
    q = p - p[0]
    x, y = q[:, 0], q[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    c = x * yn - xn * y
    a = 0.5 * c.sum()
    return p[0] + np.array([((x + xn) * c).sum(), ((y + yn) * c).sum()]) / (6.0 * a)


def _crossing_edges(p: np.ndarray) -> tuple[int, int] | None:
    """The first pair of non-adjacent edges of the closed polygon (k, 2) that touch or cross."""
    k = len(p)
    a, b = p, np.roll(p, -1, axis=0)
    i, j = np.triu_indices(k, 2)
    keep = ~((i == 0) & (j == k - 1))  # edges 0 and k-1 share vertex 0
    i, j = i[keep], j[keep]

    def orient(o, s, t):
        return np.sign((s[:, 0] - o[:, 0]) * (t[:, 1] - o[:, 1]) - (s[:, 1] - o[:, 1]) * (t[:, 0] - o[:, 0]))

    a1, b1, a2, b2 = a[i], b[i], a[j], b[j]
    straddle = (orient(a1, b1, a2) * orient(a1, b1, b2) <= 0) & (orient(a2, b2, a1) * orient(a2, b2, b1) <= 0)
    # bounding boxes overlap: the collinear case, where every orientation is 0
    lo1, hi1 = np.minimum(a1, b1), np.maximum(a1, b1)
    lo2, hi2 = np.minimum(a2, b2), np.maximum(a2, b2)
    boxes = ((lo1 <= hi2) & (lo2 <= hi1)).all(axis=1)
    hit = np.flatnonzero(straddle & boxes)
    return None if len(hit) == 0 else (int(i[hit[0]]), int(j[hit[0]]))


def _distinct_vertices(outline, what: str) -> np.ndarray:
    """``outline`` as a (k, 2) float array of finite vertices, consecutive duplicates and a
    repeated closing vertex dropped, k >= 3; else ValueError."""
    try:
        p = np.array(outline, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be a (k, 2) array of polygon vertices [m]; got {outline!r}") from None
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"{what} must be a (k, 2) array of polygon vertices [m]; got shape {p.shape}")
    if not np.isfinite(p).all():
        raise ValueError(f"{what} has non-finite vertices: {p.tolist()}")
    if len(p) > 1:
        p = p[np.r_[True, np.any(p[1:] != p[:-1], axis=1)]]
    if len(p) > 1 and np.array_equal(p[0], p[-1]):
        p = p[:-1]
    if len(p) < 3:
        raise ValueError(f"{what} needs at least 3 distinct vertices; got {len(p)}: {p.tolist()}")
    return p


def _polygon_extent(p: np.ndarray, what: str) -> float:
    """The largest side [m] of the bounding box of the polygon ``p`` (k, 2), a pad's size in
    metres (ValueError naming the unit it was given in), warned about outside the usual sizes."""
    extent = float((p.max(0) - p.min(0)).max())
    size = RANGES["pad_size"]
    if extent > size.hi:
        # the unit giving a size nearest (in ratio) a typical 2 cm pad
        unit, factor = min(
            (("centimetres", 0.01), ("millimetres", 0.001)), key=lambda u: abs(np.log(extent * u[1] / 0.02))
        )
        raise ValueError(
            f"{what} spans {extent:.4g} m, more than any pad ({size.hi:g} m): given in {unit}? "
            f"outlines are in metres: multiply it by {factor:g}"
        )
    if extent < size.lo:
        raise ValueError(
            f"{what} spans {extent:.3g} m, less than {size.lo:g} m: converted to metres twice? "
            "outlines are in metres"
        )
    check("pad_size", extent, f"{what}'s extent [m]")  # warns outside the usual sizes
    return extent


def as_polygon(outline, what: str = "outline") -> np.ndarray:
    """``outline`` as a read-only counter-clockwise polygon (k, 2) [m], or ValueError.

    Drops a repeated closing vertex and consecutive duplicates; requires >= 3 finite vertices, a
    non-zero area, no self-intersection, and a size between 0.1 mm and 0.2 m (a larger one was
    given in centimetres or millimetres: the message names which and the factor).
    """
    p = _distinct_vertices(outline, what)
    extent = _polygon_extent(p, what)
    bad = _crossing_edges(p)
    if bad is not None:
        raise ValueError(
            f"{what} is not a simple polygon: its edges {bad[0]} and {bad[1]} cross or touch; list the "
            "vertices in order around the boundary (a convex pad: its convex hull)"
        )
    area = polygon_area(p)
    if abs(area) <= 1e-12 * extent**2:
        raise ValueError(f"{what} has zero area (its vertices are collinear): {p.tolist()}")
    if area < 0:
        p = p[::-1].copy()
    p.flags.writeable = False
    return p


def points_in_polygon(points, polygon) -> np.ndarray:
    """(n,) bool: which of ``points`` (n, 2) lie inside the simple ``polygon`` (k, 2)
    (even-odd crossing rule, vectorised over the points; a point on an edge may go either way)."""
    pts = np.asarray(points, float)
    poly = np.asarray(polygon, float)
    x, y = pts[:, 0], pts[:, 1]
    inside = np.zeros(len(pts), dtype=bool)
    for (x0, y0), (x1, y1) in zip(poly, np.roll(poly, -1, axis=0), strict=True):
        if y0 == y1:
            continue  # a horizontal edge is crossed by no horizontal ray
        spans = (y0 > y) != (y1 > y)
        x_cross = x0 + (y - y0) * ((x1 - x0) / (y1 - y0))
        inside ^= spans & (x < x_cross)
    return inside


# ---------------------------------------------------------------- pad, jaw, gripper


@dataclass(frozen=True)
class PadShape:
    """A flat compliant pad: its contact face and its Winkler stiffness.

    outline : (k, 2) float [m], read-only — the contact face, a simple polygon in the tooltip
        frame's (x, y) plane (x the approach / pad length axis, y its width), stored
        counter-clockwise (:func:`as_polygon`).
    thickness : [m] the compliant layer's depth.
    modulus : [Pa] its modulus; the Winkler pressure is ``p = k d`` with ``k = modulus / thickness``.
    """

    outline: np.ndarray
    thickness: float
    modulus: float

    def __post_init__(self):
        object.__setattr__(self, "outline", as_polygon(self.outline, "pad outline"))
        object.__setattr__(self, "thickness", check("pad_thickness", self.thickness, "pad thickness"))
        object.__setattr__(self, "modulus", check("pad_modulus", self.modulus, "pad modulus"))

    @property
    def area(self) -> float:
        """Area of the contact face [m²] (shoelace)."""
        return polygon_area(self.outline)

    @property
    def centroid(self) -> np.ndarray:
        """(2,) area centroid of the contact face in the tooltip (x, y) plane [m]."""
        return polygon_centroid(self.outline)

    @property
    def extent(self) -> np.ndarray:
        """(2,) sides of the outline's bounding box along tooltip x and y [m]."""
        return self.outline.max(axis=0) - self.outline.min(axis=0)

    @property
    def stiffness(self) -> float:
        """Winkler foundation modulus ``k = modulus / thickness`` [Pa/m]."""
        return self.modulus / self.thickness

    @classmethod
    def rectangle(
        cls,
        width: float,
        length: float,
        offset=(0.0, 0.0),
        *,
        thickness: float = 0.003,
        modulus: float = SILICONE_MODULUS_PA,
    ) -> PadShape:
        """A ``width`` (tooltip y) × ``length`` (tooltip x, the approach) rectangle [m] centred at
        ``offset`` (2,) [m] in the tooltip (x, y) plane."""
        w = check("pad_size", width, "pad width")
        h = check("pad_size", length, "pad length")
        ox, oy = np.asarray(offset, float)
        for v in (ox, oy):  # the pad's place on the finger: an offset in mm (10 for 0.01) is refused
            if v:
                check("lever", abs(float(v)), "pad offset (in the tooltip frame [m])")
        pts = [
            (ox - h / 2, oy - w / 2),
            (ox + h / 2, oy - w / 2),
            (ox + h / 2, oy + w / 2),
            (ox - h / 2, oy + w / 2),
        ]
        return cls(np.array(pts), thickness, modulus)

    @classmethod
    def from_mesh(
        cls, mesh, *, thickness: float | None = None, modulus: float = SILICONE_MODULUS_PA
    ) -> PadShape:
        """The pad of a flat pad mesh (a path or a ``trimesh.Trimesh``) in the tooltip frame [m]:
        its outline is the convex hull of the vertices projected on the (x, y) plane (notches of a
        non-convex pad are filled, with a warning), its thickness the mesh's z extent unless given.

        Raises ValueError unless z is the mesh's thinnest axis (the tooltip's closing axis).
        """
        import trimesh
        from scipy.spatial import ConvexHull

        if not isinstance(mesh, trimesh.Trimesh):
            mesh = trimesh.load(mesh, force="mesh")
        ext = mesh.extents
        if not ext[2] < min(ext[0], ext[1]):
            raise ValueError(
                "the pad mesh is not flat in the tooltip (x, y) plane: its extents are "
                f"{np.round(ext, 5).tolist()}; "
                "its thickness must be along z (the closing direction): rotate it into the tooltip frame"
            )
        xy = mesh.vertices[:, :2]
        hull = ConvexHull(xy)
        outline = xy[hull.vertices]  # counter-clockwise in 2-D
        # faces facing ±z: the projected face area; the hull is larger for a non-convex pad
        front = np.abs(mesh.face_normals[:, 2]) > 0.99
        face_area = 0.5 * float(mesh.area_faces[front].sum())
        if face_area > 0 and hull.volume > 1.001 * face_area:
            log.warning(
                "pad mesh: its convex hull (%.4g m²) is larger than its faces (%.4g m²): a non-convex pad, "
                "whose notches the outline fills",
                hull.volume,
                face_area,
            )
        return cls(outline, float(ext[2]) if thickness is None else thickness, modulus)


@dataclass(frozen=True)
class Jaw:
    """One jaw of a gripper placed at a pose, in the object frame (what :func:`~.reach.pad_profile`
    presses into a mesh).

    origin : (3,) the tooltip origin, on the pad's contact face when the gripper is open [m].
    closing : (3,) unit, the direction the jaw moves (tooltip z, into the object).
    e1, e2 : (3,) unit, ``e2`` the pad length axis (tooltip x, the approach), ``e1 = e2 × closing``
        (= −tooltip y) — :func:`~.jaws.jaw_frame` ``(closing, e2)``.
    outline : (k, 2) the pad polygon in (e1, e2) coordinates about ``origin`` [m].
    stroke : [m] how far the jaw can travel (half the gripper's opening).
    stiffness : [Pa/m] the pad's Winkler modulus (:attr:`PadShape.stiffness`).
    """

    origin: np.ndarray
    closing: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    outline: np.ndarray
    stroke: float
    stiffness: float

    def __post_init__(self):
        for name in ("origin", "closing", "e1", "e2"):
            v = np.array(getattr(self, name), dtype=float)
            if v.shape != (3,) or not np.isfinite(v).all():
                raise ValueError(f"Jaw.{name} must be a finite (3,) vector; got {v.tolist()}")
            v.flags.writeable = False
            object.__setattr__(self, name, v)
        frame = np.array([self.closing, self.e1, self.e2])
        if np.abs(frame @ frame.T - np.eye(3)).max() > 1e-9 or np.linalg.det(frame) < 0:
            raise ValueError(
                "Jaw (closing, e1, e2) must be a right-handed orthonormal frame with e1 = e2 × closing: "
                "build it with workbench.sources.jaws.jaw_frame(closing, e2)"
            )
        object.__setattr__(self, "outline", as_polygon(self.outline, "Jaw.outline"))
        object.__setattr__(self, "stroke", check("opening", self.stroke, "Jaw.stroke (half the opening) [m]"))
        object.__setattr__(self, "stiffness", check("winkler_stiffness", self.stiffness, "Jaw.stiffness"))

    def turned(self, rotation: np.ndarray, pivot: np.ndarray) -> Jaw:
        """This jaw turned by ``rotation`` (3, 3) about ``pivot`` (3,) [m] (a rigid motion of the
        gripper in the object frame; the outline rides along in the jaw's own axes).  A rigid
        motion of a checked jaw is a valid jaw: only the moved vectors are made, not re-checked
        (the settle turns a jaw some twenty times a contact)."""
        R = np.asarray(rotation, float)
        p = np.asarray(pivot, float)
        out = object.__new__(Jaw)
        for name, v in (
            ("origin", p + R @ (self.origin - p)),
            ("closing", R @ self.closing),
            ("e1", R @ self.e1),
            ("e2", R @ self.e2),
        ):
            v.flags.writeable = False
            object.__setattr__(out, name, v)
        for name in ("outline", "stroke", "stiffness"):
            object.__setattr__(out, name, getattr(self, name))
        return out

    @property
    def outline_points(self) -> np.ndarray:
        """(k, 3) the pad polygon in the object frame [m]."""
        return self.origin + self.outline[:, :1] * self.e1 + self.outline[:, 1:] * self.e2


@dataclass(frozen=True)
class Gripper:
    """A parallel-jaw gripper.

    name : a label.
    tooltips : (2, 4, 4) float, read-only — each tooltip frame → gripper frame [m]: tooltip z
        the closing direction (towards the other tooltip), x the approach (gripper z).
    pad : the pads' shape (both jaws alike), in each tooltip frame.
    force : [N] the closing force of EACH jaw (a force-sensor reading, not both jaws' sum; see
        :meth:`with_total_force`).
    mu : the pad's friction coefficient if known, else None.
    opening : [m] the largest distance between the tooltips (the open gripper).
    finger_mesh : path of the finger's mesh (collision checks) or None.
    """

    name: str
    tooltips: np.ndarray
    pad: PadShape
    force: float
    mu: float | None = None
    opening: float = 0.05
    finger_mesh: Path | None = None

    def __post_init__(self):
        if not isinstance(self.pad, PadShape):
            raise ValueError(f"pad must be a PadShape; got {type(self.pad).__name__}")
        object.__setattr__(self, "force", check_jaw_force(self.force))
        if self.mu is not None:
            object.__setattr__(self, "mu", check_pad_mu(self.mu))
        object.__setattr__(
            self,
            "opening",
            check("opening", self.opening, "opening"),
        )
        if self.finger_mesh is not None:
            object.__setattr__(self, "finger_mesh", Path(self.finger_mesh))
        try:
            tips = np.array(self.tooltips, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(
                "tooltips must be two 4×4 tooltip → gripper transforms, shape (2, 4, 4)"
            ) from None
        if tips.shape != (2, 4, 4):
            raise ValueError(
                f"tooltips must be two 4×4 tooltip → gripper transforms, shape (2, 4, 4); got {tips.shape}"
            )
        tips = np.array([check_rigid(t, f"tooltip {i} (tooltip → gripper)") for i, t in enumerate(tips)])
        self._check_tooltips(tips)
        tips.flags.writeable = False
        object.__setattr__(self, "tooltips", tips)

    def _check_tooltips(self, tips: np.ndarray) -> None:
        (o0, o1), (z0, z1) = tips[:, :3, 3], tips[:, :3, 2]
        d = o1 - o0
        if not np.linalg.norm(d) > 0:
            raise ValueError("the two tooltips coincide: give each jaw's tooltip pose")
        if z0 @ z1 > -0.999:
            raise ValueError(
                f"the tooltips' closing directions (z) must be opposite for a parallel-jaw gripper; got "
                f"{np.round(z0, 3).tolist()} and {np.round(z1, 3).tolist()}"
            )
        if tips[0, :3, 0] @ tips[1, :3, 0] < 0.999:
            raise ValueError(
                "the tooltips' x axes (the pad length axis, the approach) must agree; got "
                f"{np.round(tips[0, :3, 0], 3).tolist()} and {np.round(tips[1, :3, 0], 3).tolist()}"
            )
        if not (z0 @ d > 0 and z1 @ d < 0):
            raise ValueError(
                "swapped tooltips: each tooltip's z must point from its jaw towards the other jaw, but "
                f"tooltip 0 at {np.round(o0, 4).tolist()} closes along {np.round(z0, 3).tolist()}, away from "
                f"tooltip 1 at {np.round(o1, 4).tolist()}: swap the two tooltip poses (or their translations)"
            )
        gap = float(z0 @ d)
        if gap > self.opening * (1 + 1e-9):
            raise ValueError(
                f"the tooltips are {gap:.4g} m apart along the closing axis, farther than the opening "
                f"{self.opening:.4g} m (the largest tooltip distance): pass opening >= {gap:.4g} or fix the "
                "tooltip translations"
            )

    @property
    def stroke(self) -> float:
        """How far each jaw can travel [m]: half the opening."""
        return self.opening / 2

    def with_total_force(self, total: float) -> Gripper:
        """A copy whose per-jaw ``force`` is half of ``total`` [N], the sum over both jaws."""
        check("jaw_force", total / 2 if isinstance(total, numbers.Real) else total, "half the total force")
        return dataclasses.replace(self, force=total / 2)

    def jaws(self, pose) -> tuple[Jaw, Jaw]:
        """Both jaws (tooltip 0, tooltip 1) with the gripper frame at ``pose`` (4, 4) — the gripper
        in the object frame, e.g. :attr:`~.trials.Trials.gripper_pose` — open by :attr:`opening`."""
        pose = check_rigid(pose, "pose (the gripper frame in the object frame)")
        # tooltip (x, y) -> jaw (e1, e2) = (-y, x): e1 = x × z = -y (module docstring)
        outline = np.column_stack([-self.pad.outline[:, 1], self.pad.outline[:, 0]])
        out = []
        for tip in self.tooltips:
            W = pose @ tip
            closing, e1, e2 = jaw_frame(W[:3, 2], W[:3, 0])
            out.append(Jaw(W[:3, 3], closing, e1, e2, outline, self.stroke, self.pad.stiffness))
        return out[0], out[1]


# ---------------------------------------------------------------- YAML (Dex-Net / REACH format)


def check_gripper(gripper) -> Gripper:
    """``gripper`` if it is a :class:`Gripper`, else a ValueError naming what to pass — the one
    rule of every call that takes a gripper (``evaluate_gripper``, ``evaluate_models``,
    ``simulate_gripper``).  A preset's name is not taken for it: the presets are functions that
    build one (``yumi()``), and another gripper comes from its yaml (:func:`gripper_from_yaml`)."""
    if isinstance(gripper, Gripper):
        return gripper
    name = type(gripper).__name__
    fix = (
        f"pass {gripper}() (workbench.sources.gripper.{gripper}), the preset it names"
        if isinstance(gripper, str) and gripper in _PRESETS
        else "build one: yumi(), gripper_from_yaml(path) or Gripper(...)"
    )
    got = f"{gripper!r} ({name})" if isinstance(gripper, (str, int, float)) else f"a {name}"
    raise ValueError(f"gripper must be a workbench.sources.gripper.Gripper (e.g. yumi()); got {got} — {fix}")


def _read_yaml(path) -> dict:
    import yaml

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"no such YAML file: {path}")
    with path.open() as f:
        data = yaml.safe_load(f)
    if not isinstance(data, dict) or not isinstance(data.get("params"), dict):
        raise ValueError(f"{path}: expected a mapping with 'type' and 'params' (Dex-Net's config format)")
    return data


def _tooltip_poses(data: dict, path) -> np.ndarray:
    poses = data["params"].get("tooltip_poses")
    if not isinstance(poses, list) or len(poses) != 2:
        raise ValueError(f"{path}: params.tooltip_poses must list the two tooltips' RigidTransforms")
    out = []
    for i, tp in enumerate(poses):
        p = tp.get("params", {}) if isinstance(tp, dict) else {}
        if "rotation" not in p or "translation" not in p:
            raise ValueError(
                f"{path}: tooltip_poses[{i}].params needs 'rotation' (3×3) and 'translation' (3,)"
            )
        if (p.get("from_frame"), p.get("to_frame")) not in ((None, None), ("tooltip", "gripper")):
            raise ValueError(
                f"{path}: tooltip_poses[{i}] maps {p.get('from_frame')!r} → {p.get('to_frame')!r}; "
                "expected tooltip → gripper (invert it)"
            )
        T = np.eye(4)
        try:
            T[:3, :3] = np.asarray(p["rotation"], float)
            T[:3, 3] = np.asarray(p["translation"], float)
        except ValueError:
            raise ValueError(
                f"{path}: tooltip_poses[{i}] rotation must be 3×3 and translation (3,)"
            ) from None
        out.append(T)
    return np.array(out)


def gripper_from_yaml(  # noqa: PLR0913 - each keyword overrides one field of the YAML files
    path,
    contact_yaml=None,
    *,
    pad: PadShape | None = None,
    force: float | None = None,
    mu: float | None = None,
    opening: float | None = None,
    thickness: float | None = None,
    modulus: float = SILICONE_MODULUS_PA,
    polygon_units: str | float = "cm",
    finger_mesh=None,
) -> Gripper:
    """A :class:`Gripper` from a Dex-Net ``ParallelJawGripper`` YAML (``path``: its name and the
    tooltip → gripper poses [m]) and optionally a REACH ``ContactGenerator`` YAML
    (``contact_yaml``: ``friction_coef``, ``closing_force`` [N, per jaw], ``silicone_depth`` [m]
    and the pad polygon ``geometry``, in ``polygon_units`` — centimetres in REACH's file).

    Keywords override the contact file (``thickness`` replaces ``silicone_depth``); without a
    contact file ``pad`` and ``force`` are required.  ``opening`` defaults to the tooltips'
    distance along the closing axis (the file's tooltips are the open gripper's).
    """
    from ..units import length_factor

    data = _read_yaml(path)
    tips = _tooltip_poses(data, path)
    name = str(data["params"].get("name", Path(path).stem))
    if contact_yaml is not None:
        cp = _read_yaml(contact_yaml)["params"].get("contact_params")
        if not isinstance(cp, dict):
            raise ValueError(
                f"{contact_yaml}: params.contact_params missing (a REACH ContactGenerator file?)"
            )
        if pad is None:
            if "geometry" not in cp:
                raise ValueError(
                    f"{contact_yaml}: contact_params.geometry (the pad polygon) missing; pass pad="
                )
            geo = np.asarray(cp["geometry"], float)
            if geo.ndim != 2 or geo.shape[1] not in (2, 3) or (geo.shape[1] == 3 and np.any(geo[:, 2] != 0)):
                raise ValueError(
                    f"{contact_yaml}: geometry must list the pad polygon's (x, y[, 0]) vertices in the "
                    f"tooltip plane; got shape {geo.shape}"
                )
            depth = cp.get("silicone_depth") if thickness is None else thickness
            if depth is None:
                raise ValueError(f"{contact_yaml}: no silicone_depth; pass thickness= [m]")
            pad = PadShape(geo[:, :2] * length_factor(polygon_units), float(depth), modulus)
        force = cp.get("closing_force") if force is None else force
        mu = cp.get("friction_coef") if mu is None else mu
    if pad is None or force is None:
        raise ValueError("without a contact YAML pass pad= (a PadShape) and force= (per jaw, N)")
    if opening is None:
        opening = float(tips[0, :3, 2] @ (tips[1, :3, 3] - tips[0, :3, 3]))
        if not opening > 0:
            opening = float(np.linalg.norm(tips[1, :3, 3] - tips[0, :3, 3]))  # the Gripper check names it
    return Gripper(name, tips, pad, force, mu, opening, finger_mesh)


def yumi(pad: str = "polygon") -> Gripper:
    """The ABB YuMi gripper of the REACH trials (packaged files, :data:`DATA_DIR`): tooltips of
    ``yumi_metal_spline.yaml``, 20 N per jaw, μ = 0.3, opening 0.05 m (the file's tooltips at
    ∓0.025 m), 3 mm silicone of :data:`SILICONE_MODULUS_PA`, finger ``finger.stl``.

    pad : "polygon" — the six-vertex polygon of ``area_contact_generator.yaml`` (chamfered end,
        cm → m, 5.25 cm²), what REACH's area-contact model used; "mesh" — ``round_pad.obj``
        (semicircular end, 5.07 cm²), what its collision checks and simulation used.
    """
    g = gripper_from_yaml(
        DATA_DIR / "yumi_metal_spline.yaml",
        DATA_DIR / "area_contact_generator.yaml",
        # the file's silicone_depth (5.3 mm) is a tuned value; its comment gives the true 3 mm
        thickness=0.003,
        opening=0.05,
        finger_mesh=DATA_DIR / "finger.stl",
    )
    if pad == "mesh":
        return dataclasses.replace(g, pad=PadShape.from_mesh(DATA_DIR / "round_pad.obj", thickness=0.003))
    if pad != "polygon":
        raise ValueError(
            f"pad must be 'polygon' (REACH's area-contact polygon) or 'mesh' (round_pad.obj); got {pad!r}"
        )
    return g


def parallel_jaw(
    pad: PadShape, force: float, *, opening: float, mu: float | None = None, name: str = "parallel_jaw"
) -> Gripper:
    """A parallel-jaw gripper whose open tooltips sit at ``∓opening / 2`` [m] on the gripper's x
    (the jaw axis), each closing towards the other, the approach (tooltip x) along gripper z: the
    gripper of a grasp planner that knows only its pad, its force [N per jaw] and its opening
    (e.g. thesis §4.1.4.2's SCHUNK jaws: 5 mm rubber, 20 N)."""
    o = check("opening", opening, "opening") / 2
    # tooltip axes (x, y, z) as gripper-frame columns: x the approach, z the closing, y = z × x
    tip0 = np.array([[0.0, 0.0, 1.0, -o], [0.0, -1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
    tip1 = np.array([[0.0, 0.0, -1.0, o], [0.0, 1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
    return Gripper(name, np.array([tip0, tip1]), pad, force, mu, 2 * o)


#: the gripper presets, by the name a user might pass instead of calling one
_PRESETS = {"yumi": yumi}

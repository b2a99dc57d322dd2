"""The FEM adapter: FEM pad profiles of a parallel-jaw grasp on an object mesh (thesis §3.5.2,
§4.3.2.1).

The profile source of the FEM pad, the FEM counterpart of
:func:`workbench.sources.reach.jaw_profiles` (REACH, Winkler pressure): each jaw is the
compliant pad of :mod:`workbench.fem.pad` (rigid back, bonded linear elastic layer,
frictionless Signorini contact on its condensed face, :func:`workbench.fem.contact.solve_contact`)
pressed against the rigid object mesh along the grasp axis until the pad's normal force
*along the axis* equals the gripper's reading — the force-sensor convention of §4.1.3.2, as
:func:`~.jaws.with_axis_force` does for REACH.  The solution becomes a profile by
:func:`workbench.fem.extract.extract_profile` (``profile.F`` = the pad's reaction ``Σ λ``),
moved into the object frame.  ``workbench.fem`` imports only the core of ``workbench``
(``profile``, ``units``, ``config``, ...); the grasp conventions come in here.

Jaw frame (``x_object = R x_pad + t``): pad z along the approach (into the object), pad
y (its long side) along ``up`` made perpendicular to the approach, x = y × z — the pose
of :func:`workbench.fem.bottle.grasp_pose` for a side grasp of a standing object.  The pad face is
first placed to touch the mesh (smallest gap 0); the jaw then advances by the
displacement whose axial force is the reading (Brent's method on the monotone
force–displacement curve; every solve is milliseconds once the pad is condensed).

The object is rigid here: the wall's own compliance is :mod:`workbench.fem.wall`'s business.
The mesh is one-sided towards the jaw (``MeshObstacle(facing=...)``), so a wall solid
with an inner surface (the cup's 0.5 mm wall) is seen from outside only.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from workbench.fem.bottle import Posed
from workbench.fem.contact import solve_contact
from workbench.fem.extract import extract_profile
from workbench.fem.material import Material
from workbench.fem.obstacles import MeshObstacle
from workbench.fem.pad import CondensedPad, PadGeometry, condense_pad

from ..profile import ContactProfile, ProfileSource
from ..units import closed_mesh
from .jaws import check_direction, check_grasp, check_jaw_force, jaw_frame, with_axis_force

log = logging.getLogger(__name__)

__all__ = [
    "FemPad",
    "check_jaw_reaches",
    "condensed_fem_pad",
    "fem_jaw_profile",
    "fem_jaw_profiles",
    "jaw_rotation",
]


def jaw_rotation(approach, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """(3, 3) rotation whose columns are the pad's x, y, z axes in the object frame:
    z = ``approach`` (unit), y = ``up`` made perpendicular to it, x = y × z.

    Raises ``ValueError`` for a zero or non-finite approach or up (:func:`~.jaws.check_direction`),
    or ``up`` parallel to the approach.
    """
    ez = check_direction(approach, "approach", "the jaw's closing direction, into the object")
    u = check_direction(up, "up", "the pad's length direction, across the approach")
    # up within 1e-6 rad of the approach cannot orient the jaw
    if not np.linalg.norm(u - (u @ ez) * ez) > 1e-6:
        raise ValueError(
            f"up {up!r} is parallel to the approach {approach!r}: the pad's long side is undefined — "
            "give an up direction across the approach"
        )
    ez, ex, ey = jaw_frame(ez, u)  # REACH's jaw axes: approach, width, length
    return np.column_stack([ex, ey, ez])


def _touching(obstacle: MeshObstacle, R: np.ndarray, point: np.ndarray, X: np.ndarray, h: float) -> Posed:
    """The pad pose whose undeformed face ``X`` (pad frame) just touches the object."""
    ez = R[:, 2]
    extent = float(np.ptp(obstacle.mesh.vertices, axis=0).max())
    t = point - ez * (h + extent)  # start outside the object, then close the gap
    for _ in range(60):
        d, _ = Posed(obstacle, R, t).signed_distance(X)
        gap = float(d.min())
        if not np.isfinite(gap):
            break
        t = t + ez * gap
        # first touch found to 1e-9 of the pad thickness (plus 1e-12 m absolute for a tiny pad)
        if abs(gap) <= 1e-12 + 1e-9 * h:
            return Posed(obstacle, R, t)
    raise ValueError(
        f"the pad at {np.round(point, 4).tolist()} approaching along {np.round(ez, 3).tolist()} does not "
        "settle on the object (no first touch): check the point, the approach (into the object) and units"
    )


@dataclass(frozen=True)
class FemPad:
    """The FEM pad a jaw profile condenses when it is not given one already condensed.

    geometry : a :class:`~workbench.fem.pad.PadGeometry` (default 20 × 40 × 5 mm), checked when
        made by :func:`check_pad_geometry` (a pad in millimetres is refused before it is condensed).
    material : a :class:`~workbench.fem.material.Material` (default E = 1 MPa, ν = 0.45).
    cache_dir : :func:`~workbench.fem.pad.condense_pad`'s disk cache (None: its default, False: none).
    """

    geometry: PadGeometry = field(default_factory=PadGeometry)
    material: Material = field(default_factory=Material)
    cache_dir: Any = None

    def __post_init__(self) -> None:
        check_pad_geometry(self.geometry)


def condensed_fem_pad(pad: CondensedPad | FemPad | None) -> CondensedPad:
    """``pad`` condensed: a :class:`~workbench.fem.pad.CondensedPad` as given (its geometry
    checked by :func:`check_pad_geometry`), a :class:`FemPad` (None: its defaults) condensed by
    :func:`~workbench.fem.pad.condense_pad` (disk-cached unless ``cache_dir=False``)."""
    if isinstance(pad, CondensedPad):
        check_pad_geometry(pad.geometry)
        return pad
    spec = FemPad() if pad is None else pad
    if not isinstance(spec, FemPad):
        raise ValueError(
            f"pad must be a CondensedPad (condense_pad), a FemPad or None; got {type(pad).__name__}"
        )
    return condense_pad(spec.geometry, spec.material, cache_dir=spec.cache_dir)


def fem_jaw_profile(
    mesh,
    point,
    approach,
    force: float,
    *,
    up=(0.0, 0.0, 1.0),
    pad: CondensedPad | FemPad | None = None,
    units: str | float | None = None,
    allow_scale: bool = False,
) -> ContactProfile:
    """One jaw's FEM contact profile on ``mesh``, in the object frame, at the reading ``force``.

    mesh : watertight trimesh (or path), metres unless ``units`` says otherwise.
    point : (3,) [m] where the jaw meets the object (the pad face is centred on the
        approach line through it, its first touch may be elsewhere on the face).
    approach : (3,) direction from the jaw into the object.
    force : the gripper's reading [N] > 0: the pad's normal force along ``approach``.
    pad : the pad — a :class:`FemPad` (its geometry, material and disk cache; None: the default
        20 × 40 × 5 mm pad of E = 1 MPa, ν = 0.45), condensed after the point and approach are
        checked; or a condensed pad already built (:func:`~workbench.fem.pad.condense_pad`,
        :func:`condensed_fem_pad`) — reuse it across grasps, its condensation (tens of seconds,
        disk-cached) dominates the first call.

    Returns a :class:`~workbench.profile.ContactProfile` whose normal force along
    ``approach`` is ``force`` (to 1e-9 relative) and whose normals point out of the object,
    with its :class:`~workbench.profile.ProfileSource` ``"fem_pad"``: made at ``force``, valid
    for readings up to what the layer reaches on this contact (grasp analysis refuses to scale
    it beyond, and warns when it is scaled far from ``force``: the contact grows with force).
    Raises ``ValueError`` for a bad mesh, a non-positive force, a jaw that touches
    nothing (:func:`check_jaw_reaches`: a point far outside the object, e.g. in millimetres, or an
    approach pointing away from the object at the point), or a force the layer cannot reach before
    its rigid back meets the object.
    """
    from scipy.optimize import brentq

    check_jaw_force(force)
    mesh = closed_mesh(mesh, "mesh passed to fem_jaw_profile", units=units, allow_scale=allow_scale)
    p = np.asarray(point, float)
    if p.shape != (3,) or not np.isfinite(p).all():
        raise ValueError(f"point must be a finite (3,) position [m]; got {point!r}")
    R = jaw_rotation(approach, up)
    check_jaw_reaches(mesh, p, R[:, 2])  # before the pad is condensed
    pad = condensed_fem_pad(pad)
    h = pad.geometry.thickness
    obstacle = MeshObstacle(mesh, allow_scale=True, facing=-R[:, 2])  # checked by closed_mesh above
    X = np.column_stack([pad.face_xy, np.full(len(pad.face_xy), h)])
    posed = _touching(obstacle, R, p, X, h)
    cache: dict[float, object] = {}

    def axial(delta: float) -> float:  # the pad's normal force along the approach [N]
        if delta not in cache:
            cache[delta] = solve_contact(pad, posed, delta)
        sol = cache[delta]
        return float(sol.force_vector @ np.array([0.0, 0.0, 1.0]))

    hi = 0.9 * h  # the rigid back stays clear of the object ...
    try:
        f_hi = axial(hi)
    except ValueError:  # ... unless the object reaches it earlier (a rim, a shoulder beside the pad)
        lo_ok, hi_bad = 0.0, hi
        for _ in range(30):
            mid = 0.5 * (lo_ok + hi_bad)
            try:
                axial(mid)
                lo_ok = mid
            except ValueError:
                hi_bad = mid
        hi, f_hi = lo_ok, axial(lo_ok) if lo_ok > 0 else 0.0
    if f_hi < force:
        raise ValueError(
            f"the pad reaches only {f_hi:.3g} N along the approach at {hi * 1e3:.3g} mm of its "
            f"{h * 1e3:.3g} mm layer (then the object meets the jaw's rigid back or the layer is spent), "
            f"below the reading {force} N: a stiffer or thicker pad, another grasp, or a smaller force"
        )
    # the displacement at the force to round-off-level accuracy: the profile's force matches to 1e-9
    delta = brentq(lambda d: axial(d) - force, 0.0, hi, xtol=1e-12 * h, rtol=1e-10)
    prof = extract_profile(pad, cache.get(delta) or solve_contact(pad, posed, delta), posed)
    if prof is None:  # pragma: no cover - a positive axial force has loaded nodes
        raise ValueError(f"the pad at {np.round(p, 4).tolist()} touches nothing")
    log.debug(
        "fem_jaw_profile: delta %.4g mm, %d elements, %d solves", delta * 1e3, len(prof.areas), len(cache)
    )
    # the pad reaches f_hi here: beyond it a linearly scaled profile describes no real contact
    source = ProfileSource("fem_pad", force, (0.0, f_hi), linear=False)
    return with_axis_force(prof.transformed(R, posed.t), R[:, 2], force).with_source(source)


def check_jaw_reaches(mesh, point: np.ndarray, approach: np.ndarray) -> None:
    """ValueError unless a jaw moving along ``approach`` (3,) unit can meet the object ``mesh``
    [m] at ``point`` (3,) [m]: ``point`` lies within the object's own size of its bounding box
    (:func:`workbench.units.far_from_object`: a point in millimetres is named as one), and the
    object's surface nearest to it faces the jaw, not away from it.

    The jaw sees only faces whose outward normal ``n`` has ``n · approach < 0`` (the one-sided
    :class:`~workbench.fem.obstacles.MeshObstacle` it presses); a point whose nearest face has
    ``n · approach > 0`` is on the object's far side from the jaw — an approach reversed, pointing
    out of the object there — and the pad, started outside the object, would press the opposite
    face instead, a profile at another place than the one asked for.
    """
    from ..units import far_from_object

    far = far_from_object(point, mesh.bounds)
    if far is not None:
        raise ValueError(f"point {far}")
    _, _, face = mesh.nearest.on_surface(point[None, :])
    n = np.asarray(mesh.face_normals[int(face[0])], float)
    # a face along the approach (n · approach = 0: a box's side at the edge of the face pressed)
    # is round-off away from 0; only a face turned away from the jaw is refused
    if float(n @ approach) > 1e-9:

        def shown(v: np.ndarray) -> list:  # rounded, without negative zeros
            return (np.round(v, 3) + 0.0).tolist()

        raise ValueError(
            f"approach {shown(approach)} points away from the object at point "
            f"{np.round(point, 4).tolist()}: the surface there faces {shown(n)} (its outward "
            "normal), so a jaw at the point moving along the approach touches nothing on this side (the "
            "pad would press the object's far side) — pass the direction from the jaw into the object, "
            f"e.g. approach = -normal = {shown(-n)} (jaw 2 of a grasp approaches along -axis)"
        )


def check_pad_geometry(geometry: PadGeometry) -> PadGeometry:
    """``geometry`` if it is a gripper pad's — face (width, length) and layer thickness in their
    plausible ranges (:mod:`workbench.plausible`: a pad in millimetres, 20 for 0.02, is refused
    before the minutes a 4 m² pad takes to condense) — else ValueError."""
    from ..plausible import check

    if not isinstance(geometry, PadGeometry):
        raise ValueError(f"geometry must be a PadGeometry; got {type(geometry).__name__}")
    check("pad_size", geometry.width, "PadGeometry.width")
    check("pad_size", geometry.length, "PadGeometry.length")
    check("pad_thickness", geometry.thickness, "PadGeometry.thickness")
    return geometry


def fem_jaw_profiles(mesh, grasp: dict, force: float, **kw) -> list[ContactProfile]:
    """Both jaws' FEM profiles of an antipodal ``grasp`` (``p1``, ``p2`` [m], ``axis`` from
    jaw 1 into the object, as :func:`workbench.grasp.sampling.horizontal_grasps` gives):
    jaw 1 at ``p1`` along ``axis``, jaw 2 at ``p2`` against it, each at the reading
    ``force`` [N].  Keywords as :func:`fem_jaw_profile` (pass ``pad=`` to condense once), or
    ``geometry=``, ``material=``, ``cache_dir=`` of a :class:`FemPad` in place of ``pad``."""
    p1, p2, axis = check_grasp(grasp)
    if kw.get("pad") is None:
        geometry, material = kw.pop("geometry", None) or PadGeometry(), kw.pop("material", None) or Material()
        kw["pad"] = FemPad(geometry, material, kw.pop("cache_dir", None))
    kw["pad"] = condensed_fem_pad(kw["pad"])  # once, for both jaws
    return [fem_jaw_profile(mesh, p, a, force, **kw) for p, a in ((p1, axis), (p2, -axis))]

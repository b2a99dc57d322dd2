"""The parallel-jaw grasp every jaw-profile source shares (thesis §4.1.3.2, §4.1.4).

A grasp is a dict ``{"p1", "p2", "axis"}`` (:func:`~workbench.grasp.sampling.antipodal_grasps`):
jaw 1 meets the object at ``p1`` approaching along ``axis``, jaw 2 at ``p2`` against it.
Each jaw has a frame (approach, pad width axis, pad length axis) and a force-sensor
reading along the grasp axis to which its profile is scaled.  REACH
(:mod:`~workbench.sources.reach`) and the FEM pad (:mod:`~workbench.sources.fem_jaw`) make
jaw profiles with these; :func:`checked_jaw_profile` is the check a profile of *any* source
passes before grasp analysis uses it as a jaw's contact: it lies at its jaw (pressure centre
in the pad's footprint, no deeper than the jaw advances past the grasp point,
``config.TOL.jaw_profile_*``), pushes, and is scaled to the reading within the readings its
source holds for (:class:`~workbench.profile.ProfileSource`, :func:`check_source_force`).
"""

from __future__ import annotations

import warnings

import numpy as np

from .. import config
from ..profile import ContactProfile

__all__ = [
    "check_grasp",
    "check_jaw_force",
    "check_jaw_position",
    "check_pad",
    "check_source_force",
    "checked_jaw_profile",
    "jaw_frame",
    "placed_jaw_profile",
    "with_axis_force",
]


def check_jaw_force(force) -> float:
    """``force`` (a jaw's force-sensor reading [N]) as a float if it is a plausible jaw force,
    ``(0, 500]`` N (:data:`workbench.plausible.RANGES` ``"jaw_force"``, the one rule; a bool is not a
    number here: ``force=True`` is a slip, not 1 N), else ValueError naming the likely slip."""
    from ..plausible import check

    if isinstance(force, (np.integer, np.floating)):
        force = force.item()
    try:
        return check("jaw_force", force, "force (each jaw's reading [N])")
    except ValueError as exc:
        raise ValueError(
            f"{exc}; a total force of both jaws is twice a jaw's (Gripper.with_total_force halves a total)"
        ) from None


def check_pad(pad) -> None:
    """ValueError unless ``pad`` is the jaw face ``(width, length)`` [m], two finite numbers > 0."""
    try:
        size = np.asarray(pad, dtype=float)
    except (TypeError, ValueError):
        size = np.full(0, np.nan)
    if isinstance(pad, str) or size.shape != (2,) or not (np.isfinite(size).all() and (size > 0).all()):
        raise ValueError(
            f"pad must be the jaw face (width, length) [m], two numbers > 0, e.g. (0.02, 0.04); got {pad!r}"
        )
    from ..plausible import RANGES, check, check_each

    check_each("pad_size", size, "pad (width, length) [m]", warn=False)
    lo, hi = RANGES["pad_size"].usual
    unusual = [v for v in size if not lo <= v <= hi]
    if unusual:  # one warning for the pad, not one per side
        check("pad_size", float(unusual[0]), "pad (width, length) [m]")


def check_grasp(grasp) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(p1, p2, unit axis)``, each (3,), of a grasp dict, or a ValueError naming what is missing
    or not finite — or p1 and p2 less than ``config.TOL.min_grasp_width_m`` apart (no line for the jaws to
    close along), a zero axis, or an axis more than ``config.TOL.grasp_axis_max_deg`` from the
    line p1 → p2 (parallel jaws close along the line through both contact points)."""
    if not isinstance(grasp, dict) or any(k not in grasp for k in ("p1", "p2", "axis")):
        got = sorted(grasp) if isinstance(grasp, dict) else type(grasp).__name__
        raise ValueError(
            "grasp must be a dict with 'p1', 'p2' (contact points [m]) and 'axis' (unit vector from "
            f"jaw 1 into the object), as antipodal_grasps returns; got {got}"
        )
    try:
        p1, p2, axis = (np.asarray(grasp[k], float) for k in ("p1", "p2", "axis"))
    except (TypeError, ValueError):
        p1 = p2 = axis = np.full(0, np.nan)
    if p1.shape != (3,) or p2.shape != (3,) or axis.shape != (3,):
        raise ValueError(
            f"grasp p1, p2, axis must be (3,) vectors, axis non-zero; got {grasp['p1']!r}, {grasp['p2']!r}, "
            f"{grasp['axis']!r}"
        )
    for name, v in (("p1", p1), ("p2", p2), ("axis", axis)):
        if not np.isfinite(v).all():
            raise ValueError(
                f"grasp {name} must be finite (3 numbers [m]{', a direction' if name == 'axis' else ''}); "
                f"got {v.tolist()} — a NaN or inf from an upstream computation (a failed projection, "
                "a division by a zero length?)"
            )
    width = float(np.linalg.norm(p2 - p1))
    narrowest = config.TOL.min_grasp_width_m
    if width < narrowest:
        raise ValueError(
            f"grasp p1 and p2 must be two contact points at least {narrowest * 1e3:g} mm apart (the "
            f"jaws close on the object between them); got a width of {width * 1e3:.3g} mm, p1 = "
            f"{p1.tolist()}, p2 = {p2.tolist()} — pass the points where each jaw meets the object, as "
            "antipodal_grasps does (p2 given as p1?)"
        )
    if not np.linalg.norm(axis) > 0:
        d = (p2 - p1) / width
        raise ValueError(
            f"grasp axis must be a direction (axis non-zero); got {axis.tolist()}, a zero vector, which "
            f"gives the jaws no closing direction — pass axis = (p2 - p1) / |p2 - p1| = {d.round(6).tolist()}"
        )
    from ..config import TOL

    u, d = axis / np.linalg.norm(axis), p2 - p1
    angle = float(np.degrees(np.arccos(np.clip(u @ d / np.linalg.norm(d), -1.0, 1.0))))
    if angle > TOL.grasp_axis_max_deg:
        raise ValueError(
            f"grasp axis {u.round(4).tolist()} is {angle:.1f} deg from the line p1 → p2 (at most "
            f"{TOL.grasp_axis_max_deg:g}, config.TOL.grasp_axis_max_deg): parallel jaws close along "
            "the line through both contact points — pass axis = (p2 - p1) / |p2 - p1|"
            + (" (p1 and p2 swapped?)" if angle > 90 else "")
        )
    return p1, p2, u


def check_direction(vector, name: str, meaning: str) -> np.ndarray:
    """``vector`` as a unit (3,) direction, or a ValueError naming ``name`` (``meaning``: what it
    is and an example) — a zero or non-finite one has no direction to normalise."""
    try:
        v = np.asarray(vector, dtype=float)
    except (TypeError, ValueError):
        v = np.full(0, np.nan)
    norm = float(np.linalg.norm(v)) if v.shape == (3,) and np.isfinite(v).all() else 0.0
    if not norm > 0:
        raise ValueError(
            f"{name} must be a non-zero finite (3,) direction ({meaning}); got {vector!r}"
            + (" — a zero vector has no direction" if v.shape == (3,) and np.isfinite(v).all() else "")
        )
    return v / norm


def jaw_frame(approach, up) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit (approach a, width axis e1, length axis e2), each (3,), with e2 the part of ``up`` ⟂ a."""
    a = check_direction(approach, "approach", "the jaw's closing direction, into the object")
    u = check_direction(up, "up", "the pad's length direction, across the approach")
    e2 = u - (u @ a) * a
    # e2 is a cross product of unit vectors: below 1e-9 they are parallel (pick another axis)
    if np.linalg.norm(e2) < 1e-9:
        raise ValueError("up must not be parallel to the approach direction")
    e2 /= np.linalg.norm(e2)
    return a, np.cross(e2, a), e2


def check_source_force(profile: ContactProfile, force: float) -> None:
    """Whether the reading ``force`` [N] is one ``profile``'s source holds for
    (:class:`~workbench.profile.ProfileSource`; nothing to check without one): ValueError
    outside its ``force_range``; for a source whose distribution changes with force
    (``linear=False``, the FEM pad), a ``UserWarning`` when ``force`` is more than
    ``config.TOL.profile_force_ratio_warn`` (read now) away from the reading it was made at."""
    src = profile.source
    if src is None:
        return
    lo, hi = src.force_range
    if not lo <= force <= hi:
        raise ValueError(
            f"a reading of {force:.6g} N is outside what the profile's source can produce: {src.name} made "
            f"it at {src.force:.6g} N and reaches [{lo:.6g}, {hi:.6g}] N on this contact, so scaling it "
            "linearly would describe a contact that cannot exist — ask for a force in that range, or make "
            "the profiles at this force with their source (e.g. fem_jaw_profiles(mesh, grasp, force))"
        )
    ratio = force / src.force
    limit = config.TOL.profile_force_ratio_warn
    if not src.linear and max(ratio, 1.0 / ratio) > limit:
        warnings.warn(
            f"a {src.name} profile made at {src.force:.6g} N is scaled to {force:.6g} N (x{ratio:.3g}): "
            "its pressure distribution changes with force (the contact grows as it is pressed), so the "
            f"scaled one is not the source's at {force:.6g} N (config.TOL.profile_force_ratio_warn = "
            f"{limit:g}) — make the profiles at this force",
            UserWarning,
            stacklevel=3,
        )


def with_axis_force(profile: ContactProfile, axis, force: float) -> ContactProfile:
    """The profile's pressures scaled so its normal force along ``axis`` (3,) has magnitude
    ``force`` [N] — a force-sensor reading along the grasp axis (thesis §4.1.3.2).  The
    profile's ``source`` is kept, and ``force`` checked against it (:func:`check_source_force`)."""
    check_source_force(profile, force)
    a = np.asarray(axis, float)
    fa = abs(float(profile.normal_wrench[:3] @ (a / np.linalg.norm(a))))
    if not fa > 0:
        raise ValueError("the profile has no normal force along the axis")
    return profile.with_pressures(profile.pressures * force / fa, source=profile.source)


def check_jaw_position(prof: ContactProfile, point: np.ndarray, approach: np.ndarray, pad) -> None:
    """ValueError unless ``prof`` lies at the jaw at ``point`` (3,) [m] approaching along
    ``approach`` (3,) with face ``pad = (width, length)`` [m]: its pressure centre within
    half the pad's diagonal of ``point`` in the pad plane, times
    ``1 + config.TOL.jaw_profile_plane_rtol`` (the footprint, whatever the pad's turn about
    the approach), and at most ``config.TOL.jaw_profile_depth_rtol`` times that half-diagonal
    deeper into the object than ``point`` along the approach (both read now).  Towards the jaw
    nothing is bounded: a pad stopped by a rim or a tilted face before it reaches the grasp
    point presses there, so a profile of a narrower grasp of the same face passes."""
    a = np.asarray(approach, float)
    a = a / np.linalg.norm(a)
    d = prof.pressure_center - np.asarray(point, float)
    along = float(d @ a)
    plane = float(np.linalg.norm(d - along * a))
    half = 0.5 * float(np.hypot(*pad))
    where = f"its jaw's contact point {np.round(point, 4).tolist()}"
    fix = "a profile of another grasp, pose or unit? Make the profiles at this grasp"
    if plane > half * (1.0 + config.TOL.jaw_profile_plane_rtol):
        raise ValueError(
            f"the profile's pressure centre is {plane * 1e3:.3g} mm from {where} in the pad plane, outside "
            f"the pad's footprint (half the pad's diagonal, {half * 1e3:.3g} mm, times 1 + "
            f"config.TOL.jaw_profile_plane_rtol = {config.TOL.jaw_profile_plane_rtol:g}): {fix}"
        )
    depth = config.TOL.jaw_profile_depth_rtol * half
    if along > depth:  # the jaw touches at or before its point, then advances by its compression
        raise ValueError(
            f"the profile's pressure centre is {along * 1e3:.3g} mm into the object from {where} along "
            f"the approach, more than the jaw advances past its first touch ({depth * 1e3:.3g} mm, "
            f"config.TOL.jaw_profile_depth_rtol = {config.TOL.jaw_profile_depth_rtol:g} of half the "
            f"pad's diagonal): {fix}"
        )


def checked_jaw_profile(
    prof, point: np.ndarray, approach: np.ndarray, force: float, pad: tuple[float, float]
) -> ContactProfile:
    """One jaw's profile, from any source, checked and scaled to the reading ``force`` [N].

    point : (3,) the jaw's contact point [m]; approach : (3,) unit, from the jaw into the
    object; pad : the jaw face ``(width, length)`` [m].  Raises ValueError unless ``prof``
    is a :class:`ContactProfile` at its jaw (:func:`check_jaw_position`) whose net normal
    force pushes the object along ``approach`` (normals out of the object, CONVENTIONS.md),
    and ``force`` is a reading its source holds for (:func:`check_source_force`).
    """
    if not isinstance(prof, ContactProfile):
        raise ValueError(f"profiles must be ContactProfile objects, one per jaw; got {type(prof).__name__}")
    check_pad(pad)
    return placed_jaw_profile(prof, point, approach, force, pad)


def placed_jaw_profile(
    prof: ContactProfile, point: np.ndarray, approach: np.ndarray, force: float, pad: tuple[float, float]
) -> ContactProfile:
    """:func:`checked_jaw_profile` of a ContactProfile ``prof`` and a ``pad`` already checked
    (:func:`check_pad`): its place at the jaw and its push checked, scaled to ``force`` [N]."""
    check_jaw_position(prof, point, approach, pad)
    # the jaw pushes the object along its approach: −Σ p a n · approach > 0
    push = float(prof.normal_wrench[:3] @ approach)
    if not push > 0:
        raise ValueError(
            f"the jaw at {np.round(point, 4).tolist()} would pull the object (net normal force "
            f"{push:.3g} N along its approach): the profile's normals point into the object, "
            "or the approach is reversed; normals must point out of the object (CONVENTIONS.md)"
        )
    return with_axis_force(prof, approach, force)

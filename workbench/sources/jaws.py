"""The parallel-jaw grasp every jaw-profile source shares (thesis §4.1.3.2, §4.1.4).

A grasp is a dict ``{"p1", "p2", "axis"}`` (:func:`~workbench.grasp.sampling.antipodal_grasps`):
jaw 1 meets the object at ``p1`` approaching along ``axis``, jaw 2 at ``p2`` against it.
Each jaw has a frame (approach, pad width axis, pad length axis) and a force-sensor
reading along the grasp axis to which its profile is scaled.  REACH
(:mod:`~workbench.sources.reach`) and the FEM pad (:mod:`~workbench.sources.fem_jaw`) make
jaw profiles with these; :func:`checked_jaw_profile` is the check a profile of *any* source
passes before grasp analysis uses it as a jaw's contact.
"""

from __future__ import annotations

import numbers

import numpy as np

from ..profile import ContactProfile

__all__ = [
    "check_grasp",
    "check_jaw_force",
    "check_pad",
    "checked_jaw_profile",
    "jaw_frame",
    "with_axis_force",
]


def check_jaw_force(force) -> None:
    """ValueError unless ``force`` (a jaw's force-sensor reading [N]) is a finite number > 0
    (a bool is not a number here: ``force=True`` is a slip, not 1 N)."""
    if (
        isinstance(force, (bool, np.bool_))
        or not isinstance(force, numbers.Real)
        or not (np.isfinite(force) and force > 0)
    ):
        raise ValueError(f"force must be the jaw's reading in newtons, finite and > 0; got {force!r}")


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


def check_grasp(grasp) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(p1, p2, unit axis)``, each (3,), of a grasp dict, or a ValueError naming what is missing."""
    if not isinstance(grasp, dict) or any(k not in grasp for k in ("p1", "p2", "axis")):
        got = sorted(grasp) if isinstance(grasp, dict) else type(grasp).__name__
        raise ValueError(
            "grasp must be a dict with 'p1', 'p2' (contact points [m]) and 'axis' (unit vector from "
            f"jaw 1 into the object), as antipodal_grasps returns; got {got}"
        )
    p1, p2, axis = (np.asarray(grasp[k], float) for k in ("p1", "p2", "axis"))
    if p1.shape != (3,) or p2.shape != (3,) or axis.shape != (3,) or not np.linalg.norm(axis) > 0:
        raise ValueError(f"grasp p1, p2, axis must be (3,) vectors, axis non-zero; got {p1}, {p2}, {axis}")
    return p1, p2, axis / np.linalg.norm(axis)


def jaw_frame(approach, up) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit (approach a, width axis e1, length axis e2), each (3,), with e2 the part of ``up`` ⟂ a."""
    a = np.asarray(approach, float)
    a = a / np.linalg.norm(a)
    e2 = np.asarray(up, float) - (np.asarray(up, float) @ a) * a
    # e2 is a cross product of unit vectors: below 1e-9 they are parallel (pick another axis)
    if np.linalg.norm(e2) < 1e-9:
        raise ValueError("up must not be parallel to the approach direction")
    e2 /= np.linalg.norm(e2)
    return a, np.cross(e2, a), e2


def with_axis_force(profile: ContactProfile, axis, force: float) -> ContactProfile:
    """The profile's pressures scaled so its normal force along ``axis`` (3,) has magnitude
    ``force`` [N] — a force-sensor reading along the grasp axis (thesis §4.1.3.2)."""
    a = np.asarray(axis, float)
    fa = abs(float(profile.normal_wrench[:3] @ (a / np.linalg.norm(a))))
    if not fa > 0:
        raise ValueError("the profile has no normal force along the axis")
    return profile.with_pressures(profile.pressures * force / fa)


def checked_jaw_profile(
    prof, point: np.ndarray, approach: np.ndarray, force: float, pad: tuple[float, float]
) -> ContactProfile:
    """One jaw's profile, from any source, checked and scaled to the reading ``force`` [N].

    point : (3,) the jaw's contact point [m]; approach : (3,) unit, from the jaw into the
    object; pad : the jaw face ``(width, length)`` [m].  Raises ValueError unless ``prof``
    is a :class:`ContactProfile` whose pressure centre lies within the pad's diagonal of
    ``point`` and whose net normal force pushes the object along ``approach``
    (normals out of the object, CONVENTIONS.md).
    """
    if not isinstance(prof, ContactProfile):
        raise ValueError(f"profiles must be ContactProfile objects, one per jaw; got {type(prof).__name__}")
    check_pad(pad)
    off = float(np.linalg.norm(prof.pressure_center - point))
    if off > float(np.hypot(*pad)):
        raise ValueError(
            f"the profile's pressure centre is {off:.3g} m from its jaw's contact point "
            f"{np.round(point, 4).tolist()} (more than the pad's diagonal): a profile of another grasp, "
            "pose or unit?"
        )
    # the jaw pushes the object along its approach: −Σ p a n · approach > 0
    push = float(prof.normal_wrench[:3] @ approach)
    if not push > 0:
        raise ValueError(
            f"the jaw at {np.round(point, 4).tolist()} would pull the object (net normal force "
            f"{push:.3g} N along its approach): the profile's normals point into the object, "
            "or the approach is reversed; normals must point out of the object (CONVENTIONS.md)"
        )
    return with_axis_force(prof, approach, force)

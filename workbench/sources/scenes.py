"""Contact profiles of grasp scenes with closed-form geometry (thesis §4.1.3).

:func:`elliptic_cylinder_grasp` — a parallel-jaw grasp of an elliptic cylinder
(axis z, grasp axis x, jaws at ±x), each contact an elliptic-cylinder patch with
the modified power-law pressure of Eq. 4.3: ``p̂(r) = p0 [1 − (r/r_max)^k]^(1/k)``
with ``r = |y|`` (constant along the cylinder axis, as in the thesis's FEM,
Fig 4.2), scaled so the grasp-axis component of the normal force is ``F``
(the force-sensor reading, §4.1.3.2).
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

from ..pressure import power_law
from ..profile import ContactProfile
from .surfaces import ParametricSurface, mesh_profile

#: the scene's lengths and angle: (argument, what a message calls it, plausible quantity)
_GEOMETRY = (
    ("a", "a (ellipse semi-axis along the grasp axis)", "lever"),
    ("b", "b (ellipse semi-axis across the grasp axis)", "lever"),
    ("half_angle", "half_angle (the contact's angular half-width)", "half_angle"),
    ("length", "length (the contact's length along the cylinder axis)", "pad_size"),
)


def check_elliptic_cylinder(
    a: Any, b: Any, half_angle: Any, length: Any
) -> tuple[float, float, float, float]:
    """``(a, b, half_angle, length)`` as floats if they describe the scene, else ``ValueError``:
    each > 0 and finite, then a plausible value of its quantity
    (:func:`workbench.plausible.check`: the semi-axes as offsets on the object, ``"lever"``;
    ``half_angle`` as ``"half_angle"``; ``length`` as a pad's size — so ``a=30`` is named as
    "probably in millimetres — pass 0.03" and ``half_angle=34`` as "probably in degrees"),
    and ``half_angle < π/2`` (one jaw's side).  Lengths in metres, the angle in radians.  The
    experiments call it to refuse a config before any work."""
    from ..plausible import check

    values = {"a": a, "b": b, "half_angle": half_angle, "length": length}
    for name, v in values.items():
        if (
            isinstance(v, (bool, np.bool_))
            or not isinstance(v, numbers.Real)
            or not (np.isfinite(v) and v > 0)
        ):
            raise ValueError(f"{name} must be > 0 and finite; got {v!r}")
    # beyond π the angle was given in degrees (the plausible rule names it); up to π it is in
    # radians but not one jaw's side
    if np.pi / 2 <= half_angle <= np.pi:
        raise ValueError(
            f"half_angle must be < π/2 (one jaw's side of the cylinder) [rad]; got {half_angle!r} — "
            "a jaw wrapping a quarter of the section or more is not this scene"
        )
    # the semi-axes are judged as lengths on an object, quoted as what they are
    examples = {"a": "objects a parallel jaw grips are 10-100 mm across their grasp axis (semi-axis 5-50 mm)"}
    examples["b"] = examples["a"]
    out = {
        name: check(
            key,
            values[name],
            what,
            examples=examples.get(name),
            named="semi-axis" if name in examples else None,
        )
        for name, what, key in _GEOMETRY
    }
    return out["a"], out["b"], out["half_angle"], out["length"]


def elliptic_cylinder_contact(
    a: float, b: float, half_angle: float, length: float, k: float, force: float, n_elements: int = 400
) -> ContactProfile:
    """The +x jaw's contact: ``[a cos u, b sin u, z]``, ``|u| <= half_angle``, ``|z| <= length/2``.

    a, b : semi-axes [m]; half_angle [rad]; length [m]; each checked by
    :func:`check_elliptic_cylinder`.  force : the jaw's reading [N]."""
    from .jaws import check_jaw_force

    check_jaw_force(force)  # the jaw's reading: the one rule of a jaw force
    a, b, half_angle, length = check_elliptic_cylinder(a, b, half_angle, length)
    r_max = b * np.sin(half_angle)

    def pressure(u, v, xyz):
        return power_law(np.abs(xyz[..., 1]), r_max, k)

    surf = ParametricSurface(
        "elliptic cylinder contact",
        lambda u, v: np.stack(np.broadcast_arrays(a * np.cos(u), b * np.sin(u), v), axis=-1),
        (-half_angle, half_angle),
        (-length / 2, length / 2),
        pressure=pressure,
    )
    prof = mesh_profile(surf, n_elements)
    fx = -prof.normal_wrench[0]  # the jaw pushes the object along -x
    return prof.with_pressures(prof.pressures * force / fx)


def elliptic_cylinder_grasp(
    a: float = 0.03,
    b: float = 0.02,
    half_angle: float = 0.6,
    length: float = 0.03,
    k: float = 2.4,
    force: float = 25.0,
    n_elements: int = 400,
) -> list[ContactProfile]:
    """Both jaws' profiles (the −x jaw is the +x one turned by π about z); arguments as
    :func:`elliptic_cylinder_contact` (lengths in metres, ``half_angle`` in radians)."""
    right = elliptic_cylinder_contact(a, b, half_angle, length, k, force, n_elements)
    left = right.transformed(np.diag([-1.0, -1.0, 1.0]), np.zeros(3))
    return [right, left]


def elliptic_cylinder_solid(
    a: float = 0.03, b: float = 0.02, half_angle: float = 0.6, length: float = 0.03, n_arc: int = 25
) -> Any:
    """The scene's object as a closed trimesh [m]: the convex hull of both jaws' contact
    patches (``[±a cos u, b sin u, z]``, ``|u| <= half_angle``, ``|z| <= length/2``) — an
    elliptic cylinder cut so that a jaw wrapping it touches exactly the patch, as the thesis's
    3D-printed type I objects are (§4.1.3.2).  ``n_arc`` points per patch arc (an odd count
    keeps the apex ``u = 0``, where the grasp points are); arguments
    checked by :func:`check_elliptic_cylinder`."""
    import trimesh

    a, b, half_angle, length = check_elliptic_cylinder(a, b, half_angle, length)
    if isinstance(n_arc, bool) or not isinstance(n_arc, numbers.Integral) or n_arc < 2:
        raise ValueError(f"n_arc must be an integer >= 2 (points per arc); got {n_arc!r}")
    u = np.linspace(-half_angle, half_angle, int(n_arc))
    arc = np.c_[a * np.cos(u), b * np.sin(u)]
    ring = np.r_[arc, -arc]
    pts = np.concatenate([np.c_[ring, np.full(len(ring), z)] for z in (-length / 2, length / 2)])
    return trimesh.convex.convex_hull(pts)


def elliptic_cylinder_patch_extent(
    a: float, b: float, half_angle: float, length: float
) -> tuple[float, float]:
    """(width, length) [m] of one jaw's contact patch seen along the grasp axis: ``width`` the
    chord between its edges ``u = ±half_angle`` (``[a cos u, ±b sin u]``), ``2 b sin(half_angle)``
    — twice the pressure's ``r_max`` of Eq. 4.3 in :func:`elliptic_cylinder_contact` — and the
    contact ``length`` along the cylinder axis z.  A flat jaw pad of this size, moulded to the
    patch, touches exactly the patch of :func:`elliptic_cylinder_solid`.  Arguments checked by
    :func:`check_elliptic_cylinder` (lengths in metres, ``half_angle`` in radians)."""
    a, b, half_angle, length = check_elliptic_cylinder(a, b, half_angle, length)
    return float(2 * b * np.sin(half_angle)), length

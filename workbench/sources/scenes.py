"""Contact profiles of grasp scenes with closed-form geometry (thesis §4.1.3).

:func:`elliptic_cylinder_grasp` — a parallel-jaw grasp of an elliptic cylinder
(axis z, grasp axis x, jaws at ±x), each contact an elliptic-cylinder patch with
the modified power-law pressure of Eq. (4.3): ``p̂(r) = p0 [1 − (r/r_max)^k]^(1/k)``
with ``r = |y|`` (constant along the cylinder axis, as in the thesis's FEM,
Fig 4.2), scaled so the grasp-axis component of the normal force is ``F``
(the force-sensor reading, §4.1.3.2).
"""

from __future__ import annotations

import numpy as np

from ..pressure import power_law
from ..profile import ContactProfile
from .surfaces import ParametricSurface, mesh_profile


def elliptic_cylinder_contact(
    a: float, b: float, half_angle: float, length: float, k: float, force: float, n_elements: int = 400
) -> ContactProfile:
    """The +x jaw's contact: ``[a cos u, b sin u, z]``, ``|u| <= half_angle``, ``|z| <= length/2``."""
    from .jaws import check_jaw_force

    check_jaw_force(force)  # the jaw's reading: the one rule of a jaw force
    for name, v in (("a", a), ("b", b), ("half_angle", half_angle), ("length", length)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be > 0; got {v}")
    if half_angle >= np.pi / 2:
        raise ValueError(f"half_angle must be < π/2 (one jaw's side); got {half_angle}")
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
    """Both jaws' profiles (the −x jaw is the +x one turned by π about z)."""
    right = elliptic_cylinder_contact(a, b, half_angle, length, k, force, n_elements)
    left = right.transformed(np.diag([-1.0, -1.0, 1.0]), np.zeros(3))
    return [right, left]

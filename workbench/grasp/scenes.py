"""Contact scenes with closed-form geometry for grasp experiments (thesis §4.1.3).

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
from ..surfaces import ParametricSurface, mesh_profile


def elliptic_cylinder_contact(
    a: float, b: float, half_angle: float, length: float, k: float, force: float, n_elements: int = 400
) -> ContactProfile:
    """The +x jaw's contact: ``[a cos u, b sin u, z]``, ``|u| <= half_angle``, ``|z| <= length/2``."""
    for name, v in (("a", a), ("b", b), ("half_angle", half_angle), ("length", length), ("force", force)):
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


def lever_disturbances(
    rng: np.random.Generator, n: int, weight_range=(1.0, 14.0), lever_x: float = 0.06, lever_z: float = 0.08
) -> np.ndarray:
    """(n, 6) disturbances of the thesis's §4.1.3.1 kind for the grasp above: weights
    ``m g`` in ``weight_range`` [N] (along −y) hung at lever arms ``|r_x| <= lever_x``,
    ``|r_z| <= lever_z`` [m] (``τ_x = r_z m g``, ``τ_z = −r_x m g``), plus small f_z, τ_y
    noise; nothing along the grasp axis x, which those setups never load and a planar
    3DLS cannot resist by construction (§4.1.3.4)."""
    mg = rng.uniform(*weight_range, n)
    rx = rng.uniform(-lever_x, lever_x, n)
    rz = rng.uniform(-lever_z, lever_z, n)
    w = np.zeros((n, 6))
    w[:, 1] = -mg
    w[:, 3] = rz * mg
    w[:, 5] = -rx * mg
    return w + rng.normal(0.0, 1.0, (n, 6)) * [0.0, 0.3, 0.3, 0.003, 0.003, 0.003]

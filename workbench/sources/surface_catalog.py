"""The thesis's parametric contact surfaces: S1-S6 (Table 3.1) and the
cylinder patch of Example 3.2.5, with analytic derivatives.

Normals are oriented outward from the object: from the axis for the
cylinders, from the center for the sphere/ellipsoid (``flip=True`` because
``σ_u × σ_v`` points inward there), and away from the convex body
``z ≥ r²`` for the paraboloids.  All are symmetric about the yz-plane.
"""

from __future__ import annotations

import numpy as np

from .surfaces import ParametricSurface

PI = np.pi


def _stack(*cols):
    return np.stack(np.broadcast_arrays(*cols), axis=-1)


def elliptic_cylinder(
    a: float, b: float, name: str, u_range=(0.0, PI), v_range=(0.0, 1.0)
) -> ParametricSurface:
    """``[a cos u, b sin u, v]``."""
    return ParametricSurface(
        name,
        lambda u, v: _stack(a * np.cos(u), b * np.sin(u), v),
        u_range,
        v_range,
        lambda u, v: _stack(-a * np.sin(u), b * np.cos(u), 0.0 * u),
        lambda u, v: _stack(0.0 * u, 0.0 * u, 1.0 + 0.0 * v),
        description=f"elliptic cylinder a={a}, b={b}",
    )


def ellipsoid_patch(a: float, b: float, c: float, name: str) -> ParametricSurface:
    """``[a cos u cos v, b cos u sin v, c sin u]`` on ``[-π/2, π/2] × [0, π]``."""
    return ParametricSurface(
        name,
        lambda u, v: _stack(a * np.cos(u) * np.cos(v), b * np.cos(u) * np.sin(v), c * np.sin(u)),
        (-0.5 * PI, 0.5 * PI),
        (0.0, PI),
        lambda u, v: _stack(-a * np.sin(u) * np.cos(v), -b * np.sin(u) * np.sin(v), c * np.cos(u)),
        lambda u, v: _stack(-a * np.cos(u) * np.sin(v), b * np.cos(u) * np.cos(v), 0.0 * u),
        flip=True,
        description=f"ellipsoid a={a}, b={b}, c={c}",
    )


def elliptic_paraboloid(a: float, b: float, name: str) -> ParametricSurface:
    """``[a v cos u, b v sin u, v²]`` on ``[0, π] × [0, 1]``."""
    return ParametricSurface(
        name,
        lambda u, v: _stack(a * v * np.cos(u), b * v * np.sin(u), v * v),
        (0.0, PI),
        (0.0, 1.0),
        lambda u, v: _stack(-a * v * np.sin(u), b * v * np.cos(u), 0.0 * u),
        lambda u, v: _stack(a * np.cos(u), b * np.sin(u), 2.0 * v),
        description=f"elliptic paraboloid a={a}, b={b}",
    )


S1 = elliptic_cylinder(1.0, 1.0, "S1")
S2 = elliptic_cylinder(1.0, 0.5, "S2")
S3 = ellipsoid_patch(1.0, 1.0, 1.0, "S3")
S4 = ellipsoid_patch(1.0, 0.5, 0.6, "S4")
S5 = elliptic_paraboloid(1.0, 1.0, "S5")
S6 = elliptic_paraboloid(1.0, 0.5, "S6")

#: Table 3.1, in order.
THESIS_SURFACES: dict[str, ParametricSurface] = {s.name: s for s in (S1, S2, S3, S4, S5, S6)}

#: xz-plane normal used for the planar baseline of Table 3.2.
PLANAR_NORMAL = np.array([0.0, 1.0, 0.0])


def example_3_2_5() -> ParametricSurface:
    """Example 3.2.5: ``[0.02 cos u, 0.02 sin u, v]``, ``u ∈ [π/4, 3π/4]``,
    ``v ∈ [-0.05, -0.03]`` m, uniform ``p = 10³`` Pa (use with μ = 0.3)."""
    return elliptic_cylinder(
        0.02, 0.02, "example-3.2.5", (0.25 * PI, 0.75 * PI), (-0.05, -0.03)
    ).with_pressure_scale(1e3)

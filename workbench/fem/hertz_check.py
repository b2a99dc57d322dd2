"""The condensed pad against Hertz: a rigid sphere pressed into a thick block.

Hertz (frictionless sphere of radius ``R`` on an elastic half-space, ``E* = E / (1 − ν²)``):
contact radius ``a = (3 F R / (4 E*))^(1/3)``, peak pressure ``p₀ = 3 F / (2π a²)`` and the
pressure ``p = p₀ √(1 − r²/a²)`` (Eq. 2.14 with k = 2).  :func:`hertz_block_case` presses
a graded ``40 × 40 × 20`` mm block (about 13 a deep at a = 1.5 mm, so nearly a half-space)
and compares a and p₀ with these formulas evaluated at the FE force.
"""

from __future__ import annotations

import time

import numpy as np

from .contact import solve_contact
from .extract import face_grid, nodal_pressures
from .material import Material
from .obstacles import Sphere
from .pad import PadGeometry, condense_pad

__all__ = ["fit_hertz_pressure", "hertz_block_case", "hertz_contact_radius", "hertz_peak_pressure"]


def hertz_contact_radius(force: float, R: float, e_star: float) -> float:
    """Hertz contact radius ``a = (3 F R / (4 E*))^(1/3)`` [m] of a sphere of radius ``R`` [m]
    pressed with ``force`` [N] on a half-space of plane-strain modulus ``e_star`` [Pa]."""
    return (3 * force * R / (4 * e_star)) ** (1 / 3)


def hertz_peak_pressure(force: float, a: float) -> float:
    """Hertz peak (central) pressure ``p₀ = 3 F / (2π a²)`` [Pa] for ``force`` [N] on a
    contact disc of radius ``a`` [m]: the mean pressure ``F / (π a²)`` times 3/2."""
    return 3 * force / (2 * np.pi * a**2)


def fit_hertz_pressure(r: np.ndarray, p: np.ndarray) -> tuple[float, float]:
    """``(a, p₀)`` of the Hertz profile through nodal pressures ``p`` (n,) [Pa] at radii
    ``r`` (n,) [m]: the least-squares line ``p² = p₀² − (p₀²/a²) r²`` in ``r²`` (Eq. 2.14 with
    k = 2, squared).  Pass nodes well inside the contact: the line holds only where p > 0."""
    slope, icpt = np.polyfit(r**2, p**2, 1)
    return float(np.sqrt(-icpt / slope)), float(np.sqrt(icpt))


def hertz_block_case(
    fine_size: float, growth: float, R: float = 0.02, a_target: float = 0.0015, nu: float = 0.3
) -> dict:
    """Rigid sphere of radius ``R`` [m] into a 40 × 40 × 20 mm block (E = 1 MPa, Poisson
    ratio ``nu``) by ``δ = a_target² / R``, on a mesh of hexes ``fine_size`` [m] within
    ``1.6 a_target`` of the contact, growing by ``growth`` (> 1) per element outside it; the
    pad is condensed on a patch of radius ``1.5 a_target``.

    a from :func:`fit_hertz_pressure` over the active nodes with r < 0.8 a (robust to the
    ±h/2 bias of counting active nodes, also reported as ``a_area_rel_err``); p₀ as the
    central nodal pressure (and from the fit).  Both relative to Hertz at the FE force.

    Returns one row: ``fine_size_mm``, ``a_over_h`` (a_target / fine_size), ``dofs``, ``F_N``,
    ``a_hertz_mm``, ``a_fit_mm``, ``a_rel_err``, ``a_area_rel_err``, ``p0_hertz_Pa``,
    ``p0_rel_err``, ``p0_fit_rel_err``, ``patch_edge_force_N`` (force beyond 1.4 a_target:
    0 when the patch holds the contact) and ``condense_s`` (the condensation's wall time,
    without a disk cache).
    """
    if not growth > 1:
        raise ValueError(
            f"growth must be > 1 (the mesh coarsens geometrically away from the contact); got {growth!r}"
            " — pass e.g. 1.35"
        )
    mat = Material(1.0e6, nu)
    e_star = mat.E / (1 - nu**2)
    geom = PadGeometry(0.04, 0.04, 0.02, grading=(1.6 * a_target, fine_size, growth))
    t0 = time.perf_counter()
    pad = condense_pad(geom, mat, patch_radius=1.5 * a_target, cache_dir=False)  # timed: no disk cache
    t_cond = time.perf_counter() - t0
    sol = solve_contact(pad, Sphere((0, 0, geom.thickness + R), R), a_target**2 / R)
    _, area = face_grid(pad.face_xy)
    p = nodal_pressures(pad, sol.lam)
    r = np.hypot(*pad.face_xy.T)
    F = sol.force
    a_h = hertz_contact_radius(F, R, e_star)
    p0_h = hertz_peak_pressure(F, a_h)
    sel = (sol.lam > 0) & (r < 0.8 * a_h)
    a_fit, p0_fit = fit_hertz_pressure(r[sel], p[sel])
    x, y, z = geom.axes()
    return {
        "fine_size_mm": fine_size * 1e3,
        "a_over_h": a_target / fine_size,
        "dofs": 3 * x.size * y.size * z.size,
        "F_N": F,
        "a_hertz_mm": a_h * 1e3,
        "a_fit_mm": a_fit * 1e3,
        "a_rel_err": a_fit / a_h - 1,
        "a_area_rel_err": float(np.sqrt(area[sol.lam > 0].sum() / np.pi) / a_h - 1),
        "p0_hertz_Pa": p0_h,
        "p0_rel_err": float(p[np.argmin(r)] / p0_h - 1),
        "p0_fit_rel_err": float(p0_fit / p0_h - 1),
        "patch_edge_force_N": float(sol.lam[r > 1.4 * a_target].sum()),
        "condense_s": t_cond,
    }

"""Thin-layer limits of a bonded layer of thickness ``h`` under a rigid sphere or cylinder.

Compressible layer (Winkler): each column is in uniaxial strain, ``p = M (δ − r²/(2R)) / h``
with the confined modulus ``M`` (``Material.p_wave``), over ``a = √(2Rδ)``; the force is
``F = π R M δ² / h`` (sphere) and ``P' = (4/3) (M/h) a δ`` per unit length (cylinder).

Nearly incompressible layer (thin film, lubrication), frictionless top: the shear-driven
squeeze flow ``u_r = (p'/G)(z²/2 − h z)`` has flux ``q = −h³ p'/(3G)``, and incompressibility
``div q = δ − r²/(2R)`` with ``p = p' = 0`` at the contact edge give

- cylinder (plane strain): ``a = √(6Rδ)``, ``p = G (a² − x²)² / (8 R h³)``,
  ``P' = 2 G a⁵ / (15 R h³)``;
- sphere: ``a = 2√(Rδ)``, ``p = 3G (a² − r²)² / (32 R h³)``, ``P = π G a⁶ / (32 R h³)``.

The formulas are pure functions; :func:`winkler_cases` and :func:`thin_film` are the finite
element checks against them.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
from tqdm import tqdm

from .contact import solve_contact, solve_contact_full
from .material import Material
from .obstacles import Cylinder, Sphere
from .pad import CondensedPad, PadGeometry, condense_pad

__all__ = [
    "THIN_FILM_H",
    "THIN_FILM_R",
    "thin_film",
    "thin_film_cylinder_case",
    "thin_film_cylinder_force",
    "thin_film_cylinder_half_width",
    "thin_film_cylinder_indentation",
    "thin_film_cylinder_pressure",
    "thin_film_sphere_case",
    "thin_film_sphere_force",
    "thin_film_sphere_indentation",
    "thin_film_sphere_pressure",
    "thin_film_sphere_radius",
    "winkler_cases",
    "winkler_contact_radius",
    "winkler_cylinder_force",
    "winkler_cylinder_row",
    "winkler_sphere_force",
    "winkler_sphere_row",
]

#: layer thickness [m] and indenter radius [m] of :func:`thin_film`: R so large that
#: a²/(3 h R) ≪ 1 (see there)
THIN_FILM_H = 1.0e-3
THIN_FILM_R = 50.0


# ---- compressible layer (Winkler)


def winkler_contact_radius(R: float, delta: float) -> float:
    """Contact radius (sphere) or half-width (cylinder) ``a = √(2Rδ)`` [m] of an indenter of
    radius ``R`` [m] pressed ``delta`` [m] into a Winkler layer: where ``δ = r²/(2R)``."""
    return np.sqrt(2 * R * delta)


def winkler_sphere_force(R: float, delta: float, M: float, h: float) -> float:
    """Winkler force ``F = π R M δ² / h`` [N] of a sphere of radius ``R`` [m] pressed ``delta``
    [m] into a layer of thickness ``h`` [m] and confined modulus ``M`` [Pa]."""
    return np.pi * R * M * delta**2 / h


def winkler_cylinder_force(R: float, delta: float, M: float, h: float) -> float:
    """Winkler force per unit length ``P' = (4/3) (M/h) a δ`` [N/m], ``a = √(2Rδ)``, of a
    cylinder of radius ``R`` [m] pressed ``delta`` [m] into a layer of thickness ``h`` [m] and
    confined modulus ``M`` [Pa]."""
    a = winkler_contact_radius(R, delta)
    return 4.0 / 3.0 * (M / h) * a * delta


def winkler_sphere_row(pad: CondensedPad, R: float, delta: float) -> dict:
    """The condensed ``pad`` (a thin layer) under a sphere of radius ``R`` [m] at its centre,
    pressed ``delta`` [m]: ``{shape, R, delta, a_over_h, F_fe, F_limit, rel_err}``."""
    h = pad.geometry.thickness
    M = pad.material.p_wave
    sol = solve_contact(pad, Sphere((0, 0, h + R), R), delta)
    a = winkler_contact_radius(R, delta)
    F_fe, F_limit = sol.force, winkler_sphere_force(R, delta, M, h)
    row = {"shape": "sphere", "R": R, "delta": delta, "a_over_h": a / h, "F_fe": F_fe, "F_limit": F_limit}
    return {**row, "rel_err": F_fe / F_limit - 1}


def winkler_cylinder_row(pad: CondensedPad, R: float, delta: float, strip_half_width: float = 0.002) -> dict:
    """The condensed ``pad`` under a cylinder of radius ``R`` [m] along y through its centre,
    pressed ``delta`` [m]; the FE force per unit length is read on the central strip
    ``|y| < strip_half_width`` [m], away from the pad's free ends: the strip's rows of face
    nodes times the row spacing ``length / ny``.  Keys as :func:`winkler_sphere_row`."""
    geom = pad.geometry
    h = geom.thickness
    M = pad.material.p_wave
    sol = solve_contact(pad, Cylinder((0, 0, h + R), (0, 1, 0), R), delta)
    y = pad.face_xy[:, 1]
    strip = np.abs(y) < strip_half_width
    a = winkler_contact_radius(R, delta)
    # rows told apart by their y to 1 nm, which merges the last-bit differences of one row
    rows = np.unique(np.round(y[strip], 9)).size
    F_fe = float(sol.lam[strip].sum() / (rows * geom.length / geom.ny))
    F_limit = winkler_cylinder_force(R, delta, M, h)
    row = {"shape": "cylinder", "R": R, "delta": delta, "a_over_h": a / h, "F_fe": F_fe, "F_limit": F_limit}
    return {**row, "rel_err": F_fe / F_limit - 1}


def winkler_cases(h: float, cells: int) -> list[dict]:
    """The Winkler limits on a 12 × 12 mm layer of thickness ``h`` [m], ``cells`` × ``cells`` × 2
    hexes, E = 1 MPa and nu = 0 (so M = E): spheres R = 50 mm at δ = 0.1 mm and R = 100 mm at
    δ = 0.08 mm, and a cylinder R = 50 mm at δ = 0.08 mm (:func:`winkler_sphere_row`,
    :func:`winkler_cylinder_row`).  The limits hold for a ≫ h: a/h ≈ 3-4 at h = 1 mm."""
    pad = condense_pad(PadGeometry(0.012, 0.012, h, cells, cells, 2), Material(1.0e6, 0.0))
    rows = [winkler_sphere_row(pad, R, delta) for R, delta in ((0.05, 0.1e-3), (0.1, 0.08e-3))]
    return [*rows, winkler_cylinder_row(pad, 0.05, 0.08e-3)]


# ---- nearly incompressible layer (thin film)


def thin_film_cylinder_half_width(R: float, delta: float) -> float:
    """Thin-film contact half-width ``a = √(6Rδ)`` [m] of a cylinder of radius ``R`` [m]
    pressed ``delta`` [m]: where the squeeze flux ``δ x − x³/(6R)`` vanishes."""
    return np.sqrt(6 * R * delta)


def thin_film_cylinder_indentation(a: float, R: float) -> float:
    """The indentation ``δ = a² / (6R)`` [m] of a contact half-width ``a`` [m] (the inverse
    of :func:`thin_film_cylinder_half_width`)."""
    return a**2 / (6 * R)


def thin_film_cylinder_pressure(x: np.ndarray, G: float, a: float, R: float, h: float) -> np.ndarray:
    """Thin-film pressure ``p = G (a² − x²)² / (8 R h³)`` [Pa] under a cylinder at ``x`` (n,)
    [m] across its axis (0 for ``|x| > a``); shear modulus ``G`` [Pa], half-width ``a``,
    radius ``R`` and layer thickness ``h`` [m]."""
    x = np.asarray(x, dtype=float)
    return np.where(np.abs(x) < a, G * (a**2 - x**2) ** 2 / (8 * R * h**3), 0.0)


def thin_film_cylinder_force(G: float, a: float, R: float, h: float) -> float:
    """Thin-film force per unit length ``P' = 2 G a⁵ / (15 R h³)`` [N/m] of a cylinder: the
    integral of :func:`thin_film_cylinder_pressure` over ``−a < x < a``."""
    return 2 * G * a**5 / (15 * R * h**3)


def thin_film_sphere_radius(R: float, delta: float) -> float:
    """Thin-film contact radius ``a = 2√(Rδ)`` [m] of a sphere of radius ``R`` [m] pressed
    ``delta`` [m]: where the radial squeeze flux ``δ r/2 − r³/(8R)`` vanishes."""
    return 2 * np.sqrt(R * delta)


def thin_film_sphere_indentation(a: float, R: float) -> float:
    """The indentation ``δ = a² / (4R)`` [m] of a contact radius ``a`` [m] (the inverse of
    :func:`thin_film_sphere_radius`)."""
    return a**2 / (4 * R)


def thin_film_sphere_pressure(r: np.ndarray, G: float, a: float, R: float, h: float) -> np.ndarray:
    """Thin-film pressure ``p = 3G (a² − r²)² / (32 R h³)`` [Pa] under a sphere at radii ``r``
    (n,) [m] (0 for ``r > a``); arguments as :func:`thin_film_cylinder_pressure`."""
    r = np.asarray(r, dtype=float)
    return np.where(np.abs(r) < a, 3 * G * (a**2 - r**2) ** 2 / (32 * R * h**3), 0.0)


def thin_film_sphere_force(G: float, a: float, R: float, h: float) -> float:
    """Thin-film force ``P = π G a⁶ / (32 R h³)`` [N] of a sphere: the integral of
    :func:`thin_film_sphere_pressure` over the contact disc."""
    return np.pi * G * a**6 / (32 * R * h**3)


def _film_row(
    shape: str, a_over_h: float, hex_mm: str, F_fe: float, F_limit: float, t0: float, mat: Material
) -> dict:
    return {
        "shape": shape,
        "a_over_h": a_over_h,
        "hex_mm": hex_mm,
        "F_fe": F_fe,
        "F_limit": F_limit,
        "seconds": time.perf_counter() - t0,
        "rel_err": F_fe / F_limit - 1,
        "compressibility_3a2G_over_h2K": 3 * a_over_h**2 * mat.mu / mat.bulk,
    }


def thin_film_cylinder_case(a_over_h: float, material: Material) -> dict:
    """Exact plane strain (a one-element slab 0.2 mm long, ``u_y = 0``) of a layer
    ``h = THIN_FILM_H`` under a cylinder ``R = THIN_FILM_R`` pressed to the half-width
    ``a = a_over_h · h``, 0.5 × 0.2 × 0.25 mm hexes over ``|x| < a + 5h``, on the full-mesh
    linear solver (SRI).  Returns ``{shape, a_over_h, hex_mm, F_fe, F_limit, seconds, rel_err,
    compressibility_3a2G_over_h2K}`` with the forces per unit length [N/m]."""
    h, R = THIN_FILM_H, THIN_FILM_R
    a = a_over_h * h
    half = a + 5 * h
    slab = 0.2e-3
    geom = PadGeometry(2 * half, slab, h, int(round(2 * half / 0.5e-3)), 1, 4)
    t0 = time.perf_counter()
    sol = solve_contact_full(
        geom,
        material,
        Cylinder((0, 0, h + R), (0, 1, 0), R, allow_scale=True),
        thin_film_cylinder_indentation(a, R),
        plane_strain=True,
    )
    F_limit = thin_film_cylinder_force(material.mu, a, R, h)
    return _film_row(
        "cylinder (plane strain)", a_over_h, "0.5x0.2x0.25", sol.force / slab, F_limit, t0, material
    )


def thin_film_sphere_case(a_over_h: float, material: Material) -> dict:
    """A full 3D layer ``h = THIN_FILM_H``, (2a + 10h)² face of 1 × 1 × 0.25 mm hexes, under a
    sphere ``R = THIN_FILM_R`` pressed to the contact radius ``a = a_over_h · h``, on the
    full-mesh linear solver (SRI; a/h = 20 is 39k dofs).  Keys as
    :func:`thin_film_cylinder_case`, the forces in N."""
    h, R = THIN_FILM_H, THIN_FILM_R
    a = a_over_h * h
    n = int(round(2 * (a + 5 * h) / 1.0e-3))
    geom = PadGeometry(n * 1.0e-3, n * 1.0e-3, h, n, n, 4)
    t0 = time.perf_counter()
    sphere = Sphere((0, 0, h + R), R, allow_scale=True)
    sol = solve_contact_full(geom, material, sphere, thin_film_sphere_indentation(a, R))
    F_limit = thin_film_sphere_force(material.mu, a, R, h)
    return _film_row("sphere", a_over_h, "1x1x0.25", sol.force, F_limit, t0, material)


def thin_film(
    nu: float, cylinder_a_h: Sequence[float], sphere_a_h: Sequence[float], *, progress: bool = False
) -> list[dict]:
    """Nearly incompressible bonded layer (Poisson ratio ``nu``, E = 1 MPa), frictionless top,
    against the thin-film limit: one row of :func:`thin_film_cylinder_case` per contact
    half-width ``a/h`` in ``cylinder_a_h``, then one of :func:`thin_film_sphere_case` per
    contact radius ``a/h`` in ``sphere_a_h``; ``progress`` shows a bar per shape (stderr).

    Regime of validity, all three checked: a ≫ h (corrections ~ (h/a)², +40% at a/h = 5);
    ``3 (a/h)² G/K ≪ 1`` (column compressibility, reported per row: hence nu = 0.49999);
    and ``a²/(3 h R) ≪ 1`` — the surface slides outward by up to ``a³/(6√3 h R)`` along the
    curved obstacle, a gap change the lubrication theory drops but the linearised contact
    ``d + n·u`` keeps (it cost −34% at a/h = 20 with R = 0.5 m), so R = 50 m and δ = a²/(6R)
    or a²/(4R) (the problem is linear: δ's size is moot).
    """
    mat = Material(1.0e6, nu)
    rows = [
        thin_film_cylinder_case(a_h, mat)
        for a_h in tqdm(cylinder_a_h, desc="thin film, cylinder", unit="case", disable=not progress)
    ]
    rows += [
        thin_film_sphere_case(a_h, mat)
        for a_h in tqdm(sphere_a_h, desc="thin film, sphere", unit="case", disable=not progress)
    ]
    return rows

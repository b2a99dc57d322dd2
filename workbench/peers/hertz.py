"""Hertz: a rigid sphere pressed into an elastic half-space (Johnson, *Contact Mechanics*, 1985, §4.2).

For a rigid sphere of radius ``R`` at approach ``δ`` into a half-space of Young's modulus ``E`` and
Poisson ratio ``ν`` (effective modulus ``E* = E / (1 - ν²)``, the rigid body adding no compliance):

- normal force ``F(δ) = (4/3) E* √R δ^{3/2}``;
- contact radius ``a = √(R δ)`` (``1/√2`` of the overlap radius ``√(2Rδ)``, half its area: the surface around
  the indenter sinks with it);
- pressure ``p(r) = p0 √(1 - r²/a²)``, ``p0 = 3F / (2π a²) = (2E*/π) √(δ/R)``;
- torsional friction capacity (full slip, pure rotation about the normal):
  ``τ_max = μ ∫ p r dA = 3π μ F a / 16``.

**Thin-layer caveat.**  The half-space is the theory's premise: it holds while the contact stays
small against the layer, ``a ≪ h``.  A gripper pad is a layer of thickness ``h`` (5-10 mm) bonded
to a rigid jaw; once ``a`` reaches ~``h/10`` the rigid back stiffens the contact (force above
Hertz's, contact narrower, pressure flatter), and for a nearly incompressible layer
(``ν → 0.5``) much more so (layered solids: Johnson ch. 5; Shull, *Mater. Sci. Eng. R* 36, 2002).  With a
20 mm sphere at δ = 1 mm, ``a`` = 4.5 mm is as large as a 5 mm pad: Hertz is then the *reference
shape* of the pressure (a smooth dome vanishing at the rim), not a prediction of our FEM's force.
"""

from __future__ import annotations

import logging

import numpy as np

from .. import peers as _checks
from ..profile import ContactProfile

__all__ = [
    "effective_modulus",
    "hertz_contact_radius",
    "hertz_force",
    "hertz_p0",
    "hertz_pressure",
    "hertz_profile",
    "hertz_torsion_capacity",
]

log = logging.getLogger(__name__)


def _sphere_case(R: float, delta: float) -> tuple[float, float]:
    return _checks.sphere(R, delta, "delta (approach)")


def effective_modulus(E: float, nu: float) -> float:
    """``E* = E / (1 - ν²)`` [Pa] of an elastic half-space under a rigid indenter."""
    e = _checks.modulus("E (Young's modulus)", E)
    n = _checks.poisson("nu (Poisson ratio)", nu)
    return e / (1.0 - n * n)


def hertz_contact_radius(R: float, delta: float) -> float:
    """Contact radius ``a = √(R δ)`` [m] for sphere radius ``R`` [m] and approach ``δ`` [m]."""
    r, d = _sphere_case(R, delta)
    return float(np.sqrt(r * d))


def hertz_force(R: float, delta: float, E: float, nu: float) -> float:
    """Normal force ``F = (4/3) E* √R δ^{3/2}`` [N]."""
    r, d = _sphere_case(R, delta)
    return 4.0 / 3.0 * effective_modulus(E, nu) * np.sqrt(r) * d**1.5


def hertz_p0(R: float, delta: float, E: float, nu: float) -> float:
    """Peak pressure ``p0 = 3F / (2π a²)`` [Pa] at the centre."""
    a = hertz_contact_radius(R, delta)
    return 3.0 * hertz_force(R, delta, E, nu) / (2.0 * np.pi * a * a)


def hertz_pressure(r: np.ndarray, R: float, delta: float, E: float, nu: float) -> np.ndarray:
    """Pressure ``p(r) = p0 √(1 - r²/a²)`` [Pa] at radial distances ``r`` (m,) [m] from the
    centre (zero outside ``a``); returns (m,)."""
    rr = np.asarray(r, dtype=np.float64)
    if not np.isfinite(rr).all() or (rr < 0).any():
        raise ValueError("r must be finite radial distances >= 0 [m]; got NaN/inf or negative values")
    a = hertz_contact_radius(R, delta)
    s2 = np.clip(1.0 - (rr / a) ** 2, 0.0, None)
    return hertz_p0(R, delta, E, nu) * np.sqrt(s2)


def hertz_torsion_capacity(R: float, delta: float, E: float, nu: float, mu: float) -> float:
    """Maximal friction torque about the normal ``τ_max = 3π μ F a / 16`` [N m]."""
    m = _checks.friction(mu, "torsion capacity")
    return 3.0 * np.pi * m * hertz_force(R, delta, E, nu) * hertz_contact_radius(R, delta) / 16.0


def _ring_integrals(s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Antiderivatives on ``s = r/a`` of ``√(1-s²) s`` and ``√(1-s²) s²``: ring force and ring
    radial moment, in units of ``2π p0 a²`` and ``2π p0 a³``."""
    c = np.sqrt(np.clip(1.0 - s * s, 0.0, None))
    force = -(c**3) / 3.0
    moment = (np.arcsin(np.clip(s, -1.0, 1.0)) - s * c * (1.0 - 2.0 * s * s)) / 8.0
    return force, moment


def hertz_profile(
    R: float,
    delta: float,
    E: float,
    nu: float,
    n_rings: int = 16,
    n_sectors: int = 32,
    *,
    center: np.ndarray | None = None,
) -> ContactProfile:
    """The Hertz contact as a :class:`~workbench.profile.ContactProfile` on the **sphere cap**.

    Where: on the rigid sphere (the object), centre ``center`` (3,) [m] (default ``(0, 0, R)``,
    so the cap's lowest point is the origin and the pad lies below, as in ``workbench.fem``), over
    the footprint ``r <= a``.  Why the cap and not the flat disc: under a rigid indenter the
    deformed half-space conforms to the sphere, so the contact surface *is* the cap; its normals
    tilt by up to ``asin(a/R)`` (13° at R = 20 mm, δ = 1 mm), which is what a nonplanar 6DFW sees.

    Elements: ``n_rings`` rings of equal radial width times ``n_sectors`` sectors.  Each element
    carries exactly the Hertz force over its footprint (closed-form ring integrals), sits at its
    ring's force-weighted mean radius (so the torsion integral ``∫ p r dA`` is exact too), has the
    cap's true area, and pressure = force / area.  Hence, to round-off:
    ``profile.F == hertz_force(...)`` and ``w_max(profile, μ)[5] == 3π μ F a / 16``.  The
    pressure differs from ``p(r)`` by the area ratio cap/footprint, ``1 + O(a²/R²)`` (Hertz's own
    order of accuracy), and the net normal force ``Σ p a n_z`` is ``F (1 - O(a²/R²))``.

    Returns a profile of ``n_rings * n_sectors`` elements: centers (n, 3), normals (n, 3)
    (outward from the sphere), areas (n,), pressures (n,).
    """
    r_s, d = _sphere_case(R, delta)
    F = hertz_force(r_s, d, E, nu)
    p0 = hertz_p0(r_s, d, E, nu)
    nr = _checks.count("n_rings", n_rings, 1)
    ns = _checks.count("n_sectors", n_sectors, 3)
    if center is None:
        c = np.array([0.0, 0.0, r_s])
    else:
        c = np.asarray(center, dtype=np.float64)
        if c.shape != (3,) or not np.isfinite(c).all():
            raise ValueError(f"center must be a finite (3,) point [m]; got {np.shape(center)} {center!r}")
    a = np.sqrt(r_s * d)
    s = np.linspace(0.0, 1.0, nr + 1)
    f_int, m_int = _ring_integrals(s)
    ring_force = 2.0 * np.pi * p0 * a * a * np.diff(f_int)  # (nr,) [N]
    ring_moment = 2.0 * np.pi * p0 * a**3 * np.diff(m_int)  # (nr,) [N m] = ∫ p r dA over the ring
    r_bar = ring_moment / ring_force
    r0, r1 = a * s[:-1], a * s[1:]
    # cap area of each ring: 2πR (z1 - z0), z(r) = R - √(R² - r²), written without cancellation
    dz = (r1 * r1 - r0 * r0) / (np.sqrt(r_s * r_s - r0 * r0) + np.sqrt(r_s * r_s - r1 * r1))
    ring_area = 2.0 * np.pi * r_s * dz
    phi = (np.arange(ns) + 0.5) * (2.0 * np.pi / ns)
    rb = np.repeat(r_bar, ns)
    ph = np.tile(phi, nr)
    z = r_s - np.sqrt(r_s * r_s - rb * rb)
    centers = c + np.column_stack([rb * np.cos(ph), rb * np.sin(ph), z - r_s])
    normals = (centers - c) / r_s
    areas = np.repeat(ring_area / ns, ns)
    pressures = np.repeat(ring_force / ns, ns) / areas
    log.debug("hertz_profile: R=%g m, delta=%g m, a=%g m, F=%g N, %d elements", r_s, d, a, F, nr * ns)
    return ContactProfile(centers, normals, areas, pressures)

"""Validation problems with closed-form answers (used by tests and ``fem-validation``)."""

from __future__ import annotations

import numpy as np
from skfem import FacetBasis, LinearForm, MeshHex, asm, condense, solve
from skfem.helpers import dot

from .elasticity import ELEMENT, basis, stiffness
from .material import Material


def lame_inner_displacement(material: Material, p: float = 1.0, a: float = 1.0, b: float = 2.0) -> float:
    """Lamé: inner radial displacement of a plane-strain thick cylinder under internal pressure p."""
    E, nu = material.E, material.nu
    return (1 + nu) * p * a**2 / (E * (b**2 - a**2)) * ((1 - 2 * nu) * a + b**2 / a)


def lame_cylinder_fe(
    material: Material,
    scheme: str,
    *,
    nr: int = 8,
    nt: int = 12,
    p: float = 1.0,
    a: float = 1.0,
    b: float = 2.0,
) -> float:
    """FE inner radial displacement of the same problem: a quarter cylinder of hexes with
    symmetry planes and plane strain (u_z = 0), the classic volumetric-locking benchmark."""
    m = MeshHex.init_tensor(
        np.linspace(a, b, nr + 1), np.linspace(0, np.pi / 2, nt + 1), np.array([0.0, 0.25])
    )
    r, th, z = m.p
    mesh = MeshHex(np.array([r * np.cos(th), r * np.sin(th), z]), m.t)
    K = stiffness(mesh, material, scheme)
    # flat facets on the inner circle have midpoints at a cos(dθ/2) < a
    inner = mesh.facets_satisfying(lambda x: np.hypot(x[0], x[1]) < a + 0.01 * (b - a), boundaries_only=True)

    @LinearForm
    def pressure(v, w):
        rr = np.hypot(w.x[0], w.x[1])
        return p * dot(np.array([w.x[0] / rr, w.x[1] / rr, 0 * rr]), v)

    nodal = basis(mesh).nodal_dofs  # (3, N): dof of each component at each node
    x, y, _ = mesh.p
    fixed = np.unique(np.concatenate([nodal[0][np.isclose(x, 0)], nodal[1][np.isclose(y, 0)], nodal[2]]))
    u = solve(*condense(K, asm(pressure, FacetBasis(mesh, ELEMENT, facets=inner)), D=fixed))
    on_inner = np.isclose(np.hypot(x, y), a)
    return float(((x * u[nodal[0]] + y * u[nodal[1]])[on_inner] / a).mean())


def condensed_vs_full(pad, obstacle, delta: float, label: str) -> dict:
    """One exactness check of the condensed level: the same contact solved on the
    condensed face (timed after a warm-up call) and on the full mesh; the
    pressure-field L2 and force errors, runtimes and sanity numbers."""
    import time

    from .contact import solve_contact, solve_contact_full
    from .extract import nodal_pressures

    solve_contact(pad, obstacle, delta)  # warm
    t0 = time.perf_counter()
    c = solve_contact(pad, obstacle, delta)
    tc = time.perf_counter() - t0
    t0 = time.perf_counter()
    f = solve_contact_full(pad.geometry, pad.material, obstacle, delta)
    tf = time.perf_counter() - t0
    pc, pf = nodal_pressures(pad, c.lam), nodal_pressures(pad, f.lam)
    return {
        "case": label,
        "force_N": c.force,
        "force_rel_err": abs(c.force / f.force - 1),
        "pressure_rel_l2": float(np.linalg.norm(pc - pf) / np.linalg.norm(pf)),
        "condensed_ms": tc * 1e3,
        "full_s": tf,
        "speed_ratio": tf / tc,
        "min_pressure": float(pc.min()),
        "max_penetration_m": c.max_penetration,
        "active_nodes": int((c.lam > 0).sum()),
    }

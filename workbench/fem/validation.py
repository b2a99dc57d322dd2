"""Validation problems with closed-form answers (used by tests and ``fem-validation``):
volumetric locking against Lamé's thick cylinder, and the condensed contact level against
the full-mesh solve of the same Signorini problem."""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from skfem import FacetBasis, LinearForm, MeshHex, asm, condense, solve
from skfem.helpers import dot
from tqdm import tqdm

from .contact import solve_contact, solve_contact_full
from .elasticity import ELEMENT, basis, stiffness
from .extract import nodal_pressures
from .material import Material
from .obstacles import Cylinder, Plane, Sphere
from .pad import CondensedPad, PadGeometry, condense_pad


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


def locking_rows(nus: Sequence[float], nr: int, nt: int) -> list[dict]:
    """Volumetric locking: for each Poisson ratio in ``nus`` (E = 1 MPa), the FE inner
    displacement of :func:`lame_cylinder_fe` on ``nr`` × ``nt`` hexes with selective reduced
    and with full integration, each over Lamé's (:func:`lame_inner_displacement`).
    Returns ``[{nu, sri_over_exact, full_over_exact}]``; full integration falls far below 1
    as nu -> 0.5, SRI does not."""
    rows = []
    for nu in nus:
        mat = Material(1.0e6, nu)
        exact = lame_inner_displacement(mat)
        sri = lame_cylinder_fe(mat, "sri", nr=nr, nt=nt)
        full = lame_cylinder_fe(mat, "full", nr=nr, nt=nt)
        rows.append({"nu": nu, "sri_over_exact": sri / exact, "full_over_exact": full / exact})
    return rows


def condensed_vs_full(pad, obstacle, delta: float, label: str) -> dict:
    """One exactness check of the condensed level: the same contact solved on the
    condensed face (timed after a warm-up call) and on the full mesh; the
    pressure-field L2 and force errors, runtimes and sanity numbers."""
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


def comparison_cases(h: float) -> dict[str, tuple]:
    """``{name: (obstacle, delta [m])}``: the ten indenters of :func:`compare_condensed_vs_full`
    on a layer of thickness ``h`` [m] (its face at z = h): spheres and cylinders of 5-40 mm,
    centred, off-centre and tilted, and a tilted plane already pressed 0.3 mm."""
    return {
        "sphere R20": (Sphere((0, 0, h + 0.02), 0.02), 0.6e-3),
        "sphere R10 off-center": (Sphere((0.003, -0.002, h + 0.01), 0.01), 0.5e-3),
        "sphere R40": (Sphere((0, 0, h + 0.04), 0.04), 0.8e-3),
        "cylinder R10 along y": (Cylinder((0, 0, h + 0.01), (0, 1, 0), 0.01), 0.5e-3),
        "cylinder R15 along x": (Cylinder((0, 0, h + 0.015), (1, 0, 0), 0.015), 0.6e-3),
        "cylinder tilted 20 deg": (
            Cylinder((0.001, 0, h + 0.012), (np.sin(0.35), np.cos(0.35), 0), 0.012),
            0.5e-3,
        ),
        "cylinder off-center": (Cylinder((0.004, 0, h + 0.01), (0, 1, 0), 0.01), 0.4e-3),
        "plane tilted": (Plane((0, 0, h - 0.3e-3), (0.06, 0.03, -1)), 0.0),
        "sphere R5 small contact": (Sphere((0, 0, h + 0.005), 0.005), 0.3e-3),
        "cylinder tilted about x": (Cylinder((0, 0, h + 0.012), (0, 1, 0.15), 0.012), 0.5e-3),
    }


@dataclass(frozen=True)
class CondensedVsFull:
    """What :func:`compare_condensed_vs_full` found.

    pad : the condensed pad; cases : :func:`comparison_cases` of its thickness;
    rows : one :func:`condensed_vs_full` row per case, in the order of ``cases``;
    precompute_s : the condensation's wall time [s] (no disk cache);
    sweep_forces : the force [N] of ``"sphere R20"`` at each displacement of the sweep;
    monotone : whether those forces strictly increase.
    """

    pad: CondensedPad
    cases: dict
    rows: list
    precompute_s: float
    sweep_forces: list
    monotone: bool


def compare_condensed_vs_full(
    pad_cells: Sequence[int], nu: float, delta_sweep: Sequence[float], *, progress: bool = False
) -> CondensedVsFull:
    """The condensed level against the full-mesh solve (:func:`condensed_vs_full`) on the ten
    :func:`comparison_cases` of a 16 × 20 × 4 mm layer of ``pad_cells = (nx, ny, nz)`` hexes
    (E = 1 MPa, Poisson ratio ``nu``), and the force-displacement sanity check: the sphere
    R = 20 mm pressed by each of ``delta_sweep`` [m] (increasing) on the condensed pad.
    ``progress`` shows a bar over the cases (stderr)."""
    nx, ny, nz = pad_cells
    geom = PadGeometry(0.016, 0.02, 0.004, nx, ny, nz)
    mat = Material(1.0e6, nu)
    t0 = time.perf_counter()
    pad = condense_pad(geom, mat, cache_dir=False)  # timed: no disk cache
    precompute_s = time.perf_counter() - t0
    cases = comparison_cases(geom.thickness)
    rows = [
        condensed_vs_full(pad, obs, delta, name)
        for name, (obs, delta) in tqdm(
            cases.items(), desc="condensed vs full", unit="case", disable=not progress
        )
    ]
    sweep = [solve_contact(pad, cases["sphere R20"][0], d).force for d in delta_sweep]
    monotone = bool(np.all(np.diff(sweep) > 0))
    return CondensedVsFull(pad, cases, rows, precompute_s, sweep, monotone)

"""How far the linear pad levels are from the neo-Hookean reference as the layer compresses.

One indenter of :data:`FIDELITY_CASES` on a 16 × 20 × 5 mm layer: the condensed linear
pad with selective reduced integration (the profiles' fidelity), the condensed pad with
full integration (the reference's discretization) and, optionally, the full-mesh linear
solve, each against :class:`~workbench.fem.nonlinear.NonlinearPad` at jaw displacements
given as fractions δ/h of the layer thickness; and how well a force (or peak pressure)
correction calibrated on one indenter transfers to the other.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from functools import partial

import numpy as np

from .contact import solve_contact, solve_contact_full
from .extract import face_grid, nodal_pressures
from .material import Material
from .obstacles import Cylinder, Sphere
from .pad import PadGeometry, condense_pad

__all__ = ["FIDELITY_CASES", "fidelity_case", "fidelity_setup", "transferred_correction"]

#: the indenters of :func:`fidelity_case`: radius 15 mm, centred on the layer
FIDELITY_CASES = ("cylinder R15", "sphere R15")


def fidelity_setup(pad_cells: Sequence[int], nu: float) -> tuple[PadGeometry, Material, dict]:
    """The 16 × 20 × 5 mm layer of ``pad_cells = (nx, ny, nz)`` hexes, its material (E = 1 MPa,
    Poisson ratio ``nu``) and ``{name: obstacle}`` of :data:`FIDELITY_CASES` (a cylinder
    along y and a sphere, R = 15 mm, touching the face at its centre)."""
    nx, ny, nz = pad_cells
    geom = PadGeometry(0.016, 0.02, 0.005, nx, ny, nz)
    mat = Material(1.0e6, nu)
    h = geom.thickness
    cases = {
        "cylinder R15": Cylinder((0, 0, h + 0.015), (0, 1, 0), 0.015),
        "sphere R15": Sphere((0, 0, h + 0.015), 0.015),
    }
    return geom, mat, cases


def _reference_row(name: str, delta_over_h: float, ref, a_def: np.ndarray) -> tuple[dict, np.ndarray]:
    """The neo-Hookean solution's columns shared by every level's row, and its Cauchy
    pressures λ / a [Pa] on the deformed tributary areas ``a_def`` (n,) [m²]."""
    p_nl = np.divide(ref.lam, a_def, out=np.zeros_like(ref.lam), where=a_def > 0)
    base = {
        "case": name,
        "delta_over_h": delta_over_h,
        "nl_force_N": ref.force,
        "nl_peak_kPa": p_nl.max() / 1e3,
        "nl_area_mm2": float(a_def[ref.lam > 0].sum() * 1e6),
    }
    return base, p_nl


def fidelity_case(
    name: str,
    pad_cells: Sequence[int],
    nu: float,
    delta_fractions: Sequence[float],
    full_mesh: bool = True,
) -> list[dict]:
    """Linear levels against the neo-Hookean reference for the indenter ``name`` of
    :data:`FIDELITY_CASES` on :func:`fidelity_setup`'s layer, at jaw displacements
    ``delta_fractions`` × h (e.g. 0.02 for the small-strain check, 0.2-0.6 for large strain).

    Levels: ``"condensed SRI"``, ``"condensed full"`` and, if ``full_mesh``, ``"linear full mesh"``
    (each timed on a second call, after a warm-up one).  Pressures: linear λ / A₀ (reference
    tributary areas); nonlinear the Cauchy pressure λ / a (deformed areas); fields compared
    node by node on the face grid.

    Returns per δ the reference's row (``level = "nonlinear (neo-Hookean)"``, errors 0, its
    ``seconds`` the mean per load step) then one per level: ``case``, ``delta_over_h``,
    ``nl_force_N``, ``nl_peak_kPa``, ``nl_area_mm2``, ``level``, ``seconds``,
    ``force_rel_err``, ``peak_rel_err``, ``area_rel_err``, ``pressure_rel_l2`` (relative to
    the reference).
    """
    from .nonlinear import NonlinearPad

    if name not in FIDELITY_CASES:
        raise ValueError(f"name must be one of {FIDELITY_CASES}; got {name!r}")
    geom, mat, cases = fidelity_setup(pad_cells, nu)
    obs = cases[name]
    h = geom.thickness
    deltas = [f * h for f in delta_fractions]
    nl = NonlinearPad(geom, mat)
    pads = {
        "condensed SRI": condense_pad(geom, mat),
        "condensed full": condense_pad(geom, mat, scheme="full"),
    }
    _, area0 = face_grid(pads["condensed SRI"].face_xy)
    rows = []
    t0 = time.perf_counter()
    ref = nl.solve(obs, deltas)
    t_nl = (time.perf_counter() - t0) / len(deltas)
    zero = {"force_rel_err": 0.0, "peak_rel_err": 0.0, "area_rel_err": 0.0, "pressure_rel_l2": 0.0}
    for d in deltas:
        r = ref[d]
        base, p_nl = _reference_row(name, d / h, r, nl.deformed_areas(r))
        rows.append({**base, "level": "nonlinear (neo-Hookean)", "seconds": t_nl, **zero})
        levels = {k: partial(solve_contact, pad, obs, d) for k, pad in pads.items()}
        if full_mesh:
            levels["linear full mesh"] = partial(solve_contact_full, geom, mat, obs, d)
        for level, fn in levels.items():
            fn()
            t0 = time.perf_counter()
            c = fn()
            dt = time.perf_counter() - t0
            p_l = nodal_pressures(pads["condensed SRI"], c.lam)  # same face nodes on every level
            rows.append(
                {
                    **base,
                    "level": level,
                    "seconds": dt,
                    "force_rel_err": c.force / r.force - 1,
                    "peak_rel_err": p_l.max() / p_nl.max() - 1,
                    "area_rel_err": area0[c.lam > 0].sum() * 1e6 / base["nl_area_mm2"] - 1,
                    "pressure_rel_l2": float(np.linalg.norm(p_l - p_nl) / np.linalg.norm(p_nl)),
                }
            )
    return rows


def transferred_correction(rows: Sequence[dict]) -> dict[str, dict]:
    """A correction of the condensed SRI level calibrated on the neo-Hookean reference: the
    ratio ``F_nl / F_lin`` (or of the peak pressures) at each δ/h ≥ 0.2, calibrated on one
    indenter and applied to another — how well a single δ/h-dependent factor transfers.

    rows : :func:`fidelity_case` rows of two or more indenters (other levels are skipped).
    Returns ``{"<force|peak>: <calibrated on> -> <applied to> <δ/h in %>%": {"uncorrected",
    "corrected"}}``: the applied-to indenter's relative error before and after, the latter
    ``(1 + e_applied) / (1 + e_calibrated) − 1``; only δ/h present for both indenters.
    """
    correction = {}
    sri = {(r["case"], round(r["delta_over_h"], 2)): r for r in rows if r["level"] == "condensed SRI"}
    shapes = sorted({c for c, _ in sri})
    for cal in shapes:
        for app in shapes:
            if cal == app:
                continue
            for d in sorted({d for _, d in sri if d >= 0.2}):  # the large-deformation levels only
                if (cal, d) in sri and (app, d) in sri:
                    for q in ("force", "peak"):
                        e_cal, e_app = sri[(cal, d)][f"{q}_rel_err"], sri[(app, d)][f"{q}_rel_err"]
                        correction[f"{q}: {cal} -> {app} {round(100 * d)}%"] = {
                            "uncorrected": e_app,
                            "corrected": (1 + e_app) / (1 + e_cal) - 1,
                        }
    return correction

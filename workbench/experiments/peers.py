"""Peers: what a contact costs and what it gets wrong in the simulators researchers already have.

The same contacts — a rigid sphere, a circular cylinder, the elliptic
cylinder of the thesis's grasp scene (§4.1.3, :func:`workbench.sources.scenes.elliptic_cylinder_grasp`)
and a thesis bottle (fem-fitting's family, grasped at mid-height along its section's major axis)
pressed by δ into one 16 × 20 × 5 mm silicone pad — from each peer:

- ``hertz``: the analytic half-space (sphere only; :mod:`workbench.peers.hertz`);
- ``foundation``: GraspIt!'s Winkler soft finger, ``k = E/h`` (:mod:`workbench.peers.elastic_foundation`);
- ``drake``: Drake's hydroelastic contact, ``E_hydro = E`` on a box of height 2h
  (:mod:`workbench.peers.drake_hydro`; skipped, and said so, without ``pydrake``);
- ``mujoco_hertz`` / ``mujoco_diameter``: MuJoCo's ``condim=6`` elliptic cone at the contact's
  pressure centre, torsional coefficient ``3π μ a / 16`` (the Hertz patch) or ``μ · 2a`` (the
  documentation's "diameter of the contact patch"), ``a = √(ρ δ)`` from the surface's curvature
  radius ``ρ`` (a user's estimate: the patch is not simulated), no rolling resistance;
- ours: ``condensed`` (linear pad condensed to its face), ``linear`` (the full mesh) and the
  reference ``neo-Hookean`` (finite strain, :class:`workbench.fem.nonlinear.NonlinearPad`).

Against the neo-Hookean reference at each δ: jaw force, contact area, pressure field (relative
L2 on a 0.2 mm grid of the pad face), torsion length ``τ_max/(μ f_n)`` (exact 6DFW), the 6DFW
set's support along the six axis twists per unit force, and at one δ the 6DLS fitted to each
peer's 6DFWs scored at the reference's exact 6DFW surface
(:func:`workbench.peers.metrics.fitted_ls_error`) and the resistance margins of
the two-jaw grasp against lever disturbances (§4.1.3.1) with the exact 6DFW sets of the
reference as the truth (:func:`workbench.grasp.exact.resists_exact`), at equal jaw force.  Each
peer's cost per query (one contact at one δ) is timed; the runtime-versus-error figure sweeps the
resolution knob of the condensed pad, Drake and the Winkler grid at one δ.

The cases and their neo-Hookean references are :mod:`workbench.peers.pad_cases`, the errors and
margins :mod:`workbench.peers.comparison`, the Hertz check :mod:`workbench.peers.hertz_block`,
MuJoCo's coefficients :func:`workbench.peers.mujoco_cone.patch_coefficients`; this driver composes
them, times each peer and writes the tables, the figure and the summary.
"""

from __future__ import annotations

import logging
import time
from functools import partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench.fem.contact import solve_contact, solve_contact_full
from workbench.fem.extract import extract_profile, face_grid
from workbench.fem.pad import condense_pad
from workbench.grasp.margin import MARGIN_SPAN, check_steps, margin_rel_err, margin_vs_truth
from workbench.peers import metrics
from workbench.peers.comparison import (
    compare,
    equal_force_margins,
    fem_row,
    hertz_row,
    profile_row,
    reference_measures,
)
from workbench.peers.hertz_block import hertz_half_space
from workbench.peers.mujoco_cone import PATCH_TORSIONS, patch_coefficients
from workbench.peers.pad_cases import CASES, drake_pad, reference_case, setup_case
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.pareto import at_equal
from workbench.runner.results import save_figure, write_csv, write_summary
from workbench.timing import median_runtime
from workbench.wrench import check_mu

log = logging.getLogger(__name__)

NAME = "peers"

DEFAULT_CONFIG = {
    "seed": 0,
    "E": 1.0e6,  # Young's modulus of the pad [Pa]
    "nu": 0.45,  # Poisson ratio (the FEM fidelity study's value)
    "mu": 0.5,  # Coulomb friction
    "pad_mm": [16.0, 20.0, 5.0],  # width (x), length (y), thickness h [mm]
    "pad_cells": [16, 20, 5],  # hexes of the FEM pads (1 mm)
    # the thesis bottle costs most (its exact Newton distance makes each query slow: minutes
    # of the run)
    "cases": ["sphere", "cylinder", "elliptic_cylinder", "bottle"],
    "radius_mm": 15.0,  # sphere and cylinder radius
    "ellipse_mm": [30.0, 20.0],  # elliptic cylinder semi-axes along the pad normal / across (scene's a, b)
    # the thesis bottle (fem-fitting's family, workbench.fem.bottle.bottle_family(24, 8, seed 0)):
    # which one, the grasp height as a fraction of its height, the approach along the section's
    # major axis; Drake takes it as a mesh of n_theta x n_z vertices
    "bottle": {"index": 0, "height": 0.5, "mesh": [256, 320]},
    "ellipse_sections": 720,  # facets around Drake's elliptic cylinder mesh (~0.2 mm at the contact)
    "deltas_mm": [0.25, 0.5, 1.0, 2.0],  # jaw displacements: δ/h = 5 ... 40 %
    # full 2x2x2 volumetric integration locks at nu = 0.45 (+10 % force at δ = 0.1 mm against the
    # SRI linear pad, which the reference must match at small strain); 0.1 of it is kept against
    # the hourglass modes of pure SRI at finite strain (workbench/fem/nonlinear.py)
    "reference_stabilization": 0.1,
    "sweep_delta_mm": 1.0,  # the δ of the runtime-vs-error sweeps
    "condensed_sweep_cells": [[8, 10, 3], [12, 15, 4], [16, 20, 5]],  # 2, 1.33, 1 mm hexes
    "drake_sweep_resolution_over_R": [0.2, 0.1, 0.05, 0.025, 0.0125],  # rigid tessellation hints
    "drake_resolution_over_R": 0.0125,  # the per-δ rows' hint (Drake's R/80 default)
    "foundation_cells": [40, 80, 160],  # Winkler grid per side; the last is used per δ
    "margin_delta_mm": 1.0,
    # at margin_delta_mm each peer's fitted 6DLS (this model, fitted to the 6DFWs of 2 ls_twists
    # twists of the thesis's sampling) is scored at the reference's exact 6DFW surface points of
    # ls_directions uniform normals (workbench.peers.metrics.fitted_ls_error)
    "ls_model": "ellipsoid_sdp",
    "ls_twists": 500,  # 1,000 wrenches: at 100 twists a Hertz peer's error varied 2x over seeds
    "ls_directions": 2000,
    "n_disturbances": 16,  # lever disturbances (§4.1.3.1) for the margins
    "margin_steps": 10,  # bisection steps on log2 s in [1/64, 64]
    "grid_mm": 0.2,  # pressure comparison grid spacing
    # where Hertz applies: a rigid sphere R on thick blocks (40 x 40 x H, 80 x 80 x 2H mm ...), graded
    # to fine_mm under a contact of radius a_mm; the layer adds stiffness at first order in a/H, so
    # the half-space force is read off two depths by Richardson extrapolation (F_inf = 2 F_2H - F_H)
    "hertz_block": {"R_mm": 20.0, "a_mm": 1.5, "nu": 0.3, "fine_mm": 0.45, "depths_mm": [20.0, 40.0]},
    "repeats": 5,  # timing repeats (median after one warm-up)
    # where the neo-Hookean reference cases run (workbench.runner.parallel.row_client): 0 = a local Dask
    # cluster (one task per case), 1 = serially here, N = N local workers; scheduler = an address
    "workers": 0,
    "scheduler": "",
}
#: what each key means, its unit and plausible range (``workbench run peers --help``)
KEYS = {
    "E": Key("pad Young's modulus (silicone)", "Pa", "pad_modulus"),
    "nu": Key("pad Poisson ratio", "", "poisson"),
    "mu": Key("Coulomb friction coefficient, > 0", "", "mu"),
    # one quantity for the three: the thickness is judged as a pad size too (Key has no
    # per-position quantities for a list)
    "pad_mm": Key(
        "pad [width (x), length (y), thickness h]",
        "mm",
        fields={0: ("pad_size", 1e-3), 1: ("pad_size", 1e-3), 2: ("pad_thickness", 1e-3)},
    ),
    "pad_cells": Key("[nx, ny, nz] hexes of the FEM pads"),
    "cases": Key("contacts compared, at least one", choices=lambda: CASES),
    "radius_mm": Key("sphere and cylinder radius, in [1, 1000)", "mm"),
    "ellipse_mm": Key("elliptic cylinder semi-axes [along the pad normal, across]", "mm"),
    "bottle": Key(
        "thesis bottle: index 0-23, grasp height as a fraction of its height, Drake mesh [n_theta, n_z]"
    ),
    "ellipse_sections": Key("facets around Drake's elliptic cylinder mesh"),
    "deltas_mm": Key("jaw displacements, each below the pad thickness", "mm", "compression", 1e-3),
    "reference_stabilization": Key("fraction of full integration kept against hourglass modes (neo-Hookean)"),
    "sweep_delta_mm": Key(
        "jaw displacement of the runtime-vs-error sweeps, one of deltas_mm", "mm", "compression", 1e-3
    ),
    "condensed_sweep_cells": Key("[nx, ny, nz] hexes of the condensed pads of the runtime sweep"),
    "drake_sweep_resolution_over_R": Key("Drake's rigid tessellation hints of the runtime sweep, / R"),
    "drake_resolution_over_R": Key("Drake's rigid tessellation hint of the per-delta rows, / R, < 1"),
    "foundation_cells": Key("Winkler grid cells per side of the runtime sweep (the last is used per delta)"),
    "margin_delta_mm": Key(
        "jaw displacement of the fitted 6DLS and the margins, one of deltas_mm", "mm", "compression", 1e-3
    ),
    "ls_model": Key("6DLS fitted to each peer's 6DFWs", choices=lambda: _ls_models()),
    "ls_twists": Key("thesis-sampled twists of that fit (2 ls_twists wrenches)"),
    "ls_directions": Key("uniform normals at which the fitted 6DLS is scored"),
    "n_disturbances": Key("lever disturbances (thesis §4.1.3.1) of the margins"),
    "margin_steps": Key("bisection steps on log2 s in [1/64, 64]"),
    "grid_mm": Key("pressure comparison grid spacing, below the pad's width and length", "mm"),
    "hertz_block": Key(
        "Hertz check: sphere R_mm, contact a_mm, block nu, finest hex fine_mm, depths_mm [H, 2H] (mm)",
        fields={"nu": ("poisson", 1.0)},
    ),
    "repeats": Key("timing repeats (median after one warm-up)"),
}

QUICK_CONFIG = {
    "hertz_block": {"R_mm": 20.0, "a_mm": 1.5, "nu": 0.3, "fine_mm": 0.6, "depths_mm": [20.0, 40.0]},
    "pad_cells": [8, 10, 3],
    "cases": ["sphere", "cylinder"],
    "deltas_mm": [0.5, 1.0],
    "condensed_sweep_cells": [[8, 10, 3]],
    "drake_sweep_resolution_over_R": [0.1, 0.05],
    "drake_resolution_over_R": 0.05,
    "foundation_cells": [40, 80],
    "n_disturbances": 4,
    "ls_twists": 200,
    "ls_directions": 500,
    "margin_steps": 6,
    "grid_mm": 0.4,
    "repeats": 2,
}

#: the errors reported per peer and case as the worst (largest |value|) over the jaw displacements
ERRORS = ("force_rel_err", "area_rel_err", "pressure_rel_l2", "torsion_rel_err", "torque_rel_err")
#: the columns of peers.csv and sweep.csv
TABLE_KEYS = [
    "case",
    "delta_mm",
    "delta_over_h",
    "peer",
    "setting",
    "ms_per_query",
    "force_N",
    "force_rel_err",
    "area_mm2",
    "area_rel_err",
    "pressure_rel_l2",
    "torsion_length_mm",
    "torsion_rel_err",
    "support_max_rel_err",
    "torque_rel_err",
]
SWEEP_KEYS = [
    "case",
    "peer",
    "setting",
    "ms_per_query",
    "force_rel_err",
    "pressure_rel_l2",
    "torsion_rel_err",
]
#: what each word measures (the summary's "definitions"; the report states them)
DEFINITIONS = {
    "force": "the jaw's sensor reading: net normal force on the object along the pad normal [N]",
    "area": "FEM: tributary area of the loaded face nodes (neo-Hookean: deformed); Hertz: pi a^2; "
    "foundation: the loaded grid cells (projected); Drake: its contact polygons on the object "
    "(curved) - curved and projected areas differ by O(delta/R), 2-7 % here",
    "pressure_rel_l2": "||p - p_ref|| / ||p_ref|| on a grid of the pad face (unsigned)",
    "torsion_rel_err": "torsion length tau_max/(mu f_n) per unit jaw force, peer/ref - 1",
    "torque_rel_err": "torque capacity mu f_n x torsion length at this delta, peer/ref - 1",
    "margin_rel_err": "median over disturbances of |s/s_true - 1| (unsigned), equal jaw force",
    "margin_bias": "median s/s_true - 1 (> 0: optimistic)",
    "ls_rel_err": "the 6DLS fitted (ls_model) to the peer's 6DFWs at equal jaw force against the "
    "reference's exact 6DFW surface at points of uniform normals: exp(mean |ln g|) - 1, g the ratio "
    "of the truth's radius to the fit's along each ray (a set 2x too small or too large: +100 %); "
    "the reference's own value is the model's own error. MuJoCo: none - its point contact's cone "
    "slice spans 3 of the 6 dimensions (fx, fy, tau_z; its supports are compared instead)",
    "ls_bias": "exp(median ln(1/g)) - 1 (> 0: the peer's fitted 6DLS lies outside the truth: optimistic)",
    "support_max_rel_err": "the largest |peer/ref - 1| of the 6DFW set's supports along the six axis "
    "twists per unit jaw force (forces and torques each compared where above 1e-3 of their "
    "group's largest)",
    "worst over delta": "the errors per peer and case are the largest |value| over deltas_mm",
}


def _ls_models() -> tuple[str, ...]:
    """The 6DLS models a peer's fit may use (workbench.limit_surface.fit_score, imported late)."""
    from workbench.limit_surface.fit_score import MODELS

    return tuple(MODELS)


def _positive_list(config: dict, key: str, n: int | None = None, integer: bool = False) -> list:
    v = config[key]
    kind = "integers >= 1" if integer else "numbers > 0"
    ok = isinstance(v, list) and (n is None or len(v) == n) and len(v) > 0
    ok = ok and all(
        (isinstance(x, int) and not isinstance(x, bool) and x >= 1)
        if integer
        else (isinstance(x, (int, float)) and not isinstance(x, bool) and np.isfinite(x) and x > 0)
        for x in v
    )
    if not ok:
        size = f"{n} " if n else ""
        raise ValueError(f"{key} must be a list of {size}{kind}; got {v!r}")
    return v


def _positive(config: dict, key: str, unit: str, upper: float = np.inf) -> float:
    v = config[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (np.isfinite(v) and 0 < v < upper):
        raise ValueError(f"{key} must be a number in (0, {upper:g}) [{unit}]; got {v!r}")
    return float(v)


def _check_lists(config: dict) -> list:
    """The pad, the meshes and the sweeps' lists; returns ``pad_mm`` ``[w, l, h]``."""
    pad_mm = _positive_list(config, "pad_mm", 3)
    if not config["condensed_sweep_cells"]:
        raise ValueError("condensed_sweep_cells must list at least one [nx, ny, nz] (the vs-Drake reading)")
    _positive_list(config, "pad_cells", 3, integer=True)
    _positive_list(config, "foundation_cells", integer=True)
    _positive_list(config, "drake_sweep_resolution_over_R")
    _positive_list(config, "ellipse_mm", 2)
    for cells in config["condensed_sweep_cells"]:
        _positive_list({"condensed_sweep_cells": cells}, "condensed_sweep_cells", 3, integer=True)
    return pad_mm


def _check_hertz_block(hb) -> None:
    keys = {"R_mm", "a_mm", "nu", "fine_mm", "depths_mm"}
    if not (isinstance(hb, dict) and set(hb) == keys):
        raise ValueError(
            f"hertz_block must be a dict of exactly {sorted(keys)} (e.g. the default "
            f"{DEFAULT_CONFIG['hertz_block']}); got {hb!r}"
        )
    for k in ("R_mm", "a_mm", "fine_mm"):
        _positive(hb, k, "mm")
    d1, d2 = _positive_list(hb, "depths_mm", 2)
    if d2 != 2 * d1 or not hb["a_mm"] < 0.5 * hb["R_mm"] or not hb["a_mm"] < 0.2 * d1:
        raise ValueError(
            "hertz_block must have depths_mm = [H, 2H] (Richardson in a/H) and a contact small against "
            f"both the sphere and the block (a_mm < R_mm / 2, a_mm < H / 5); got {hb!r}"
        )


def _check_sizes(config: dict, w: float, ln: float) -> None:
    _positive(config, "radius_mm", "mm (a sphere or cylinder of 1-500 mm)", 1000.0)
    if config["radius_mm"] < 1.0:
        raise ValueError(f"radius_mm is in millimetres (15 mm = 15); got {config['radius_mm']!r}")
    _positive(config, "grid_mm", "mm", min(w, ln))
    _positive(config, "drake_resolution_over_R", "-", 1.0)


def _check_bottle(bt) -> None:
    if not (
        isinstance(bt, dict)
        and isinstance(bt.get("index"), int)
        and 0 <= bt["index"] < 24
        and isinstance(bt.get("height"), (int, float))
        and 0 < bt["height"] < 1
        and isinstance(bt.get("mesh"), list)
        and len(bt["mesh"]) == 2
        and all(isinstance(v, int) and v >= 8 for v in bt["mesh"])
    ):
        raise ValueError(
            "bottle must be {'index': 0-23 (of the 24 thesis bottles), 'height': fraction in (0, 1), "
            f"'mesh': [n_theta, n_z] >= 8}}; got {bt!r}"
        )


def _check_counts(config: dict) -> None:
    from workbench.limit_surface.fit_score import min_wrenches

    need = metrics.min_twists(config["ls_model"])  # checks the model's name too
    if not (isinstance(config["ls_twists"], int) and config["ls_twists"] >= need):
        raise ValueError(
            f"ls_twists must be an integer >= {need} for ls_model {config['ls_model']!r} (2 ls_twists "
            f"wrenches against its {min_wrenches(config['ls_model'])} unknowns); got {config['ls_twists']!r}"
        )
    for key in (
        "repeats",
        "n_disturbances",
        "ellipse_sections",
        "ls_twists",
        "ls_directions",
    ):
        if isinstance(config[key], bool) or not isinstance(config[key], int) or config[key] < 1:
            raise ValueError(f"{key} must be an integer >= 1; got {config[key]!r}")
    check_steps(config["margin_steps"], "margin_steps")  # the margin's own rule


def _check_deltas(config: dict, h: float) -> None:
    if not config["cases"]:
        raise ValueError(f"cases must name at least one of {CASES}; got []")
    if not config["deltas_mm"] or not all(0 < d < h for d in config["deltas_mm"]):
        raise ValueError(
            f"deltas_mm must be jaw displacements in (0, h = {h}) mm; got {config['deltas_mm']!r}"
        )
    for key in ("sweep_delta_mm", "margin_delta_mm"):
        if config[key] not in config["deltas_mm"]:
            raise ValueError(f"{key} = {config[key]!r} must be one of deltas_mm {config['deltas_mm']!r}")


def check_config(config: dict) -> None:
    """The CLI checks settings with this before any work (careless input fails here, not after
    minutes of neo-Hookean references)."""
    check_workers(config["workers"], config["scheduler"])
    for key, spec in KEYS.items():  # E, ν, μ, the pad and the jaw displacements (also for run(config))
        check_key(key, spec, config[key])
    w, ln, h = _check_lists(config)
    check_mu(config["mu"], what="torsion length tau_max / (mu f_n)")  # and not 0 (the Key's range takes it)
    _check_hertz_block(config["hertz_block"])
    _check_sizes(config, w, ln)
    _check_bottle(config["bottle"])
    _check_counts(config)
    _check_deltas(config, h)


def _peer_rows(case: str, delta: float, config: dict, ctx: dict) -> dict:
    """``{peer: {"profile", "area", "field" | "coefficients", "seconds"}}`` at one δ (timed)."""
    rep = config["repeats"]
    geom, obs, rho, h = ctx["geom"], ctx["obstacle"], ctx["rho"], ctx["geom"].thickness
    rows = {}
    pad, area0 = ctx["pad"], ctx["area0"]

    def condensed():
        s = solve_contact(pad, obs, delta)
        return s, extract_profile(pad, s, obs)

    t, (s, prof) = median_runtime(condensed, rep)
    rows["condensed"] = {**fem_row(pad, area0, s, prof), "seconds": t}
    if ctx["full_mesh"]:
        t0 = time.perf_counter()
        s = solve_contact_full(geom, ctx["material"], obs, delta)
        prof = extract_profile(pad, s, obs)
        rows["linear"] = {**fem_row(pad, area0, s, prof), "seconds": time.perf_counter() - t0}
    E, nu = config["E"], config["nu"]
    w, ln = geom.width, geom.length
    if case == "sphere":
        from workbench.peers.hertz import hertz_profile

        R = config["radius_mm"] * 1e-3
        t, prof = median_runtime(partial(hertz_profile, R, delta, E, nu, center=ctx["center"]), rep)
        rows["hertz"] = {**hertz_row(prof, R, delta), "seconds": t}
    from workbench.peers.elastic_foundation import PadGrid, foundation_profile

    n = config["foundation_cells"][-1]
    winkler = PadGrid(w, ln, n, n, edge="warn" if case == "sphere" else "cut")
    fp = partial(foundation_profile, obs, delta, E, h, grid=winkler)
    t, prof = median_runtime(fp, rep)
    rows["foundation"] = {**profile_row(prof), "seconds": t}
    drake = ctx.get("drake")
    if drake is not None:
        t, prof = median_runtime(partial(drake.profile, delta), rep)
        rows["drake"] = {**profile_row(prof), "seconds": t}
    for kind in PATCH_TORSIONS:
        coef = patch_coefficients(config["mu"], rho, delta, kind)
        t, _ = median_runtime(partial(metrics.cone_supports, coef), rep)
        rows[f"mujoco_{kind}"] = {"profile": None, "coefficients": coef, "seconds": t}
    return rows


def _references(config: dict) -> tuple[dict, str]:
    """The neo-Hookean reference of every case (a task each): ``({case: reference_case(...)}, ran_on)``."""
    refs: dict[str, dict] = {}
    _, ran_on = run_rows(
        partial(reference_case, config=config),
        config["cases"],
        lambda case, res: refs.__setitem__(case, res),
        config,
        min_rows=2,
        progress=tqdm(total=len(config["cases"]), desc="neo-Hookean references", unit="case"),
    )
    return refs, ran_on


def _case_context(case: str, config: dict, skipped: dict) -> dict:
    """The pads and obstacle of one case, shared by its δ rows (Drake's absence noted in ``skipped``)."""
    geom, mat, obs, center, rho = setup_case(case, config)
    pad = condense_pad(geom, mat)
    _, area0 = face_grid(pad.face_xy)
    drake, why = drake_pad(case, obs, geom, config, config["drake_resolution_over_R"])
    if drake is None:
        skipped[f"drake/{case}"] = why
    return {
        "geom": geom,
        "material": mat,
        "obstacle": obs,
        "rho": rho,
        "pad": pad,
        "area0": area0,
        "center": center,
        "drake": drake,
        "full_mesh": True,
    }


def _run_case(case: str, config: dict, ref_case: dict, grid: np.ndarray, res: dict) -> None:
    """Every peer of one case at every δ against its reference: rows into ``res["table"]``, the
    runtime sweep, margins and fitted 6DLS at their δ into ``res``."""
    mu = config["mu"]
    ctx = _case_context(case, config, res["skipped"])
    geom = ctx["geom"]
    for d in [d * 1e-3 for d in config["deltas_mm"]]:
        r = ref_case["rows"][d]
        ref = reference_measures(r, ref_case["face_xy"], grid, mu)
        base = {"case": case, "delta_mm": d * 1e3, "delta_over_h": d / geom.thickness}
        res["table"].append(
            {
                **base,
                "peer": "neo-Hookean",
                "setting": "reference",
                "ms_per_query": 1e3 * ref_case["seconds"],
                "force_N": ref["force_N"],
                "area_mm2": ref["area"] * 1e6,
                "torsion_length_mm": 1e3 * ref["torsion_length"],
            }
        )
        rows = _peer_rows(case, d, config, ctx)
        for peer, row in rows.items():
            res["table"].append(
                {
                    **base,
                    "peer": peer,
                    "setting": _setting(peer, config),
                    "ms_per_query": 1e3 * row["seconds"],
                    **compare(row, ref, grid, mu),
                }
            )
        if d == config["sweep_delta_mm"] * 1e-3:
            res["sweep"] += _sweep(case, d, config, ref, grid, ctx["obstacle"], geom, ctx["material"])
        if d == config["margin_delta_mm"] * 1e-3:
            res["margins"][case] = _case_margins(rows, r["profile"], ctx["center"], config)
            res["ls"][case] = _case_ls(rows, r["profile"], config)


def _case_summary(peer: str, s: dict, m: dict | None, ls: dict | None) -> None:
    """One peer and case's summary ``s`` (its per-δ lists) completed: median cost, the worst
    errors over δ, the margins ``m`` and fitted 6DLS ``ls`` at their δ."""
    s["ms_per_query"] = float(np.median(s.pop("ms_per_query_per_delta")))
    for k in ERRORS:
        vals = [v for v in s[k + "_per_delta"] if v is not None]
        s[k] = float(max(vals, key=abs)) if vals else (0.0 if peer == "neo-Hookean" else None)
    s["margin_rel_err"] = None if m is None else m["median_abs_rel_err"]
    # signed: the median s/s_true - 1 (> 0: the peer promises more than the truth holds)
    s["margin_bias"] = None if m is None else float(np.expm1(m["median_log_ratio"]))
    s["margin"] = m
    s["ls_rel_err"] = None if ls is None else ls["rel_err"]
    s["ls_bias"] = None if ls is None else ls["bias"]
    s["ls"] = ls


def _summarize(table: list[dict], margins_out: dict, ls_out: dict) -> dict:
    """Per peer and case: errors per δ, margin at the margin δ, median cost."""
    summary_peers: dict = {}
    for row in table:
        s = summary_peers.setdefault(row["peer"], {}).setdefault(row["case"], {"delta_mm": []})
        s["delta_mm"].append(row["delta_mm"])
        for k in (*ERRORS, "support_max_rel_err", "ms_per_query"):
            s.setdefault(k + "_per_delta", []).append(row.get(k))
    for peer, cases in summary_peers.items():
        for case, s in cases.items():
            m = margins_out.get(case, {}).get(peer)
            _case_summary(peer, s, m, ls_out.get(case, {}).get(peer))
    return summary_peers


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    check_config(config)
    refs, ran_on = _references(config)
    grid, _ = metrics.face_grid_points(*(v * 1e-3 for v in config["pad_mm"][:2]), config["grid_mm"] * 1e-3)
    hertz_block = hertz_half_space(config["hertz_block"], config["E"])
    res: dict = {"table": [], "sweep": [], "skipped": {}, "margins": {}, "ls": {}}
    versions_peers = _peer_versions()
    for case in tqdm(config["cases"], desc="peers", unit="case"):
        _run_case(case, config, refs[case], grid, res)
    table, sweep, skipped = res["table"], res["sweep"], res["skipped"]
    summary_peers = _summarize(table, res["margins"], res["ls"])
    headline_cmp = _headline_vs_drake(sweep)
    _figure(sweep, table, config["sweep_delta_mm"], out)
    write_csv(out / "peers.csv", TABLE_KEYS, [[r.get(k) for k in TABLE_KEYS] for r in table])
    write_csv(out / "sweep.csv", SWEEP_KEYS, [[r.get(k) for k in SWEEP_KEYS] for r in sweep])
    summary = {
        "peers": summary_peers,
        "reference": "the neo-Hookean pad (NonlinearPad, stabilization "
        f"{config['reference_stabilization']:g}) on the same mesh",
        "sweep": sweep,
        "hertz_half_space": hertz_block,
        "vs_drake": headline_cmp,
        "skipped": skipped,
        "peer_versions": versions_peers,
        "mapping": _mapping(config),
        "references_ran_on": ran_on,
        "sweep_delta_mm": config["sweep_delta_mm"],
        "margin_delta_mm": config["margin_delta_mm"],
        # what each word measures (the report states them)
        "definitions": DEFINITIONS,
        # margins are bisected on log2 s over [1/64, 64]: relative differences below this are unresolved
        "margin_resolution": float(2.0 ** (2 * np.log2(MARGIN_SPAN) / 2 ** config["margin_steps"]) - 1),
        "figures": [str(out / "runtime_vs_error.png")],
        "headline": _headline(summary_peers, headline_cmp, skipped, hertz_block, config["sweep_delta_mm"]),
    }
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _setting(peer: str, config: dict) -> str:
    return {
        "condensed": "x".join(map(str, config["pad_cells"])) + " hexes",
        "linear": "x".join(map(str, config["pad_cells"])) + " hexes, full mesh",
        "foundation": f"{config['foundation_cells'][-1]}^2 cells",
        "drake": f"resolution R*{config['drake_resolution_over_R']:g}",
        "hertz": "analytic",
        "mujoco_hertz": "torsion 3*pi*mu*a/16",
        "mujoco_diameter": "torsion mu*2a",
    }.get(peer, "")


def _case_margins(rows: dict, ref_profile, center: np.ndarray, config: dict) -> dict:
    """``{peer: margin errors}`` of every peer's two-jaw grasp against the neo-Hookean truth at its
    jaw force (:func:`workbench.peers.comparison.equal_force_margins`), and ``"truth_margins"``."""
    truth, m = equal_force_margins(
        rows,
        ref_profile,
        center,
        config["mu"],
        seed=config["seed"],
        n_disturbances=config["n_disturbances"],
        steps=config["margin_steps"],
    )
    out: dict = {
        peer: {"median_abs_rel_err": margin_rel_err(s, truth), **margin_vs_truth(s, truth)}
        for peer, s in m.items()
    }
    out["truth_margins"] = truth.tolist()
    return out


def _case_ls(rows: dict, ref_profile, config: dict) -> dict:
    """``{peer: fitted_ls_error(...)}`` for every peer with a contact profile, and the reference's
    own fit (the floor) under ``"neo-Hookean"``."""
    kw = {
        "model": config["ls_model"],
        "n_twists": config["ls_twists"],
        "n_directions": config["ls_directions"],
        "seed": config["seed"],
    }
    mu = config["mu"]
    out = {"neo-Hookean": metrics.fitted_ls_error(ref_profile, ref_profile, mu, **kw).as_dict()}
    for peer, row in rows.items():
        if row.get("profile") is not None:
            out[peer] = metrics.fitted_ls_error(row["profile"], ref_profile, mu, **kw).as_dict()
    return out


def _sweep(case, d, config, ref, grid, obs, geom, mat) -> list[dict]:
    """Runtime vs error at one δ over each peer's resolution knob."""
    mu, rep = config["mu"], config["repeats"]
    pts = []

    def add(peer, setting, seconds, prof, row):
        c = compare(row, ref, grid, mu)
        pts.append({"case": case, "peer": peer, "setting": setting, "ms_per_query": 1e3 * seconds, **c})

    for cells in config["condensed_sweep_cells"]:
        g2, m2, o2, _, _ = setup_case(case, config, cells)
        pad = condense_pad(g2, m2)
        _, a0 = face_grid(pad.face_xy)

        def q(pad=pad, o2=o2):
            s = solve_contact(pad, o2, d)
            return s, extract_profile(pad, s, o2)

        t, (s, prof) = median_runtime(q, rep)
        add("condensed", "x".join(map(str, cells)), t, prof, {**fem_row(pad, a0, s, prof)})
    from workbench.peers.elastic_foundation import PadGrid, foundation_profile

    for n in config["foundation_cells"]:
        winkler = PadGrid(geom.width, geom.length, n, n, edge="warn" if case == "sphere" else "cut")
        fp = partial(foundation_profile, obs, d, config["E"], geom.thickness, grid=winkler)
        t, prof = median_runtime(fp, rep)
        add("foundation", f"{n}^2", t, prof, profile_row(prof))
    # Drake's knob: the rigid tessellation hint (sphere, cylinder) or the facets of the mesh
    res = config["drake_resolution_over_R"]
    if case == "bottle":
        nt, nz = config["bottle"]["mesh"]
        knob = [
            (f"{a}x{b} mesh", {**config, "bottle": {**config["bottle"], "mesh": [a, b]}}, res)
            for a, b in ((nt // 2, nz // 2), (nt, nz))
        ]
    elif case == "elliptic_cylinder":
        n = config["ellipse_sections"]
        knob = [(f"{k} facets", {**config, "ellipse_sections": k}, res) for k in (n // 4, n // 2, n)]
    else:
        knob = [(f"R*{f:g}", config, f) for f in config["drake_sweep_resolution_over_R"]]
    for label, cfg, f in knob:
        drake, _ = drake_pad(case, obs, geom, cfg, f)
        if drake is None:
            break
        t, prof = median_runtime(partial(drake.profile, d), rep)
        add("drake", label, t, prof, profile_row(prof))
    return pts


_FLIP = {None: None, "at most": ">=", "at least": "<="}


def _headline_vs_drake(sweep: list[dict]) -> dict:
    """Where the condensed FEM sits against Drake: its error at Drake's runtime (error ratio Drake /
    condensed) and its runtime at Drake's error (runtime ratio Drake / condensed), per case and
    metric, read on each method's Pareto front at Drake's default-resolution point."""
    out = {}
    for case in sorted({p["case"] for p in sweep}):
        cond = [p for p in sweep if p["case"] == case and p["peer"] == "condensed"]
        dr = [p for p in sweep if p["case"] == case and p["peer"] == "drake"]
        if not cond or not dr:
            continue
        res = {}
        for metric in ("force_rel_err", "pressure_rel_l2"):
            ct = [p["ms_per_query"] for p in cond]
            ce = [max(abs(p[metric]), 1e-16) for p in cond]
            dp = dr[-1]  # the finest hint: Drake's default R/80
            de = max(abs(dp[metric]), 1e-16)
            at_t = at_equal(ct, ce, runtime_at=dp["ms_per_query"])
            at_e = at_equal(ct, ce, error_at=de)
            res[metric] = {
                "drake_ms": dp["ms_per_query"],
                "drake_error": de,
                "condensed_error_at_drake_ms": at_t["value"],
                "error_ratio_drake_over_condensed": de / at_t["value"],
                "error_ratio_clamped": at_t["clamped"],
                # the ratio divides by the condensed value: a bound on it flips ("at most" -> ">=")
                "error_ratio_bound": _FLIP[at_t["beyond"]],
                "condensed_ms_at_drake_error": at_e["value"],
                "runtime_ratio_drake_over_condensed": dp["ms_per_query"] / at_e["value"],
                "runtime_ratio_clamped": at_e["clamped"],
                "runtime_ratio_bound": _FLIP[at_e["beyond"]],
            }
        out[case] = res
    return out


def _figure(sweep: list[dict], table: list[dict], sweep_delta_mm: float, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    metrics_ = ("force_rel_err", "pressure_rel_l2", "torsion_rel_err")
    cases = sorted({p["case"] for p in sweep})
    fig, axes = plt.subplots(
        len(metrics_),
        max(1, len(cases)),
        figsize=(4.2 * max(1, len(cases)), 10),
        squeeze=False,
        constrained_layout=True,
    )
    colors = {
        "condensed": "C0",
        "foundation": "C2",
        "drake": "C3",
        "linear": "C4",
        "hertz": "C1",
        "mujoco_hertz": "C5",
        "mujoco_diameter": "C6",
    }
    for j, case in enumerate(cases):
        for i, m in enumerate(metrics_):
            ax = axes[i, j]
            for peer in colors:
                pts = [p for p in sweep if p["case"] == case and p["peer"] == peer and p.get(m) is not None]
                if peer in ("linear", "hertz", "mujoco_hertz", "mujoco_diameter"):  # one point each
                    pts += [
                        r
                        for r in table
                        if r["case"] == case
                        and r["peer"] == peer
                        and r["delta_mm"] == sweep_delta_mm
                        and r.get(m) is not None
                    ]
                if not pts:
                    continue
                x = [p["ms_per_query"] for p in pts]
                y = [max(abs(p[m]), 1e-6) for p in pts]
                ax.loglog(x, y, "o-" if len(pts) > 1 else "s", color=colors[peer], ms=4, label=peer)
            ref_ms = [r["ms_per_query"] for r in table if r["case"] == case and r["peer"] == "neo-Hookean"]
            if ref_ms:
                ax.axvline(ref_ms[0], color="k", ls=":", lw=0.8, label="neo-Hookean (reference)")
            ax.set_xlabel("ms per query")
            ax.set_ylabel(f"|{m}|")
            ax.set_title(f"{case}", fontsize=9)
            ax.grid(True, which="both", lw=0.3)
    handles = {}
    for ax in axes.ravel():
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(lab, h)
    fig.legend(list(handles.values()), list(handles), loc="outside lower center", ncol=4, fontsize=7)
    fig.suptitle("Runtime vs error against the neo-Hookean pad (one δ; each knob's resolutions)")
    save_figure(fig, out / "runtime_vs_error.png")


def _peer_versions() -> dict:
    from importlib import metadata

    out = {}
    for pkg in ("drake", "mujoco"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def _mapping(config: dict) -> dict:
    E, h = config["E"], config["pad_mm"][2] * 1e-3
    return {
        "foundation": f"k = E/h = {E / h:.4g} Pa/m (GraspIt!'s plain Winkler layer, kind='simple')",
        "drake": f"E_hydro = k H = E = {E:.4g} Pa, box of height 2h (H = h = {h:g} m): Winkler",
        "mujoco_hertz": "friction = (mu, mu, 3 pi mu a/16, 0, 0), a = sqrt(rho delta), rho: curvature radius",
        "mujoco_diameter": "friction = (mu, mu, 2 a mu, 0, 0): the docs' 'diameter of the contact patch'",
        "hertz": "E* = E/(1 - nu^2), a = sqrt(R delta) (half-space: no layer)",
    }


def _headline(peers: dict, cmp: dict, skipped: dict, hertz_block: dict, sweep_delta_mm: float) -> list[str]:
    lines = []
    floor = {c: s.get("ls_rel_err") for c, s in peers.get("neo-Hookean", {}).items()}
    if any(v is not None for v in floor.values()):
        lines.append(
            "fitted 6DLS: symmetric radial error against the reference's exact 6DFW surface; the "
            "reference's own fit (the model's own error) "
            + ", ".join(f"{c} {100 * v:.1f}%" for c, v in floor.items() if v is not None)
        )
    for peer in ("condensed", "linear", "hertz", "foundation", "drake", "mujoco_hertz"):
        if peer not in peers:
            continue
        parts = []
        for case, s in peers[peer].items():
            f = s.get("force_rel_err")
            t = s.get("torsion_rel_err")
            ls = s.get("ls_rel_err")
            parts.append(
                f"{case}: force {'n/a' if f is None else f'{100 * f:+.0f}%'}, torsion {100 * t:+.0f}%, "
                + ("" if ls is None else f"fitted 6DLS {100 * ls:.0f}%, ")
                + f"{s['ms_per_query']:.3g} ms"
            )
        lines.append(f"{peer} (worst over δ vs neo-Hookean) — " + "; ".join(parts))
    for case, res in cmp.items():
        r = res["force_rel_err"]
        be, bt = r["error_ratio_bound"] or "", r["runtime_ratio_bound"] or ""
        lines.append(
            f"condensed FEM vs Drake ({case}, force at δ = {sweep_delta_mm:g} mm): at Drake's "
            f"{r['drake_ms']:.3g} ms per query Drake's error / the condensed one = "
            f"{be}{r['error_ratio_drake_over_condensed']:.2g}; at Drake's error ({r['drake_error']:.2g}) "
            f"Drake's runtime / the condensed one = {bt}{r['runtime_ratio_drake_over_condensed']:.2g} "
            "(>= / <=: read beyond the condensed sweep's measured range)"
        )
    hb = hertz_block
    lines.append(
        f"our condensed FEM vs Hertz where it applies: force {100 * hb['force_rel_err'][0]:+.1f}% "
        f"(a/H = {hb['a_over_H'][0]:.3g}), {100 * hb['force_rel_err'][1]:+.1f}% "
        f"(a/H = {hb['a_over_H'][1]:.3g}), "
        f"half-space limit {100 * hb['extrapolated_force_rel_err']:+.1f}%"
    )
    if skipped:
        lines.append("skipped: " + "; ".join(f"{k} ({v})" for k, v in skipped.items()))
    return lines


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))

"""Does small-strain linear theory hold where the cup is measured?

The measured plastic cup closes 4–23 mm at 10 N per jaw (``s`` = 437–2530 N/m) —
up to half its radius, 10–40 wall thicknesses.  Steps (each a function of
:mod:`workbench.fem.wall_linearity`, which this driver composes):

1. the linear wall (:mod:`workbench.fem.wall`, PET) at every measured grasp, calibrated by one
   effective Young's modulus ``E_lin`` on all of them (``s ∝ E`` exactly);
2. at ``n_grasps`` grasps spread over the heights, the geometrically nonlinear wall
   (:mod:`workbench.fem.wall_nonlinear`: total Lagrangian St. Venant–Kirchhoff, load stepping,
   same mesh, clamps and jaws) at ``E_lin``, its load curve up to ``force_stop``;
3. per grasp: ``s_nl / s_lin`` at 10 N (how far linear theory is off at the closings
   it predicts), the closing, and the work ``∫ f dΔ`` of each;
4. each model calibrated by its own single E on these grasps (the nonlinear one through
   the f / E scaling of :func:`workbench.fem.wall_nonlinear.curve_stiffness`): which one matches
   the measured stiffness better (median |log ratio|, Spearman).

Each grasp's two load curves are one row: a Dask task (``workers`` / ``scheduler``; the
numbers are the serial run's), checkpointed by the driver.  The mesh is coarser than
minimal-work's (the nonlinear wall is solved ~10× per load step); both models share it.
"""

from __future__ import annotations

import logging
import time
from functools import partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench.code_key import code_digest
from workbench.fem.calibration import stiffness_scores
from workbench.fem.material import Material
from workbench.fem.wall_linearity import (
    calibrate_models,
    grasp_comparison,
    grasp_load_curves,
    linear_at_grasps,
    measured_object_wall,
    pick_grasps,
)
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import CHECKOUT, Checkpoint, save_figure, write_summary

NAME = "wall-nonlinear"
log = logging.getLogger(__name__)

DEFAULT_CONFIG = {
    "seed": 0,
    "data_dir": str(CHECKOUT.parent / "shared" / "data" / "deformable_objects"),  # meshes/, stiffness_maps/
    "object": "plastic_cup",  # a measured object of data_dir
    "E": 2.5e9,  # PET before calibration [Pa]
    "nu": 0.4,
    "thickness": 0.5e-3,
    "mesh": [16, 8],  # hexes around, along (coarse: both models share it; the lip adds rows)
    "n_grasps": 3,  # nonlinear load curves at this many grasps, spread over the heights
    "grasps": None,  # or these grasp indices of the map (replaces n_grasps)
    "force": 10.0,  # N per jaw (thesis)
    "force_stop": 13.0,  # load curves run to this mean jaw force [N] (room to calibrate E)
    "step_mm": 1.5,  # closing increment of the load stepping
    "max_closing_mm": 40.0,
    # where the grasps' load curves run (workbench.runner.parallel.row_client): 0 = a local Dask cluster of
    # one worker per core from NL_MIN_ROWS grasps, 1 = serially here, N = N local workers;
    # scheduler = an existing cluster's address.  Neither changes a number.
    "workers": 0,
    "scheduler": "",
}
WHERE_KEYS = ("out", "workers", "scheduler")
#: a local cluster for the load curves from this many grasps (a curve takes far longer than a cluster's start)
NL_MIN_ROWS = 2
#: what each key means, its unit and plausible range (``workbench run wall-nonlinear --help``)
KEYS = {
    "data_dir": Key("folder with meshes/NAME.obj and stiffness_maps/NAME.json (deformable_objects)"),
    "object": Key("a measured object of data_dir"),
    "E": Key("wall Young's modulus before calibration (PET)", "Pa", "wall_modulus"),
    "nu": Key("wall Poisson ratio", "", "poisson"),
    "thickness": Key("wall thickness", "m", "wall_thickness"),
    "mesh": Key("wall hexes [around, along the height] (both models share it)"),
    "n_grasps": Key("nonlinear load curves at this many grasps, spread over the heights"),
    "grasps": Key("null, or distinct grasp indices of the map (replaces n_grasps)"),
    "force": Key("force per jaw at which the models' stiffness is compared (thesis: 10)", "N", "jaw_force"),
    "force_stop": Key("the load curves run to this mean jaw force (room to calibrate E)", "N", "jaw_force"),
    "step_mm": Key("closing increment of the load stepping", "mm", "closing", 1e-3),
    # a cap, not judged as a "closing": its 40 mm default is above that quantity's usual 20 mm
    # (the measured cup closes up to 23 mm at 10 N), which would warn on every run
    "max_closing_mm": Key("the load stepping stops at this closing, > step_mm", "mm", "closing", 1e-3),
}
QUICK_CONFIG = {"n_grasps": 1, "mesh": [12, 6], "force": 3.0, "force_stop": 3.3, "step_mm": 2.0}


def check_config(config: dict) -> None:
    """What the defaults' types cannot tell: plausible physical numbers (:data:`KEYS`, also for
    run(config)), and ``grasps`` is None or distinct grasp indices."""
    for key, spec in KEYS.items():
        check_key(key, spec, config[key])
    g = config["grasps"]
    if g is not None and (
        not isinstance(g, list)
        or not g
        or not all(isinstance(k, int) and not isinstance(k, bool) and k >= 0 for k in g)
        or len(set(g)) != len(g)
    ):
        raise ValueError(f"grasps must be null or a list of distinct grasp indices >= 0; got {g!r}")
    check_workers(config["workers"], config["scheduler"])


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    key_config = {k: v for k, v in config.items() if k not in WHERE_KEYS}
    ckpt = Checkpoint(out / "rows.jsonl", key_config, code=code_digest(__name__))
    name, F = config["object"], config["force"]
    geo, wall, L, measured = object_inputs(config)
    n = len(L) // 2
    # 1. linear, all grasps, one E
    lin = linear_at_grasps(wall, geo, L, measured)
    E_lin = config["E"] * lin.scale
    # 2. nonlinear (and linear on the same grasp-frame mesh) at the picked grasps, rows on Dask
    z = 0.5 * (L[:n, 2] + L[n:, 2])
    pick = pick_grasps(lin.ok, z, n_grasps=config["n_grasps"], grasps=config["grasps"], name=name)
    todo = [int(k) for k in pick if f"nl/{k}" not in ckpt]
    with tqdm(total=len(todo), desc="nonlinear wall", unit="grasp") as bar:
        _, ran_on = run_rows(
            partial(_grasp_curves, geo=geo, E=E_lin, L=L, config=config),
            todo,
            lambda k, res: ckpt.add(f"nl/{k}", res),
            config,
            min_rows=NL_MIN_ROWS,
            progress=bar,
        )
    # 3. per grasp: stiffness ratio, closings and work of both models
    rows = [
        grasp_comparison(
            k,
            ckpt.rows[f"nl/{k}"],
            z=z[k],
            measured=measured[k],
            s_linear_all=lin.stiffness[k] * lin.scale,
            force=F,
        )
        for k in pick
    ]
    both = [r for r in rows if np.isfinite(r["s_linear"]) and np.isfinite(r["s_nonlinear"])]
    if not both:
        raise ValueError("no grasp where both models reach the force without resting on the base")
    # 4. each model with its own single E on these grasps, and on random halves of them
    cal = calibrate_models(
        np.array([r["measured"] for r in both]),
        np.array([r["s_linear"] for r in both]),
        [ckpt.rows[f"nl/{r['grasp']}"] for r in both],
        E_lin=E_lin,
        force=F,
        force_stop=config["force_stop"],
    )
    compare, held = cal.compare, cal.held_out
    ratios = np.array([r["ratio_nl_lin"] for r in both])
    ok = lin.ok
    summary = {
        "object": name,
        "E_linear_calibrated_Pa": E_lin,
        "linear_all_grasps": {"n": int(ok.sum())}
        | stiffness_scores(lin.stiffness[ok] * lin.scale, measured[ok]),
        "grasps": rows,
        "ratio_nl_lin": {
            "min": float(ratios.min()),
            "median": float(np.median(ratios)),
            "max": float(ratios.max()),
        },
        "calibrated_on_these_grasps": compare,
        "held_out_over_halves": held,
        "wall": {"mesh": config["mesh"], "dofs": int(wall.basis.N), "top": "lip" if geo.lip else "other"},
        "ran_on": ran_on,
        "figures": [_figure(out, rows, [ckpt.rows[f"nl/{r['grasp']}"] for r in rows], F)],
    }
    summary["headline"] = _headline(name, E_lin, F, ratios, both, rows, compare, held)
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def object_inputs(config: dict) -> tuple:
    """The object's wall geometry and linear wall at PET, its grasp locations ``L`` (2n, 3)
    [m] (jaw a of grasp k at row k, jaw b at k + n) and measured stiffness (n,) [N/m]
    (:func:`workbench.fem.wall_linearity.measured_object_wall` at the run's settings)."""
    return measured_object_wall(
        config["data_dir"],
        config["object"],
        Material(config["E"], config["nu"]),
        thickness=config["thickness"],
        mesh=config["mesh"],
    )


def _grasp_curves(k: int, geo, E: float, L: np.ndarray, config: dict) -> dict:
    """One grasp's row (a Dask task): :func:`workbench.fem.wall_linearity.grasp_load_curves` at
    Young's modulus ``E`` [Pa] at the run's settings."""
    n = len(L) // 2
    return grasp_load_curves(
        geo,
        Material(E, config["nu"]),
        L[[k, k + n]],
        n_theta=config["mesh"][0],
        force=config["force"],
        force_stop=config["force_stop"],
        step=config["step_mm"] * 1e-3,
        max_closing=config["max_closing_mm"] * 1e-3,
    )


def _headline(name, E_lin, F, ratios, both, rows, compare, held) -> list[str]:
    lines = [
        f"{name}: at the linear model's calibrated E ({E_lin / 1e9:.2f} GPa) the nonlinear wall's "
        f"stiffness at {F:g} N is {np.median(ratios):.2f}x the linear one "
        f"(range {ratios.min():.2f}-{ratios.max():.2f}) over "
        f"{len(both)} grasps, closings {min(r['closing_linear_mm'] for r in both):.1f}-"
        f"{max(r['closing_linear_mm'] for r in both):.1f} mm; "
        f"{sum(r['rests_on_base']['nonlinear'] for r in rows)} of {len(rows)} rest on the base (nonlinear), "
        f"{sum(r['rests_on_base']['linear'] for r in rows)} (linear)"
    ] + [
        f"{m} (own E {v['E_effective_Pa'] / 1e9:.2f} GPa): median |log(s/s_measured)| "
        f"{v['median_abs_log_ratio']:.2f} on these grasps"
        for m, v in compare.items()
        if v
    ]
    for m in ("linear", "nonlinear"):
        if held and held[m]:
            a = held[m]["median_abs_log_ratio"]
            lines.append(
                f"{m}, E fitted on random halves of the {held['n_grasps']} grasps: held-out median "
                f"|log ratio| {a['median']:.2f} (p10-p90 {a['p10']:.2f}-{a['p90']:.2f}), Spearman "
                f"{held[m]['spearman']['median']:.2f}"
            )
    return lines


def _figure(out: Path, rows: list[dict], curves: list[dict], F: float) -> str:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.2, 3.8))
    for r, cv in zip(rows, curves, strict=True):
        c = np.asarray(cv["closing"]) * 1e3
        (line,) = ax.plot(c, np.mean(cv["jaw_forces"], axis=1), label=f"z = {r['z_m'] * 1e3:.0f} mm")
        if np.isfinite(r["s_linear"]):
            ax.plot(c, r["s_linear"] * c * 1e-3, ls="--", color=line.get_color(), lw=0.8)
        ax.plot(F / r["measured"] * 1e3, F, "o", color=line.get_color(), mfc="none")
    ax.axhline(F, color="0.6", lw=0.6)
    ax.set_xlabel("jaw closing Δ [mm]")
    ax.set_ylabel("jaw force [N]")
    ax.set_title("nonlinear (solid) vs linear (dashed) wall; measured (o)", fontsize=9)
    ax.legend(fontsize=7)
    return str(save_figure(fig, out / "fig_force_closing.png"))


if __name__ == "__main__":
    from workbench.runner.cli import main

    main(["run", NAME, *__import__("sys").argv[1:]])

"""Does small-strain linear theory hold where the cup is measured?

The measured plastic cup closes 4–23 mm at 10 N per jaw (``s`` = 437–2530 N/m) —
up to half its radius, 10–40 wall thicknesses.  Steps:

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
from scipy.optimize import brentq
from tqdm import tqdm

from workbench.code_key import code_digest
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import CHECKOUT, Checkpoint, save_figure, write_summary
from workbench.stats import rank_correlation

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
    lin = _linear_all(wall, geo, L, measured)
    E_lin = config["E"] * lin["scale"]
    # 2. nonlinear (and linear on the same grasp-frame mesh) at the picked grasps, rows on Dask
    z = 0.5 * (L[:n, 2] + L[n:, 2])
    pick = _pick(config, lin["ok"], z, name)
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
    rows = [_grasp_row(k, ckpt.rows[f"nl/{k}"], z, measured, lin, config) for k in pick]
    both = [r for r in rows if np.isfinite(r["s_linear"]) and np.isfinite(r["s_nonlinear"])]
    if not both:
        raise ValueError("no grasp where both models reach the force without resting on the base")
    # 4. each model with its own single E on these grasps, and on random halves of them
    curves = [ckpt.rows[f"nl/{r['grasp']}"] for r in both]
    compare, held = _calibrate(both, curves, E_lin, config)
    ratios = np.array([r["ratio_nl_lin"] for r in both])
    ok = lin["ok"]
    summary = {
        "object": name,
        "E_linear_calibrated_Pa": E_lin,
        "linear_all_grasps": {
            "n": int(ok.sum()),
            "median_abs_log_ratio": float(
                np.median(np.abs(np.log(lin["s_pet"][ok] * lin["scale"] / measured[ok])))
            ),
            "spearman": rank_correlation(lin["s_pet"][ok], measured[ok]),
        },
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
    [m] (jaw a of grasp k at row k, jaw b at k + n) and measured stiffness (n,) [N/m]."""
    import trimesh

    from workbench.fem.material import Material
    from workbench.fem.object_wall import object_wall
    from workbench.fem.wall_grasps import read_locations

    d, name = Path(config["data_dir"]), config["object"]
    mesh = trimesh.load(d / "meshes" / f"{name}.obj", force="mesh")
    L, measured = read_locations(d / "stiffness_maps" / f"{name}.json")
    if measured is None:
        raise ValueError(f"{name}: the map has no 'stiffness_map' to compare with")
    nt, nz = config["mesh"]
    pet = Material(config["E"], config["nu"])
    geo, wall = object_wall(mesh, pet, thickness=config["thickness"], n_theta=nt, n_z=nz)
    return geo, wall, L, measured


def _linear_all(wall, geo, L: np.ndarray, measured: np.ndarray) -> dict:
    """Step 1: the linear wall at PET at every grasp, ``s_pet`` (n,) [N/m]; ``ok`` (n,) where
    both it and the map resolve the grasp (not rigid, not failed); ``scale`` = the one factor
    on E that matches the measured stiffness in the median of log ratios (``s ∝ E``)."""
    from workbench.fem.wall_grasps import stiffness_at

    lin = stiffness_at(wall, geo, L)
    s = np.array([r["stiffness"] for r in lin])
    ok = np.isfinite(s) & (s < 1e9) & (measured < 1e9)  # 1e9 N/m: the map's and ours' "rigid"
    return {"s_pet": s, "ok": ok, "scale": float(np.exp(np.median(np.log(measured[ok] / s[ok]))))}


def _pick(config: dict, ok: np.ndarray, z: np.ndarray, name: str) -> np.ndarray:
    """The grasps of step 2: ``grasps`` as given (checked), or ``n_grasps`` of the resolved
    ones spread over the heights, base to lip (one: mid-height)."""
    cand = np.flatnonzero(ok)
    if config["grasps"] is None:
        n_pick = min(config["n_grasps"], cand.size)  # more than there are: every grasp once
        at = np.linspace(0, cand.size - 1, n_pick) if n_pick > 1 else [cand.size // 2]
        return cand[np.argsort(z[cand])][np.round(at).astype(int)]
    pick = np.asarray(config["grasps"], int)
    bad = [int(k) for k in pick if not (0 <= k < ok.size and ok[k])]
    if bad:
        raise ValueError(
            f"grasps {bad} of {name} are not grasps 0..{ok.size - 1} that both the map and the linear "
            f"wall resolve (rigid or failed); choose among {cand.tolist()}"
        )
    return pick


def _grasp_curves(k: int, geo, E: float, L: np.ndarray, config: dict) -> dict:
    """One grasp's row (a Dask task): the nonlinear wall's load curve at Young's modulus ``E``
    [Pa] up to ``force_stop``, and the linear squeeze to ``force`` on the same grasp-frame mesh
    at the same E (its closing decides whether a jaw reaches the clamped base too)."""
    from workbench.fem.material import Material
    from workbench.fem.wall import squeeze
    from workbench.fem.wall_nonlinear import grasp_frame_wall, squeeze_nonlinear

    n = len(L) // 2
    w, centre = grasp_frame_wall(geo, Material(E, config["nu"]), L[k], L[k + n], n_theta=config["mesh"][0])
    res = squeeze_nonlinear(
        w,
        centre,
        force=config["force_stop"],
        step=config["step_mm"] * 1e-3,
        max_closing=config["max_closing_mm"] * 1e-3,
    )
    lin = squeeze(w, centre, np.array([1.0, 0.0, 0.0]), force=config["force"])
    return {
        "closing": res.closing.tolist(),
        "jaw_forces": res.jaw_forces.tolist(),
        "newton_iterations": res.newton_iterations,
        "on_clamp": res.on_clamp,
        "seconds": res.seconds,
        "s_linear": float(lin.stiffness),
        "on_clamp_linear": bool(lin.on_clamp),
    }


def _grasp_row(k: int, r: dict, z: np.ndarray, measured: np.ndarray, lin: dict, config: dict) -> dict:
    """Step 3 at grasp ``k`` from its checkpointed curves ``r``."""
    from workbench.fem.wall_nonlinear import curve_stiffness

    F = config["force"]
    fm = np.mean(r["jaw_forces"], axis=1)
    s_nl, w_nl = curve_stiffness(r["closing"], r["jaw_forces"], F)
    s_l = np.nan if r["on_clamp_linear"] else r["s_linear"]
    return {
        "grasp": int(k),
        "z_m": float(z[k]),
        "measured": float(measured[k]),
        # log(measured / linear) of the linear wall calibrated on all grasps (step 1)
        "linear_residual_log": float(np.log(measured[k] / (lin["s_pet"][k] * lin["scale"]))),
        "s_linear": float(s_l),
        "s_nonlinear": s_nl,
        "rests_on_base": {"linear": r["on_clamp_linear"], "nonlinear": bool(r["on_clamp"])},
        "ratio_nl_lin": s_nl / s_l,
        "closing_linear_mm": F / s_l * 1e3,
        "closing_nonlinear_mm": F / s_nl * 1e3,
        "work_linear_mJ": 0.5 * F**2 / s_l * 1e3,  # ∫ f dΔ of a linear spring
        "work_nonlinear_mJ": w_nl * 1e3,
        # 1e-12 N: a curve that never left zero force has no imbalance to speak of
        "jaw_force_imbalance": float(
            np.abs(np.diff(np.asarray(r["jaw_forces"])[-1]))[0] / max(fm[-1], 1e-12)
        ),
        "load_curve_mm_N": np.column_stack([np.asarray(r["closing"]) * 1e3, fm]).round(4).tolist(),
        "newton_iterations": r["newton_iterations"],
        "seconds": r["seconds"],
    }


def _calibrate(both: list[dict], curves: list[dict], E_lin: float, config: dict) -> tuple:
    """Step 4: each model's own single E on the grasps ``both`` (the nonlinear one through the
    f / E scaling of its ``curves``), and the same fitted on random halves, scored on the rest."""
    from workbench.fem.calibration import split_scores, split_scores_of
    from workbench.fem.wall_nonlinear import curve_stiffness

    F = config["force"]
    meas = np.array([r["measured"] for r in both])

    def s_nl_at(c: float, idx=slice(None)) -> np.ndarray:  # at E = E_lin * c
        return np.array(
            [curve_stiffness(cv["closing"], cv["jaw_forces"], F, c)[0] for cv in np.asarray(curves)[idx]]
        )

    def misfit(c: float, idx=slice(None)) -> float:  # median log ratio over grasps idx at E_lin * c
        s = s_nl_at(c, idx)
        return float(np.median(np.log(s / meas[idx]))) if np.isfinite(s).all() else -np.inf

    # the curves reach force_stop: E down to that fraction (1e-4 above it: the curve's last point)
    lo = F / config["force_stop"] * 1.0001
    c_nl = brentq(misfit, lo, 100.0) if misfit(lo) < 0 < misfit(100.0) else float("nan")
    s_l = np.array([r["s_linear"] for r in both])
    c_l = float(np.exp(np.median(np.log(meas / s_l))))
    compare = {}
    for model, s in (("linear", s_l * c_l), ("nonlinear", s_nl_at(c_nl) if np.isfinite(c_nl) else None)):
        compare[model] = (
            None
            if s is None
            else {
                "E_effective_Pa": E_lin * (c_l if model == "linear" else c_nl),
                "median_abs_log_ratio": float(np.median(np.abs(np.log(s / meas)))),
                "spearman": rank_correlation(s, meas) if len(meas) > 2 else None,
            }
        )
    if len(both) < 6:  # halves of fewer than three grasps score nothing
        return compare, None

    def nl_predict(train) -> np.ndarray:
        if not misfit(lo, train) < 0 < misfit(100.0, train):
            return np.full(len(meas), np.nan)
        return s_nl_at(brentq(misfit, lo, 100.0, args=(train,)))

    held = {"n_grasps": len(both), "linear": split_scores(s_l, meas)}
    held["nonlinear"] = split_scores_of(nl_predict, meas) if np.isfinite(c_nl) else None
    return compare, held


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

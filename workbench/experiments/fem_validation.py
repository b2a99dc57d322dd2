"""FEM validation: SRI vs locking, Hertz, thin-layer limits, condensed vs full-mesh contact.

(a) selective reduced integration against the Lamé thick-walled cylinder as
nu -> 0.5; (a') Hertz: rigid sphere into a thick block on graded meshes, a and
p0 against the Hertz formulas for the computed force, with mesh convergence;
(b) compressible thin-layer (Winkler) limits: sphere F = π R M δ² / h,
cylinder P' = (4/3)(M/h) a δ with a = sqrt(2Rδ); (c) the condensed face solve
against the full-mesh Signorini solve on diverse cases (pressure field, force,
speed); (d) p >= 0, no penetration, monotone F(δ); (e) linear vs neo-Hookean at
δ/h = 2/20/40/60% (force, peak pressure, area, pressure field, runtime);
(b') the nearly incompressible thin-film limit.  The checks themselves are
workbench.fem.validation (a, c, d), workbench.fem.hertz_check (a'),
workbench.fem.thin_layer (b, b') and workbench.fem.linear_vs_nonlinear (e); this driver
writes their CSVs, the figure, the renders and the summary.
"""

from __future__ import annotations

import time
import warnings
from functools import partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench.fem import linear_vs_nonlinear
from workbench.fem.contact import solve_contact
from workbench.fem.hertz_check import hertz_block_case
from workbench.fem.linear_vs_nonlinear import FIDELITY_CASES, transferred_correction
from workbench.fem.material import Material
from workbench.fem.thin_layer import thin_film, winkler_cases
from workbench.fem.validation import CondensedVsFull, compare_condensed_vs_full, locking_rows
from workbench.plausible import ImplausibleWarning
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import save_figure, write_csv, write_summary

NAME = "fem-validation"

DEFAULT_CONFIG = {
    "seed": 0,
    "nus": [0.3, 0.45, 0.49, 0.499, 0.4999],
    "cylinder_mesh": [8, 12],  # radial, circumferential hexes (Lamé)
    "winkler_h": 0.001,
    "winkler_cells": 36,  # face cells per side of the 12 mm Winkler pad
    "compare_pad": [16, 20, 4],  # nx, ny, nz of the 16 x 20 x 4 mm comparison pad
    "compare_nu": 0.499,
    "delta_sweep": [0.1e-3, 0.2e-3, 0.3e-3, 0.4e-3, 0.5e-3],
    "hertz_fine_sizes": [0.6e-3, 0.45e-3, 0.3e-3],  # a = 1.5 mm: a/h = 2.5, 3.3, 5
    "hertz_growth": 1.35,
    "fidelity_pad": [16, 20, 5],  # 16 x 20 x 5 mm, 1 mm hexes
    "fidelity_nu": 0.45,  # full integration locks +7-9% here (+26-31% at 0.49), see the 2% rows
    "fidelity_deltas": [0.02, 0.2, 0.4, 0.6],  # δ/h
    "fidelity_full_mesh": True,
    "thin_film_nu": 0.49999,  # K/G = 5e4: the column compressibility term 3 (a/h)² G/K stays <= 0.054
    "thin_film_cylinder_a_h": [5, 10, 15, 20, 30],  # plane strain, 0.5 x 0.25 mm hexes on h = 1 mm
    "thin_film_sphere_a_h": [10, 15, 20],  # 3D, 1 x 1 x 0.25 mm hexes (a/h = 20: 39k dofs, over a minute)
    # where the two neo-Hookean fidelity cases run (workbench.runner.parallel.row_client): 0 = a
    # local Dask cluster (full size) while this process runs the other checks, 1 = serially
    # here, N = N local workers; scheduler = an existing cluster's address
    "workers": 0,
    "scheduler": "",
}


#: what each key means, its unit and plausible range (``workbench run fem-validation --help``)
KEYS = {
    "nus": Key("Poisson ratios of the Lamé volumetric-locking check", "", "poisson"),
    "cylinder_mesh": Key("[radial, circumferential] hexes of the Lamé thick-walled cylinder"),
    "winkler_h": Key(
        "thickness of the compressible thin layer (Winkler limits, 12 mm pad)", "m", "pad_thickness"
    ),
    "winkler_cells": Key("face cells per side of the 12 mm Winkler pad"),
    "compare_pad": Key("[nx, ny, nz] hexes of the 16 x 20 x 4 mm condensed-vs-full pad"),
    "compare_nu": Key("Poisson ratio of the condensed-vs-full pad", "", "poisson"),
    "delta_sweep": Key("indentations of the force-displacement (monotonicity) check", "m", "compression"),
    "hertz_fine_sizes": Key("finest hex size under the Hertz contact (a = 1.5 mm), one mesh each", "m"),
    "hertz_growth": Key("geometric growth of the Hertz mesh away from the contact, > 1"),
    "fidelity_pad": Key("[nx, ny, nz] hexes of the 16 x 20 x 5 mm linear-vs-neo-Hookean pad"),
    "fidelity_nu": Key("Poisson ratio of the linear-vs-neo-Hookean pad", "", "poisson"),
    "fidelity_deltas": Key("indentations of the linear-vs-neo-Hookean check, as fractions delta/h"),
    "fidelity_full_mesh": Key("also the full-mesh linear level of that check"),
    # not a "poisson" Key: 0.49999 is deliberately beyond real silicone (the usual range ends at
    # 0.4999), so the Key would warn on the default and call it a per-cent slip; check_config
    # refuses values outside (-1, 0.5) by the same rule, without the warning
    "thin_film_nu": Key("Poisson ratio of the nearly incompressible thin-film layer, in (-1, 0.5)"),
    "thin_film_cylinder_a_h": Key("contact half-widths a/h of the plane-strain thin-film check"),
    "thin_film_sphere_a_h": Key("contact radii a/h of the 3D thin-film check"),
}


def check_config(config: dict) -> None:
    """The CLI checks settings with this before any work (workbench.runner.experiment_config.build_config)."""
    for key, spec in KEYS.items():  # the Poisson ratios and sizes (also for run(config))
        check_key(key, spec, config[key])
    with warnings.catch_warnings():  # 0.49999 is beyond the usual range on purpose (KEYS above)
        warnings.simplefilter("ignore", ImplausibleWarning)
        try:
            Material(1.0e6, config["thin_film_nu"])  # the Poisson rule: refused outside (-1, 0.5)
        except ValueError as exc:
            raise ValueError(f"thin_film_nu: {exc}") from None
    check_workers(config["workers"], config["scheduler"])


QUICK_CONFIG = {
    "hertz_fine_sizes": [0.6e-3],
    "nus": [0.3, 0.499, 0.4999],
    "winkler_cells": 24,
    "compare_pad": [8, 10, 3],
    "delta_sweep": [0.1e-3, 0.3e-3],
    "fidelity_pad": [8, 10, 3],
    "fidelity_full_mesh": False,
    "thin_film_cylinder_a_h": [10, 20],
    "thin_film_sphere_a_h": [],
}


def fidelity_case(name: str, config: dict) -> list[dict]:
    """(e) one indenter of :data:`FIDELITY_CASES` with this config's pad, Poisson ratio, δ/h and
    levels (:func:`workbench.fem.linear_vs_nonlinear.fidelity_case`): a task of its own (the
    cylinder's load stepping takes minutes), the driver runs the other checks meanwhile."""
    return linear_vs_nonlinear.fidelity_case(
        name,
        config["fidelity_pad"],
        config["fidelity_nu"],
        config["fidelity_deltas"],
        full_mesh=config["fidelity_full_mesh"],
    )


def _locking(config: dict, out: Path) -> list[dict]:
    # (a) locking
    locking = locking_rows(config["nus"], *config["cylinder_mesh"])
    write_csv(
        out / "locking.csv", ["nu", "sri_over_exact", "full_over_exact"], [list(r.values()) for r in locking]
    )
    return locking


def _winkler(config: dict, out: Path) -> list[dict]:
    # (b) compressible thin-layer (Winkler) limits, nu = 0 (M = E)
    winkler = winkler_cases(config["winkler_h"], config["winkler_cells"])
    write_csv(out / "thin_layer.csv", list(winkler[0]), [list(w.values()) for w in winkler])
    return winkler


def _compare_cases(config: dict, out: Path) -> CondensedVsFull:
    # (c) condensed vs full-mesh linear, (d) sanity
    cmp = compare_condensed_vs_full(
        config["compare_pad"], config["compare_nu"], config["delta_sweep"], progress=True
    )
    write_csv(out / "condensed_vs_full.csv", list(cmp.rows[0]), [list(r.values()) for r in cmp.rows])
    return cmp


def _figure(config: dict, out: Path, locking: list[dict], film: list[dict], cmp: CondensedVsFull) -> Path:
    geom, mat, sweep = cmp.pad.geometry, cmp.pad.material, cmp.sweep_forces
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 3.6))
    nus = [r["nu"] for r in locking]
    axes[0].semilogx([0.5 - v for v in nus], [r["sri_over_exact"] for r in locking], "o-", label="SRI")
    axes[0].semilogx(
        [0.5 - v for v in nus], [r["full_over_exact"] for r in locking], "s--", label="full 2x2x2"
    )
    axes[0].axhline(1.0, color="k", lw=0.8)
    axes[0].set_xlabel("0.5 - nu")
    axes[0].set_ylabel("u_r / u_r Lamé")
    axes[0].set_title("volumetric locking, thick cylinder")
    axes[0].invert_xaxis()
    axes[0].legend()
    axes[1].plot(np.array(config["delta_sweep"]) * 1e3, sweep, "o-")
    axes[1].set_xlabel("jaw displacement δ [mm]")
    axes[1].set_ylabel("contact force [N]")
    axes[1].set_title(f"sphere R20 on {geom.thickness * 1e3:.0f} mm layer, nu = {mat.nu}")
    for shape, marker in (("cylinder (plane strain)", "o-"), ("sphere", "s-")):
        sel = [r for r in film if r["shape"] == shape]
        if sel:
            axes[2].plot(
                [r["a_over_h"] for r in sel], [r["F_fe"] / r["F_limit"] for r in sel], marker, label=shape
            )
    axes[2].axhline(1.0, color="k", lw=0.8)
    axes[2].axhspan(0.95, 1.05, color="0.9")
    axes[2].set_xlabel("a / h")
    axes[2].set_ylabel("F / F thin-film limit")
    axes[2].set_title(f"incompressible thin layer, nu = {config['thin_film_nu']}")
    axes[2].legend()
    fig_path = save_figure(fig, out / "fem_validation.png")
    return fig_path


def _renders(pad, cases: dict, out: Path) -> list[str]:
    # offscreen renders of extracted profiles (Fig 3.11(d) style), pressure-colored with
    # the friction the pad exerts for a torsion and a sliding motion of the object
    from workbench.fem.extract import extract_profile
    from workbench.runner.viz import render_friction_arrows

    renders = []
    twists = {
        "torsion about z": np.array([0, 0, 0, 0, 0, 1.0]),
        "sliding along +x": np.array([1.0, 0, 0, 0, 0, 0]),
    }
    for name in ("sphere R20", "cylinder tilted 20 deg"):
        obs, delta = cases[name]
        prof = extract_profile(pad, solve_contact(pad, obs, delta), obs)
        slug = name.replace(" ", "_")
        renders.append(str(render_friction_arrows(prof, twists, out / f"profile_{slug}.png", title=name)))

    return renders


def _checks(config: dict, out: Path) -> dict:
    """(a)-(d) and (b'): every check but the neo-Hookean fidelity, with their CSVs, the
    figure and the profile renders — the driver's share while the fidelity cases run."""
    locking = _locking(config, out)
    winkler = _winkler(config, out)
    film = thin_film(
        config["thin_film_nu"],
        config["thin_film_cylinder_a_h"],
        config["thin_film_sphere_a_h"],
        progress=True,
    )
    write_csv(out / "thin_film.csv", list(film[0]), [list(w.values()) for w in film])

    # (a') Hertz mesh convergence
    hz = [
        hertz_block_case(size, config["hertz_growth"])
        for size in tqdm(config["hertz_fine_sizes"], desc="Hertz", unit="mesh")
    ]
    write_csv(out / "hertz_convergence.csv", list(hz[0]), [list(r.values()) for r in hz])

    cmp = _compare_cases(config, out)
    fig_path = _figure(config, out, locking, film, cmp)
    renders = _renders(cmp.pad, cmp.cases, out)
    return {
        "locking": locking,
        "winkler": winkler,
        "film": film,
        "hz": hz,
        "rows": cmp.rows,
        "precompute_s": cmp.precompute_s,
        "sweep": cmp.sweep_forces,
        "monotone": cmp.monotone,
        "fig_path": fig_path,
        "renders": renders,
    }


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    fid_of: dict[str, list[dict]] = {}
    # the neo-Hookean cylinder's load stepping (minutes) and sphere as tasks, the rest here
    # meanwhile: two cases are worth a cluster at full size, not in --quick
    min_rows = None if config.get("quick") else 2
    done, ran_on = run_rows(
        partial(fidelity_case, config=config),
        FIDELITY_CASES,
        fid_of.__setitem__,
        config,
        min_rows=min_rows,
        meanwhile=partial(_checks, config, out),
    )
    locking, winkler, film, hz, rows = (done[k] for k in ("locking", "winkler", "film", "hz", "rows"))
    precompute_s, sweep, monotone = done["precompute_s"], done["sweep"], done["monotone"]
    fig_path, renders = done["fig_path"], done["renders"]
    fid = [r for name in FIDELITY_CASES for r in fid_of[name]]
    write_csv(out / "linear_vs_nonlinear.csv", list(fid[0]), [list(r.values()) for r in fid])
    fidelity = {
        f"{r['case']} {round(100 * r['delta_over_h'])}%": {
            k: r[k] for k in ("force_rel_err", "peak_rel_err", "area_rel_err", "pressure_rel_l2", "seconds")
        }
        for r in fid
        if r["level"] == "condensed SRI"
    }

    correction = transferred_correction(fid)
    summary_ms = float(np.median([r["condensed_ms"] for r in rows]))
    summary_ratio = float(np.median([r["speed_ratio"] for r in rows]))
    worst_l2 = max(r["pressure_rel_l2"] for r in rows)
    worst_f = max(r["force_rel_err"] for r in rows)
    summary = {
        "locking": locking,
        "hertz": {"a_rel_err": hz[-1]["a_rel_err"], "p0_rel_err": hz[-1]["p0_rel_err"], "convergence": hz},
        "thin_layer": winkler,
        "thin_film": film,
        "condensed_vs_reference": {
            "pressure_rel_l2": worst_l2,
            "force_rel_err": worst_f,
            "reference": "full-mesh linear",
        },
        "condensed_vs_full_cases": rows,
        "pad_precompute_s": precompute_s,
        "median_condensed_ms": summary_ms,
        "median_speed_ratio": summary_ratio,
        "force_displacement": {"delta_m": config["delta_sweep"], "force_N": sweep, "monotone": monotone},
        "fidelity": {
            "reference": "neo-Hookean, full integration, augmented-Lagrangian frictionless contact",
            "condensed_sri_vs_nonlinear": fidelity,
            "calibrated_correction": correction,
            "rows": fid,
        },
        "figures": [str(fig_path), *renders],
        "fidelity_ran_on": ran_on,
        # (c)'s runtimes (median_condensed_ms, speed ratio) are taken in this process, beside
        # the fidelity cases when they ran on workers: workers=1 gives the machine's own
        "timings_beside_workers": ran_on != "serial",
        "headline": [
            f"SRI u/u_exact at nu={locking[-1]['nu']}: {locking[-1]['sri_over_exact']:.4f} "
            f"(full integration {locking[-1]['full_over_exact']:.4f})",
            f"Hertz at a/h = {hz[-1]['a_over_h']:.1f}: a {100 * hz[-1]['a_rel_err']:+.2f}%, "
            f"p0 {100 * hz[-1]['p0_rel_err']:+.2f}%",
            "thin-layer limits: "
            + ", ".join(f"{w['shape']} a/h={w['a_over_h']:.1f}: {100 * w['rel_err']:+.1f}%" for w in winkler),
            "incompressible thin film: "
            + ", ".join(f"{w['shape']} a/h={w['a_over_h']}: {100 * w['rel_err']:+.1f}%" for w in film),
            "condensed SRI vs neo-Hookean (force, peak pressure): "
            + ", ".join(
                f"{k} {100 * v['force_rel_err']:+.0f}%/{100 * v['peak_rel_err']:+.0f}%"
                for k, v in fidelity.items()
            ),
            f"condensed vs full-mesh on {len(rows)} cases: pressure L2 <= {worst_l2:.1e}, "
            f"force <= {worst_f:.1e}; median {summary_ms:.1f} ms vs full, ratio {summary_ratio:.0f}x",
        ],
    }
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))

"""Runtime against error of the workbench's own knobs: one Pareto front per knob.

Each point is one setting of one knob measured as (runtime [s], error against that family's best
reference); per family the front (:func:`workbench.runner.pareto.pareto_front`), where the default
setting sits on it, and the cheapest setting within error budgets of 1e-1, 1e-2 and 1e-3.

Families (the knobs and defaults as the library reads them):

* ``twist count K (<model>)`` — K = 2n training wrenches of the thesis sampler (§3.3.2, n
  rotations + n translations; ``SamplerSpec.n`` = 300, i.e. K = 600) for the default 6DLS
  (``ellipsoid_sdp``: ``grasp.models.contact_sets("6dls")``) and the quartic with normals.
  Error: Eq. 3.18 on held-out exact 6DFWs (the kernel's) — the model's own error, not its
  distance from the largest K's model, which would hide the bias that more K cannot remove.
  Runtime: sampling, the K wrenches and the fit of one contact.
* ``limit-surface model`` — the four fits of ``limit_surface.fit_score.MODELS`` on the same
  K = 600 wrenches; error as above, runtime the fit alone.
* ``linearisation M`` — ``model.linearize(M, "outer")`` of the default model
  (``config.DEFAULTS.linearization_M``); error: the mean support-function ratio
  outer / inner - 1 (``bench_limit_surface.support_ratio``), which bounds either polytope's
  relative error against the exact model; runtime: linearising plus one support LP on the
  outer polytope (a query of the size the grasp LPs see).
* ``FEM mesh x fidelity`` — a R 15 mm sphere pressed 1 mm (20 % of the 5 mm layer) into
  fem-validation's 16 x 20 mm fidelity pad, at ``press``'s three fidelities and hex sizes
  around the default 1 mm (``PadGeometry``'s spacing); error: |F / F_ref - 1| against the
  neo-Hookean solve on the finest mesh; runtime per solve, the condensed level's cached
  precompute reported beside it.
* ``quadrature rtol`` — ``surface_wrenches(rtol=...)`` (``config.TOL.quadrature_rtol``) on the
  continuous S1-S6; error: the largest scaled difference (per component by mu F, mu F l_s, as
  the tolerance is defined) from the tightest rtol's wrenches; runtime per wrench.

Writes results/benchmarks/pareto.json and pareto.png.
Run: python benchmarks/bench_pareto.py [--quick] [--out PATH]
"""

from __future__ import annotations

import argparse
import os
import time
from functools import partial
from pathlib import Path

import numpy as np
from bench_limit_surface import support_ratio  # the sibling benchmark's outer/inner gap
from bench_wrench import machine_roofline  # the sibling benchmark's FMA roofline

from workbench import frictional_wrenches, mesh_profile, sample_twists_thesis, surface_wrenches, w_max
from workbench.config import DEFAULTS, TOL
from workbench.limit_surface.cache import SamplerSpec
from workbench.limit_surface.fit_score import MODELS, fit_model, min_wrenches
from workbench.runner.pareto import pareto_front
from workbench.runner.results import save_figure, versions, write_json
from workbench.sources.surface_catalog import THESIS_SURFACES
from workbench.sources.surfaces import surface_moments
from workbench.timing import median_runtime

ROOT = Path(__file__).resolve().parents[1]
BUDGETS = (1e-1, 1e-2, 1e-3)
#: the default 6DLS of grasp analysis: contact_sets("6dls") fits ModelSpec(method="sdp")
DEFAULT_MODEL = "ellipsoid_sdp"
#: a call this long is timed once: a coarser setting of the same code ran first, so no JIT or
#: problem build is left in it, and repeating the finest FEM solves would exceed the budget
LONG_CALL_S = 1.0
FILL_S, MAX_REPEATS = 0.25, 15

FULL = {
    "surfaces": list(THESIS_SURFACES),
    "mesh_elements": 1500,  # as bench_limit_surface
    "n_heldout": 4000,
    "K": {
        "ellipsoid_sdp": [40, 100, 200, 400, 600, 1000, 2000],
        "quartic_normals": [200, 400, 600, 1000, 2000],
    },
    "M": [50, 100, 200, 500, 1000, 2000, 5000],
    "support_dirs": 40,
    "hex_mm": [2.0, 4 / 3, 1.0, 0.8, 2 / 3],
    "rtol": [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-9],
    "rtol_twists": 32,
    "repeats": 3,
}
QUICK = {
    "surfaces": ["S1", "S4"],
    "mesh_elements": 600,
    "n_heldout": 1000,
    "K": {"ellipsoid_sdp": [40, 200, 600], "quartic_normals": [200, 600]},
    "M": [50, 200, 1000],
    "support_dirs": 10,
    "hex_mm": [2.0, 1.0],
    "rtol": [1e-3, 1e-5, 1e-7],
    "rtol_twists": 8,
    "repeats": 2,
}


def timed(fn, repeats: int, warm: bool) -> tuple[float, object]:
    """Median runtime of ``fn`` and its result; ``warm``: code of the same kind already ran (no JIT
    or problem build left), so the first call is timed too and, if long, is the measurement."""
    if not warm:
        fn()  # the warm-up
    t0 = time.perf_counter()
    result = fn()
    first = time.perf_counter() - t0
    if first >= LONG_CALL_S:
        return first, result
    # a short call is repeated to fill about FILL_S (its median then resists scheduler stalls on a
    # shared 2-core machine), at least ``repeats`` times and at most MAX_REPEATS
    n = int(min(max(repeats, FILL_S / max(first, 1e-9)), MAX_REPEATS))
    return median_runtime(fn, n, warmup=0)


# ------------------------------------------------------------------------------- limit surfaces
class Contact:
    """One normalised S1-S6 mesh profile with its exact w_max and held-out exact 6DFWs."""

    def __init__(self, name: str, cfg: dict) -> None:
        self.name = name
        self.prof = mesh_profile(THESIS_SURFACES[name], cfg["mesh_elements"]).normalized()
        self.w_max = w_max(self.prof)
        self.test = frictional_wrenches(
            self.prof, sample_twists_thesis(cfg["n_heldout"] // 2, self.prof, seed=2)
        )

    def build(self, model: str, K: int):
        """Sample K thesis twists, their 6DFWs and fit ``model``: one contact's limit surface."""
        xi = sample_twists_thesis(K // 2, self.prof, seed=1)
        W = frictional_wrenches(self.prof, xi)
        return fit_model(model, W, w_max=self.w_max, twists=xi)


def k_family(contacts: list[Contact], model: str, cfg: dict) -> dict:
    default_K = 2 * SamplerSpec(kind="thesis").n
    per: dict[int, list[tuple[float, float]]] = {K: [] for K in cfg["K"][model]}
    for c in contacts:
        c.build(model, min(per))  # the fitter's problem build (cached per subspace dimension)
        for K in per:
            t, fitted = timed(lambda c=c, K=K: c.build(model, K), cfg["repeats"], warm=True)
            per[K].append((t, fitted.fitting_error(c.test)))
    points = [{**_mean_point(f"K={K}", v, K == default_K), "K": K} for K, v in per.items()]
    return {
        "knob": "SamplerSpec(kind='thesis').n (K = 2n training twists, thesis §3.3.2)",
        "reference": f"exact 6DFWs, {cfg['n_heldout']} held-out twists",
        "reference_setting": None,
        "error_metric": "Eq. 3.18 on held-out exact 6DFWs (kernel), mean over "
        + ", ".join(c.name for c in contacts),
        "runtime_metric": "sample K twists + K wrenches + fit, one contact, mean over surfaces of medians",
        "note": "the grasp analysis default sampler 'mix' adds the author's downsampled grid to these "
        "K = 600 (config.DEFAULTS.ls_training_sampler)",
        "points": points,
    }


def _mean_point(setting: str, runs: list[tuple[float, float]], is_default: bool) -> dict:
    """One setting's point from its (runtime [s], error) per surface: the means, and the errors."""
    return {
        "setting": setting,
        "runtime_s": float(np.mean([t for t, _ in runs])),
        "error": float(np.mean([e for _, e in runs])),
        "error_per_surface": [e for _, e in runs],
        "is_default": is_default,
    }


def model_family(contacts: list[Contact], cfg: dict) -> dict:
    K = 2 * SamplerSpec(kind="thesis").n
    per: dict[str, list[tuple[float, float]]] = {m: [] for m in MODELS if K >= min_wrenches(m)}
    for i, c in enumerate(contacts):
        xi = sample_twists_thesis(K // 2, c.prof, seed=1)
        W = frictional_wrenches(c.prof, xi)
        for m in per:
            fit = partial(fit_model, m, W, w_max=c.w_max, twists=xi)
            t, fitted = timed(fit, cfg["repeats"], warm=i > 0)
            per[m].append((t, fitted.fitting_error(c.test)))
    points = [_mean_point(m, v, m == DEFAULT_MODEL) for m, v in per.items()]
    return {
        "knob": "limit-surface model (grasp.models.contact_sets: '6dls' / '6dls_quartic')",
        "reference": f"exact 6DFWs, {cfg['n_heldout']} held-out twists",
        "reference_setting": None,
        "error_metric": f"Eq. 3.18 on held-out exact 6DFWs, K = {K} thesis wrenches, mean over surfaces",
        "runtime_metric": "the fit alone (wrenches given), mean over surfaces of medians",
        "points": points,
    }


def m_family(contacts: list[Contact], cfg: dict) -> dict:
    K = 2 * SamplerSpec(kind="thesis").n
    from scipy.optimize import linprog

    def query(model, M: int, u: np.ndarray) -> float:
        outer = model.linearize(M, "outer", seed=5)
        res = linprog(-u, A_ub=outer.A, b_ub=outer.b, bounds=[(None, None)] * 6, method="highs")
        return -res.fun

    per: dict[int, list[tuple[float, float]]] = {M: [] for M in cfg["M"]}
    for i, c in enumerate(contacts):
        model = c.build(DEFAULT_MODEL, K)
        dirs = np.random.default_rng(6).standard_normal((cfg["support_dirs"], 6)) * model.scale
        for j, M in enumerate(per):
            t, _ = timed(partial(query, model, M, dirs[0]), cfg["repeats"], warm=i + j > 0)
            per[M].append((t, support_ratio(model, M, dirs) - 1.0))
    points = [
        {
            "setting": f"M={M}",
            "M": M,
            "runtime_s": float(np.mean([t for t, _ in v])),
            "error": float(np.mean([e for _, e in v])),
            "error_per_surface": [e for _, e in v],
            "is_default": M == DEFAULTS.linearization_M,
        }
        for M, v in per.items()
    ]
    return {
        "knob": "config.DEFAULTS.linearization_M (model.linearize(M, 'inner'/'outer'), Eqs. 3.19–3.24)",
        "reference": "none: the outer polytope against the inner (the exact model lies between)",
        "reference_setting": None,
        "error_metric": f"mean over {cfg['support_dirs']} random directions of h_outer / h_inner - 1 "
        f"(support functions), {DEFAULT_MODEL} at K = {K}, mean over surfaces",
        "runtime_metric": "linearize(M, 'outer') + one support LP over it (HiGHS)",
        "points": points,
    }


# ------------------------------------------------------------------------------------------ FEM
def fem_family(cfg: dict) -> dict:
    from workbench.experiments.peers import DEFAULT_CONFIG as PEERS_CONFIG
    from workbench.fem import press
    from workbench.fem.contact import solve_contact
    from workbench.fem.material import Material
    from workbench.fem.obstacles import Sphere
    from workbench.fem.pad import PadGeometry, condense_pad

    # fem-validation's fidelity case "sphere R15" (16 x 20 x 5 mm pad, E = 1 MPa, nu = 0.45 as
    # Material()) at 20 % compression: the smallest jaw displacement of fem-fitting (1 mm)
    width, length, h, R = 0.016, 0.02, 0.005, 0.015
    delta = 0.2 * h
    mat = Material()
    obs = Sphere((0.0, 0.0, h + R), R)
    default_hex_mm = PadGeometry().width / PadGeometry().nx * 1e3  # 1 mm hexes

    def geometry(a_mm: float) -> PadGeometry:
        # round half up: the layer keeps at least the in-plane hex size through its thickness
        n = [int(side / (a_mm * 1e-3) + 0.5) for side in (width, length, h)]
        return PadGeometry(width, length, h, *n)

    points, precompute = [], {}
    fidelities = ("condensed", "linear", "nonlinear")
    for fid in fidelities:
        for j, a in enumerate(sorted(cfg["hex_mm"], reverse=True)):  # coarse first: it warms up
            g = geometry(a)
            label = f"{fid} {g.nx}x{g.ny}x{g.nz}"
            if fid == "condensed":
                t0 = time.perf_counter()
                pad = condense_pad(g, mat)  # the default disk cache: built once per mesh
                precompute[label] = {
                    "condense_s": pad.seconds,
                    "from_cache": pad.from_cache,
                    "load_or_build_s": time.perf_counter() - t0,
                }
                fn = lambda pad=pad: solve_contact(pad, obs, delta)  # noqa: E731
            else:
                # the neo-Hookean pad as the peers experiment's reference (one meaning of "the
                # reference"): full volumetric integration locks at nu = 0.45 (+10 % force)
                opts = (
                    {"stabilization": PEERS_CONFIG["reference_stabilization"]} if fid == "nonlinear" else {}
                )
                fn = lambda g=g, fid=fid, o=opts: press(g, mat, obs, [delta], fidelity=fid, **o)[delta]  # noqa: E731
            t, sol = timed(fn, cfg["repeats"], warm=j > 0)
            points.append(
                {
                    "setting": label,
                    "fidelity": fid,
                    "hex_mm": round(a, 4),
                    "mesh": [g.nx, g.ny, g.nz],
                    "runtime_s": t,
                    # the jaw's force sensor: the net normal force along the pad normal, as the
                    # peers experiment's force (Σλ, the sum of magnitudes, is larger on a curve)
                    "force_N": float(sol.force_vector[2]),
                    "is_default": fid == "condensed" and np.isclose(a, default_hex_mm),
                }
            )
    ref = max((p for p in points if p["fidelity"] == "nonlinear"), key=lambda p: np.prod(p["mesh"]))
    for p in points:
        p["error"] = abs(p["force_N"] / ref["force_N"] - 1.0)
    return {
        "knob": "workbench.fem.press(fidelity=...) x PadGeometry(nx, ny, nz)",
        "reference": f"neo-Hookean (stabilization {PEERS_CONFIG['reference_stabilization']:g}, as peers), "
        f"{ref['setting'].split()[1]} hexes",
        "reference_setting": ref["setting"],
        "error_metric": "|F / F_ref - 1| (F the jaw force: net normal force along the pad normal), "
        "R 15 mm sphere 1 mm into a 16 x 20 x 5 mm pad",
        "runtime_metric": "one solve; condensed: the face solve, its precompute (cached on disk) in "
        "condensed_precompute",
        "condensed_precompute": precompute,
        "points": points,
    }


# ---------------------------------------------------------------------------------- quadrature
def rtol_family(cfg: dict) -> dict:
    rtols = sorted(cfg["rtol"], reverse=True)
    ref_rtol = rtols[-1]
    times: dict[float, list[float]] = {r: [] for r in rtols}
    errs: dict[float, list[float]] = {r: [] for r in rtols}
    n_twists = 0
    for i, name in enumerate(cfg["surfaces"]):
        s = THESIS_SURFACES[name].normalized()
        xi = sample_twists_thesis(cfg["rtol_twists"] // 2, s.length_scale, seed=3)
        n_twists += len(xi)
        F = surface_moments(s).F
        scale = np.array([F] * 3 + [F * s.length_scale] * 3)  # the tolerance's own units (mu = 1)
        ref = surface_wrenches(s, xi, rtol=ref_rtol)
        for j, r in enumerate(rtols):
            t, W = timed(
                lambda s=s, xi=xi, r=r: surface_wrenches(s, xi, rtol=r), cfg["repeats"], warm=i + j > 0
            )
            times[r].append(t)
            errs[r].append(float((np.abs(W - ref) / scale).max()))
    points = [
        {
            "setting": f"rtol={r:g}",
            "rtol": r,
            "runtime_s": float(np.sum(times[r]) / n_twists),
            "error": float(np.max(errs[r])),
            "error_per_surface": errs[r],
            "is_default": r == TOL.quadrature_rtol,
        }
        for r in rtols
    ]
    return {
        "knob": "config.TOL.quadrature_rtol (surface_wrenches(rtol=...))",
        "reference": f"rtol = {ref_rtol:g}",
        "reference_setting": f"rtol={ref_rtol:g}",
        "error_metric": "max over surfaces, twists and components of |W - W_ref| / (mu F, mu F l_s)",
        "runtime_metric": f"seconds per wrench ({cfg['rtol_twists']} thesis twists per surface)",
        "points": points,
    }


# ------------------------------------------------------------------------------------- summary
def summarise(fam: dict) -> dict:
    """Front, the default's place on it and the cheapest setting per error budget."""
    pts = fam["points"]
    t = np.array([p["runtime_s"] for p in pts])
    # an exact reference (error 0) floored at round-off: the front needs log-able errors
    e = np.maximum([p["error"] for p in pts], np.finfo(float).eps)
    front = pareto_front(t, e)
    for i, p in enumerate(pts):
        p["on_front"] = bool(i in front)
    (d,) = [i for i, p in enumerate(pts) if p["is_default"]]
    fam["front"] = [pts[i]["setting"] for i in front]
    fam["default"] = pts[d]["setting"]
    fam["default_on_front"] = pts[d]["on_front"]
    fam["default_error"] = pts[d]["error"]
    fam["default_runtime_s"] = pts[d]["runtime_s"]
    fam["default_dominated_by"] = [
        p["setting"]
        for i, p in enumerate(pts)
        if i != d and t[i] <= t[d] and e[i] <= e[d] and (t[i] < t[d] or e[i] < e[d])
    ]
    fam["cheapest_within"] = {
        f"{b:g}": next((pts[i]["setting"] for i in front if pts[i]["error"] <= b), None) for b in BUDGETS
    }
    return fam


def _decade_limits(values: list[float]) -> tuple[float, float]:
    """Log-axis limits around ``values`` with margins, spanning at least a decade (so that a
    major, labelled tick falls inside)."""
    lo, hi = min(values) / 1.5, max(values) * 1.5
    if hi / lo < 10:
        g = np.sqrt(lo * hi)
        lo, hi = g / np.sqrt(10), g * np.sqrt(10)
    return lo, hi


def figure(families: dict, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    n = len(families)
    cols = 3
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5.0 * cols, 3.9 * rows), squeeze=False)
    for ax, (name, fam) in zip(axes.ravel(), families.items(), strict=False):
        pts = fam["points"]
        groups = sorted({p.get("fidelity", "") for p in pts})
        for k, grp in enumerate(groups):
            sel = [p for p in pts if p.get("fidelity", "") == grp and p["error"] > 0]
            ax.scatter(
                [p["runtime_s"] for p in sel],
                [p["error"] for p in sel],
                s=22,
                color=f"C{k}",
                label=grp or None,
            )
            for p in sel:
                ax.annotate(p["setting"].replace(f"{grp} ", ""), (p["runtime_s"], p["error"]), fontsize=6)
        front = [p for p in pts if p["on_front"] and p["error"] > 0]
        front.sort(key=lambda p: p["runtime_s"])
        ax.plot([p["runtime_s"] for p in front], [p["error"] for p in front], "k-", lw=0.8, label="front")
        d = next(p for p in pts if p["is_default"])
        ax.scatter(
            [d["runtime_s"]],
            [d["error"]],
            s=160,
            marker="*",
            facecolors="none",
            edgecolors="r",
            label="default",
        )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(*_decade_limits([p["runtime_s"] for p in pts]))
        ax.set_ylim(*_decade_limits([p["error"] for p in pts if p["error"] > 0]))
        for axis in (ax.xaxis, ax.yaxis):  # minor labels overprint; a decade holds a major one
            axis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("runtime [s]")
        ax.set_ylabel("error")
        ax.set_title(f"{name}\nref: {fam['reference']}", fontsize=8)
        ax.legend(fontsize=6)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    fig.suptitle(
        "runtime vs error of the workbench's knobs (reference points, error 0, not drawn)", fontsize=9
    )
    fig.tight_layout()
    return save_figure(fig, path)


def run(quick: bool, out: Path) -> dict:
    cfg = QUICK if quick else FULL
    t_start = time.perf_counter()
    load_start = os.getloadavg()[0]
    contacts = [Contact(name, cfg) for name in cfg["surfaces"]]
    steps = {
        f"twist count K ({m})": partial(k_family, contacts, m, cfg)
        for m in ("ellipsoid_sdp", "quartic_normals")
    }
    steps["limit-surface model"] = partial(model_family, contacts, cfg)
    steps["linearisation M"] = partial(m_family, contacts, cfg)
    steps["FEM mesh x fidelity"] = partial(fem_family, cfg)
    steps["quadrature rtol"] = partial(rtol_family, cfg)
    families, family_wall_s = {}, {}
    for name, step in steps.items():
        t0 = time.perf_counter()
        families[name] = step()
        family_wall_s[name] = time.perf_counter() - t0
    families = {k: summarise(v) for k, v in families.items()}
    png = figure(families, out.with_suffix(".png"))
    result = {
        "benchmark": "runtime vs error of the workbench's own knobs, one Pareto front per knob",
        "quick": quick,
        "error_budgets": list(BUDGETS),
        "families": families,
        "figure": str(png.relative_to(ROOT)) if png.is_relative_to(ROOT) else str(png),
        "timing": f"median of >= {cfg['repeats']} calls after a warm-up (short calls repeated to fill "
        f"{FILL_S} s, at most {MAX_REPEATS}); a call of >= {LONG_CALL_S} s after a coarser setting of the "
        "same code (no JIT or build left) is timed once",
        "machine": {
            **machine_roofline(quick=True),
            "cpu_count": os.cpu_count(),
            # other work on the machine slows solver-heavy timings most (thread pools on 2 cores)
            "load_average_1min_start": load_start,
            "load_average_1min_end": os.getloadavg()[0],
        },
        "versions": versions(),
        "family_wall_s": family_wall_s,
        "wall_time_s": time.perf_counter() - t_start,
    }
    write_json(out, result)
    return result


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "results" / "benchmarks" / "pareto.json"))
    args = parser.parse_args()
    res = run(args.quick, Path(args.out).resolve())
    for name, f in res["families"].items():
        print(
            f"{name:32s} default {f['default']:22s} error {f['default_error']:.3g} "
            f"runtime {f['default_runtime_s']:.3g} s  on front {f['default_on_front']}  "
            f"cheapest within {f['cheapest_within']}"
        )
    print(f"wall time {res['wall_time_s']:.0f} s, FMA {res['machine']['fma_gflops_measured']:.1f} GFLOP/s")


if __name__ == "__main__":
    main()

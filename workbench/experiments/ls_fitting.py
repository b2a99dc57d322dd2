"""Fig 3.9/3.10: ellipsoid and quartic 6DLS fitted to K = 100..1,000 wrenches of S1-S6.

Thesis §3.5.1.3, under two sampling/scoring protocols:

* ``"thesis-text"`` (``heldout_error``, always run): the sampler the thesis describes (§3.3.2:
  K/2 Fibonacci rotations + K/2 translations, pitch ``h ∈ [−1, 1]·l_s``) gives
  the K training wrenches, a separate seed the ``n_heldout`` held-out ones; the
  error is Eq. 3.18 on the held-out wrenches.
* ``"thesis-code"`` (``thesis_protocol_error``, ``thesis_code=True``): the author's code
  (:mod:`workbench.twists_author`, 48 483 twists at ``fine_level`` 0); Fig 3.9
  trains on K wrenches drawn from that set and scores Eq. 3.18 on all of it;
  the code's own training set (grid downsampling, a few hundred wrenches) is
  scored the same way (``thesis_protocol_error.downsampled``).

Wrenches come from the continuous surfaces (or fine meshes with
``wrench_source=mesh``), normalised by the exact ``w_max``.  The error a user can
compare across protocols is the sampler-independent one (``support_error``,
:mod:`workbench.limit_surface.support_error`): radial distance at exact surface
points of uniformly distributed normals.  The models are named as in
:mod:`workbench.limit_surface.fit_score`: ``ellipsoid_sdp`` is the PSD-constrained
least squares of Eq. 3.11 with ``A ⪰ 0`` (Eq. 3.12 without its log-det term, whose
effect ``sdp_log_det_effect`` measures: none at ``α = 1e-6·K``); the unconstrained
least-squares ellipsoid ``ellipsoid_lsq`` (Eq. 3.13) and the SCS solver are reported
next to it.  ``quartic_normals`` is fitted to the wrenches *and* their sampling twists
(outward normals by maximum dissipation, as the author's code does with other weights,
see :func:`workbench.fit_quartic`); ``quartic_values`` is Eq. 3.17 on the values
alone, as the thesis text writes it (fem-fitting's Table 3.3 quartic).
"""

from __future__ import annotations

import time
from functools import partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench import config as wb_config
from workbench.limit_surface.fit_score import FitScore, convexity, min_wrenches
from workbench.limit_surface.protocols import (
    ExactContact,
    fit_score,
    thesis_code_sample_of,
    thesis_code_training_draws,
    thesis_text_wrenches,
)
from workbench.limit_surface.thesis_code import ThesisCodeSample, check_protocol_config
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import save_figure, write_csv, write_summary
from workbench.sources.surface_catalog import THESIS_SURFACES
from workbench.sources.surfaces import check_rtol
from workbench.twists_author import AUTHOR_LEVELS
from workbench.wrench import check_mu

NAME = "ls-fitting"
#: the models fitted (workbench.limit_surface.fit_score), and the two whose support errors,
#: SCS fits and Fig 3.10 sections are measured
KINDS = ["ellipsoid_lsq", "ellipsoid_sdp", "quartic_values", "quartic_normals"]
SUPPORT_KINDS = ("ellipsoid_sdp", "quartic_normals")
FITS_CSV_COLUMNS = ["surface", "K", "model", "solver", "heldout_error", "fit_time_s", "fallback"]
#: §3.6 and §5: the models "reached as low as 0.02 and 0.04 mean wrench error" — best
#: values over six surfaces and 2,932 FEM contacts, not bounds; Fig 3.9's curves are not
#: printed as numbers anywhere in the thesis
THESIS_AS_LOW_AS = {"quartic": 0.02, "ellipsoid": 0.04}

DEFAULT_CONFIG = {
    "seed": 0,
    "mu": 1.0,
    "surfaces": list(THESIS_SURFACES),
    "K": [100, 200, 300, 400, 600, 800, 1000],
    "n_heldout": 20_000,
    "wrench_source": "continuous",  # "continuous" (adaptive quadrature) or "mesh"
    # relative accuracy of the continuous wrenches (config.TOL.quadrature_rtol is 1e-5): 1e-4 is
    # already 1.8 decades below the smallest error it feeds (Fig 3.9's lowest mean, ~0.006)
    "quad_rtol": 1e-4,
    "mesh_elements": 2000,  # wrench_source=mesh, and the contact box of the thesis-code grid
    "thesis_code": True,  # also run the thesis-code protocol (the thesis-text one always runs)
    "fine_level": 0,  # thesis-code: the author's twist grid (0: 48,483 twists)
    "downsample_steps": 2.5,  # thesis-code: grid cells per wrench range (downsamplewrench.m)
    "support_directions": 4000,  # sampler-independent error: normals per surface
    "log_det_alphas": [0.0, 1e-6, 1e-3, 1e-2],  # α/K of Eq. 3.12 measured at solver_comparison_K
    "solver_comparison_K": 600,  # K at which SCS is also run (and support errors measured)
    "section_surface": "S4",  # Fig 3.10
    "section_K": 600,
    # where the surfaces run (workbench.runner.parallel.row_client): 0 = a local Dask cluster of one
    # worker per core (continuous wrenches: minutes a surface), 1 = serially here, N = N local
    # workers; scheduler = an existing cluster's address.  Neither changes a number but the
    # fit timings, which are per fit on one core either way.
    "workers": 0,
    "scheduler": "",
}


def check_config(config: dict) -> None:
    """The CLI checks settings with this before any work (workbench.runner.experiment_config.build_config)."""
    check_protocol_config(config)
    for key, spec in KEYS.items():  # μ, the surface names, the words (also for run(config))
        check_key(key, spec, config[key])
    check_mu(config["mu"], what="limit surface")  # and not 0 (the Key's range takes it)
    check_rtol(config["quad_rtol"], "quad_rtol")  # by its key, before any work
    if not config["surfaces"] or len(set(config["surfaces"])) < len(config["surfaces"]):
        raise ValueError(
            f"surfaces must name at least one thesis surface, each once; got {config['surfaces']}"
        )
    check_workers(config["workers"], config["scheduler"])


QUICK_CONFIG = {"K": [200, 600], "n_heldout": 4000, "wrench_source": "mesh", "mesh_elements": 800}
#: what each key means, its unit and plausible range (``workbench run ls-fitting --help``)
KEYS = {
    "mu": Key("friction coefficient, > 0 (normalised wrenches do not depend on it; thesis: 1)", "", "mu"),
    "surfaces": Key("thesis surfaces to fit, each once", choices=lambda: tuple(THESIS_SURFACES)),
    "K": Key("training wrenches per fit (the quartics need >= 126)"),
    "n_heldout": Key("held-out wrenches per surface for Eq. 3.18"),
    "wrench_source": Key(
        "the surfaces' wrenches: adaptive quadrature or a mesh", choices=("continuous", "mesh")
    ),
    "quad_rtol": Key("relative accuracy of the continuous wrenches, > 0"),
    "mesh_elements": Key("triangles of the mesh (wrench_source=mesh, and the thesis-code grid's box)"),
    "thesis_code": Key("also run the thesis-code protocol (the thesis-text one always runs)"),
    "fine_level": Key(
        "the author's twist grid fineLevel (0: 48,483 twists)", choices=lambda: sorted(AUTHOR_LEVELS)
    ),
    "downsample_steps": Key("thesis-code training grid: cell widths per wrench range, >= 2 (author: 2.5)"),
    "support_directions": Key("uniform normals per surface for the sampler-independent error"),
    "log_det_alphas": Key("alpha / K of Eq. 3.12's log-det penalty, measured at solver_comparison_K"),
    "solver_comparison_K": Key("K at which SCS also runs and the support errors are measured"),
    "section_surface": Key("surface of Fig 3.10's cross-sections", choices=lambda: tuple(THESIS_SURFACES)),
    "section_K": Key("K of Fig 3.10's cross-sections"),
}


def _contact(name: str, config: dict) -> ExactContact:
    """Thesis surface ``name``, normalised, with its exact wrenches of ``wrench_source``."""
    return ExactContact.of_surface(
        THESIS_SURFACES[name],
        config["mu"],
        config["support_directions"],
        source=config["wrench_source"],
        mesh_elements=config["mesh_elements"],
        quad_rtol=config["quad_rtol"],
    )


def _fit(contact: ExactContact, kind: str, W: np.ndarray, xi: np.ndarray, **fit) -> FitScore:
    """:func:`~workbench.limit_surface.protocols.fit_score` of model ``kind`` on wrenches
    W (K, 6) of ``contact`` with twists xi (K, 6); ``fit``: its ``test``, ``solver``,
    ``support_seed``.  Fast fits (the ellipsoids) are timed 3x (median) because single
    calls right after the parallel quadrature can stall on thread-pool contention (Numba
    and BLAS on 2 cores)."""
    repeats = 1 if kind.startswith("quartic") else 3
    return fit_score(contact, kind, W, twists=xi, repeats=repeats, **fit)


def _support(fs: FitScore) -> dict:
    e = fs.support
    return {"radial_mean": e.radial_mean, "radial_p95": e.radial_p95, "eq318_mean": e.eq318_mean}


def _thesis_code_rows(contact: ExactContact, config: dict, seed: int) -> dict:
    """The thesis-code protocol on one surface: the author's twist grid, its wrenches
    (:func:`~workbench.limit_surface.protocols.thesis_code_sample_of`); Fig 3.9 trains on K
    of them (:func:`~workbench.limit_surface.protocols.thesis_code_training_draws` with
    ``seed``), the code's own fit on the grid-downsampled ones (:func:`_downsampled`); Eq. 3.18
    over all of them."""
    code = thesis_code_sample_of(contact, config["fine_level"], config["downsample_steps"])
    W, xi = code.wrenches, code.twists
    out = {"n_pool": len(W), "error": {k: {} for k in KINDS}, "fit_s": {k: {} for k in KINDS}}
    for K, idx in zip(config["K"], thesis_code_training_draws(len(W), config["K"], seed), strict=True):
        for kind in KINDS:
            if K < min_wrenches(kind):
                continue
            with_support = K == config["solver_comparison_K"] and kind in SUPPORT_KINDS
            support_seed = config["seed"] if with_support else None
            fs = _fit(contact, kind, W[idx], xi[idx], test=W, support_seed=support_seed)
            out["error"][kind][str(K)] = fs.test_error
            out["fit_s"][kind][str(K)] = fs.fit_s
            if with_support:
                out.setdefault("support", {})[kind] = _support(fs)
    out["downsampled"] = _downsampled(contact, code, config)
    return out


def _downsampled(contact: ExactContact, code: ThesisCodeSample, config: dict) -> dict:
    """The author's own fit: trained on the grid-downsampled wrenches of ``code``, Eq. 3.18
    on all of them; ``n_train``, ``<kind>`` errors and the support errors ``<kind>_support``
    (a model absent with fewer wrenches than its unknowns)."""
    out: dict = {"n_train": len(code.train)}
    for kind in ("ellipsoid_sdp", "quartic_normals", "quartic_values"):
        if len(code.train) >= min_wrenches(kind):
            with_support = kind in SUPPORT_KINDS
            fs = _fit(
                contact,
                kind,
                code.train_wrenches,
                code.train_twists,
                test=code.wrenches,
                support_seed=config["seed"] if with_support else None,
            )
            out[kind] = fs.test_error
            if with_support:
                out[f"{kind}_support"] = _support(fs)
    return out


def fig_3_9_vs_thesis(table: dict, config: dict) -> dict:
    """Mean over surfaces per K of the ellipsoid_sdp and quartic_normals errors, the lowest
    of them, and its ratio to the thesis's "as low as" value of its family."""
    out = {}
    for kind, family in (("ellipsoid_sdp", "ellipsoid"), ("quartic_normals", "quartic")):
        ks = [str(k) for k in config["K"] if str(k) in table[kind][config["surfaces"][0]]]
        mean = {k: float(np.mean([table[kind][s][k] for s in config["surfaces"]])) for k in ks}
        lowest = min(mean.values())
        out[kind] = {
            "mean_over_surfaces": mean,
            "lowest": lowest,
            "thesis_as_low_as": THESIS_AS_LOW_AS[family],
            "ratio_to_thesis": lowest / THESIS_AS_LOW_AS[family],
        }
    return out


def section_figure(config: dict, out: Path, models: dict, W: np.ndarray) -> str:
    """Fig 3.10: the 3D cross-section (f_x, f_z, τ_y) of both models (other components 0)
    with the wrench dots near that section, offscreen pyvista."""
    from workbench.runner.viz import _pyvista, save_screenshot

    pv = _pyvista()
    comps = [0, 2, 4]
    labels = ["f_x", "f_z", "tau_y"]
    n = 61
    g = np.linspace(-1.3, 1.3, n)
    grid = pv.ImageData(dimensions=(n, n, n), spacing=(g[1] - g[0],) * 3, origin=(g[0],) * 3)
    pts = np.asarray(grid.points)
    plotter = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(1100, 520))
    for j, (name, model) in enumerate(models.items()):
        x = np.zeros((len(pts), 6))
        x[:, comps] = pts
        grid.point_data["f"] = model.value(x * model.scale)
        surf = grid.contour([1.0], scalars="f")
        x_hat = W / model.scale
        # dots near the section: the other components below 0.4 of their unit range — a slab thin
        # enough to sit near the cut, thick enough to hold dots (a display choice, no result)
        near = np.abs(np.delete(x_hat, comps, axis=1)).max(axis=1) < 0.4
        plotter.subplot(0, j)
        plotter.add_mesh(surf, color="lightsteelblue", opacity=0.55, smooth_shading=True)
        if near.any():
            plotter.add_points(
                x_hat[near][:, comps], color="darkorange", point_size=6, render_points_as_spheres=True
            )
        plotter.add_text(
            f"({'ab'[j]}) {name}, {config['section_surface']}, K={config['section_K']}", font_size=10
        )
        plotter.show_grid(xtitle=labels[0], ytitle=labels[1], ztitle=labels[2])
        plotter.camera_position = "iso"
    return str(save_screenshot(plotter, out / "fig_3_10_cross_sections.png"))


_BUILT: dict = {}  # per process: the first fit of each kind (problem builds), done once


def _warm(config: dict) -> dict:
    """Seconds of each kind's first fit in this process — cvxpy's problem builds — done once
    per process (driver or Dask worker) before any timed fit, so builds stay out of the
    fit timings wherever a surface runs."""
    if not _BUILT:
        contact = _contact(config["surfaces"][0], config)
        W0, xi0 = thesis_text_wrenches(contact, max(config["K"]), config["seed"] + 999)
        _BUILT.update({kind: _fit(contact, kind, W0, xi0).fit_s for kind in KINDS})
    return dict(_BUILT)


def _surface(job: tuple[int, str, str], config: dict) -> dict:
    """One part of surface ``name`` (the i-th), run in the driver or on a Dask worker
    (``workbench.runner.parallel.map_rows``): ``part`` "fits" — every fit and error of the thesis-text
    protocol (:func:`_text_rows`) — or "code" — the thesis-code protocol
    (:func:`_thesis_code_rows`, {"code": ...}), a task of its own: its 48,483-twist quadrature
    is most of a surface's time, and the two halves of six surfaces balance two workers where
    six whole surfaces left a long tail."""
    i, name, part = job
    _warm(config)
    contact = _contact(name, config)
    if part == "code":
        return {"code": _thesis_code_rows(contact, config, config["seed"] + 10_000 * i + 3)}
    return _text_rows(i, name, contact, config)


def _text_rows(i: int, name: str, contact: ExactContact, config: dict) -> dict:
    """The thesis-text part of surface ``name`` (the i-th): every K's fits (:func:`_fits_at`)
    scored on ``n_heldout`` held-out wrenches, and at ``solver_comparison_K`` the SCS fits and
    the log-det penalty (:func:`_comparison`)."""
    W_test, _ = thesis_text_wrenches(contact, config["n_heldout"], config["seed"] + 10_000 * i + 1)
    res = {key: {kind: {} for kind in KINDS} for key in ("err", "train_err", "rt", "radial")}
    res.update(rows=[], solver_rows=[], convex={}, support={}, log_det={}, section=None)
    for K in config["K"]:
        W, xi = thesis_text_wrenches(contact, K, config["seed"] + 10_000 * i + 2 + K)
        _fits_at(res, name, contact, (W, xi, W_test), config)
        if K == config["solver_comparison_K"]:
            _comparison(res, name, contact, (W, xi, W_test), config)
    return res


def _fits_at(res: dict, name: str, contact: ExactContact, sample: tuple, config: dict) -> None:
    """Every model's fit to ``sample`` = (W (K, 6), xi (K, 6), W_test (N, 6)) of surface
    ``name``, recorded into ``res`` (:func:`_text_rows`); Fig 3.10's models at ``section_K``."""
    W, xi, W_test = sample
    K = len(W)
    section = name == config["section_surface"] and K == config["section_K"]
    for kind in KINDS:
        if K < min_wrenches(kind):
            continue  # underdetermined (126 coefficients): fit_quartic refuses, we do not fake it
        with_support = K == config["solver_comparison_K"] and kind in SUPPORT_KINDS
        fs = _fit(contact, kind, W, xi, test=W_test, support_seed=config["seed"] if with_support else None)
        res["convex"].setdefault(kind, []).append(convexity(fs.model))
        res["err"][kind][str(K)] = fs.test_error
        res["radial"][kind][str(K)] = fs.test_radial
        res["train_err"][kind][str(K)] = fs.train_error
        res["rt"][kind][str(K)] = fs.fit_s
        solver = fs.model.info["solver"] if kind != "ellipsoid_lsq" else "lstsq"
        res["rows"].append([name, K, kind, solver, fs.test_error, fs.fit_s, fs.fallback])
        if with_support:
            res["support"][kind] = _support(fs)
        if section and kind in SUPPORT_KINDS:
            models = res["section"][0] if res["section"] else {}
            models[kind] = fs.model
            res["section"] = (models, W)


def _comparison(res: dict, name: str, contact: ExactContact, sample: tuple, config: dict) -> None:
    """At ``solver_comparison_K``: the SCS fits of :data:`SUPPORT_KINDS` and Eq. 3.12's log-det
    penalty ``α = a·K`` of ``log_det_alphas``, recorded into ``res`` (:func:`_text_rows`)."""
    W, xi, W_test = sample
    K = len(W)
    for kind in SUPPORT_KINDS:
        fs = _fit(contact, kind, W, xi, solver="SCS", test=W_test)
        # the solver that answered (an SDP ellipsoid whose least squares is definite: lstsq)
        res["solver_rows"].append(
            [name, K, kind, fs.model.info["solver"], fs.test_error, fs.fit_s, fs.fallback]
        )
    for a in config["log_det_alphas"]:
        fs = fit_score(contact, "ellipsoid_sdp", W, alpha=a * K, test=W_test, support_seed=config["seed"])
        res["log_det"][f"{a:g}"] = {
            "heldout_error": fs.test_error,
            "support_radial": fs.support.radial_mean,
        }


def _collect(done: dict[str, dict], config: dict) -> dict:
    """The surfaces' results (``_surface``) joined, surfaces in config order: "err", "train_err",
    "rt", "radial" {kind: {surface: {K: value}}}; "rows", "solver_rows" (fits.csv); "convex_min"
    {kind: [value per fit]}; "support" {protocol: {kind: {surface: errors}}}; "log_det"; "code"
    {kind: {surface: {K: error}}} (None without the thesis-code protocol) and its "code_rows";
    "section" (models, W) of Fig 3.10."""
    names = config["surfaces"]
    t = {
        key: {kind: {n: done[n][key][kind] for n in names} for kind in KINDS}
        for key in ("err", "train_err", "rt", "radial")
    }
    t["rows"] = [row for n in names for row in done[n]["rows"]]
    t["solver_rows"] = [row for n in names for row in done[n]["solver_rows"]]
    t["convex_min"] = {}
    for n in names:
        for kind, v in done[n]["convex"].items():
            t["convex_min"].setdefault(kind, []).extend(v)
    t["support"] = {"thesis-text": {}}
    for n in names:
        for kind, v in done[n]["support"].items():
            t["support"]["thesis-text"].setdefault(kind, {})[n] = v
    t["log_det"] = {n: done[n]["log_det"] for n in names if done[n]["log_det"]}
    code_rows = {n: done[n]["code"] for n in names if done[n]["code"] is not None}
    t["code_rows"] = code_rows
    t["code"] = {k: {n: r["error"][k] for n, r in code_rows.items()} for k in KINDS} if code_rows else None
    if code_rows:
        for kind in SUPPORT_KINDS:
            t["support"].setdefault("thesis-code", {})[kind] = {
                n: r["support"][kind] for n, r in code_rows.items()
            }
            t["support"].setdefault("thesis-code-downsampled", {})[kind] = {
                n: r["downsampled"][f"{kind}_support"]
                for n, r in code_rows.items()
                if f"{kind}_support" in r["downsampled"]  # absent: fewer wrenches than unknowns
            }
    t["section"] = next((done[n]["section"] for n in names if done[n]["section"] is not None), ({}, None))
    return t


def _fig_3_9(t: dict, config: dict, out: Path) -> str:
    """Fig 3.9: (a) error vs K under each protocol, (b) fit time vs K."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    err, code, rt = t["err"], t["code"], t["rt"]
    panels = [("thesis-text: held-out", err)] + ([("thesis-code: all grid wrenches", code)] if code else [])
    fig, axes = plt.subplots(1, len(panels) + 1, figsize=(5.5 * (len(panels) + 1), 3.8))
    for p, (title, table) in enumerate(panels):
        for j, name in enumerate(config["surfaces"]):
            for kind, style in (("ellipsoid_sdp", "--o"), ("quartic_normals", "-s"), ("quartic_values", ":")):
                ks = [int(k) for k in table[kind][name]]
                label = name if kind == "quartic_normals" else None
                axes[p].plot(ks, list(table[kind][name].values()), style, color=f"C{j}", ms=3, label=label)
        for family, v in THESIS_AS_LOW_AS.items():
            axes[p].axhline(v, color="k", lw=0.7, ls="--" if family == "ellipsoid" else "-")
        axes[p].set_xlabel("number of wrenches K")
        axes[p].set_ylabel("wrench error (Eq. 3.18)")
        axes[p].set_title(f"Fig 3.9(a), {title}", fontsize=9)
    axes[0].legend(
        fontsize=7,
        title="quartic_normals solid (dotted: quartic_values), ellipsoid_sdp dashed;\n"
        "black: thesis 'as low as' 0.02 / 0.04",
        title_fontsize=6,
    )
    for j, name in enumerate(config["surfaces"]):
        for kind, style in (("ellipsoid_sdp", "--o"), ("quartic_normals", "-s")):
            ks = [int(k) for k in rt[kind][name]]
            axes[-1].plot(ks, list(rt[kind][name].values()), style, color=f"C{j}", ms=3)
    axes[-1].set_xlabel("number of wrenches K")
    axes[-1].set_ylabel("fit time [s]")
    axes[-1].set_yscale("log")
    axes[-1].set_title(f"Fig 3.9(b): runtime (SDP: Clarabel, quartic: {_quartic_solver()})")
    return str(save_figure(fig, out / "fig_3_9_error_runtime.png"))


def _quartic_solver() -> str:
    return wb_config.DEFAULTS.quartic_solver


def _solver_label(kind: str) -> str:
    """The solver a default fit of ``kind`` uses (the figures' legends): the SDP ellipsoid's where
    its constraint is active (a definite least squares is returned as it is)."""
    sdp = f"lstsq or {wb_config.DEFAULTS.ellipsoid_solver}"
    return {"ellipsoid_lsq": "lstsq", "ellipsoid_sdp": sdp}.get(kind, _quartic_solver())


def _runtime_vs_error(t: dict, config: dict, out: Path) -> str:
    """Runtime vs error of every model and solver at the comparison K."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4))
    Kc = str(config["solver_comparison_K"])
    marker = {"ellipsoid_lsq": "o", "ellipsoid_sdp": "s", "quartic_values": "v", "quartic_normals": "^"}
    for kind in KINDS:
        if Kc in t["err"][kind][config["surfaces"][0]]:
            ax.scatter(
                [t["rt"][kind][s][Kc] for s in config["surfaces"]],
                [t["err"][kind][s][Kc] for s in config["surfaces"]],
                marker=marker[kind],
                label=f"{kind} ({_solver_label(kind)})",
            )
    for kind in SUPPORT_KINDS:
        pts = [(r[5], r[4]) for r in t["solver_rows"] if r[2] == kind]
        if pts:
            ax.scatter(
                *zip(*pts, strict=True),
                marker=marker[kind],
                facecolors="none",
                edgecolors="k",
                label=f"{kind} (SCS)",
            )
    ax.set_xscale("log")
    ax.set_xlabel("fit time [s]")
    ax.set_ylabel("held-out error")
    ax.set_title(f"runtime vs error, K = {Kc}, S1-S6")
    ax.legend(fontsize=8)
    return str(save_figure(fig, out / "runtime_vs_error.png"))


def _not_below(kind: str, table: dict, config: dict) -> list[tuple[str, int]]:
    """(surface, K) with K >= 200 where ``kind``'s error is not below ellipsoid_sdp's."""
    return [
        (s, k)
        for s in config["surfaces"]
        for k in config["K"]
        if k >= 200 and table[kind][s][str(k)] >= table["ellipsoid_sdp"][s][str(k)]
    ]


def _summary(t: dict, config: dict, run: dict) -> dict:
    """summary.json's content but the headline, from the joined tables ``t`` (:func:`_collect`) and
    ``run``'s bookkeeping (first_fit_incl_problem_build_s, surfaces_ran_on, figures)."""
    err, radial, rt, support, log_det, code_rows = (
        t[k] for k in ("err", "radial", "rt", "support", "log_det", "code_rows")
    )
    Kc = config["solver_comparison_K"]
    losses = _not_below("quartic_normals", err, config)
    losses_values = _not_below("quartic_values", err, config)
    vs_thesis = {"thesis-text": fig_3_9_vs_thesis(err, config)}
    if code_rows:
        vs_thesis["thesis-code"] = fig_3_9_vs_thesis(t["code"], config)
    big = [k for k in config["K"] if k >= 200]
    two = ("ellipsoid_sdp", "quartic_normals")
    return {
        "heldout_error": err,
        "heldout_radial_error": {k: radial[k] for k in two},
        "quartic_normals_below_ellipsoid_sdp_radial_for_K_ge_200": not _not_below(
            "quartic_normals", radial, config
        ),
        "train_error": {k: t["train_err"][k] for k in two},
        "fit_runtime_s": rt,
        "first_fit_incl_problem_build_s": run["first_fit_incl_problem_build_s"],
        "surfaces_ran_on": run["surfaces_ran_on"],
        "convexity_min_relative_eigenvalue": {k: min(v) for k, v in t["convex_min"].items()},
        # a quartic is certified SOS-convex (fit_quartic); its Hessian eigenvalues at the sampled
        # points, relative to the largest, are then >= 0 up to eigvalsh's rounding (~1e-16):
        # -1e-12 leaves four decades for it
        "all_models_convex": all(
            min(v) > 0 if not k.startswith("quartic") else min(v) >= -1e-12
            for k, v in t["convex_min"].items()
        ),
        "n_models_checked": sum(len(v) for v in t["convex_min"].values()),
        "solver_comparison": [dict(zip(FITS_CSV_COLUMNS, r, strict=True)) for r in t["solver_rows"]],
        "quartic_normals_below_ellipsoid_sdp_for_K_ge_200": not losses,
        "quartic_normals_below_ellipsoid_sdp_for_K_gt_200": not [1 for _, k in losses if k > 200],
        "quartic_normals_not_below_ellipsoid_sdp_at": [f"{s}@K={k}" for s, k in losses],
        "quartic_values_not_below_ellipsoid_sdp_at": [f"{s}@K={k}" for s, k in losses_values],
        "max_heldout_error_ellipsoid_sdp": max(
            err["ellipsoid_sdp"][s][str(k)] for s in config["surfaces"] for k in config["K"]
        ),
        "max_heldout_error_quartic_normals_K_ge_200": max(
            err["quartic_normals"][s][str(k)] for s in config["surfaces"] for k in big
        ),
        "thesis": {
            "as_low_as": THESIS_AS_LOW_AS,
            "quote": "the quartic and ellipsoidal 6DLS models reached as low as 0.02 and 0.04 mean "
            "wrench error (§3.6; six parametric surfaces and 2,932 FEM contacts together)",
        },
        "protocols": {
            "thesis-text": "thesis §3.3.2 sampler (K/2 rotations + K/2 translations, h in [-1, 1] l_s); "
            "Eq. 3.18 on n_heldout held-out wrenches of the same sampler",
            "thesis-code": f"the author's twist grid (fineLevel {config['fine_level']}); Fig 3.9: K wrenches "
            "drawn from it, Eq. 3.18 on all of it; downsampled: trained on one wrench per grid cell "
            f"({config['downsample_steps']} widths per range), Eq. 3.18 on all",
        },
        "fig_3_9_vs_thesis": vs_thesis,
        "thesis_protocol_error": (
            {
                **{
                    k: t["code"][k]
                    for k in ("ellipsoid_sdp", "quartic_normals", "quartic_values", "ellipsoid_lsq")
                },
                "downsampled": {n: r["downsampled"] for n, r in code_rows.items()},
                "n_pool": {n: r["n_pool"] for n, r in code_rows.items()},
            }
            if code_rows
            else None
        ),
        "support_error": support,
        "support_error_mean_radial": {
            p: {k: float(np.mean([v["radial_mean"] for v in by.values()])) for k, by in by_kind.items()}
            for p, by_kind in support.items()
        },
        "support_error_note": (
            f"radial |f^(1/deg) - 1| at the exact surface points of {config['support_directions']} normals "
            f"uniform on the sphere of normalised twists, models at K = {Kc} (and the downsampled fit): "
            "independent of the training sampler, comparable across protocols and model degrees"
        ),
        "sdp_log_det_effect": {
            "alpha_per_wrench": [f"{a:g}" for a in config["log_det_alphas"]],
            "by_surface": log_det,
            "max_change_vs_alpha_0": {
                f"{a:g}": max(
                    abs(v[f"{a:g}"]["heldout_error"] - v["0"]["heldout_error"]) for v in log_det.values()
                )
                for a in config["log_det_alphas"]
            }
            if "0" in next(iter(log_det.values()), {})
            else None,
        },
        "quartic_not_fitted_below_K": min_wrenches("quartic_values"),
        "figures": run["figures"],
    }


def _headline(s: dict, config: dict) -> list[str]:
    Kc = str(config["solver_comparison_K"])
    rt, first = s["fit_runtime_s"], config["surfaces"][0]
    losses, losses_values = (
        [f"{n}@{k}" for n, k in _not_below(kind, s["heldout_error"], config)]
        for kind in ("quartic_normals", "quartic_values")
    )
    return [
        f"quartic_normals below ellipsoid_sdp for every K >= 200 on every surface: "
        f"{s['quartic_normals_below_ellipsoid_sdp_for_K_ge_200']}; for K > 200: "
        f"{s['quartic_normals_below_ellipsoid_sdp_for_K_gt_200']}; not below at {losses}",
        f"quartic_values (Eq. 3.17 as in the thesis) not below ellipsoid_sdp at {losses_values}",
        f"radial error |f^(1/d) - 1|: quartic_normals below ellipsoid_sdp for every K >= 200: "
        f"{s['quartic_normals_below_ellipsoid_sdp_radial_for_K_ge_200']}",
        *(
            f"Fig 3.9, {p}: lowest mean over surfaces ellipsoid_sdp {v['ellipsoid_sdp']['lowest']:.4f} "
            f"({v['ellipsoid_sdp']['ratio_to_thesis']:.2f}x the thesis's 'as low as' 0.04), quartic_normals "
            f"{v['quartic_normals']['lowest']:.4f} ({v['quartic_normals']['ratio_to_thesis']:.2f}x 0.02)"
            for p, v in s["fig_3_9_vs_thesis"].items()
        ),
        "sampler-independent radial error, mean over surfaces: "
        + "; ".join(
            f"{p} " + ", ".join(f"{k} {v:.4f}" for k, v in by.items())
            for p, by in s["support_error_mean_radial"].items()
        ),
        f"median fit time at K = {Kc}: "
        + ", ".join(
            f"{k} {np.median([rt[k][n][Kc] for n in config['surfaces']]):.2g} s"
            for k in KINDS
            if Kc in rt[k][first]
        ),
    ]


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    # one-time problem builds in this process, kept out of the fit timings (and measured)
    build_s = _warm(config)

    # every surface's fits and errors, here or on Dask workers: the thesis-code halves first
    # (the larger tasks), then the fits
    done: dict[str, dict] = {name: {"code": None} for name in config["surfaces"]}
    parts = ("code", "fits") if config["thesis_code"] else ("fits",)
    jobs = [(i, name, part) for part in parts for i, name in enumerate(config["surfaces"])]
    # a continuous-source surface takes minutes (adaptive quadrature): two already pay for a
    # cluster's start; mesh-source (quick) surfaces take seconds
    min_rows = 2 if config["wrench_source"] == "continuous" else None
    with tqdm(total=len(jobs), desc="surface parts", unit="part") as bar:
        _, ran_on = run_rows(
            partial(_surface, config=config),
            jobs,
            lambda job, r: done[job[1]].update(r),
            config,
            n_rows=len(config["surfaces"]),
            min_rows=min_rows,
            progress=bar,
        )
    t = _collect(done, config)
    write_csv(out / "fits.csv", FITS_CSV_COLUMNS, t["rows"] + t["solver_rows"])

    # Fig 3.9, runtime vs error, Fig 3.10
    figs = [_fig_3_9(t, config, out), _runtime_vs_error(t, config, out)]
    section_models, section_W = t["section"]
    if section_models and section_W is not None:
        figs.append(section_figure(config, out, section_models, section_W))

    run_info = {"first_fit_incl_problem_build_s": build_s, "surfaces_ran_on": ran_on, "figures": figs}
    summary = _summary(t, config, run_info)
    summary["headline"] = _headline(summary, config)
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))

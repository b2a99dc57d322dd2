"""Minimal work (thesis §4.3, Eqs. 4.4–4.6, Table 4.6) on the three measured hollow objects.

Steps, per object of ``deformable_objects/`` (plastic_cup, mustard, shampoo; read by path):

1. the measured stiffness map, interpolated over the surface
   (:class:`~workbench.grasp.stiffness_map.StiffnessMap`; leave-one-grasp-out error);
2. the wall FEM at the measured grasps (:func:`workbench.fem.grasp_walls.wall_stiffness`),
   calibrated by **one scalar** (:func:`workbench.fem.grasp_walls.calibrated_wall`) — an effective
   Young's modulus at fixed thickness (linear elasticity: ``s ∝ E`` exactly) — on a
   random half of the grasps and checked on the other half (Spearman, median
   ``|log(s_fem / s_measured)|``);
3. horizontal antipodal candidate grasps (:func:`workbench.grasp.work_table.candidate_grasps`),
   REACH profiles of both jaws at 10 N (§4.3.2.1) — or, with ``profiles="fem"``, the FEM
   pad pressed on the mesh to the same reading (:func:`workbench.sources.fem_jaw.fem_jaw_profiles`)
   — and the ellipsoidal 6DLS of each;
4. the metrics per task (vertical lifting: one pose; lifting and 90° rotation: three
   poses about the grasp axis; quality = minimum over poses): ``q_robust`` (Eq. 2.101),
   ``q_force = 1 − f⊥/f⊥max`` and ``q_work = 1 − W/W_max`` (Eqs. 4.4–4.6) over the 6DLS itself
   (``work_representation="model"``: each ellipsoid as its second-order cone) — or over the
   thesis's ``C_outer`` of ``M`` tangent half-spaces (``"outer"``), an outer approximation whose
   minimal forces on these curved jaws are several times below the 6DLS's (and finite where the
   6DLS and the exact 6DFW resist at no force): a lower bound, not the metric;
5. **simulated ground truth** (no robot data here; steps 3-5:
   :func:`workbench.grasp.work_table.grasp_row`): the gripper closes to ``safety ×`` the force
   the *exact* 6DFW sets of the profiles need (capped at the gripper's ``force_cap``), with
   friction and force noise; the grasp succeeds iff (a) the task wrench is resisted by the
   exact 6DFW sets in most noise samples at every pose and (b) the jaw closing at that force,
   from the *calibrated wall FEM* (not the interpolated map), stays below ``closing_limit_mm``
   (content not dislodged, wall not creased).  The truth shares no limit surface, no map
   interpolation and no linearisation with the metrics under test;
6. Table 4.6 (:func:`workbench.grasp.work_table.table_4_6`): balanced accuracy at σ = 0.5 with
   ``W_max``, ``f⊥max`` chosen on a training half of the grasps, reported on the other half.

Rows (one per candidate grasp, and one per FEM grasp of the calibration) are
checkpointed, so a killed run resumes.  The wall squeezes (step 2 and every candidate's), the
candidate grasps (step 3-5) and the nonlinear walls' load curves run as Dask tasks
(:mod:`workbench.runner.parallel`: a local cluster of one worker per core when there are many,
``workers`` / ``scheduler``); a worker process builds an object's wall once for its squeezes
(:func:`workbench.fem.grasp_walls.linear_wall`, a per-process memo), the candidates' tasks get
their squeeze's row and build no wall, and the driver renders the stiffness maps meanwhile.  The
squeezes depend only on the wall settings, so a second run at them (e.g. ``profiles="fem"``) reads
them from the machine's shared cache.  The rows are the serial run's, bit for bit
(``tests/test_parallel.py``).
"""

from __future__ import annotations

import json
import logging
import time
from functools import partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench.code_key import code_digest
from workbench.fem.grasp_walls import (
    NonlinearWallSettings,
    WallSettings,
    calibrated_stiffness,
    calibrated_wall,
    load_curve,
    load_mesh,
    mesh_digest,
    object_files,
    series_compliance,
    wall_stiffness,
)
from workbench.grasp.quality_table import training_split
from workbench.grasp.work_table import (
    METRICS,
    TASKS,
    GraspRowSettings,
    candidate_grasps,
    grasp_row,
    largest_jaw_force,
    measured_map,
    nan_if_none,
    nonlinear_work_table,
    table_4_6,
)
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import (
    CHECKOUT,
    Checkpoint,
    content_hash,
    read_shared,
    save_figure,
    shared_cache_path,
    write_csv,
    write_shared,
    write_summary,
)

NAME = "minimal-work"
log = logging.getLogger(__name__)

THESIS_TABLE_4_6 = {  # thesis Table 4.6, objects 1-3 and All
    "vertical_lifting": {
        "q_robust": {"1": 0.500, "2": 0.391, "3": 0.500, "All": 0.487},
        "q_force": {"1": 0.711, "2": 0.539, "3": 0.535, "All": 0.606},
        "q_work": {"1": 0.833, "2": 0.831, "3": 0.610, "All": 0.775},
    },
    "lift_and_rotate": {
        "q_robust": {"1": 0.575, "2": 0.516, "3": 0.630, "All": 0.562},
        "q_force": {"1": 0.600, "2": 0.714, "3": 0.570, "All": 0.641},
        "q_work": {"1": 0.875, "2": 0.759, "3": 0.760, "All": 0.789},
    },
}

DEFAULT_CONFIG = {
    "seed": 0,
    "data_dir": str(CHECKOUT.parent / "shared" / "data" / "deformable_objects"),  # meshes/, stiffness_maps/
    "objects": ["plastic_cup", "mustard", "shampoo"],
    # filled-object masses [kg] (the thesis filled them with wet towels; masses unstated):
    # about the water mass of half the convex-hull volume (cup 353 ml, mustard 531, shampoo 508)
    "mass_kg": {"plastic_cup": 0.18, "mustard": 0.27, "shampoo": 0.25},
    "mu": 0.5,  # jaw-pad friction coefficient (thesis §4.1: 0.3-0.5)
    "n_heights": 8,  # candidate grasp heights, evenly inside the object's z extent
    "n_angles": 6,  # candidate grasp-axis angles in [0, π)
    "jaw": [0.02, 0.04],  # pad width, length [m]
    "grasp_force": 10.0,  # N per jaw: the force the profiles and q_robust use (§4.3.3.1)
    "profiles": "reach",  # jaw profiles: "reach" (§4.3.2.1) or "fem" (the FEM pad, workbench.sources.fem_jaw)
    "reach_closing_mm": 1.0,  # REACH pad compression past first touch
    "M": 200,  # linearisation directions of the 6DLS (C_outer, Eq. 3.28; q_robust's polytope)
    # the minimal-force program of q_force / q_work: "model" = the 6DLS itself (Eq. 4.4 exactly),
    # "outer" = the thesis's C_outer of M half-spaces (optimistic: forces below the 6DLS's)
    "work_representation": "model",
    "robust_samples": 30,  # N_r of q_robust
    "E": 2.5e9,  # wall FEM before calibration (PET)
    "nu": 0.4,
    "thickness": 0.5e-3,
    "mesh": [48, 24],
    "safety": 1.25,  # truth: the gripper closes to safety x the exactly required force ...
    "force_cap": 20.0,  # ... at most this [N per jaw]
    "closing_limit_mm": 5.0,  # truth: larger jaw closings crease the wall / dislodge the content
    "noise_samples": 8,  # truth: friction and force samples per grasp
    "sigma_mu": 0.1,  # relative
    "sigma_force": 0.1,  # relative
    "sigma": 0.5,  # quality threshold (thesis §4.3.4)
    "train_fraction": 0.5,
    # beyond the thesis (§4.3.5): W from the geometrically nonlinear wall's force-closing
    # curve (workbench.fem.wall_nonlinear at the calibrated E) at every candidate grasp of these
    # objects, beside W from the linear stiffness; [] skips it (it is slow: tens of seconds to
    # minutes a grasp, docs/decisions.md)
    "nl_work_objects": [],
    "nl_mesh": [16, 8],  # hexes around, along (the wall-nonlinear experiment's mesh)
    "nl_step_mm": 0.5,  # closing increment of the load stepping
    "nl_max_closing_mm": 15.0,  # 3x the truth's closing limit: a grasp needing more fails anyway
    # where the candidate grasps and load curves run (workbench.runner.parallel.row_client): 0 = a
    # local Dask cluster of one worker per core when there are many, 1 = serially here, N = N
    # local workers; scheduler = an existing cluster's address.  Neither changes a number.
    "workers": 0,
    "scheduler": "",
}
#: settings that do not enter the checkpoint key: where rows run changes no number
WHERE_KEYS = ("out", "workers", "scheduler")
#: a local cluster for the load curves from this many (a curve takes far longer than a cluster's start)
NL_MIN_ROWS = 8
#: grasps of one object per wall-stiffness task (each short; a worker factorises each wall once)
WALL_ROWS_PER_TASK = 8
NL_KEYS = ("nl_work_objects", "nl_mesh", "nl_step_mm", "nl_max_closing_mm")
QUICK_CONFIG = {
    "n_heights": 3,
    "n_angles": 2,
    "robust_samples": 8,
    "mesh": [24, 12],
    "noise_samples": 4,
    "nl_work_objects": ["shampoo"],
    "nl_mesh": [12, 6],
    "nl_step_mm": 1.0,
}


def _paths(config: dict, name: str) -> tuple[Path, Path]:
    """(mesh, measured map) of object ``name`` in the run's ``data_dir``."""
    return object_files(config["data_dir"], name)


PROFILE_SOURCES = ("reach", "fem")
#: what each key means, its unit and plausible range (``workbench run minimal-work --help``)
KEYS = {
    "data_dir": Key("folder with meshes/NAME.obj and stiffness_maps/NAME.json (deformable_objects)"),
    "objects": Key("measured objects of data_dir"),
    "mass_kg": Key("filled mass of each object, {object: kg}", "kg", "mass"),
    "mu": Key("jaw-pad friction coefficient, > 0 (thesis §4.1: 0.3-0.5)", "", "mu"),
    "n_heights": Key("candidate grasp heights, evenly inside the object's z extent"),
    "n_angles": Key("candidate grasp-axis angles in [0, pi) per height"),
    "jaw": Key("jaw pad [width, length]", "m", "pad_size"),
    "grasp_force": Key("force per jaw of the profiles and q_robust (thesis §4.3.3.1)", "N", "jaw_force"),
    "profiles": Key("jaw contact profiles: REACH (§4.3.2.1) or the FEM pad", choices=PROFILE_SOURCES),
    "reach_closing_mm": Key("REACH pad compression past first touch", "mm", "compression", 1e-3),
    "M": Key("linearisation directions of the 6DLS (C_outer, Eq. 3.28)"),
    "work_representation": Key(
        "q_force / q_work program: the 6DLS itself or the thesis's C_outer", choices=("model", "outer")
    ),
    "robust_samples": Key("pose samples N_r of q_robust"),
    "E": Key("wall Young's modulus before calibration (PET)", "Pa", "wall_modulus"),
    "nu": Key("wall Poisson ratio", "", "poisson"),
    "thickness": Key("wall thickness", "m", "wall_thickness"),
    "mesh": Key("wall hexes [around, along the height]"),
    "safety": Key("truth: the gripper closes to safety x the exactly required force"),
    "force_cap": Key("truth: largest force per jaw the gripper closes to", "N", "jaw_force"),
    "closing_limit_mm": Key(
        "truth: larger jaw closings crease the wall or dislodge the content", "mm", "closing", 1e-3
    ),
    "noise_samples": Key("truth: friction and force samples per grasp"),
    "sigma_mu": Key("truth: relative standard deviation of the friction coefficient", "", "relative_noise"),
    "sigma_force": Key("truth: relative standard deviation of the jaw force", "", "relative_noise"),
    "sigma": Key("quality threshold, < 1 (thesis §4.3.4: 0.5)"),
    "train_fraction": Key("fraction of the grasps the normalisers are fitted on, in (0, 1)"),
    "nl_work_objects": Key("objects (of objects) whose W also comes from the nonlinear wall; [] skips it"),
    "nl_mesh": Key("nonlinear wall hexes [around, along the height]"),
    "nl_step_mm": Key("closing increment of the nonlinear load stepping", "mm", "closing", 1e-3),
    "nl_max_closing_mm": Key("the nonlinear load stepping stops at this closing", "mm", "closing", 1e-3),
}


def check_config(config: dict) -> None:
    """Before any work: every key by its :data:`KEYS` entry (a known profile source, plausible
    physical numbers), and every object's mesh and measured map where ``data_dir`` says."""
    known = set(DEFAULT_CONFIG["objects"]) | set(config["objects"])
    unknown = sorted(set(config["nl_work_objects"]) - known)
    if unknown:
        raise ValueError(f"nl_work_objects {unknown} are not objects of this experiment ({sorted(known)})")
    _check_values(config)
    check_workers(config["workers"], config["scheduler"])
    for name in config["objects"]:
        _paths(config, name)


def _check_values(config: dict) -> None:
    """The numbers the run would refuse only after minutes of work (a mass in grams at the
    first grasp, σ at the normaliser fit), refused before any."""
    masses = config["mass_kg"]
    missing = [o for o in config["objects"] if not isinstance(masses, dict) or o not in masses]
    if missing:
        example = {o: DEFAULT_CONFIG["mass_kg"].get(o, 0.2) for o in config["objects"]}
        raise ValueError(
            f"mass_kg must give every object's filled mass [kg]; missing {missing} — e.g. "
            f"--set 'mass_kg={json.dumps(example)}'"
        )
    for key, spec in KEYS.items():  # μ, masses, forces, closings, the wall, the jaw (also for run(config))
        check_key(key, spec, config[key])
    if config["mu"] == 0:  # the Key's range takes it (an idealisation, not a slip)
        raise ValueError(
            "mu must be > 0: frictionless jaws hold no object against gravity, so every grasp fails "
            "and the qualities compare nothing; give the jaw-pad friction (thesis §4.1: 0.3-0.5)"
        )
    sigma = config["sigma"]  # fit_normaliser's condition, checked at the end of a run
    if (
        isinstance(sigma, bool)
        or not isinstance(sigma, (int, float))
        or not (np.isfinite(sigma) and sigma < 1)
    ):
        raise ValueError(
            f"sigma must be a finite quality threshold < 1 (0.5 in the thesis, §4.3.4); got {sigma!r}"
        )
    tf = config["train_fraction"]
    if isinstance(tf, bool) or not isinstance(tf, (int, float)) or not 0 < tf < 1:
        raise ValueError(
            f"train_fraction must be in (0, 1) (the grasps the normalisers are fitted on); got {tf!r}"
        )


def _wall_task(job: tuple, config: dict) -> list[tuple[str, dict]]:
    """The linear wall's stiffness at a chunk of one object's grasps, in the driver or a Dask
    worker: ``job`` = (object, kind, grasp numbers (m,), locations (2m, 3): the first jaws, then
    the second); [(checkpoint key ``<kind>/<object>/<number>``, row of
    :func:`workbench.fem.grasp_walls.wall_stiffness`)]."""
    name, kind, ids, P = job
    rows = wall_stiffness(str(_paths(config, name)[0]), WallSettings.from_config(config), P, list(ids))
    return [(f"{kind}/{name}/{i}", row) for i, row in zip(ids, rows, strict=True)]


def _grasp_task(job: tuple, config: dict) -> dict:
    """One candidate grasp's row (:func:`workbench.grasp.work_table.grasp_row`) from ``job`` =
    (object, index, grasp, calibration scale, seed, the grasp's wall stiffness row), in the
    driver or a Dask worker."""
    name, k, g, scale, seed, fem = job
    mesh_path, map_path = _paths(config, name)
    mesh, smap = load_mesh(str(mesh_path)), measured_map(str(map_path))
    run = GraspRowSettings.from_config(config)
    return grasp_row(name, k, g, mesh, smap, calibrated_stiffness(fem, scale), run, seed)


def _load_curve_task(job: tuple, config: dict) -> dict:
    """The nonlinear wall's load curve at one candidate grasp
    (:func:`workbench.fem.grasp_walls.load_curve`), ``job`` = (index, object, grasp index,
    grasp, calibration scale, jaw force to reach [N]): its checkpoint entry."""
    _, name, k, g, scale, force = job
    nl = NonlinearWallSettings.from_config(config)
    return load_curve(str(_paths(config, name)[0]), g, scale, force, nl, label=f"{name} grasp {k}")


def _wall_jobs(ckpt, locations: dict, config: dict) -> tuple[list[tuple], dict]:
    """The wall tasks still to run (chunks of :data:`WALL_ROWS_PER_TASK` grasps of one object)
    and {(object, kind): shared cache path} of the rows to share once computed; rows found in
    the machine's shared cache are checkpointed here instead."""
    jobs, shared = [], {}
    for (name, kind), L in locations.items():
        n = len(L) // 2
        todo = [i for i in range(n) if f"{kind}/{name}/{i}" not in ckpt]
        path = shared_cache_path(
            "wall-rows",
            {
                "mesh_file": mesh_digest(str(_paths(config, name)[0])),
                "locations": L,
                **{k: config[k] for k in ("E", "nu", "thickness", "mesh", "jaw")},
            },
        )
        cached = read_shared(path) if todo else None
        from_shared = isinstance(cached, list) and len(cached) == n
        if cached is not None and not from_shared:
            log.warning("shared wall rows %s hold no %d rows for %s; computing them again", path, n, name)
        if from_shared:
            for i in todo:
                ckpt.add(f"{kind}/{name}/{i}", cached[i])
            todo = []
        else:
            shared[name, kind] = path
        for c in range(0, len(todo), WALL_ROWS_PER_TASK):
            ids = todo[c : c + WALL_ROWS_PER_TASK]
            jobs.append((name, kind, ids, L[np.r_[ids, np.asarray(ids) + n]]))
    return jobs, shared


def wall_rows(ckpt, locations: dict, config: dict) -> dict:
    """Step 2's FEM and every candidate's wall stiffness: ``locations`` {(object, kind): (2n, 3)
    grasp points, the first jaws then the second} — kind "fem" (the measured grasps) or "wall"
    (the candidates) — to {(object, kind): n rows} (checkpointed as ``<kind>/<object>/<i>``).
    The squeezes run as Dask tasks of :data:`WALL_ROWS_PER_TASK` grasps of one object (a worker
    factorises each object's wall once); they do not depend on the profiles or the metrics, so
    they are shared on this machine by every run at the same wall settings (minimal-work with
    REACH and with FEM pads, a sweep's points), keyed by every input and the code."""
    jobs, shared = _wall_jobs(ckpt, locations, config)
    n_rows = sum(len(j[2]) for j in jobs)
    with tqdm(total=n_rows, desc="wall FEM", unit="grasp") as bar:
        run_rows(
            partial(_wall_task, config=config),
            jobs,
            lambda job, rows: [ckpt.add(key, row) for key, row in rows],
            config,
            n_rows=n_rows,
            progress=bar,
        )
    out = {}
    for (name, kind), L in locations.items():
        rows = [ckpt.rows[f"{kind}/{name}/{i}"] for i in range(len(L) // 2)]
        if (name, kind) in shared:  # without this run's checkpoint fields (its key and config hash)
            write_shared(
                shared[name, kind],
                [{k: v for k, v in r.items() if k not in ("key", "config_hash")} for r in rows],
            )
        out[name, kind] = rows
    return out


def _objects(config: dict) -> dict:
    """Steps 1 and 3 per object: its mesh, measured map (a file without measurements is
    refused), the map's leave-one-grasp-out error, the candidate grasps, and the wall's grasp
    points ``at`` {(object, "fem" | "wall"): (2n, 3)} with the measured stiffness (n,) of the
    map's grasps."""
    from workbench.fem.wall_grasps import read_locations
    from workbench.grasp.stiffness_map import leave_one_out

    ob = {"meshes": {}, "smaps": {}, "cands": {}, "interp": {}, "at": {}, "measured": {}}
    for name in config["objects"]:
        mesh_path, map_path = _paths(config, name)
        ob["meshes"][name] = load_mesh(str(mesh_path))
        ob["smaps"][name] = measured_map(str(map_path))  # refuses a file without measurements
        # 1. the measured map's leave-one-grasp-out error
        ob["interp"][name] = leave_one_out(ob["smaps"][name])
        # 3. candidate grasps (their wall stiffness is computed with step 2's)
        cands = candidate_grasps(
            ob["meshes"][name], name, config["n_heights"], config["n_angles"], config["mu"]
        )
        ob["cands"][name] = cands
        ob["at"][name, "fem"], ob["measured"][name] = read_locations(map_path)
        ob["at"][name, "wall"] = np.array([g["p1"] for g in cands] + [g["p2"] for g in cands])
    return ob


def _calibrate(ob: dict, wall: dict, rng: np.random.Generator, config: dict) -> tuple[dict, dict, list]:
    """Step 2 per object: one scalar calibrated on half of the measured grasps, checked on the
    other (:func:`workbench.fem.grasp_walls.calibrated_wall`); (validation, figure data, every
    candidate as (object, index, grasp, measured map, scale))."""
    validation, fig_data, grasps_all = {}, {}, []
    wall_settings = WallSettings.from_config(config)
    for name in config["objects"]:
        validation[name], fig_data[name] = calibrated_wall(
            wall[name, "fem"],
            ob["at"][name, "fem"],
            ob["measured"][name],
            rng,
            str(_paths(config, name)[0]),
            wall_settings,
            config["grasp_force"],  # the measurements' target force (§4.3.3.1)
        )
        scale = validation[name]["calibrated"]["scale"]
        grasps_all += [(name, k, g, ob["smaps"][name], scale) for k, g in enumerate(ob["cands"][name])]
    return validation, fig_data, grasps_all


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    rng = np.random.default_rng(config["seed"])
    # the nonlinear-work settings change only their own rows (keyed by them below)
    ckpt = Checkpoint(
        out / "rows.jsonl",
        {k: v for k, v in config.items() if k not in WHERE_KEYS and k not in NL_KEYS},
        code=code_digest(__name__),
    )
    n_resumed = len(ckpt.rows)
    ob = _objects(config)
    # 2. the wall FEM at the measured grasps and at every candidate (Dask tasks)
    wall = wall_rows(ckpt, ob["at"], config)
    validation, fig_data, grasps_all = _calibrate(ob, wall, rng, config)
    # 3-5. profiles, metrics and simulated truth per candidate (Dask); the driver renders the maps
    rows, ran_on, stiffness_figures = _candidate_rows(
        ckpt, grasps_all, wall, out, ob["meshes"], fig_data, config
    )
    skipped = [
        {"object": r["object"], "grasp": r["grasp"], "reason": r["skipped"]} for r in rows if "skipped" in r
    ]
    keep = [i for i, r in enumerate(rows) if "skipped" not in r]
    grasps_all, rows = [grasps_all[i] for i in keep], [rows[i] for i in keep]
    # the training half of Table 4.6 (W_max, f_max), shared by the nonlinear-work comparison
    split = training_split(len(rows), config["train_fraction"], config["seed"] + 1)
    t_nl = time.perf_counter()
    nonlinear = _nonlinear_work_of(ckpt, grasps_all, rows, split, config)
    t_nl = time.perf_counter() - t_nl
    # 6. Table 4.6: W_max and f_max on a training half, balanced accuracy on the rest
    table, normalisers, class_balance = table_4_6(
        rows, split, config["objects"], config["sigma"], config["seed"]
    )
    figures = _figures(out, rows, config) + stiffness_figures
    _write_grasps_csv(out, rows)
    series = series_compliance(validation, {n: d["predicted"] for n, d in fig_data.items()})
    summary = {
        **_table_summary(table, nonlinear),
        **_grasp_counts(rows, skipped, split, config),
        "class_balance": class_balance,
        "normalisers": normalisers,
        "ground_truth": _ground_truth_note(config),
        "stiffness_validation": validation,
        "series_compliance": series,
        "stiffness_interpolation": ob["interp"],
        "ms_per_grasp": _ms_per_grasp(rows),
        "n_resumed": n_resumed,
        "grasps_ran_on": ran_on,
        "seconds": {  # this invocation (resumed rows cost nothing)
            "total": time.perf_counter() - t_start,
            "nonlinear_work": t_nl,
            "table_4_6_without_nonlinear_work": time.perf_counter() - t_start - t_nl,
        },
        "figures": figures,
    }
    summary["headline"] = _headline(table, validation, series)
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _table_summary(table: dict, nonlinear: dict | None) -> dict:
    """The summary's Table 4.6 entries."""
    return {
        "table_4_6": {t: {m: table[t][m] for m in METRICS} for t in TASKS},
        # percentile bootstrap over the held-out grasps (workbench.grasp.threshold)
        "table_4_6_interval_95": {t: {m: table[t]["interval_95"][m] for m in METRICS} for t in TASKS},
        "thesis_table_4_6": THESIS_TABLE_4_6,
        "beyond_thesis_q_work_fem": {t: table[t]["q_work_fem"] for t in TASKS},
        "beyond_thesis_nonlinear_work": nonlinear,
    }


def _grasp_counts(rows: list[dict], skipped: list[dict], split: np.ndarray, config: dict) -> dict:
    """The summary's counts of grasps."""
    objs = np.array([r["object"] for r in rows])
    return {
        "n_grasps": len(rows),
        "skipped_grasps": skipped,  # candidates without a profile (profiles="fem" only)
        "n_grasps_per_object": {n: int((objs == n).sum()) for n in config["objects"]},
        "n_test": int((~split).sum()),
    }


def _ms_per_grasp(rows: list[dict]) -> dict:
    secs = np.array([r["seconds"] for r in rows])
    return {"median": float(np.median(secs) * 1e3), "max": float(secs.max() * 1e3)}


def _candidate_rows(ckpt, grasps_all, wall: dict, out: Path, meshes: dict, fig_data: dict, config: dict):
    """Rows of every candidate grasp (checkpoint ``grasp/<object>/<k>``), the missing ones as
    Dask tasks while the driver renders the stiffness maps: (rows, where they ran, map figures).
    ``wall`` : the candidates' wall stiffness rows (:func:`wall_rows`, kind "wall")."""
    todo = [
        (
            name,
            k,
            g,
            scale,
            config["seed"] * 100_003 + 1009 * config["objects"].index(name) + k,
            wall[name, "wall"][k],
        )
        for name, k, g, _, scale in grasps_all
        if f"grasp/{name}/{k}" not in ckpt
    ]
    with tqdm(total=len(todo), desc="minimal work", unit="grasp") as bar:
        stiffness_figures, ran_on = run_rows(
            partial(_grasp_task, config=config),
            todo,
            lambda job, row: ckpt.add(f"grasp/{job[0]}/{job[1]}", row),
            config,
            progress=bar,
            meanwhile=lambda: _stiffness_figures(out, meshes, fig_data),
        )
    return [ckpt.rows[f"grasp/{x[0]}/{x[1]}"] for x in grasps_all], ran_on, stiffness_figures


def _write_grasps_csv(out: Path, rows: list[dict]) -> None:
    cols = ["object", "grasp", "z", "angle_deg", "s_map_1", "s_map_2", "s_fem"]
    per_task = ("truth", "q_robust", "f_sum", "W", "f_required")
    xyz = [f"{v}_{c}" for v in ("p1", "p2", "axis") for c in "xyz"]
    write_csv(
        out / "grasps.csv",
        [*cols, *xyz, *(f"{t}_{m}" for t in TASKS for m in per_task)],
        [
            [r[c] for c in cols]
            + [*r["p1"], *r["p2"], *r["axis"]]
            + [r[t][m] for t in TASKS for m in per_task]
            for r in rows
        ],
    )


def _ground_truth_note(config: dict) -> str:
    return (
        "SIMULATED, not robot data: the gripper closes to safety x the per-jaw force the exact 6DFW sets "
        f"of the two {'REACH' if config['profiles'] == 'reach' else 'FEM pad'} profiles need against "
        "every pose's gravity wrench (bisection with "
        "workbench.grasp.exact.resists_exact), capped at force_cap; success iff the exact sets resist "
        "every pose in most of noise_samples draws of friction (sigma_mu) and force (sigma_force), and "
        "the jaw closing at that force from the calibrated wall FEM (workbench.fem.object_wall, one "
        "effective E per "
        "object) is at most closing_limit_mm. No limit surface, map interpolation or linearisation is "
        "shared with the metrics; but the closing test (f/s) and W = f (f/s + eps) grow with the same "
        "ratio, so part of q_work's lead over q_force is built into this truth."
    )


def _headline(table: dict, validation: dict, series: dict) -> list[str]:
    return (
        [
            f"{t}: balanced accuracy All q_robust {table[t]['q_robust']['All']:.3f}, q_force "
            f"{table[t]['q_force']['All']:.3f}, q_work {table[t]['q_work']['All']:.3f} (thesis "
            f"{THESIS_TABLE_4_6[t]['q_robust']['All']}/{THESIS_TABLE_4_6[t]['q_force']['All']}/"
            f"{THESIS_TABLE_4_6[t]['q_work']['All']}); simulated truth"
            for t in TASKS
        ]
        + [_validation_line(n, v) for n, v in validation.items()]
        + [
            f"series compliance (pads, fingers) <= {series['bound_m_per_N'] * 1e6:.1f} um/N (stiffest "
            f"measured grasp: {series['from_object']}): it lowers the median calibrated stiffness by <= "
            f"{max(series['effect_at_median'].values()) * 100:.1f} % on any object"
        ]
    )


def _validation_line(name: str, v: dict) -> str:
    """The headline of one object's stiffness validation and its missing-physics measurements."""
    mp = v["missing_physics"]
    far = mp["away_from_clamps"]["scores"]
    return (
        f"{name}: FEM vs measured stiffness, held-out Spearman {v['spearman']:.2f}, median |log ratio| "
        f"{v['median_abs_log_ratio']:.2f} (effective E {v['calibrated']['E_effective_Pa'] / 1e9:.2f} GPa; "
        f"over 200 halves {v['over_random_halves']['median_abs_log_ratio']['median']:.2f}); residual vs "
        f"predicted closing/width Spearman {mp['closing_fraction']['spearman_residual']:.2f}, measured "
        f"closing <= {mp['closing_fraction']['measured_closing_over_width_max']:.2f} x width; grasps >= "
        f"{mp['away_from_clamps']['near_m'] * 1e3:.0f} mm from a clamp: median |log ratio| "
        + ("n/a" if far is None else f"{far['median_abs_log_ratio']['median']:.2f}")
        + " over 200 halves"
    )


def _nonlinear_work_of(ckpt, grasps_all, rows, split, config) -> dict | None:
    """The nonlinear-work comparison on the ``nl_work_objects`` that are objects of this run
    (None without any; the others are logged and skipped)."""
    nl_objects = [n for n in config["nl_work_objects"] if n in config["objects"]]
    if len(nl_objects) < len(config["nl_work_objects"]):
        log.warning(
            "nonlinear work: %s not among objects, skipped",
            sorted(set(config["nl_work_objects"]) - set(nl_objects)),
        )
    return _nonlinear_work(ckpt, grasps_all, rows, split, config, nl_objects) if nl_objects else None


def _load_curves(ckpt, grasps_all, rows, sel: list[int], key, config: dict) -> None:
    """The load curve of every selected candidate not yet checkpointed (Dask tasks; a rigid
    or never-resisted grasp's entry is ``curve`` None without a task)."""
    jobs = []
    for i in [i for i in sel if key(i) not in ckpt]:
        name, k, g, _, scale = grasps_all[i]
        r = rows[i]
        need = largest_jaw_force(r)
        if not np.isfinite(nan_if_none(r["s_fem"])) or not np.isfinite(need):  # rigid, or never resisted
            ckpt.add(key(i), {"curve": None})
        else:
            # 0.1 % past the largest force so the curve's last step brackets it despite round-off
            jobs.append((i, name, k, g, scale, need * 1.001))
    with tqdm(total=len(jobs), desc="nonlinear work", unit="grasp") as bar:
        run_rows(
            partial(_load_curve_task, config=config),
            jobs,
            lambda job, res: ckpt.add(key(job[0]), res),
            config,
            min_rows=NL_MIN_ROWS,
            progress=bar,
        )


def _nonlinear_work(ckpt, grasps_all, rows, split, config, objects: list[str]) -> dict:
    """Scope 9 (§4.3.5): per candidate grasp of ``objects``, the nonlinear wall's
    load curve up to the largest jaw force of any pose, ``W_nl = max over poses Σ_i ∫ f dΔ``
    at the jaws' minimal forces (:func:`workbench.grasp.work_table.nonlinear_work`), and Table
    4.6's balanced accuracy of ``q_work`` from it beside ``q_work`` from the linear stiffness
    (``f² / 2s``), on the same grasps with the same ``split`` (n,) bool (True: training).
    Rows checkpointed."""
    nl = {k: config[k] for k in NL_KEYS if k != "nl_work_objects"}
    tag = content_hash(nl, 8)
    sel = [i for i, x in enumerate(grasps_all) if x[0] in objects]

    def key(i: int) -> str:  # the checkpoint key of candidate i's load curve
        return f"nlw/{tag}/{grasps_all[i][0]}/{grasps_all[i][1]}"

    _load_curves(ckpt, grasps_all, rows, sel, key, config)
    entries = [ckpt.rows[key(i)] for i in sel]
    objs = np.array([grasps_all[i][0] for i in sel])
    table = nonlinear_work_table([rows[i] for i in sel], entries, split[sel], objs, objects, config["sigma"])
    secs = [e["seconds"] for e in entries if "seconds" in e]
    return {
        "objects": objects,
        "skipped_not_in_objects": sorted(set(config["nl_work_objects"]) - set(objects)),
        "n_grasps": len(sel),
        "n_curves": len(secs),
        "settings": nl,
        "table": table,
        "seconds_per_curve": {"median": float(np.median(secs)), "max": float(max(secs))} if secs else None,
        "note": (
            "q_work from the wall's elastic work U = Σ ∫ f dΔ (not Eq. 4.5's W = Σ f (f/s + ε), which "
            "has no 1/2 and no load curve): U from the St. Venant-Kirchhoff wall's load curve at the "
            "linear model's calibrated E (coarser mesh nl_mesh), against U = Σ f²/2s from the "
            "calibrated linear stiffness; the same grasps, split and thresholding; simulated truth"
        ),
    }


def _figures(out: Path, rows: list[dict], config: dict) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(
        1, len(config["objects"]), figsize=(4 * len(config["objects"]), 3.6), squeeze=False
    )
    for ax, name in zip(axes[0], config["objects"], strict=True):
        sel = [r for r in rows if r["object"] == name]
        z = np.array([r["z"] for r in sel]) * 1e3
        a = np.array([r["angle_deg"] for r in sel])
        W = np.array([nan_if_none(r["lift_and_rotate"]["W"]) for r in sel])
        ok = np.array([r["lift_and_rotate"]["truth"] for r in sel])
        sc = ax.scatter(a, z, c=np.log10(np.where(np.isfinite(W), W, np.nan)), cmap="RdYlGn_r", s=60)
        ax.scatter(a[~ok], z[~ok], marker="x", c="k", s=30, label="truth: fails")
        ax.set_xlabel("grasp axis angle [deg]")
        ax.set_ylabel("height [mm]")
        ax.set_title(f"{name}: minimal work (lift+rotate)")
        fig.colorbar(sc, ax=ax, label="log10 W [J]")
    axes[0][0].legend(loc="lower left", fontsize=7)
    fig.tight_layout()
    return [str(save_figure(fig, out / "fig_4_13_work.png"))]


def _stiffness_figures(out: Path, meshes: dict, fig_data: dict) -> list[str]:
    """Measured vs calibrated-FEM stiffness: the scatter of all objects, and per object
    both maps on its mesh (:mod:`workbench.runner.stiffness_figures`)."""
    from workbench.runner.stiffness_figures import plot_stiffness_validation, render_stiffness_maps

    panels = {}
    for name, d in fig_data.items():
        n = len(d["measured"])
        panels[name] = {
            "measured": d["measured"],
            "predicted": d["predicted"],
            "train": np.isin(np.arange(n), d["train"]),
            "test": np.isin(np.arange(n), d["test"]),
        }
    paths = [plot_stiffness_validation(panels, out / "fig_stiffness_validation.png")]
    for name, d in fig_data.items():
        paths.append(
            render_stiffness_maps(
                meshes[name].vertices,
                meshes[name].faces,
                d["L"],
                d["measured"],
                d["predicted"],
                out / f"fig_stiffness_map_{name}.png",
                title=name,
            )
        )
    return [str(p) for p in paths]


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))

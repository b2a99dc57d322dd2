"""Minimal work (thesis §4.3, Eqs. 4.4–4.6, Table 4.6) on the three measured hollow objects.

Steps, per object of ``deformable_objects/`` (plastic_cup, mustard, shampoo; read by path):

1. the measured stiffness map, interpolated over the surface
   (:class:`~workbench.grasp.stiffness_map.StiffnessMap`; leave-one-grasp-out error);
2. the wall FEM at the measured grasps (:func:`workbench.fem.object_wall.object_wall`,
   :func:`workbench.fem.wall_grasps.stiffness_at`), calibrated by **one scalar** — an effective
   Young's modulus at fixed thickness (linear elasticity: ``s ∝ E`` exactly) — on a
   random half of the grasps and checked on the other half (Spearman, median
   ``|log(s_fem / s_measured)|``);
3. horizontal antipodal candidate grasps (:func:`~workbench.grasp.sampling.horizontal_grasps`),
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
5. **simulated ground truth** (no robot data here): the gripper closes to
   ``safety ×`` the force the *exact* 6DFW sets of the profiles need (capped at the
   gripper's ``force_cap``), with friction and force noise; the grasp succeeds iff
   (a) the task wrench is resisted by the exact 6DFW sets in most noise samples at
   every pose and (b) the jaw closing at that force, from the *calibrated wall FEM*
   (not the interpolated map), stays below ``closing_limit_mm`` (content not
   dislodged, wall not creased).  The truth shares no limit surface, no map
   interpolation and no linearisation with the metrics under test;
6. Table 4.6: balanced accuracy at σ = 0.5 with ``W_max``, ``f⊥max`` chosen on a
   training half of the grasps, reported on the other half.

Rows (one per candidate grasp, and one per FEM grasp of the calibration) are
checkpointed, so a killed run resumes.  The wall squeezes (step 2 and every candidate's), the
candidate grasps (step 3-5) and the nonlinear walls' load curves run as Dask tasks
(:mod:`workbench.runner.parallel`: a local cluster of one worker per core when there are many,
``workers`` / ``scheduler``); a worker process builds an object's wall once for its squeezes
(:func:`_object_wall`, a per-process memo), the candidates' tasks get their squeeze's row and
build no wall, and the driver renders the stiffness maps meanwhile.  The squeezes depend only
on the wall settings, so a second run at them (e.g. ``profiles="fem"``) reads them from the
machine's shared cache.  The rows are the serial run's, bit for bit (``tests/test_parallel.py``).
"""

from __future__ import annotations

import json
import logging
import time
from functools import lru_cache, partial
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench import config as settings  # `config` is the run's dict here
from workbench.code_key import code_digest
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import (
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
ROOT = Path(__file__).resolve().parents[1]
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
    "data_dir": str(ROOT.parent / "shared" / "data" / "deformable_objects"),  # meshes/ and stiffness_maps/
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

TASKS = ("vertical_lifting", "lift_and_rotate")
METRICS = ("q_robust", "q_force", "q_work")


def _paths(config: dict, name: str) -> tuple[Path, Path]:
    d = Path(config["data_dir"])
    mesh, smap = d / "meshes" / f"{name}.obj", d / "stiffness_maps" / f"{name}.json"
    if not mesh.exists() or not smap.exists():
        raise ValueError(
            f"{name}: {mesh} or {smap} not found — set data_dir to the deformable_objects folder "
            "(meshes/ and stiffness_maps/, CC BY-NC 4.0, read by path)"
        )
    return mesh, smap


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


@lru_cache(maxsize=8)
def _mesh(path: str):
    """The object's mesh, read once per process (driver and each worker)."""
    import trimesh

    return trimesh.load(path, force="mesh")


@lru_cache(maxsize=8)
def _measured_map(path: str):
    """The measured map's :class:`~workbench.grasp.stiffness_map.StiffnessMap`, once per process."""
    from workbench.fem.wall_grasps import read_locations
    from workbench.grasp.stiffness_map import StiffnessMap

    L, measured = read_locations(path)
    if measured is None:
        raise ValueError(
            f"{path}: minimal-work needs the measured 'stiffness_map' (one value per location) "
            "beside 'stiffness_locations'; for locations without measurements use "
            "`workbench run wall-stiffness --set object=... --set locations=...`"
        )
    return StiffnessMap.from_measured(L, np.r_[measured, measured])


@lru_cache(maxsize=4)
def _object_wall(path: str, E: float, nu: float, thickness: float, n_theta: int, n_z: int):
    """The object's linear wall, assembled and factorised once per process (seconds; it
    cannot be sent to a worker: the sparse factor does not pickle)."""
    from workbench.fem.material import Material
    from workbench.fem.object_wall import object_wall

    return object_wall(_mesh(path), Material(E, nu), thickness=thickness, n_theta=n_theta, n_z=n_z)


def _wall_of(name: str, config: dict):
    """(geometry, wall) of object ``name`` at the run's wall settings."""
    nt, nz = config["mesh"]
    path = str(_paths(config, name)[0])
    return _object_wall(path, float(config["E"]), float(config["nu"]), float(config["thickness"]), nt, nz)


@lru_cache(maxsize=2)
def _fem_pad(jaw: tuple):
    """The FEM pad (profiles="fem"), condensed once per process (its disk cache: once per machine)."""
    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry, condense_pad

    return condense_pad(PadGeometry(*jaw), Material())


def _jaws_of(mesh, g: dict, config: dict) -> list:
    """Both jaws' contact profiles at grasp ``g`` (``profiles``: REACH or the FEM pad)."""
    if config["profiles"] == "reach":
        from workbench.sources.reach import jaw_profiles

        return jaw_profiles(
            mesh,
            g,
            config["grasp_force"],
            pad=tuple(config["jaw"]),
            closing=config["reach_closing_mm"] * 1e-3,
            allow_scale=True,
        )
    from workbench.sources.fem_jaw import fem_jaw_profiles

    return fem_jaw_profiles(mesh, g, config["grasp_force"], pad=_fem_pad(tuple(config["jaw"])))


def _grasp_task(job: tuple, config: dict) -> dict:
    """One candidate grasp's row (:func:`_grasp_row`) from ``job`` = (object, index, grasp,
    calibration scale, seed, the grasp's wall stiffness row), in the driver or a Dask worker."""
    name, k, g, scale, seed, fem = job
    mesh_path, map_path = _paths(config, name)
    return _grasp_row(
        name,
        k,
        g,
        _mesh(str(mesh_path)),
        _measured_map(str(map_path)),
        scale,
        fem,
        partial(_jaws_of, config=config),
        config,
        seed,
    )


def _wall_task(job: tuple, config: dict) -> list[tuple[str, dict]]:
    """The linear wall's stiffness at a chunk of one object's grasps, in the driver or a Dask
    worker: ``job`` = (object, kind, grasp numbers (m,), locations (2m, 3): the first jaws, then
    the second); [(checkpoint key ``<kind>/<object>/<number>``, row of
    :func:`workbench.fem.wall_grasps.stiffness_at`)]."""
    from workbench.fem.wall_grasps import stiffness_at

    name, kind, ids, P = job
    geo, wall = _wall_of(name, config)
    rows = stiffness_at(
        wall, geo.surface, P, z_range=geo.z_range, jaw=tuple(config["jaw"]), grasp_ids=list(ids)
    )
    return [(f"{kind}/{name}/{i}", row) for i, row in zip(ids, rows, strict=True)]


def _wall_rows(ckpt, locations: dict, config: dict) -> dict:
    """Step 2's FEM and every candidate's wall stiffness: ``locations`` {(object, kind): (2n, 3)
    grasp points, the first jaws then the second} — kind "fem" (the measured grasps) or "wall"
    (the candidates) — to {(object, kind): n rows} (checkpointed as ``<kind>/<object>/<i>``).
    The squeezes run as Dask tasks of :data:`WALL_ROWS_PER_TASK` grasps of one object (a worker
    factorises each object's wall once); they do not depend on the profiles or the metrics, so
    they are shared on this machine by every run at the same wall settings (minimal-work with
    REACH and with FEM pads, a sweep's points), keyed by every input and the code."""
    jobs, shared = [], {}
    for (name, kind), L in locations.items():
        n = len(L) // 2
        todo = [i for i in range(n) if f"{kind}/{name}/{i}" not in ckpt]
        path = shared_cache_path(
            "wall-rows",
            {
                "mesh_file": _mesh_digest(str(_paths(config, name)[0])),
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


@lru_cache(maxsize=8)
def _mesh_digest(path: str) -> str:
    """SHA-256 of the mesh file's bytes (the key of results computed from it)."""
    import hashlib

    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _num(x) -> float:
    return float("nan") if x is None else float(x)


def run(config: dict) -> dict:
    from workbench.fem.wall_grasps import read_locations
    from workbench.grasp.stiffness_map import leave_one_out

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
    meshes, smaps, cands, validation, interp, grasps_all, fig_data, at = {}, {}, {}, {}, {}, [], {}, {}
    measured = {}
    for name in config["objects"]:
        mesh_path, map_path = _paths(config, name)
        meshes[name] = _mesh(str(mesh_path))
        smaps[name] = _measured_map(str(map_path))  # refuses a file without measurements
        # 1. the measured map's leave-one-grasp-out error
        interp[name] = leave_one_out(smaps[name])
        # 3. candidate grasps (their wall stiffness is computed with step 2's)
        cands[name] = _candidates(meshes[name], name, config)
        at[name, "fem"], measured[name] = read_locations(map_path)
        at[name, "wall"] = np.array([g["p1"] for g in cands[name]] + [g["p2"] for g in cands[name]])
    # 2. the wall FEM at the measured grasps and at every candidate (Dask tasks)
    wall = _wall_rows(ckpt, at, config)
    for name in config["objects"]:
        # 2. one scalar calibrated on half of the measured grasps, checked on the other
        validation[name], fig_data[name] = _calibrated_wall(
            wall[name, "fem"], at[name, "fem"], measured[name], name, rng, config
        )
        scale = validation[name]["calibrated"]["scale"]
        grasps_all += [(name, k, g, smaps[name], scale) for k, g in enumerate(cands[name])]
    # 3-5. profiles, metrics and simulated truth per candidate (Dask); the driver renders the maps
    rows, ran_on, stiffness_figures = _candidate_rows(ckpt, grasps_all, wall, out, meshes, fig_data, config)
    skipped = [
        {"object": r["object"], "grasp": r["grasp"], "reason": r["skipped"]} for r in rows if "skipped" in r
    ]
    keep = [i for i, r in enumerate(rows) if "skipped" not in r]
    grasps_all, rows = [grasps_all[i] for i in keep], [rows[i] for i in keep]
    # the training half of Table 4.6 (W_max, f_max), shared by the nonlinear-work comparison
    split = np.random.default_rng(config["seed"] + 1).random(len(rows)) < config["train_fraction"]
    t_nl = time.perf_counter()
    nonlinear = _nonlinear_work_of(ckpt, grasps_all, rows, split, config)
    t_nl = time.perf_counter() - t_nl
    # 6. Table 4.6: W_max and f_max on a training half, balanced accuracy on the rest
    table, normalisers, class_balance = _table_4_6(rows, split, config)
    figures = _figures(out, rows, config) + stiffness_figures
    _write_grasps_csv(out, rows)
    secs = np.array([r["seconds"] for r in rows])
    series = _series_compliance(validation, fig_data)
    objs = np.array([r["object"] for r in rows])
    summary = {
        "table_4_6": {t: {m: table[t][m] for m in METRICS} for t in TASKS},
        # percentile bootstrap over the held-out grasps (workbench.grasp.threshold)
        "table_4_6_interval_95": {t: {m: table[t]["interval_95"][m] for m in METRICS} for t in TASKS},
        "thesis_table_4_6": THESIS_TABLE_4_6,
        "beyond_thesis_q_work_fem": {t: table[t]["q_work_fem"] for t in TASKS},
        "beyond_thesis_nonlinear_work": nonlinear,
        "n_grasps": len(rows),
        "skipped_grasps": skipped,  # candidates without a profile (profiles="fem" only)
        "n_grasps_per_object": {n: int((objs == n).sum()) for n in config["objects"]},
        "n_test": int((~split).sum()),
        "class_balance": class_balance,
        "normalisers": normalisers,
        "ground_truth": _ground_truth_note(config),
        "stiffness_validation": validation,
        "series_compliance": series,
        "stiffness_interpolation": interp,
        "ms_per_grasp": {"median": float(np.median(secs) * 1e3), "max": float(secs.max() * 1e3)},
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


def _calibrated_wall(
    fem_rows: list[dict],
    L: np.ndarray,
    measured: np.ndarray,
    name: str,
    rng: np.random.Generator,
    config: dict,
) -> tuple[dict, dict]:
    """Step 2 for object ``name``: from the FEM at its measured grasps (``fem_rows``, one per
    grasp: :func:`_wall_rows`; the grasps ``L`` (2n, 3) and their ``measured`` stiffness (n,) of
    the map file), one factor calibrated on a random half (drawn from ``rng``) and scored on the
    other, and what the factor leaves (series compliance, large deflection, the clamps).  Returns
    the validation summary and the stiffness figures' data."""
    from workbench.fem.calibration import missing_physics, one_factor_validation

    mesh_path = _paths(config, name)[0]
    fem = np.array([_num(r["stiffness"]) for r in fem_rows])
    n_g = len(fem)
    z_mid = 0.5 * (L[:n_g, 2] + L[n_g:, 2])
    validation, train, test = one_factor_validation(fem, measured, rng, heights=z_mid, E=config["E"])
    geo = _wall_geometry(str(mesh_path), float(config["thickness"]), config["mesh"][1])
    z_lo, z_hi = geo.z_range
    validation["missing_physics"] = missing_physics(
        fem,
        measured,
        width=np.linalg.norm(L[n_g:] - L[:n_g], axis=1),
        clamp_distance=np.minimum(z_mid - z_lo, z_hi - z_mid if geo.clamp_top else np.inf),
        force=config["grasp_force"],  # the measurements' target force (§4.3.3.1)
    )
    scale = validation["calibrated"]["scale"]
    rigid = settings.TOL.rigid_stiffness_threshold
    predicted = np.where(fem < rigid, fem * scale, np.inf)  # rigid stays rigid
    return validation, {"L": L, "measured": measured, "predicted": predicted, "train": train, "test": test}


def _candidates(mesh, name: str, config: dict) -> list[dict]:
    """Step 3: horizontal antipodal grasps at ``n_heights`` heights inside the object's z
    extent and ``n_angles`` axis angles."""
    from workbench.grasp.sampling import horizontal_grasps

    lo, hi = mesh.bounds[:, 2]
    heights = np.linspace(lo, hi, config["n_heights"] + 2)[1:-1]
    cands = horizontal_grasps(mesh, heights, config["n_angles"], config["mu"], pad=None)
    if not cands:
        raise ValueError(
            f"{name}: no horizontal antipodal grasp within friction cone mu={config['mu']} at "
            f"{config['n_heights']} heights x {config['n_angles']} angles — raise n_heights, "
            "n_angles or mu"
        )
    return cands


def _candidate_rows(ckpt, grasps_all, wall: dict, out: Path, meshes: dict, fig_data: dict, config: dict):
    """Rows of every candidate grasp (checkpoint ``grasp/<object>/<k>``), the missing ones as
    Dask tasks while the driver renders the stiffness maps: (rows, where they ran, map figures).
    ``wall`` : the candidates' wall stiffness rows (:func:`_wall_rows`, kind "wall")."""
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


def _inf_for_nan(rows: list[dict], task: str, key: str) -> np.ndarray:
    """(n,) ``row[task][key]`` of every row, a missing (None / NaN: unresisted) value as inf."""
    x = np.array([_num(r[task][key]) for r in rows])
    return np.where(np.isnan(x), np.inf, x)


def _table_4_6(rows: list[dict], split: np.ndarray, config: dict) -> tuple[dict, dict, dict]:
    """Table 4.6 per task: normalisers fitted on the training grasps (``split``), balanced
    accuracy of each metric on the held-out ones (:func:`~workbench.grasp.quality_table.quality_table`);
    (table, normalisers, class balance).  ``table[task]["interval_95"]``: each metric's bootstrap
    interval of its overall balanced accuracy."""
    from workbench.grasp.quality_table import quality_table

    objs = np.array([r["object"] for r in rows])
    table, normalisers, class_balance = {}, {}, {}
    for task in TASKS:
        truth = np.array([r[task]["truth"] for r in rows])
        f, W, W_fem = (_inf_for_nan(rows, task, key) for key in ("f_sum", "W", "W_fem"))
        scored = quality_table(
            truth,
            split,
            objs,
            config["objects"],
            qualities={"q_robust": np.array([r[task]["q_robust"] for r in rows])},
            costs={"q_force": f, "q_work": W, "q_work_fem": W_fem},
            sigma=config["sigma"],
            seed=config["seed"],
        )
        fitted = scored["normalisers"]
        normalisers[task] = {
            "f_max_N": fitted["q_force"],
            "W_max_J": fitted["q_work"],
            "W_fem_max_J": fitted["q_work_fem"],
        }
        table[task] = {**scored["accuracy"], "interval_95": scored["interval_95"]}
        class_balance[task] = {"success": int(truth.sum()), "failure": int((~truth).sum())}
        # per object on the held-out grasps: with one class only, balanced accuracy is that
        # class's recall (0 or 1 for a constant prediction)
        class_balance[task]["held_out"] = {
            n: [int((truth & ~split & (objs == n)).sum()), int((~truth & ~split & (objs == n)).sum())]
            for n in config["objects"]
        }
    return table, normalisers, class_balance


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


def _series_compliance(validation: dict, fig_data: dict) -> dict:
    """One gripper measured every object: the tightest bound on its series compliance (pads,
    fingers) holds for all, and the most it lowers each object's median calibrated stiffness."""
    key = "series_compliance_bound_m_per_N"
    tight = min(validation, key=lambda n: validation[n]["missing_physics"][key])
    c_max = validation[tight]["missing_physics"][key]
    series = {"bound_m_per_N": c_max, "from_object": tight, "effect_at_median": {}}
    for n in validation:
        p = np.asarray(fig_data[n]["predicted"])
        series["effect_at_median"][n] = 1.0 - 1.0 / (1.0 + float(np.median(p[np.isfinite(p)])) * c_max)
    return series


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


def _nonlinear_work(ckpt, grasps_all, rows, split, config, objects: list[str]) -> dict:
    """Scope 9 (§4.3.5): per candidate grasp of ``objects``, the nonlinear wall's
    load curve up to the largest jaw force of any pose, ``W_nl = max over poses Σ_i ∫ f dΔ``
    at the jaws' minimal forces (:func:`workbench.fem.wall_nonlinear.curve_work`), and Table 4.6's
    balanced accuracy of ``q_work`` from it beside ``q_work`` from the linear stiffness
    (``f² / 2s``), on the same grasps with the same ``split`` (n,) bool (True: training).
    Rows checkpointed."""
    from workbench.fem.wall_nonlinear import curve_work
    from workbench.grasp.threshold import fit_normaliser, held_out_accuracy

    nl = {k: config[k] for k in NL_KEYS if k != "nl_work_objects"}
    tag = content_hash(nl, 8)
    sel = [i for i, x in enumerate(grasps_all) if x[0] in objects]

    def key(i: int) -> str:  # the checkpoint key of candidate i's load curve
        return f"nlw/{tag}/{grasps_all[i][0]}/{grasps_all[i][1]}"

    def need(r) -> float:  # the largest jaw force over both tasks' poses [N]
        f = np.array([x for t in TASKS for pose in r[t]["forces"] for x in pose], float)
        return float(np.nanmax(f)) if np.isfinite(f).any() else float("nan")

    jobs = []
    for i in [i for i in sel if key(i) not in ckpt]:
        name, k, g, _, scale = grasps_all[i]
        r = rows[i]
        if not np.isfinite(_num(r["s_fem"])) or not np.isfinite(need(r)):  # rigid, or never resisted
            ckpt.add(key(i), {"curve": None})
        else:
            # 0.1 % past the largest force so the curve's last step brackets it despite round-off
            jobs.append((i, name, k, g, scale, need(r) * 1.001))
    with tqdm(total=len(jobs), desc="nonlinear work", unit="grasp") as bar:
        run_rows(
            partial(_load_curve, config=config),
            jobs,
            lambda job, res: ckpt.add(key(job[0]), res),
            config,
            min_rows=NL_MIN_ROWS,
            progress=bar,
        )
    W_nl = {t: np.full(len(sel), np.inf) for t in TASKS}
    W_lin = {t: np.full(len(sel), np.inf) for t in TASKS}
    W_map = {t: np.array([_num(rows[i][t]["W"]) for i in sel]) for t in TASKS}
    for j, i in enumerate(sel):
        r, c = rows[i], ckpt.rows[key(i)]
        for t in TASKS:
            W_lin[t][j] = _num(r[t]["W_fem"])
            poses = [np.asarray(p, float) for p in r[t]["forces"]]
            if any(np.isnan(p).any() for p in poses):
                continue  # a pose not resisted: inf, as the linear W
            if not np.isfinite(_num(r["s_fem"])):
                W_nl[t][j] = 0.0  # rigid: no wall work, as f² / 2s with s = inf
            elif c["curve"] is not None:
                cv = c["curve"]
                w = [
                    curve_work(cv["closing"], cv["jaw_forces"], p, rigid_beyond=c["on_clamp"])[0]
                    for p in poses
                ]
                sums = np.array([x.sum() for x in w])
                # a force past the curve's end (max closing): predicted to fail, like unresisted
                W_nl[t][j] = np.inf if np.isnan(sums).any() else float(sums.max())
    split, objs = split[sel], np.array([grasps_all[i][0] for i in sel])
    table = {}
    for t in TASKS:
        truth = np.array([rows[i][t]["truth"] for i in sel])
        table[t] = {}
        variants = (
            ("q_work_map", np.where(np.isnan(W_map[t]), np.inf, W_map[t])),  # the thesis's (Table 4.6)
            ("q_work_fem_linear", W_lin[t]),
            ("q_work_fem_nonlinear", W_nl[t]),
        )
        for label, W in variants:
            pred = 1 - W / fit_normaliser(W[split], truth[split], config["sigma"]) >= config["sigma"]
            per = held_out_accuracy(pred, truth, split, objs, objects)
            table[t][label] = {n: v for n, v in per.items() if v is not None}
        fin = np.isfinite(W_lin[t]) & np.isfinite(W_nl[t]) & (W_lin[t] > 0)
        table[t]["W_nonlinear_over_linear"] = {
            "median": float(np.median(W_nl[t][fin] / W_lin[t][fin])) if fin.any() else None,
            "n": int(fin.sum()),
        }
    secs = [ckpt.rows[key(i)]["seconds"] for i in sel if "seconds" in ckpt.rows[key(i)]]
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


@lru_cache(maxsize=4)
def _wall_geometry(path: str, thickness: float, n_z: int):
    """The object's wall geometry (ray casting), once per process."""
    from workbench.fem.object_wall import wall_geometry

    return wall_geometry(_mesh(path), thickness=thickness, n_z=n_z)


def _load_curve(job: tuple, config: dict) -> dict:
    """The nonlinear wall's force-closing curve at one candidate grasp, ``job`` = (index,
    object, grasp index, grasp, calibration scale, jaw force to reach [N]); its checkpoint
    entry (``curve`` None with the ``error`` when the squeeze refuses the grasp)."""
    from workbench.fem.material import Material
    from workbench.fem.wall_nonlinear import grasp_frame_wall, squeeze_nonlinear

    _, name, k, g, scale, force = job
    geo = _wall_geometry(str(_paths(config, name)[0]), float(config["thickness"]), config["nl_mesh"][1])
    mat = Material(config["E"] * scale, config["nu"])  # the linear model's calibrated E
    t0 = time.perf_counter()
    try:
        wall, centre = grasp_frame_wall(geo, mat, g["p1"], g["p2"], n_theta=config["nl_mesh"][0])
        res = squeeze_nonlinear(
            wall,
            centre,
            force=force,
            step=config["nl_step_mm"] * 1e-3,
            max_closing=config["nl_max_closing_mm"] * 1e-3,
            jaw=tuple(config["jaw"]),
        )
    except ValueError as e:  # e.g. no wall under a jaw: recorded, not hidden
        log.warning("nonlinear work %s grasp %d: %s", name, k, e)
        return {"curve": None, "error": str(e)}
    return {
        "curve": {"closing": res["closing"].tolist(), "jaw_forces": res["jaw_forces"].tolist()},
        "on_clamp": res["on_clamp"],
        "seconds": time.perf_counter() - t0,
    }


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


def _grasp_row(name, k, g, mesh, smap, scale, fem: dict, jaws_of, config, seed: int) -> dict:
    """Metrics and simulated truth of one candidate grasp (module docstring, steps 3-5);
    ``fem`` : its row of the linear wall's stiffness (:func:`_wall_task`), before calibration."""
    from workbench.grasp.exact import ExactContacts
    from workbench.grasp.models import contact_sets
    from workbench.grasp.robust import Perturbation, q_robust
    from workbench.grasp.simulated_truth import simulated_success
    from workbench.grasp.tasks import task_wrenches
    from workbench.grasp.work import minimal_work_poses

    t0 = time.perf_counter()
    F0, mu = config["grasp_force"], config["mu"]
    try:
        profiles = jaws_of(mesh, g)
    except ValueError as e:  # no FEM pad profile: the object reaches the jaw's rigid back first
        if config["profiles"] == "reach":
            raise
        log.warning("%s grasp %d skipped: %s", name, k, e)
        return {"object": name, "grasp": k, "skipped": str(e)}
    contacts = [contact_sets(p, "6dls", M=config["M"], seed=config["seed"])[0] for p in profiles]
    s_map = smap(np.array([g["p1"], g["p2"]]))
    s_fem = np.inf if fem["rigid"] or fem["failed"] else fem["stiffness"] * scale
    com, mass = mesh.convex_hull.center_mass, config["mass_kg"][name]  # the filled object's centre
    exact = ExactContacts(profiles, seed=config["seed"])
    rng = np.random.default_rng(seed)
    row = {
        "object": name,
        "grasp": k,
        "z": float(g["center"][2]),
        "angle_deg": float(np.degrees(np.arctan2(g["axis"][1], g["axis"][0])) % 180),
        "s_map_1": float(s_map[0]),
        "s_map_2": float(s_map[1]),
        "s_fem": float(s_fem),
        # the grasp itself (object frame [m]), for judges that re-run it (minimal-work-engine)
        "p1": [float(x) for x in g["p1"]],
        "p2": [float(x) for x in g["p2"]],
        "axis": [float(x) for x in g["axis"]],
    }
    poses = {task: task_wrenches(task, mass, com, g["axis"]) for task in TASKS}
    q_robust_of: dict[bytes, float] = {}  # the tasks share the 0° pose: its q_robust once

    def q_of(w: np.ndarray) -> float:
        key = np.ascontiguousarray(w).tobytes()
        if key not in q_robust_of:
            perturb = Perturbation(n_samples=config["robust_samples"])
            q_robust_of[key] = q_robust(contacts, mu, mass, com, perturb, w_ext=w, seed=0)
        return q_robust_of[key]

    # every pose of both tasks on one LP (the 0° pose they share is solved once)
    mw_all = minimal_work_poses(
        contacts, np.vstack(list(poses.values())), mu, s_map, representation=config["work_representation"]
    )
    k0 = 0
    for task, ws in poses.items():
        mw, k0 = mw_all[k0 : k0 + len(ws)], k0 + len(ws)
        f_sum = max(m.f_sum for m in mw)
        W = max(m.W for m in mw)
        # beyond the thesis: the work from the calibrated FEM's force-deflection line, ∫ f dΔ = f²/(2 s)
        W_fem = max(float(np.sum(m.forces**2 / (2 * s_fem))) if m.feasible else np.inf for m in mw)
        qr = min(q_of(w) for w in ws)
        truth, f_req = simulated_success(
            exact,
            ws,
            mu,
            F0,
            stiffness=s_fem,
            safety=config["safety"],
            force_cap=config["force_cap"],
            closing_limit=config["closing_limit_mm"] * 1e-3,
            noise_samples=config["noise_samples"],
            sigma_mu=config["sigma_mu"],
            sigma_force=config["sigma_force"],
            rng=rng,
        )
        row[task] = {
            "truth": truth,
            "q_robust": float(qr),
            "f_sum": float(f_sum),
            "W": float(W),
            "W_fem": float(W_fem),
            "f_required": float(f_req),
            "forces": [m.forces.tolist() for m in mw],  # per pose, per jaw [N] (NaN: unresisted)
        }
    row["seconds"] = time.perf_counter() - t0
    return row


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
        W = np.array([_num(r["lift_and_rotate"]["W"]) for r in sel])
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

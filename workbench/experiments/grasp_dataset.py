"""§4.2.2, Figs 4.8–4.9: a dataset of top grasps, each scored by every contact model.

The thesis samples top grasps of each object with Mahler et al.'s friction-cone sampler, keeps
those that collide with neither the object nor the table (the grasp axis between the jaws'
*bottoms*, Fig 4.8(d)), and scores each with the robust wrench resistance of Eq. 2.101 under
each contact model; Fig 4.9 maps the qualities on "a representative flat object from the EGAD
dataset".  Here the same on the meshes at hand — the 24 bottles and bowls of the thesis's FEM
study standing upright and the five measured hollow objects (each folder skipped when absent) —
and on the flattest of them lying on its broad side (its oriented box's shortest side vertical),
which stands in for the EGAD object.  Each candidate's contact is recomputed from the gripper's
pose (:func:`~workbench.grasp.gripper_eval.gripper_contact`) and shared by the models.

The thesis states no μ, mass, pad size or candidates per object for §4.2: they are this module's
defaults (μ 0.3 and 20 N per jaw as §4.1.3–4.1.4; the 5 mm rubber of §4.1.4.2 on a 20 × 40 mm
pad).  The truth every q is judged by is the models' own resistance question: no trial judges
these grasps (physical-trials and the engine experiments do that).
"""

from __future__ import annotations

import glob
import time
from functools import lru_cache, partial
from pathlib import Path

import numpy as np

from workbench.grasp.dataset_rows import (
    DatasetOptions,
    dataset_cost,
    quality_agreement,
    quality_summary,
    score_candidate,
)
from workbench.grasp.inputs import Task
from workbench.grasp.models import MODELS
from workbench.grasp.rest_pose import flatness, rest_on_table
from workbench.grasp.robust import Perturbation
from workbench.grasp.top_grasps import TopGraspSpec, sample_top_grasps
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_checkpointed
from workbench.runner.results import CHECKOUT, content_hash, write_csv, write_parquet, write_summary
from workbench.sources.gripper import PadShape, parallel_jaw

NAME = "grasp-dataset"

_DATA = CHECKOUT.parent / "shared" / "data"
DEFAULT_CONFIG = {
    "seed": 0,  # the candidates' sampler and each row's perturbations
    # "default": every .obj of thesis_dir and objects_dir (a folder that is absent is skipped);
    # else a glob or a list of .obj paths [m], each resting upright on z = 0 once its lowest
    # point is moved there
    "meshes": "default",
    "thesis_dir": str(_DATA / "thesis_objects"),
    "objects_dir": str(_DATA / "deformable_objects" / "meshes"),
    "n_per_object": 1000,  # top grasps scored per object (the first k of a larger n are the same)
    # the flat object of Figs 4.8-4.9: the flattest mesh lying on its broad side, n candidates
    "n_report_object": 1000,
    # antipodal candidates drawn per object at most, in blocks of 2,000: an object wider than the
    # opening keeps only grasps on its narrow parts (0016: 1,000 top grasps, all on its neck, after
    # 1,018,000 candidates); an object that keeps fewer than n is logged and counted as it is
    "max_candidates": 2_000_000,
    "models": ["soft_point", "planar", "6dls", "6dfc"],
    "mu": 0.3,  # the pads' friction (§4.1.3, the REACH gripper's)
    "sampling_mu": 0.5,  # the sampler's wider cone: "a larger friction coefficient ... preserves more grasps"
    "jaw_force": 20.0,  # N per jaw (§4.1.4.2)
    "pad": [0.02, 0.04],  # m, (width, length along the approach)
    "pad_thickness": 0.005,  # m, the 5 mm rubber of §4.1.4.2
    "pad_modulus": 1.0e6,  # Pa, the rubber's (the thesis states none): Winkler k = modulus / thickness
    "opening": 0.1,  # m, the open gripper's jaw distance
    "max_tilt_deg": 10.0,  # Dex-Net's max_approach_table_angle
    "table_clearance": 0.005,  # m, Dex-Net's table_offset
    "mass_kg": 0.2,  # every object's mass, its centre the filled object's (the thesis states none)
    "robust_samples": 10,  # N_r of Eq. 2.101 (the thesis's example: 10)
    # True: the object free to turn between the pads until their normal forces balance, each pad
    # pressed until it carries its force; False: each pad pressed so at the planned pose, where an
    # off-square grasp meets it along an edge (a strip pressed deep, with a couple no free object
    # holds still under) - one press a pad instead of a search (docs/decisions.md has the cost)
    "settle": True,
    "workers": 0,
    "scheduler": "",
}
KEYS = {
    "meshes": Key('"default", a glob of .obj files, or a list of .obj paths (metres)'),
    "thesis_dir": Key("folder of the thesis's 24 meshes (CC BY-NC 4.0)"),
    "objects_dir": Key("folder of the five measured objects' meshes (CC BY-NC 4.0)"),
    "n_per_object": Key("top grasps scored per object, >= 1"),
    "n_report_object": Key("top grasps scored on the flat report object, >= 2"),
    "max_candidates": Key("antipodal candidates drawn per object at most, >= 2000"),
    "models": Key("contact models scoring each grasp", choices=lambda: MODELS),
    "mu": Key("pad friction coefficient", "", "mu"),
    "sampling_mu": Key("the sampler's friction cone", "", "mu"),
    "jaw_force": Key("closing force per jaw", "N", "jaw_force"),
    "pad": Key("pad (width, length along the approach)", "m", "pad_size"),
    "pad_thickness": Key("pad rubber thickness", "m", "pad_thickness"),
    "pad_modulus": Key("pad rubber modulus", "Pa", "pad_modulus"),
    "opening": Key("the open gripper's jaw distance", "m", "opening"),
    "max_tilt_deg": Key("largest grasp-axis tilt from the table, in [0, 90]", "deg"),
    "table_clearance": Key("how far above the table the jaws stay", "m"),
    "mass_kg": Key("every object's mass", "kg", "mass"),
    "robust_samples": Key("perturbed samples of Eq. 2.101 per grasp (N_r), >= 1"),
    "settle": Key("the object free to turn between the pads (true) or held by the table (false)"),
}
QUICK_CONFIG = {"n_per_object": 3, "n_report_object": 12, "robust_samples": 5}
#: keys that choose which rows a run holds, not what a row is: a run that grows resumes its rows
_SET_KEYS = ("meshes", "thesis_dir", "objects_dir", "n_per_object", "n_report_object", "max_candidates")
_BLOCK = 2000  # antipodal candidates per sampler block
_REPORT = "_lying"  # suffix of the report object's name: the flattest mesh on its broad side


def check_config(config: dict) -> None:
    """The settings, before any work: each key's rule, the counts, the gripper, the meshes."""
    for key, spec in KEYS.items():
        check_key(key, spec, config[key])
    for key, least in (
        ("n_per_object", 1),
        ("n_report_object", 2),
        ("robust_samples", 1),
        ("max_candidates", _BLOCK),
    ):
        v = config[key]
        if isinstance(v, bool) or not isinstance(v, int) or v < least:
            raise ValueError(f"{key} must be an integer >= {least}; got {v!r}")
    pad = config["pad"]
    if not (isinstance(pad, list | tuple) and len(pad) == 2):
        raise ValueError(f"pad must be [width, length] in metres, e.g. [0.02, 0.04]; got {pad!r}")
    if not isinstance(config["settle"], bool):
        raise ValueError(f"settle must be true or false; got {config['settle']!r}")
    if not config["models"] or len(set(config["models"])) != len(config["models"]):
        raise ValueError(f"models must name one or more of {MODELS}, each once; got {config['models']}")
    _gripper(config)
    _spec(config)
    mesh_files(config)
    check_workers(config["workers"], config["scheduler"])


def mesh_files(config: dict) -> dict[str, str]:
    """``{name: path}`` of the run's meshes, sorted by name ("default": both data folders, each
    skipped when absent; a glob that matches nothing and a missing file are refused)."""
    spec = config["meshes"]
    if isinstance(spec, str) and spec.lstrip().startswith("["):  # a list given on the command line
        import json

        try:
            spec = json.loads(spec)
        except json.JSONDecodeError:
            raise ValueError(f"meshes: {spec!r} is neither a glob nor a JSON list of paths") from None
    if spec == "default":
        paths = [
            p for d in (config["thesis_dir"], config["objects_dir"]) for p in sorted(glob.glob(f"{d}/*.obj"))
        ]
        if not paths:
            raise ValueError(
                f"no meshes: neither {config['thesis_dir']} nor {config['objects_dir']} holds .obj files "
                "(the CC BY-NC data beside the checkout); pass --set meshes='DIR/*.obj'"
            )
    elif isinstance(spec, str):
        paths = sorted(glob.glob(spec))
        if not paths:
            raise ValueError(
                f"meshes: the glob {spec!r} matches no file; give a glob of .obj files or a list"
            )
    else:
        paths = [str(p) for p in spec]
        missing = [p for p in paths if not Path(p).is_file()]
        if not paths or missing:
            raise ValueError(
                f"meshes must list existing mesh files; missing: {missing or 'all (empty list)'}"
            )
    return _named(paths)


def _named(paths: list[str]) -> dict[str, str]:
    """``{name: path}`` sorted by name, each object named by its file's stem: refused when a path
    is not an .obj file, is listed twice, or two files share a stem."""
    folders = [p for p in paths if Path(p).is_dir()]
    if folders:
        raise ValueError(f"meshes: {folders[0]} is not a file; give .obj files (a glob such as DIR/*.obj)")
    not_obj = [p for p in paths if Path(p).suffix.lower() != ".obj"]
    if not_obj:
        raise ValueError(
            f"meshes must be .obj files (Wavefront); got {not_obj}: convert them, e.g. with trimesh"
        )
    twice = sorted({p for p in paths if paths.count(p) > 1})
    if twice:
        raise ValueError(f"meshes lists {twice} more than once; list each file once")
    names: dict[str, list[str]] = {}
    for p in paths:
        names.setdefault(Path(p).stem, []).append(p)
    shared = {n: ps for n, ps in names.items() if len(ps) > 1}
    if shared:
        raise ValueError(
            f"meshes: files share a name (the object's name in the table): {shared}; "
            "give each object a distinct file name"
        )
    return dict(sorted((n, ps[0]) for n, ps in names.items()))


def _gripper(config: dict):
    w, length = config["pad"]
    pad = PadShape.rectangle(w, length, thickness=config["pad_thickness"], modulus=config["pad_modulus"])
    return parallel_jaw(
        pad, config["jaw_force"], opening=config["opening"], mu=config["mu"], name="top_grasp_jaws"
    )


def _spec(config: dict, axis_at: str = "jaw_bottom") -> TopGraspSpec:
    return TopGraspSpec(
        axis_at=axis_at, max_tilt_deg=config["max_tilt_deg"], table_clearance=config["table_clearance"]
    )


@lru_cache(maxsize=4)
def _rested(path: str, lying: bool):
    """The mesh at ``path`` resting on the table (:func:`~workbench.grasp.rest_pose.rest_on_table`),
    read once per process (driver and each worker) for the last few meshes."""
    import trimesh

    return rest_on_table(trimesh.load(path, force="mesh"), lying)


def _row_task(job: tuple, config: dict) -> dict:
    """One candidate's row (driver or Dask worker): ``(object, path, lying, k, p1, p2, pose, com)``."""
    name, path, lying, k, p1, p2, pose, com = job
    mesh, _ = _rested(path, lying)
    opts = DatasetOptions(
        mu=config["mu"],
        robust=Perturbation(n_samples=config["robust_samples"]),
        settle=config["settle"],
        seed=config["seed"],
    )
    row = score_candidate(
        mesh,
        _gripper(config),
        np.asarray(pose),
        Task(mass=config["mass_kg"], com=tuple(com)),
        config["models"],
        opts,
    )
    return {"object": name, "candidate": k, "p1": list(p1), "p2": list(p2), **row}


def _key(job: tuple) -> str:
    return f"{job[0]}/{job[3]:06d}/{content_hash([job[4], job[5]], 10)}"


#: the remedy of a mesh file in another unit: the driver reads files, it has no units key
_FILE_UNIT_FIX = (
    "re-export the file in metres (scale it by {factor:g}, e.g. with trimesh: "
    "m = trimesh.load(path); m.apply_scale({factor:g}); m.export(path))"
)


def _mesh_of(name: str, path: str):
    """The object lying on the table, or a refusal that names its file (a mesh in millimetres or
    centimetres, an open or empty mesh, a folder): the file's own mesh is judged, before it is
    rested, with the remedy a user of the command line has (re-export the file in metres)."""
    import trimesh

    from workbench.units import closed_mesh

    if not Path(path).is_file():
        raise ValueError(f"meshes: {path} is not a file; give .obj files (a glob such as DIR/*.obj)")
    what = f"{name} ({path})"
    try:
        closed_mesh(trimesh.load(path, force="mesh"), what, fix=_FILE_UNIT_FIX, override=None)
        mesh = _rested(path, True)[0]
    except (ValueError, IndexError, AttributeError) as e:
        msg = str(e)
        raise ValueError(msg if msg.startswith(what) else f"{what}: {msg}") from None
    return mesh


def _objects(config: dict, files: dict[str, str]) -> tuple[list[tuple], dict, str]:
    """The candidates (jobs), per-object counts and the report object's name."""
    from workbench.grasp.robust import check_object_mass

    gripper, spec = _gripper(config), _spec(config)
    flat = {}
    for name, p in files.items():
        mesh = _mesh_of(name, p)
        try:  # the one mass against each object's volume: a density no object has is refused
            check_object_mass(config["mass_kg"], mesh)
        except ValueError as e:
            raise ValueError(f"mass_kg {config['mass_kg']} on {name} ({p}): {e}") from None
        flat[name] = flatness(mesh)
    report = min(flat, key=flat.get)
    # the report object first: without two top grasps there is no Fig 4.9, say so before the rest
    plan = [(report + _REPORT, files[report], True, config["n_report_object"])]
    plan += [(n, p, False, config["n_per_object"]) for n, p in files.items()]
    jobs, counts = [], {}
    for name, path, lying, n in plan:
        mesh, _ = _rested(path, lying)
        com = mesh.convex_hull.center_mass  # the filled object's centre
        top = sample_top_grasps(
            mesh,
            n,
            config["sampling_mu"],
            gripper,
            spec,
            seed=config["seed"],
            block=_BLOCK,
            max_blocks=-(-config["max_candidates"] // _BLOCK),
        )
        if lying and len(top) < 2:
            raise ValueError(
                f"the flattest object, {name}, has {len(top)} top grasp(s) in {top.n_candidates} candidates "
                f"(dropped: {top.dropped}): Fig 4.9 needs two; check the gripper's opening "
                f"({config['opening']} m) against the object, or leave the object out of meshes"
            )
        counts[name] = {
            "candidates": top.n_candidates,
            "kept": len(top),
            "dropped": top.dropped,
            "flatness": flatness(mesh),
        }
        for k, (g, pose) in enumerate(top):
            jobs.append(
                (name, path, lying, k, g["p1"].tolist(), g["p2"].tolist(), pose.tolist(), com.tolist())
            )
    return jobs, counts, report + _REPORT


def _fig_4_8(config: dict, path: str) -> dict:
    """The report object's kept grasps under both axis definitions, from the first block of
    candidates, the block its rows start from (the counts are the result: a block keeps fewer
    than it draws, by design)."""
    import logging

    from workbench.grasp import top_grasps as _top
    from workbench.quiet_log import quieted

    mesh, _ = _rested(path, True)
    out = {}
    for axis_at in ("jaw_bottom", "centre"):
        with quieted(logging.getLogger(_top.__name__)):
            top = sample_top_grasps(
                mesh,
                _BLOCK,
                config["sampling_mu"],
                _gripper(config),
                _spec(config, axis_at),
                seed=config["seed"],
                block=_BLOCK,
                max_blocks=1,
            )
        out[axis_at] = {"candidates": top.n_candidates, "kept": len(top), **top.dropped}
    return out


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    files = mesh_files(config)
    jobs, counts, report = _objects(config, files)
    key_config = {k: v for k, v in config.items() if k not in _SET_KEYS}
    ckpt, n_resumed, ran_on = run_checkpointed(
        partial(_row_task, config=config),
        jobs,
        _key,
        out,
        key_config,
        desc=NAME,
        unit="grasp",
        code=_row_code(),
    )
    rows = [ckpt.rows[_key(j)] for j in jobs]
    table = write_parquet(out / "table.parquet", rows)
    models = config["models"]
    write_csv(
        out / "objects.csv",
        ["object", "flatness", "candidates", "kept", *sorted(counts[report]["dropped"])],
        [
            [n, c["flatness"], c["candidates"], c["kept"], *(c["dropped"][k] for k in sorted(c["dropped"]))]
            for n, c in counts.items()
        ],
    )
    fig48 = _fig_4_8(config, files[report.removesuffix(_REPORT)])
    rep = [r for r in rows if r["object"] == report]
    fig49 = _fig_4_9(rep, models)
    scored = [r for r in rows if r["status"] == "scored"]
    ms = {m: float(np.median([r[f"t_{m}_build_ms"] + r[f"t_{m}_q_ms"] for r in scored])) for m in models}
    total = np.array([_row_ms(r, models) for r in scored])
    all_ms = float(np.median(total))
    cost = dataset_cost(float(total.mean()), 500_000)
    report_mesh, _ = _rested(files[report.removesuffix(_REPORT)], True)
    figures = [str(p) for p in _figures(config, rep, report, report_mesh, out)]
    summary = {
        "n_objects": len(files),
        "report_object": {"name": report, "flatness": counts[report]["flatness"]},
        "counts": counts,
        "n_rows": len(rows),
        "n_scored": sum(r["status"] == "scored" for r in rows),
        "fig_4_8": fig48,
        "fig_4_9": fig49,
        "throughput": {
            "contact_ms_median": float(np.median([r["t_contact_ms"] for r in scored])),
            "model_ms_median": ms,
            "all_models_ms": all_ms,
            "all_models_ms_mean": float(total.mean()),
            "grasps_per_s_per_core": 1e3 / all_ms,
            "rows_ran_on": ran_on,
        },
        # a dataset's total scales with the mean time a row takes, not the median
        "cost_500k": cost,
        "n_resumed": n_resumed,
        "table": str(table),
        "figures": figures,
        "headline": _headline(fig48, fig49, models, float(total.mean()), len(rows), cost["core_hours"]),
    }
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


def _row_ms(row: dict, models) -> float:
    """What one scored row took [ms]: its contact and every model's build and q."""
    return row["t_contact_ms"] + sum(row[f"t_{m}_build_ms"] + row[f"t_{m}_q_ms"] for m in models)


def _row_code() -> str:
    from workbench.code_key import code_digest, normalized_function

    return content_hash(
        [
            code_digest(
                "workbench.grasp.dataset_rows", "workbench.grasp.top_grasps", "workbench.grasp.rest_pose"
            ),
            normalized_function(_row_task),
            normalized_function(_rested),
        ]
    )


def _fig_4_9(rows: list[dict], models) -> dict:
    """Per model on the report object :func:`~workbench.grasp.dataset_rows.quality_summary`; 6DLS
    against 6DFC :func:`~workbench.grasp.dataset_rows.quality_agreement`."""
    q = {m: [r[f"q_{m}"] for r in rows] for m in models}
    out = {m: quality_summary(q[m], [r["candidate"] for r in rows]) for m in models}
    if {"6dls", "6dfc"} <= set(models):
        rho, dq = quality_agreement(q["6dls"], q["6dfc"])
        out |= {"spearman_6dls_6dfc": rho, "median_abs_dq_6dls_6dfc": dq}
    return out


def _headline(fig48: dict, fig49: dict, models, mean_ms: float, n_rows: int, core_hours: float) -> list[str]:
    return [
        f"Fig 4.8: {fig48['jaw_bottom']['kept']} top grasps kept with the jaw-bottom axis, "
        f"{fig48['centre']['kept']} with the centre axis, of {fig48['jaw_bottom']['candidates']} candidates",
        "Fig 4.9: max q " + ", ".join(f"{m} {fig49[m]['max_q']:.2f}" for m in models),
        f"{n_rows} grasps, {mean_ms:.0f} ms a grasp (mean) for every model on one core "
        f"(500K grasps: {core_hours:.0f} core-hours)",
    ]


def _figures(config: dict, rows: list[dict], report: str, mesh, out: Path) -> list[Path]:
    """Fig 4.9(a-d) on the report object: its outline from above and each grasp's axis coloured by
    its q (the higher drawn on top), the best grasp thick, one panel per model; ``mesh``: the
    report object as it lies."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    from workbench.runner.results import save_figure

    models = config["models"]
    ncol = min(2, len(models))
    nrow = -(-len(models) // ncol)
    fig, axes = plt.subplots(
        nrow, ncol, figsize=(5.0 * ncol, 2.8 * nrow + 0.8), squeeze=False, constrained_layout=True
    )
    seg = np.array([[r["p1"][:2], r["p2"][:2]] for r in rows]) * 1e3
    norm = plt.Normalize(0, 1)
    for ax, m in zip(axes.ravel(), models, strict=False):
        q = np.array([r[f"q_{m}"] for r in rows])
        order = np.argsort(q, kind="stable")
        ax.plot(mesh.vertices[:, 0] * 1e3, mesh.vertices[:, 1] * 1e3, ",", color="0.75")
        lc = LineCollection(seg[order], cmap="RdYlGn", norm=norm, linewidths=1.0)
        lc.set_array(q[order])
        ax.add_collection(lc)
        best = order[-1]
        if q[best] > 0:  # a best grasp only where some grasp holds
            ax.plot(*seg[best].T, color=plt.cm.RdYlGn(norm(q[best])), lw=3.5, solid_capstyle="round")
        ax.set_aspect("equal")
        ax.set_title(f"{m}: max q {q.max():.2f}, q ≥ 0.5 on {np.mean(q >= 0.5):.0%}", fontsize=8)
        ax.set_xlabel("x [mm]", fontsize=7)
        ax.set_ylabel("y [mm]", fontsize=7)
        ax.tick_params(labelsize=7)
    for ax in axes.ravel()[len(models) :]:
        ax.axis("off")
    fig.colorbar(lc, ax=axes.ravel().tolist(), shrink=0.8, label="q (Eq. 2.101)")
    title = f"Fig 4.9 on {report}: {len(rows)} top grasps from above, coloured by q; thick: the best"
    fig.suptitle(title, fontsize=9)
    return [save_figure(fig, out / "fig_4_9_quality_map.png"), _best_figure(config, mesh, rows, report, out)]


def _best_figure(config: dict, mesh, rows: list[dict], report: str, out: Path) -> Path:
    """Fig 4.9(e-h): each model's best grasp on the report object, its contact recomputed from the
    row's grasp points as the row computed it."""
    from workbench.grasp.gripper_eval import gripper_contact
    from workbench.grasp.top_grasps import top_grasp_pose
    from workbench.runner.grasp_figures import best_grasps_figure

    gripper, best = _gripper(config), {}
    for m in config["models"]:
        r = max(rows, key=lambda r, m=m: r[f"q_{m}"])
        pose = top_grasp_pose(np.asarray(r["p1"]), np.asarray(r["p2"]), gripper, _spec(config).axis_at)
        best[m] = (gripper_contact(mesh, gripper, pose, settle=config["settle"]), r[f"q_{m}"])
    title = f"Fig 4.9(e-h) on {report}: each model's best grasp"
    return best_grasps_figure(mesh, best, out / "fig_4_9_best_grasps.png", title=title)

"""Table 3.3: ellipsoid and quartic 6DLS fitted to FEM contact profiles of the thesis's objects.

Thesis §3.5.2.  A parallel-jaw pad (5 mm silicone on a rigid 20 × 40 mm jaw,
long side vertical) squeezes each object of ``object_sets`` — the thesis's own 24 meshes
(``thesis_meshes``: Fig 3.11(b), read from ``objects_dir``, :class:`workbench.fem.mesh_object.MeshObject`)
and our parametric family of 24 bottles (``bottle_family``: :func:`workbench.fem.bottle.bottle_family`,
8 asymmetric) — at its set's grasp heights (``heights``; the family's ``family_heights``, or
``heights`` when the meshes are absent and the family stands in for them), from two approach directions
(along the cross-section's major and minor axis), with three jaw displacements
after first touch.  Each contact is solved by the condensed linear pad
(``fidelity="condensed"``; frictionless, rigid object), the contact profile is
extracted on the bottle surface, and both 6DLS models are fitted and scored
under two protocols (the fitters are the same; only the wrenches differ):

* "thesis-text" (``ellipsoid_sdp_error_mean`` …): 600 frictional wrenches of the
  sampler the thesis describes (§3.3.2), Eq. 3.18 on ``n_heldout`` held-out
  wrenches of the same sampler (and on the training ones, ``train_error``);
* "thesis-code" (``thesis_protocol_error``): the author's code — the twist grid
  of ``fine_level`` (48 483 twists), trained on one wrench per occupied cell of a
  coarse wrench grid (a few hundred), Eq. 3.18 on all 48 483
  (:mod:`workbench.limit_surface.thesis_code`).

The error to compare across protocols is the sampler-independent one
(``support_error``: radial distance at exact surface points of uniform normals,
:mod:`workbench.limit_surface.support_error`).  The models are named as in
:mod:`workbench.limit_surface.fit_score`: Table 3.3's "ellipsoid" is ``ellipsoid_sdp``
(the PSD-constrained least-squares fit), its "quartic" ``quartic_values`` (Eq. 3.17 on
the values alone), as the thesis writes both; ``ellipsoid_lsq`` is reported beside them.

The author's grid is axis-aligned, so the thesis-code protocol depends on the frame
the contact is written in; it uses the author's, the object frame (z = the bottle's
axis, ``code_frame``).  On every ``ablation_every``-th profile the protocol is
repeated with one thing changed (``protocol_ablation``): the jaw frame (z = the
grasp axis), the code's bounding box that contains the object origin
(``convertelementinfo.m`` zero-fills its node array — a quirk, not adopted), 3 mm
elements (the thesis's element size, :func:`workbench.coarsen.coarsen_profile`), and
the author's fitting objective (L1 values, twist directions, ``‖A‖``;
:mod:`workbench.limit_surface.author_objective`).

The sweep checkpoints every profile (``rows.jsonl``), so a killed run resumes
where it stopped and a finished one re-solves nothing.  The summary's top-level Table 3.3 is
the first set of ``object_sets`` that ran (``headline_object_set``); ``object_sets`` holds each
set's own, side by side.
"""

from __future__ import annotations

import logging
import time
from functools import lru_cache, partial
from itertools import product
from pathlib import Path

import numpy as np
from tqdm import tqdm

from workbench import config as cfg
from workbench.code_key import code_digest
from workbench.fem.bottle import Bottle, BottleParams, bottle_family, grasp_pose
from workbench.fem.contact import solve_contact
from workbench.fem.extract import extract_profile
from workbench.fem.material import Material
from workbench.fem.mesh_object import MeshObject
from workbench.fem.pad import PadGeometry, condense_pad
from workbench.fem.validation import condensed_vs_full
from workbench.limit_surface.profile_fits import (
    ABLATION_VARIANTS,
    FAMILY,
    MODELS,
    TABLE_MODELS,
    ProfileFitSettings,
    ablation_due,
    profile_fit_row,
)
from workbench.limit_surface.thesis_code import check_protocol_config
from workbench.runner.experiment_keys import Key, check_key
from workbench.runner.parallel import check_workers, run_rows
from workbench.runner.results import CHECKOUT, Checkpoint, save_figure, write_csv, write_summary
from workbench.twists_author import AUTHOR_LEVELS
from workbench.wrench import check_mu

NAME = "fem-fitting"
log = logging.getLogger(__name__)

# the fits of every profile (MODELS), Table 3.3's two (TABLE_MODELS, FAMILY: the thesis's name of
# each) and the protocol ablation's variants: workbench.limit_surface.profile_fits
THESIS_TABLE_3_3 = {"quartic": (0.011, 0.006), "ellipsoid": (0.019, 0.005), "n_profiles": 2932}

#: the object sets fem-fitting can press, in the order a run lists them
OBJECT_SETS = ("thesis_meshes", "bottle_family")

DEFAULT_CONFIG = {
    "seed": 0,
    # the thesis's 24 meshes (when objects_dir holds them), then our parametric family beside them
    "object_sets": ["thesis_meshes", "bottle_family"],
    "objects_dir": str(CHECKOUT.parent / "shared" / "data" / "thesis_objects"),
    "objects_glob": "*.obj",  # which meshes of objects_dir
    "n_objects": 24,
    "n_asymmetric": 8,
    # grasp heights as fractions of the object's height: the thesis's 2,932 contacts are 24 objects
    # x 2 approaches x 3 displacements x ~20 heights "spread vertically" (§3.5.2); 21 heights
    # from 0.25 to 0.75 give 3,024
    "heights": [round(0.25 + 0.025 * i, 3) for i in range(21)],
    # the family's heights beside the meshes (7: 1,008 profiles, for make reproduce's budget);
    # it takes `heights` when it runs alone or the meshes are absent
    "family_heights": [0.25, 0.333, 0.417, 0.5, 0.583, 0.667, 0.75],
    "approaches": {"major": 0.0, "minor": float(np.pi / 2)},  # angle from the section's major axis
    "deltas_mm": [1.0, 2.0, 3.0],  # jaw displacement after first touch (§3.5.2: 1-3 mm)
    "pad": {"width": 0.02, "length": 0.04, "thickness": 0.005, "nx": 20, "ny": 40, "nz": 5},
    "E": 1.0e6,  # silicone [Pa]; profiles are normalised, so E only scales the force
    "nu": 0.45,  # as the linear-vs-nonlinear table of fem-validation
    "mu": 1.0,  # normalised wrenches do not depend on mu
    "n_wrenches": 600,  # thesis: 600 per profile
    "n_heldout": 2000,
    "pitch_range": [-1.0, 1.0],  # thesis-text sampler: h ~ U[lo, hi]·l_s (config.py Defaults.pitch_range)
    "thesis_code": True,  # also the thesis-code protocol (the author's twist grid, downsampled training)
    "fine_level": 0,  # its twist grid (0: the FEM study's, 48,483 twists)
    "downsample_steps": 2.5,  # its training grid: cells per wrench range
    "support_directions": 2000,  # sampler-independent error: uniform normals per profile
    "code_frame": "object",  # frame of the author's axis-aligned grid: "object" (theirs) or "jaw"
    "ablation_every": 16,  # protocol ablation on every n-th profile (0: none)
    "ablation_cell_mm": 3.0,  # element size of the coarsened variant (the thesis's 3 mm)
    "reference_cases": 3,  # bottle contacts also solved on the full mesh (condensed vs reference)
    "reference_delta_mm": 2.0,
    "render_examples": 4,
    # where the profiles run (workbench.runner.parallel.row_client): 0 = a local Dask cluster of one
    # worker per core when there are many profiles, 1 = serially here, N = N local workers;
    # scheduler = an existing cluster's address.  Neither changes a number of the results.
    "workers": 0,
    "scheduler": "",
}
_PAD_M = {"width": ("pad_size", 1.0), "length": ("pad_size", 1.0), "thickness": ("pad_thickness", 1.0)}
#: what each key means, its unit and plausible range (``workbench run fem-fitting --help``)
KEYS = {
    "object_sets": Key("object sets to press, in order (the first that runs heads the summary)"),
    "objects_dir": Key("folder of the thesis's meshes (OBJ, metres); absent: that set is skipped"),
    "objects_glob": Key("which meshes of objects_dir (a glob, e.g. '000[1-8]*.obj')"),
    "family_heights": Key("the family's grasp heights beside the meshes, fractions in (0, 1)"),
    "n_objects": Key("bottles of the family (thesis: 24)"),
    "n_asymmetric": Key("asymmetric bottles among them (thesis: 8)"),
    "heights": Key("grasp heights as fractions of the bottle height, in (0, 1)"),
    "approaches": Key("approach name -> grasp-axis angle from the section's major axis", "rad"),
    "deltas_mm": Key(
        "jaw displacements after first touch, each below the pad thickness", "mm", "compression", 1e-3
    ),
    "pad": Key("silicone pad: width, length, thickness [m] and hexes nx, ny, nz", "m", fields=_PAD_M),
    "E": Key("pad Young's modulus (profiles are normalised: E only scales the force)", "Pa", "pad_modulus"),
    "nu": Key("pad Poisson ratio", "", "poisson"),
    "mu": Key("friction coefficient, > 0 (normalised wrenches do not depend on it)", "", "mu"),
    "n_wrenches": Key("thesis-text wrenches per profile, >= 126 (the quartic's unknowns; thesis: 600)"),
    "n_heldout": Key("held-out wrenches per profile for Eq. 3.18, >= 1"),
    "pitch_range": Key("thesis-text sampler: pitch h ~ U[lo, hi] x the length scale l_s"),
    "thesis_code": Key("also run the thesis-code protocol (the author's twist grid, downsampled training)"),
    "fine_level": Key(
        "the author's twist grid fineLevel (0: 48,483 twists)", choices=lambda: sorted(AUTHOR_LEVELS)
    ),
    "downsample_steps": Key("thesis-code training grid: cell widths per wrench range, >= 2 (author: 2.5)"),
    "support_directions": Key("uniform normals per profile for the sampler-independent error"),
    "code_frame": Key("frame of the author's axis-aligned grid", choices=("object", "jaw")),
    "ablation_every": Key("protocol ablation on every n-th profile (0: none)"),
    "ablation_cell_mm": Key(
        "element size of the coarsened ablation variant, in [0.1, 100] (thesis: 3)", "mm"
    ),
    "reference_cases": Key("bottle contacts also solved on the full mesh (condensed vs reference)"),
    "reference_delta_mm": Key("jaw displacement of those reference contacts", "mm", "compression", 1e-3),
    "render_examples": Key("profiles rendered as figures"),
}


def check_config(config: dict) -> None:
    """Refuse settings the defaults cannot judge, before any work (build_config calls it)."""
    check_protocol_config(config)
    check_workers(config["workers"], config["scheduler"])
    for key, spec in KEYS.items():  # E, ν, μ, the pad's sizes, the words (also for run(config))
        check_key(key, spec, config[key])
    check_mu(config["mu"], what="limit surface")  # and not 0 (the Key's range takes it)
    geom = PadGeometry(**config["pad"])
    for key in ("heights", "family_heights"):
        if not config[key] or not all(0 < h < 1 for h in config[key]):
            raise ValueError(f"{key} are fractions of the object's height in (0, 1); got {config[key]}")
    sets = config["object_sets"]
    if not sets or len(set(sets)) != len(sets) or not set(sets) <= set(OBJECT_SETS):
        raise ValueError(f"object_sets must be distinct names of {list(OBJECT_SETS)}; got {sets!r}")
    if not all(0 < d < geom.thickness * 1e3 for d in config["deltas_mm"]):
        raise ValueError(
            f"deltas_mm are jaw displacements after first touch in (0, {geom.thickness * 1e3:g}) mm "
            f"(the pad's thickness); got {config['deltas_mm']}"
        )
    if not (isinstance(config["ablation_every"], int) and config["ablation_every"] >= 0):
        raise ValueError(
            f"ablation_every must be an integer >= 0 (0: no ablation); got {config['ablation_every']!r}"
        )
    ProfileFitSettings.from_config(config)  # the fits' own rules: n_wrenches, ablation_cell_mm, ...


QUICK_CONFIG = {
    "objects_glob": "0006*.obj",
    "n_objects": 2,
    "n_asymmetric": 1,
    "heights": [0.5],
    "family_heights": [0.5],
    "reference_cases": 1,
    "render_examples": 2,
}


def _profile_key(label: str, h: float, approach: str, delta_mm: float) -> str:
    return f"{label}/h{h:.3f}/{approach}/d{delta_mm:.2f}"


@lru_cache(maxsize=2)
def _family(n_objects: int, n_asymmetric: int, seed: int) -> tuple[list[BottleParams], list[Bottle]]:
    """The bottle family, built once per process (driver and each worker)."""
    params = bottle_family(n_objects, n_asymmetric, seed)
    return params, [Bottle(p) for p in params]


@lru_cache(maxsize=2)
def _mesh_objects(objects_dir: str, glob: str) -> tuple[MeshObject, ...]:
    """The meshes of ``objects_dir`` matching ``glob``, sorted by name, read once per process
    (none when the folder is absent)."""
    folder = Path(objects_dir)
    return tuple(MeshObject(f) for f in sorted(folder.glob(glob))) if folder.is_dir() else ()


def _objects(config: dict) -> list[tuple[str, str, object]]:
    """``(set, label, object)`` of every object the run presses, set by set in ``object_sets``
    order (a set with no object, e.g. meshes absent, contributes none: :func:`_skipped`)."""
    out: list[tuple[str, str, object]] = []
    for name in config["object_sets"]:
        if name == "bottle_family":
            _, bottles = _family(config["n_objects"], config["n_asymmetric"], config["seed"])
            out += [(name, f"bottle{i:02d}", b) for i, b in enumerate(bottles)]
        else:
            out += [
                (name, f"mesh-{m.name}", m)
                for m in _mesh_objects(config["objects_dir"], config["objects_glob"])
            ]
    return out


def _skipped(config: dict) -> dict[str, str]:
    """The sets of ``object_sets`` that have no object here, and why."""
    if "thesis_meshes" in config["object_sets"] and not _mesh_objects(
        config["objects_dir"], config["objects_glob"]
    ):
        return {"thesis_meshes": f"no {config['objects_glob']} in {config['objects_dir']}"}
    return {}


def _heights(set_name: str, config: dict) -> list[float]:
    """A set's grasp heights: ``family_heights`` for the family beside the meshes, else ``heights``."""
    beside = "thesis_meshes" in config["object_sets"] and not _skipped(config)
    return config["family_heights"] if set_name == "bottle_family" and beside else config["heights"]


def run_plan(config: dict) -> dict:
    """What a run of ``config`` would press, without pressing: the sets skipped (and why), the
    objects and heights of each set that runs, and the profiles per set and in all (grasps ×
    jaw displacements; empty contacts, if any, are counted here)."""
    skipped = _skipped(config)
    objects = _objects(config)
    sets = [n for n in config["object_sets"] if n not in skipped]
    n_obj = {n: sum(o[0] == n for o in objects) for n in sets}
    per = {
        n: n_obj[n] * len(_heights(n, config)) * len(config["approaches"]) * len(config["deltas_mm"])
        for n in sets
    }
    return {
        "skipped": skipped,
        "n_objects": n_obj,
        "heights": {n: _heights(n, config) for n in sets},
        "n_profiles_per_set": per,
        "n_profiles": sum(per.values()),
    }


def _at(obj, hf: float) -> float:
    """The absolute height [m] of fraction ``hf`` of an object's height (a mesh's base may not
    be at z = 0)."""
    return getattr(obj, "z0", 0.0) + hf * obj.params.height


@lru_cache(maxsize=2)
def _pad(pad: tuple, E: float, nu: float):
    """The condensed pad from its content-hash disk cache in the user cache directory
    (``workbench.fem.pad.pad_cache_dir``: shared by every run, sweep point and worker on a machine; the
    driver builds it first), kept per process: a worker loads it once for all its tasks."""
    return condense_pad(PadGeometry(**dict(pad)), Material(E, nu))


def _pad_of(config: dict):
    return _pad(tuple(sorted(config["pad"].items())), config["E"], config["nu"])


def _ablated(j: int, k: int, config: dict) -> bool:
    """Whether profile ``k`` (jaw displacement index) of grasp ``j`` gets the protocol
    ablation: every ``ablation_every``-th profile in grasp order (none when 0)."""
    return ablation_due(j * len(config["deltas_mm"]) + k, config["ablation_every"])


def _job_rows(job: tuple, config: dict) -> list[tuple[str, dict]]:
    """The rows of one grasp (bottle ``i``, height fraction, approach) at its jaw displacements
    ``todo`` (indices into ``deltas_mm``).  Each displacement ``k`` is solved as the whole sweep
    solves it: displacements 0..k in order, each warm-started from the one before (a few ms
    each), so a row is the same whether its task holds one profile or the grasp's all, and
    whether the run was resumed.  Runs in the driver or in a Dask worker; returns (key, row)."""
    j, i, hf, name, ang, todo = job
    set_name, label, b = _objects(config)[i]
    pad = _pad_of(config)
    pose = grasp_pose(b, _at(b, hf), ang, pad.face_xy, pad.geometry.thickness)
    out, prev = [], None
    for k in range(max(todo) + 1):
        dmm = config["deltas_mm"][k]
        t0 = time.perf_counter()
        try:
            sol = solve_contact(pad, pose, dmm * 1e-3, warm=prev)
        except ValueError as exc:
            # the object reaches deeper into the pad than its layer: the jaw would hit it (e.g.
            # the pad reaching below a short object's base); this and the deeper presses of the
            # grasp are recorded as unsolved, with why, and left out of the table
            log.warning("%s h=%.3f %s: %s", label, hf, name, exc)
            base = {"object_set": set_name, "object": label, "height_frac": hf, "approach": name}
            out += [
                (
                    _profile_key(label, hf, name, config["deltas_mm"][m]),
                    {**base, "delta_mm": config["deltas_mm"][m], "empty": False, "unsolved": str(exc)},
                )
                for m in todo
                if m >= k
            ]
            break
        t1 = time.perf_counter()
        prev = sol
        if k not in todo:
            continue
        prof = extract_profile(pad, sol, pose)
        t2 = time.perf_counter()
        row = {
            "object_set": set_name,
            "object": label,
            "asymmetric": b.params.asymmetric,
            "height_frac": hf,
            "approach": name,
            "delta_mm": dmm,
            "solve_ms": (t1 - t0) * 1e3,
            "extract_ms": (t2 - t1) * 1e3,
            "profile_ms": (t2 - t0) * 1e3,
            "force_N": sol.force,
            "lcp_iterations": sol.iterations,
            "max_penetration_m": sol.max_penetration,
            "empty": prof is None,
        }
        if prof is not None:
            row.update(
                n_elements=len(prof),
                area_mm2=float(prof.areas.sum() * 1e6),
                peak_pressure_kPa=float(prof.pressures.max() / 1e3),
                **profile_fit_row(
                    prof,
                    ProfileFitSettings.from_config(config),
                    config["seed"] + 1000 * j + k,
                    to_object=(pose.R, pose.t),
                    ablate=_ablated(j, k, config),
                ),
            )
        out.append((_profile_key(label, hf, name, dmm), row))
    return out


def reference_cases(config: dict) -> list[tuple[str, object]]:
    """(label, pose) of the contacts also solved on the full mesh (condensed vs reference),
    tasks of the run (:func:`run_task`): ``reference_cases`` bottles at mid-height,
    alternating ends of the family and approaches, and an elliptic cylinder (the family's
    degenerate member: constant section, no twist or lean).  Builds (or loads) the pad."""
    _, bottles = _family(config["n_objects"], config["n_asymmetric"], config["seed"])
    pad = _pad_of(config)
    h = pad.geometry.thickness
    cases = []
    for i in range(min(config["reference_cases"], len(bottles))):
        b = bottles[-1 - i] if i % 2 else bottles[i]
        name, ang = list(config["approaches"].items())[i % len(config["approaches"])]
        cases.append(
            (f"bottle {bottles.index(b)} {name}", grasp_pose(b, 0.5 * b.params.height, ang, pad.face_xy, h))
        )
    ell = Bottle(BottleParams(height=0.2, a0=0.04, aspect0=0.6, aspect1=0.6))
    cases.append(
        ("elliptic cylinder 40 x 24 mm, minor axis", grasp_pose(ell, 0.1, np.pi / 2, pad.face_xy, h))
    )
    return cases


def run_task(task: tuple, config: dict):
    """One task of a run, in the driver or a Dask worker: ``("rows", job)`` — a grasp's
    profile rows (:func:`_job_rows`; ``job`` as in :func:`row_tasks`) — or
    ``("reference", label, pose)`` — one condensed-vs-full-mesh check
    (:func:`reference_cases`; seconds each, so they run beside the rows)."""
    if task[0] == "reference":
        _, label, pose = task
        return condensed_vs_full(_pad_of(config), pose, config["reference_delta_mm"] * 1e-3, label)
    return _job_rows(task[1], config)


def _examples(jobs: list[tuple], objects: list[tuple], pad, config: dict) -> dict:
    """The profiles rendered as examples: the first grasp, then asymmetric objects' grasps, at the
    third jaw displacement (solved again here: cheap, and present after a resume too);
    ``objects`` as :func:`_objects`."""
    chosen: dict = {}
    if len(config["deltas_mm"]) < 3:
        return chosen
    for _j, i, hf, name, ang in jobs:
        if len(chosen) >= config["render_examples"]:
            break
        b = objects[i][2]
        if (i, name) in chosen or not (b.params.asymmetric or not chosen):
            continue
        pose = grasp_pose(b, _at(b, hf), ang, pad.face_xy, pad.geometry.thickness)
        prev = None
        try:
            for d in config["deltas_mm"][:3]:
                prev = solve_contact(pad, pose, d * 1e-3, warm=prev)
        except ValueError:  # an unsolved press (the rows record why): not an example
            continue
        prof = extract_profile(pad, prev, pose)
        if prof is not None:
            dmm = config["deltas_mm"][2]
            chosen[(i, name)] = (prof, f"{objects[i][1]} {name}, jaw displacement {dmm:g} mm")
    return chosen


def _ablation_summary(rows: list[dict]) -> dict | None:
    """Per variant and model of :data:`TABLE_MODELS`: the variant's mean Eq. 3.18 error
    beside the thesis-code row's on the same profiles (paired), and their ratio."""
    sub = [r for r in rows if "abl_jaw_frame_ellipsoid_sdp" in r]
    if not sub:
        return None
    out = {"n_profiles": len(sub), "variants": ABLATION_VARIANTS}
    for name in ABLATION_VARIANTS:
        out[name] = {}
        for m in TABLE_MODELS:
            pair = [
                (r[f"abl_{name}_{m}"], r[f"{m}_code_error"])
                for r in sub
                if r.get(f"abl_{name}_{m}") is not None and r.get(f"{m}_code_error") is not None
            ]
            if pair:
                v, base = np.array(pair).T
                out[name][m] = {
                    "mean": float(v.mean()),
                    "std": float(v.std()),
                    "protocol_mean": float(base.mean()),
                    "ratio": float(v.mean() / base.mean()),
                    "n_profiles": len(pair),
                }
        out[name]["n_train"] = _stats([r[f"abl_{name}_n_train"] for r in sub])
    return out


def _column(rows: list[dict], key: str) -> np.ndarray:
    """(n,) values of ``key`` over the rows that have it."""
    return np.array([r[key] for r in rows if r.get(key) is not None], float)


def _stats(values: list) -> dict:
    v = np.asarray(values, float)
    return {"mean": float(v.mean()), "min": float(v.min()), "max": float(v.max())}


def _renders(examples: dict, objects: list[tuple], markers: dict, out: Path) -> list[str]:
    """The example profiles with their friction arrows and each object set with its grasp points
    (offscreen pyvista; ``objects`` as :func:`_objects`); [] with a warning when rendering fails
    (a convenience: the tables are the result)."""
    figures = []
    try:
        from workbench.runner.viz import render_friction_arrows

        twists = {"torsion about the grasp axis": np.array([0, 0, 0, 0, 0, 1.0])}
        for (i, name), (prof, title) in examples.items():
            path = out / f"profile_{objects[i][1]}_{name}.png"
            figures.append(str(render_friction_arrows(prof, twists, path, title=title)))
        for set_name, file in (("thesis_meshes", "thesis_objects.png"), ("bottle_family", "family.png")):
            mine = [(i, o) for i, (s, _, o) in enumerate(objects) if s == set_name]
            if mine:
                marks = {k: np.array(markers[i]) for k, (i, _) in enumerate(mine) if i in markers}
                figures.append(str(_render_family([o for _, o in mine], marks, out / file, set_name)))
    except Exception as exc:
        log.warning("offscreen rendering failed: %s", exc)
    return figures


def _render_family(bottles: list, markers: dict, path: Path, what: str = "bottle family") -> Path:
    """Fig 3.11(b): a set of objects in a grid, with the grasp points of each object."""
    from workbench.runner.viz import _pyvista, save_screenshot

    pv = _pyvista()
    cols = 8
    meshes = [b.to_trimesh(64, 60) if isinstance(b, Bottle) else b.to_trimesh() for b in bottles]
    # a grid cell a fifth larger than the largest object, so every set fits its own grid
    dx, dz = (
        1.2 * max(float(np.ptp(m.vertices[:, 0])) for m in meshes),
        1.2 * max(float(np.ptp(m.vertices[:, 2])) for m in meshes),
    )
    plotter = pv.Plotter(off_screen=True, window_size=(1400, 720))
    for k, (b, m) in enumerate(zip(bottles, meshes, strict=True)):
        shift = np.array([(k % cols) * dx, 0.0, -(k // cols) * dz])
        color = "salmon" if b.params.asymmetric else "lightsteelblue"
        plotter.add_mesh(pv.wrap(m).translate(shift, inplace=False), color=color, smooth_shading=True)
        if k in markers:
            plotter.add_points(markers[k] + shift, color="black", point_size=6, render_points_as_spheres=True)
    plotter.view_xz()
    plotter.reset_camera()
    plotter.add_text(f"{what} (red: asymmetric) with grasp points", font_size=10)
    return save_screenshot(plotter, path)


def _checkpoint(out: Path, config: dict) -> Checkpoint:
    """The row checkpoint of this configuration: the settings that change no row (where the
    rows run, the output folder, the rendering) are left out of its key, and the meshes' folder
    is keyed by the content of the meshes it gave (moved data reuses the rows, changed data
    does not)."""
    import hashlib

    skip = ("out", "quick", "render_examples", "workers", "scheduler", "objects_dir")
    key = {k: v for k, v in config.items() if k not in skip}
    digest = hashlib.sha256()
    for m in _mesh_objects(config["objects_dir"], config["objects_glob"]):
        digest.update(m.name.encode() + b"\0" + m.digest.encode())
    key["objects_digest"] = digest.hexdigest()[:16]
    return Checkpoint(out / "rows.jsonl", key, code=code_digest(__name__))


def _plan(objects: list[tuple], pad, config: dict, ckpt: Checkpoint) -> tuple[list, list, dict]:
    """The grasps ``(j, i, height fraction, approach, angle)`` (``i`` indexes ``objects``, as
    :func:`_objects`; each at its set's heights), those with jaw displacements not in the
    checkpoint (their indices appended to the tuple), and the grasp points of each object
    (object frame, for the set's figure)."""
    h = pad.geometry.thickness
    grasps = [
        (i, hf, approach)
        for i, (set_name, _, _) in enumerate(objects)
        for hf, approach in product(_heights(set_name, config), config["approaches"].items())
    ]
    jobs = [(j, i, hf, name, ang) for j, (i, hf, (name, ang)) in enumerate(grasps)]
    markers: dict = {}
    todo_jobs = []
    for j, i, hf, name, ang in jobs:
        label, b = objects[i][1], objects[i][2]
        pose = grasp_pose(b, _at(b, hf), ang, pad.face_xy, h)
        markers.setdefault(i, []).append(pose.to_object(np.array([[0.0, 0.0, h]]))[0])
        todo = [k for k, d in enumerate(config["deltas_mm"]) if _profile_key(label, hf, name, d) not in ckpt]
        if todo:
            todo_jobs.append((j, i, hf, name, ang, todo))
    return jobs, todo_jobs, markers


def row_tasks(todo_jobs: list[tuple], config: dict) -> list[tuple[str, tuple]]:
    """The ``("rows", (j, i, height fraction, approach, angle, todo))`` tasks of the grasps
    ``todo_jobs`` (``todo``: the jaw-displacement indices still to do): one task per profile
    on short runs (a grasp's 3 would leave 2 workers idle), per grasp on long ones (from
    ``config.RUN.grasp_tasks_from`` grasps: a profile's task re-solves the jaw
    displacements before it); the tasks with the protocol ablation (the longest) first."""
    if len(todo_jobs) >= cfg.RUN.grasp_tasks_from:
        rows = [("rows", job) for job in todo_jobs]
    else:
        rows = [("rows", (*job[:-1], [k])) for job in todo_jobs for k in job[-1]]
    rows.sort(key=lambda t: not any(_ablated(t[1][0], k, config) for k in t[1][-1]))
    return rows


def _sweep(jobs: list, todo_jobs: list, ref_cases: list, ckpt: Checkpoint, config: dict, meanwhile):
    """Run the missing profile rows and the full-mesh reference cases (first: the longest
    tasks) with :func:`workbench.runner.parallel.run_rows`, here or on Dask workers; the driver
    alone writes the checkpoint, and runs ``meanwhile()`` while the tasks run.  Returns
    (what ``meanwhile`` returned, where the tasks ran, (their wall time [s], their task-stream
    statistics: :func:`workbench.runner.parallel.map_rows`), the reference cases' results in
    ``ref_cases`` order)."""
    n_total = len(jobs) * len(config["deltas_mm"])
    n_todo = sum(len(job[-1]) for job in todo_jobs)
    bar = tqdm(total=n_total, initial=n_total - n_todo, desc="fem-fitting", unit="profile")
    # the longest first: the full-mesh references, then the rows (those with the ablation first)
    tasks = [("reference", label, pose) for label, pose in ref_cases] + row_tasks(todo_jobs, config)
    ref_of: dict[str, dict] = {}

    def keep(task, res) -> None:
        if task[0] == "reference":
            ref_of[task[1]] = res
            return
        for key, row in res:
            ckpt.add(key, row)
        bar.update(len(res))

    t0 = time.perf_counter()
    stream: dict = {}
    task = partial(run_task, config=config)
    renders, where = run_rows(task, tasks, keep, config, n_rows=n_todo, meanwhile=meanwhile, stats=stream)
    tasks_s = time.perf_counter() - t0
    bar.close()
    return renders, where, (tasks_s, stream), [ref_of[label] for label, _ in ref_cases]


def _write_tables(out: Path, rows: list[dict], ref: list[dict]) -> None:
    """profiles.csv (every key of any row: the first may lack e.g. a quartic left out or
    the ablation's) and condensed_vs_full.csv."""
    cols = [c for c in dict.fromkeys(k for r in rows for k in r) if c not in ("config_hash",)]
    write_csv(out / "profiles.csv", cols, [[r.get(c) for c in cols] for r in rows])
    write_csv(out / "condensed_vs_full.csv", list(ref[0]), [list(r.values()) for r in ref])


def _errors(rows: list[dict], config: dict) -> dict:
    """The error columns of the rows: {"test", "train", "code" (None without the thesis-code
    protocol), "support": {protocol: {model: (n,)}}} and the profile times "profile_ms" (n,).
    Thesis-code columns cover the rows where the model was fitted (the quartic needs >= 126
    wrenches)."""
    test = {m: np.array([r[f"{m}_error"] for r in rows]) for m in MODELS}
    code = {m: _column(rows, f"{m}_code_error") for m in MODELS} if config["thesis_code"] else None
    support = {"thesis-text": {m: _column(rows, f"{m}_support") for m in MODELS}}
    if code:
        support["thesis-code"] = {m: _column(rows, f"{m}_code_support") for m in MODELS}
    return {
        "test": test,
        "train": {m: np.array([r[f"{m}_train_error"] for r in rows]) for m in TABLE_MODELS},
        "code": code,
        "support": support,
        "profile_ms": np.array([r["profile_ms"] for r in rows]),
    }


def _protocol_tables(errors: dict) -> list[tuple[str, dict]]:
    """(protocol, {model: (n,) Eq. 3.18 errors}) of Table 3.3."""
    return [("thesis-text", errors["test"])] + ([("thesis-code", errors["code"])] if errors["code"] else [])


def _histogram(errors: dict, n_rows: int, out: Path) -> str:
    """Table 3.3's error histograms under both protocols, and the profile times."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prof_ms = errors["profile_ms"]
    fig, ax = plt.subplots(1, 2, figsize=(11, 3.8))
    tables = _protocol_tables(errors)
    top = max(t[m].max() for _, t in tables for m in TABLE_MODELS if len(t[m]))
    bins = np.linspace(0, top * 1.05, 50)
    for j, (proto, t) in enumerate(tables):
        for m, color in zip(TABLE_MODELS, ("C0", "C1"), strict=True):
            if not len(t[m]):  # never fitted under this protocol (the summary says why)
                continue
            ax[0].hist(
                t[m],
                bins,
                alpha=0.55 if j == 0 else 1.0,
                color=color,
                histtype="stepfilled" if j == 0 else "step",
                label=f"{m} {proto} {t[m].mean():.4f} (thesis {THESIS_TABLE_3_3[FAMILY[m]][0]})",
            )
    ax[0].set_xlabel("fitting error Eq. 3.18")
    ax[0].set_ylabel("profiles")
    ax[0].set_title(f"{n_rows} FEM contact profiles, two protocols")
    ax[0].legend(fontsize=7)
    ax[1].hist(prof_ms, 40, color="gray")
    ax[1].axvline(50, color="r", lw=0.8, label="50 ms target")
    ax[1].set_xlabel("contact solve + extraction [ms]")
    ax[1].set_title(f"per profile: median {np.median(prof_ms):.1f} ms, mean {prof_ms.mean():.1f} ms")
    ax[1].legend()
    return str(save_figure(fig, out / "table_3_3_histogram.png"))


def _mean_std(v: np.ndarray) -> dict:
    """Mean and std of ``v``; None for both when no profile has the value (a set where a
    model was never fitted: the quartic's thesis-code training set below its 126 unknowns)."""
    if len(v) == 0:
        return {"mean": None, "std": None}
    return {"mean": float(v.mean()), "std": float(v.std())}


def _cell_vs_thesis(model: str, v: np.ndarray) -> dict:
    """A Table 3.3 cell: the mean and std of ``model``'s Eq. 3.18 errors ``v`` (n,), on how many
    profiles it was fitted, the thesis's value and the ratio of the means (None when unfitted)."""
    thesis = THESIS_TABLE_3_3[FAMILY[model]]
    ratio = float(v.mean() / thesis[0]) if len(v) else None
    return {**_mean_std(v), "n_profiles": len(v), "thesis": thesis, "ratio_of_means": ratio}


def _unsolved(rows: list[dict]) -> dict:
    """The presses the pad could not take (the object deeper in it than its layer), left out of
    the table: their count and their grasps."""
    bad = [r for r in rows if "unsolved" in r]
    grasps = {f"{r['object']} h={r['height_frac']:.3f} {r['approach']}" for r in bad}
    return {"n_unsolved": len(bad), "unsolved": sorted(grasps)}


def _summary(rows: list[dict], all_rows: list[dict], errors: dict, ref: list[dict], config: dict, run: dict):
    """summary.json's content but the headline: Table 3.3 of the non-empty ``rows``, the
    reference cases ``ref``, and ``run``'s bookkeeping (n_bottles, n_resumed, tasks_ran_on,
    tasks_wall_s, the pad's pad_precompute_s, pad_precompute_cached, pad_load_s, figures; the set's
    n_objects, objects (their kind, for the count) and n_heights)."""
    err, code_err, prof_ms = errors["test"], errors["code"], errors["profile_ms"]
    return {
        "n_profiles": len(rows),
        "n_empty": sum(r["empty"] for r in all_rows),
        **_unsolved(all_rows),
        # rows taken from the checkpoint of an earlier (killed or finished) run; wall_time_s
        # then covers only the rest, row_compute_s is the sweep's own time over all rows
        "n_resumed": run["n_resumed"],
        # where this run's tasks ran — the profile rows and the full-mesh reference cases,
        # while the driver rendered the examples — and their wall time (with the cluster's start)
        "tasks_ran_on": run["tasks_ran_on"],
        "tasks_wall_s": run["tasks_wall_s"],
        # the tasks' own compute seconds (busy_s) per worker from Dask's task stream, and the
        # utilisation busy / (wall x workers): how much of tasks_wall_s the workers computed
        "tasks_stream": run["tasks_stream"],
        "row_compute_s": float(
            sum(
                r["profile_ms"] / 1e3
                + sum(r.get(f"{m}_fit_s", 0.0) + r.get(f"{m}_code_fit_s", 0.0) for m in MODELS)
                for r in all_rows
                if "unsolved" not in r
            )
        ),
        "count": (
            f"{run['n_objects']} {run['objects']} x {run['n_heights']} heights x {len(config['approaches'])} "
            f"approach directions x {len(config['deltas_mm'])} displacements "
            f"(thesis: {THESIS_TABLE_3_3['n_profiles']})"
        ),
        "fidelity": "condensed (linear elastic pad, frictionless, rigid object)",
        # the pad's own checks (Hertz, condensed vs full mesh vs neo-Hookean) are fem-validation's
        # results, not read here: experiments run in any order
        "pad_validation": "results/fem-validation (workbench run fem-validation)",
        **{f"{m}_error_{k}": v for m in MODELS for k, v in _mean_std(err[m]).items()},
        "train_error": {m: _mean_std(v) for m, v in errors["train"].items()},
        "protocols": {
            "thesis-text": f"{config['n_wrenches']} wrenches of the thesis §3.3.2 sampler; Eq. 3.18 on "
            f"{config['n_heldout']} held-out ones (the *_error_mean/std keys)",
            "thesis-code": f"the author's twist grid (fineLevel {config['fine_level']}), trained on one "
            f"wrench per grid cell ({config['downsample_steps']} widths per range), Eq. 3.18 on all; the "
            f"grid axis-aligned in the {config['code_frame']} frame",
        },
        "protocol_ablation": _ablation_summary(rows) if code_err else None,
        "thesis_protocol_error": (
            {
                **{m: {**_mean_std(v), "n_profiles": len(v)} for m, v in code_err.items()},
                "quartic_underdetermined": sum(r.get("quartic_values_code_error") is None for r in rows),
                "n_train": _stats([r["code_n_train"] for r in rows]),
                "n_pool": _stats([r["code_n_pool"] for r in rows]),
            }
            if code_err
            else None
        ),
        "table_3_3_vs_thesis": {
            proto: {m: _cell_vs_thesis(m, t[m]) for m in TABLE_MODELS}
            for proto, t in _protocol_tables(errors)
        },
        "support_error": {
            proto: {m: _mean_std(v) for m, v in t.items()} for proto, t in errors["support"].items()
        },
        "support_error_note": (
            f"radial |f^(1/deg) - 1| at exact 6DFW surface points of {config['support_directions']} normals "
            "uniform on the sphere of normalised twists: independent of the training sampler"
        ),
        "quartic_values_below_ellipsoid_sdp_fraction": float(
            np.mean(err["quartic_values"] < err["ellipsoid_sdp"])
        ),
        "thesis_table_3_3": THESIS_TABLE_3_3,
        "condensed_vs_reference": {
            "pressure_rel_l2": max(r["pressure_rel_l2"] for r in ref),
            "force_rel_err": max(r["force_rel_err"] for r in ref),
            "reference": "full-mesh linear (same pad mesh)",
            "cases": ref,
        },
        "seconds_per_profile": float(prof_ms.mean() / 1e3),
        "profile_ms": {
            "mean": float(prof_ms.mean()),
            "median": float(np.median(prof_ms)),
            "p95": float(np.percentile(prof_ms, 95)),
            "max": float(prof_ms.max()),
            "fraction_le_50ms": float(np.mean(prof_ms <= 50)),
        },
        "fit_seconds_mean": {m: float(np.mean([r[f"{m}_fit_s"] for r in rows])) for m in MODELS},
        **{k: run[k] for k in ("pad_precompute_s", "pad_precompute_cached", "pad_load_s")},
        "dims": {str(d): int(sum(r["dim"] == d for r in rows)) for d in sorted({r["dim"] for r in rows})},
        "figures": run["figures"],
    }


def _table_cell(model: str, cell: dict, n_profiles: int) -> str:
    """A model's Table 3.3 cell of the headline: mean ± std beside the thesis's, and on how many
    of the ``n_profiles`` it was fitted (the quartic needs >= 126 training wrenches)."""
    thesis = THESIS_TABLE_3_3[FAMILY[model]]
    if cell["mean"] is None:
        return f"{model} not fitted on any profile (under 126 training wrenches on each)"
    fitted = "" if cell["n_profiles"] == n_profiles else f", fitted on {cell['n_profiles']}"
    return (
        f"{model} {cell['mean']:.4f} ± {cell['std']:.4f} (thesis's {FAMILY[model]} {thesis[0]} ± "
        f"{thesis[1]}, ratio {cell['ratio_of_means']:.2f}{fitted})"
    )


def _headline(summary: dict, errors: dict, pad_load_s: float, from_cache: bool) -> list[str]:
    prof_ms = errors["profile_ms"]
    abl = summary["protocol_ablation"]
    return [
        *(
            f"Table 3.3 on {summary['n_profiles']} profiles, {proto}: "
            + ", ".join(
                _table_cell(m, v[m], summary["n_profiles"]) for m in ("quartic_values", "ellipsoid_sdp")
            )
            for proto, v in summary["table_3_3_vs_thesis"].items()
        ),
        *(
            [
                f"{summary['n_unsolved']} presses unsolved and left out (the object reaches deeper into "
                f"the pad than its layer): {'; '.join(summary['unsolved'])}"
            ]
            if summary["n_unsolved"]
            else []
        ),
        "sampler-independent radial error (mean): "
        + "; ".join(
            f"{proto} " + ", ".join(f"{m} {v['mean']:.4f}" for m, v in t.items() if v["mean"] is not None)
            for proto, t in summary["support_error"].items()
        ),
        *(
            [
                f"thesis-code protocol ablation on {abl['n_profiles']} profiles, ellipsoid_sdp / "
                "quartic_values mean error ratio to the protocol's: "
                + "; ".join(
                    f"{v} {abl[v]['ellipsoid_sdp']['ratio']:.2f} / "
                    + (f"{abl[v]['quartic_values']['ratio']:.2f}" if "quartic_values" in abl[v] else "n/a")
                    for v in ABLATION_VARIANTS
                    if "ellipsoid_sdp" in abl[v]
                )
            ]
            if abl
            else []
        ),
        f"contact profile: mean {prof_ms.mean():.1f} ms, median {np.median(prof_ms):.1f} ms, "
        f"p95 {np.percentile(prof_ms, 95):.1f} ms after a {summary['pad_precompute_s']:.1f} s pad precompute"
        + (f" (loaded from the disk cache in {pad_load_s:.1f} s)" if from_cache else ""),
    ]


#: what a set's block of ``object_sets`` in the summary keeps of :func:`_summary`
_SET_KEYS = (
    "n_profiles",
    "n_empty",
    "n_unsolved",
    "unsolved",
    "count",
    "table_3_3_vs_thesis",
    "thesis_protocol_error",
    "protocol_ablation",
    "support_error",
    "quartic_values_below_ellipsoid_sdp_fraction",
    "dims",
)


def _set_line(name: str, block: dict) -> str:
    """A headline line of an object set beside the headline one."""
    if "skipped" in block:
        return f"{name} skipped: {block['skipped']}"
    t = block["table_3_3_vs_thesis"]["thesis-text"]
    return (
        f"{name}: quartic_values {t['quartic_values']['mean']:.4f}, ellipsoid_sdp "
        f"{t['ellipsoid_sdp']['mean']:.4f} (thesis-text, {block['n_profiles']} profiles)"
    )


def _set_summaries(
    rows: list[dict],
    ordered: list[dict],
    objects: list[tuple],
    ref: list[dict],
    config: dict,
    info: dict,
    skipped: dict,
) -> tuple[dict, dict]:
    """The summary of the first set that ran (the headline set: :func:`_summary` of its rows),
    with ``object_sets``: each set's own Table 3.3 (:data:`_SET_KEYS`), its object counts and
    heights, and the skipped sets with why.  Returns it and the headline set's errors."""
    sets = [n for n in config["object_sets"] if n not in skipped]
    per_set = {}
    for name in sets:
        mine = [r for r in rows if r["object_set"] == name]
        errors = _errors(mine, config)
        own = {
            **info,
            "n_objects": sum(o[0] == name for o in objects),
            "objects": "meshes" if name == "thesis_meshes" else "bottles",
            "n_heights": len(_heights(name, config)),
        }
        everyone = [r for r in ordered if r["object_set"] == name]
        per_set[name] = (errors, _summary(mine, everyone, errors, ref, config, own))
    errors, summary = per_set[sets[0]]
    summary["headline_object_set"] = sets[0]
    ran = {
        name: {
            **{k: v for k, v in block.items() if k in _SET_KEYS},
            "n_objects": sum(o[0] == name for o in objects),
            "n_asymmetric": sum(o[0] == name and o[2].params.asymmetric for o in objects),
            "heights": _heights(name, config),
        }
        for name, (_, block) in per_set.items()
    }
    # in object_sets' order, a skipped set where it would have run
    summary["object_sets"] = {
        name: ran[name] if name in ran else {"skipped": skipped[name]} for name in config["object_sets"]
    }
    return summary, errors


def run(config: dict) -> dict:
    t_start = time.perf_counter()
    out = Path(config["out"])
    out.mkdir(parents=True, exist_ok=True)
    skipped = _skipped(config)
    for name, why in skipped.items():
        log.warning("fem-fitting: object set %s skipped (%s)", name, why)
    objects = _objects(config)
    if not objects:
        raise ValueError(f"fem-fitting: no object to press — {skipped}; run the bottle_family set")
    t0 = time.perf_counter()
    pad = _pad_of(config)  # built here once (or loaded from its disk cache) before any worker needs it
    pad_load_s = time.perf_counter() - t0

    # the grasps not yet in the checkpoint, and the full-mesh reference cases, run as tasks
    ckpt = _checkpoint(out, config)
    n_resumed = len(ckpt.rows)
    jobs, todo_jobs, markers = _plan(objects, pad, config, ckpt)
    ref_cases = reference_cases(config)

    def meanwhile() -> list[str]:  # the driver's share: the example profiles, rendered
        return _renders(_examples(jobs, objects, pad, config), objects, markers, out)

    renders, tasks_ran_on, (tasks_s, stream), ref = _sweep(
        jobs, todo_jobs, ref_cases, ckpt, config, meanwhile
    )

    # Table 3.3 over every profile of each set, the reference cases, the figures
    # in grasp order, not the checkpoint's (the order the tasks finished in): the same table and
    # the same sums to the last bit whatever the workers
    ordered = [
        ckpt.rows[_profile_key(objects[i][1], hf, name, d)]
        for _, i, hf, name, _ in jobs
        for d in config["deltas_mm"]
    ]
    rows = [r for r in ordered if not (r["empty"] or "unsolved" in r)]
    if not rows:
        raise RuntimeError("no contact profile was produced; check the pad placement")
    _write_tables(out, rows, ref)
    info = {
        "n_resumed": n_resumed,
        "tasks_ran_on": tasks_ran_on,
        "tasks_wall_s": tasks_s,
        "tasks_stream": stream,
        "pad_precompute_s": pad.seconds,  # the build time, also when loaded from the disk cache
        "pad_precompute_cached": pad.from_cache,
        "pad_load_s": pad_load_s,
        "figures": [],
    }
    summary, errors = _set_summaries(rows, ordered, objects, ref, config, info, skipped)
    summary["figures"] = [_histogram(errors, summary["n_profiles"], out), *renders]
    summary["headline"] = [
        f"object set {summary['headline_object_set']} (of {', '.join(summary['object_sets'])})",
        *_headline(summary, errors, pad_load_s, pad.from_cache),
        *(
            _set_line(name, v)
            for name, v in summary["object_sets"].items()
            if name != summary["headline_object_set"]
        ),
    ]
    return write_summary(out, NAME, config, summary, time.perf_counter() - t_start)


if __name__ == "__main__":
    from workbench.runner.cli import main

    raise SystemExit(main(["run", NAME, *__import__("sys").argv[1:]]))

"""Thesis Table 4.6 (§4.3): the minimal-work metrics of candidate grasps against a simulated
truth, and their held-out balanced accuracy.

* :func:`candidate_grasps`: horizontal antipodal grasps of a measured object (§4.3.2);
* :func:`grasp_row`: one candidate's metrics per task — ``q_robust`` (Eq. 2.101),
  ``q_force`` and ``q_work``'s minimal forces and work (Eqs. 4.4–4.6) — and its simulated
  truth (:func:`workbench.grasp.simulated_truth.simulated_success`), with the jaws' contact
  profiles from REACH (§4.3.2.1) or the FEM pad (:func:`jaw_profiles_of`);
* :func:`table_4_6`: normalisers ``W_max``, ``f⊥max`` fitted on a training split, balanced
  accuracy of each metric on the held-out grasps, per object and overall;
* :func:`nonlinear_work_table`: ``q_work`` from the nonlinear wall's load curves
  (:func:`workbench.fem.grasp_walls.pose_work`) beside the map's and the linear wall's (§4.3.5).

Rows are plain dicts (JSON-able, checkpointed by the driver); an unresisted pose's forces are
NaN and its cost (``f_sum``, ``W``) reads as inf.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..fem.grasp_walls import pose_work

log = logging.getLogger(__name__)

__all__ = [
    "METRICS",
    "TASKS",
    "GraspRowSettings",
    "candidate_grasps",
    "fem_pad",
    "grasp_row",
    "inf_for_nan",
    "jaw_profiles_of",
    "largest_jaw_force",
    "measured_map",
    "nan_if_none",
    "nonlinear_work",
    "nonlinear_work_table",
    "table_4_6",
]

#: the two tasks of Table 4.6 (vertical lifting: one pose; lifting and 90° rotation: three)
TASKS = ("vertical_lifting", "lift_and_rotate")
#: its three metrics
METRICS = ("q_robust", "q_force", "q_work")


@dataclass(frozen=True)
class GraspRowSettings:
    """What a candidate's row depends on besides the grasp: the run's ``seed`` (the 6DLS fits
    and the exact 6DFW sets), the profiles' force ``grasp_force`` [N per jaw] and source
    ``profiles`` ("reach" or "fem"), the pad ``jaw`` (width, length) [m] and REACH's
    ``reach_closing`` [m], friction ``mu``, the 6DLS linearisation ``M``, the filled objects'
    ``mass_kg`` {object: kg}, ``q_robust``'s ``robust_samples``, the minimal-force program's
    ``work_representation`` ("model" or "outer"), and the truth's ``safety``, ``force_cap`` [N],
    ``closing_limit`` [m], ``noise_samples``, ``sigma_mu`` and ``sigma_force`` (relative)."""

    seed: int
    grasp_force: float
    profiles: str
    jaw: tuple[float, float]
    reach_closing: float
    mu: float
    M: int
    mass_kg: Mapping[str, float]
    robust_samples: int
    work_representation: str
    safety: float
    force_cap: float
    closing_limit: float
    noise_samples: int
    sigma_mu: float
    sigma_force: float

    @classmethod
    def from_config(cls, config: Mapping) -> GraspRowSettings:
        """From a run's settings of the same names (``reach_closing_mm`` and
        ``closing_limit_mm`` in millimetres)."""
        return cls(
            seed=config["seed"],
            grasp_force=config["grasp_force"],
            profiles=config["profiles"],
            jaw=tuple(config["jaw"]),
            reach_closing=config["reach_closing_mm"] * 1e-3,
            mu=config["mu"],
            M=config["M"],
            mass_kg=config["mass_kg"],
            robust_samples=config["robust_samples"],
            work_representation=config["work_representation"],
            safety=config["safety"],
            force_cap=config["force_cap"],
            closing_limit=config["closing_limit_mm"] * 1e-3,
            noise_samples=config["noise_samples"],
            sigma_mu=config["sigma_mu"],
            sigma_force=config["sigma_force"],
        )


def nan_if_none(x) -> float:
    """``x`` as a float, None (a NaN through JSON) as NaN."""
    return float("nan") if x is None else float(x)


def inf_for_nan(rows: list[dict], task: str, key: str) -> np.ndarray:
    """(n,) ``row[task][key]`` of every row, a missing (None / NaN: unresisted) value as inf."""
    x = np.array([nan_if_none(r[task][key]) for r in rows])
    return np.where(np.isnan(x), np.inf, x)


@lru_cache(maxsize=8)
def measured_map(path: str):
    """The measured map file's :class:`~workbench.grasp.stiffness_map.StiffnessMap`, once per process."""
    from ..fem.wall_grasps import read_locations
    from .stiffness_map import StiffnessMap

    L, measured = read_locations(path)
    if measured is None:
        raise ValueError(
            f"{path}: minimal-work needs the measured 'stiffness_map' (one value per location) "
            "beside 'stiffness_locations'; for locations without measurements use "
            "`workbench run wall-stiffness --set object=... --set locations=...`"
        )
    return StiffnessMap.from_measured(L, np.r_[measured, measured])


def candidate_grasps(mesh, name: str, n_heights: int, n_angles: int, mu: float) -> list[dict]:
    """Horizontal antipodal grasps of ``mesh`` (object ``name``) at ``n_heights`` heights evenly
    inside its z extent and ``n_angles`` axis angles (:func:`~workbench.grasp.sampling.horizontal_grasps`);
    ``ValueError`` when there is none."""
    from .sampling import horizontal_grasps

    lo, hi = mesh.bounds[:, 2]
    heights = np.linspace(lo, hi, n_heights + 2)[1:-1]
    cands = horizontal_grasps(mesh, heights, n_angles, mu, pad=None)
    if not cands:
        raise ValueError(
            f"{name}: no horizontal antipodal grasp within friction cone mu={mu} at "
            f"{n_heights} heights x {n_angles} angles — raise n_heights, n_angles or mu"
        )
    return cands


@lru_cache(maxsize=2)
def fem_pad(jaw: tuple):
    """The FEM pad (width, length ``jaw`` [m]), condensed once per process (its disk cache:
    once per machine)."""
    from ..fem.material import Material
    from ..fem.pad import PadGeometry, condense_pad

    return condense_pad(PadGeometry(*jaw), Material())


def jaw_profiles_of(mesh, g: dict, run: GraspRowSettings) -> list:
    """Both jaws' contact profiles at grasp ``g`` at ``run.grasp_force``: REACH
    (:func:`workbench.sources.reach.jaw_profiles`) or the FEM pad
    (:func:`workbench.sources.fem_jaw.fem_jaw_profiles`), as ``run.profiles`` says."""
    if run.profiles == "reach":
        from ..sources.reach import jaw_profiles

        return jaw_profiles(
            mesh, g, run.grasp_force, pad=run.jaw, closing=run.reach_closing, allow_scale=True
        )
    from ..sources.fem_jaw import fem_jaw_profiles

    return fem_jaw_profiles(mesh, g, run.grasp_force, pad=fem_pad(run.jaw))


def _row_head(name: str, k: int, g: dict, s_map: np.ndarray, s_fem: float) -> dict:
    """The grasp's own columns of its row."""
    return {
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


def _q_robust_memo(contacts: list, run: GraspRowSettings) -> Callable:
    """``q_robust`` of a pose's wrench (6,), each distinct wrench once (the tasks share the 0° pose)."""
    from .robust import Perturbation, q_robust

    q_robust_of: dict[bytes, float] = {}

    def q_of(w: np.ndarray) -> float:
        key = np.ascontiguousarray(w).tobytes()
        if key not in q_robust_of:
            perturb = Perturbation(n_samples=run.robust_samples)
            q_robust_of[key] = q_robust(contacts, run.mu, w, perturb, seed=0)
        return q_robust_of[key]

    return q_of


def _task_entry(
    mw: list, ws: np.ndarray, q_of: Callable, exact, s_fem: float, run: GraspRowSettings, rng
) -> dict:
    """One task's entry of a row: its poses' minimal forces ``mw``, wrenches ``ws`` (k, 6)."""
    from .simulated_truth import TruthModel, simulated_success

    f_sum = max(m.f_sum for m in mw)
    W = max(m.W for m in mw)
    # beyond the thesis: the work from the calibrated FEM's force-deflection line, ∫ f dΔ = f²/(2 s)
    W_fem = max(float(np.sum(m.forces**2 / (2 * s_fem))) if m.feasible else np.inf for m in mw)
    qr = min(q_of(w) for w in ws)
    truth, f_req = simulated_success(
        exact,
        ws,
        run.mu,
        run.grasp_force,
        stiffness=s_fem,
        model=TruthModel(
            run.safety, run.force_cap, run.closing_limit, run.noise_samples, run.sigma_mu, run.sigma_force
        ),
        rng=rng,
    )
    return {
        "truth": truth,
        "q_robust": float(qr),
        "f_sum": float(f_sum),
        "W": float(W),
        "W_fem": float(W_fem),
        "f_required": float(f_req),
        "forces": [m.forces.tolist() for m in mw],  # per pose, per jaw [N] (NaN: unresisted)
    }


def grasp_row(name: str, k: int, g: dict, mesh, smap, s_fem: float, run: GraspRowSettings, seed: int) -> dict:
    """Metrics and simulated truth of candidate ``k`` of object ``name`` (grasp ``g`` of
    :func:`candidate_grasps` on ``mesh``): the jaws' profiles (:func:`jaw_profiles_of`), the
    ellipsoidal 6DLS of each, the stiffness map ``smap`` at the two contact points, and per
    task of :data:`TASKS` ``q_robust`` (min over poses), the minimal forces' ``f_sum`` and
    work ``W`` (Eqs. 4.4–4.5, max over poses), ``W_fem`` from the calibrated wall stiffness
    ``s_fem`` [N/m] (inf: rigid), and the truth from ``seed``.  A grasp without FEM-pad
    profiles is a row with ``skipped`` (REACH's refusal is raised)."""
    from .exact import ExactContacts
    from .models import ModelParameters, contact_sets
    from .tasks import task_wrenches
    from .work import minimal_work_poses

    t0 = time.perf_counter()
    try:
        profiles = jaw_profiles_of(mesh, g, run)
    except ValueError as e:  # no FEM pad profile: the object reaches the jaw's rigid back first
        if run.profiles == "reach":
            raise
        log.warning("%s grasp %d skipped: %s", name, k, e)
        return {"object": name, "grasp": k, "skipped": str(e)}
    contacts = [contact_sets(p, "6dls", ModelParameters(M=run.M), seed=run.seed)[0] for p in profiles]
    s_map = smap(np.array([g["p1"], g["p2"]]))
    com, mass = mesh.convex_hull.center_mass, run.mass_kg[name]  # the filled object's centre
    exact = ExactContacts(profiles, seed=run.seed)
    rng = np.random.default_rng(seed)
    row = _row_head(name, k, g, s_map, s_fem)
    poses = {task: task_wrenches(task, mass, com, g["axis"]) for task in TASKS}
    q_of = _q_robust_memo(contacts, run)
    # every pose of both tasks on one LP (the 0° pose they share is solved once)
    mw_all = minimal_work_poses(
        contacts, np.vstack(list(poses.values())), run.mu, s_map, representation=run.work_representation
    )
    k0 = 0
    for task, ws in poses.items():
        mw, k0 = mw_all[k0 : k0 + len(ws)], k0 + len(ws)
        row[task] = _task_entry(mw, ws, q_of, exact, s_fem, run, rng)
    row["seconds"] = time.perf_counter() - t0
    return row


def table_4_6(
    rows: list[dict], split: np.ndarray, objects: list[str], sigma: float, seed: int
) -> tuple[dict, dict, dict]:
    """Table 4.6 per task of the candidates' ``rows`` (:func:`grasp_row`): normalisers fitted on
    the training grasps (``split`` (n,) bool, True: training), balanced accuracy at threshold
    ``sigma`` of each metric on the held-out ones, per object of ``objects`` and "All"
    (:func:`~workbench.grasp.quality_table.quality_table`, bootstrap from ``seed``);
    (table, normalisers, class balance).  ``table[task]["interval_95"]``: each metric's
    bootstrap interval of its overall balanced accuracy."""
    from .quality_table import quality_table

    objs = np.array([r["object"] for r in rows])
    table, normalisers, class_balance = {}, {}, {}
    for task in TASKS:
        truth = np.array([r[task]["truth"] for r in rows])
        f, W, W_fem = (inf_for_nan(rows, task, key) for key in ("f_sum", "W", "W_fem"))
        scored = quality_table(
            truth,
            split,
            objs,
            objects,
            qualities={"q_robust": np.array([r[task]["q_robust"] for r in rows])},
            costs={"q_force": f, "q_work": W, "q_work_fem": W_fem},
            sigma=sigma,
            seed=seed,
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
            for n in objects
        }
    return table, normalisers, class_balance


def largest_jaw_force(row: dict) -> float:
    """The largest minimal jaw force [N] of any pose of both tasks of a :func:`grasp_row` row
    (NaN when no pose is resisted)."""
    f = np.array([x for t in TASKS for pose in row[t]["forces"] for x in pose], float)
    return float(np.nanmax(f)) if np.isfinite(f).any() else float("nan")


def nonlinear_work(row: dict, task: str, entry: Mapping) -> float:
    """``W_nl`` [J] of a :func:`grasp_row` row's ``task``: the work along its load curve
    ``entry`` (:func:`workbench.fem.grasp_walls.load_curve`; ``curve`` None: not computed) at
    the poses' minimal forces, max over poses; inf when a pose is not resisted (as the linear
    W) or the curve is missing or too short, 0 on a rigid wall (``f² / 2s`` with ``s = inf``)."""
    poses = [np.asarray(p, float) for p in row[task]["forces"]]
    if any(np.isnan(p).any() for p in poses):
        return np.inf  # a pose not resisted: inf, as the linear W
    if not np.isfinite(nan_if_none(row["s_fem"])):
        return 0.0  # rigid: no wall work, as f² / 2s with s = inf
    if entry["curve"] is not None:
        return pose_work(entry, poses)
    return np.inf


def nonlinear_work_table(
    rows: list[dict],
    entries: list[Mapping],
    split: np.ndarray,
    objs: np.ndarray,
    objects: list[str],
    sigma: float,
) -> dict:
    """Table 4.6's balanced accuracy of ``q_work`` per task on ``rows`` (:func:`grasp_row`) from
    three works: the map's ``W`` (the thesis's), the calibrated linear wall's ``W_fem`` and the
    nonlinear wall's (:func:`nonlinear_work` on each row's load-curve ``entries``); normalisers
    on ``split`` (n,) bool (True: training), accuracy at ``sigma`` per object of ``objs`` (n,)
    among ``objects``; and the median ratio nonlinear / linear over grasps where both are finite."""
    from .threshold import fit_normaliser, held_out_accuracy

    table = {}
    for t in TASKS:
        W_nl = np.full(len(rows), np.inf)
        W_lin = np.full(len(rows), np.inf)
        W_map = np.array([nan_if_none(r[t]["W"]) for r in rows])
        for j, (r, c) in enumerate(zip(rows, entries, strict=True)):
            W_lin[j] = nan_if_none(r[t]["W_fem"])
            W_nl[j] = nonlinear_work(r, t, c)
        truth = np.array([r[t]["truth"] for r in rows])
        table[t] = {}
        variants = (
            ("q_work_map", np.where(np.isnan(W_map), np.inf, W_map)),  # the thesis's (Table 4.6)
            ("q_work_fem_linear", W_lin),
            ("q_work_fem_nonlinear", W_nl),
        )
        for label, W in variants:
            pred = 1 - W / fit_normaliser(W[split], truth[split], sigma) >= sigma
            per = held_out_accuracy(pred, truth, split, objs, objects)
            table[t][label] = {n: v for n, v in per.items() if v is not None}
        fin = np.isfinite(W_lin) & np.isfinite(W_nl) & (W_lin > 0)
        table[t]["W_nonlinear_over_linear"] = {
            "median": float(np.median(W_nl[fin] / W_lin[fin])) if fin.any() else None,
            "n": int(fin.sum()),
        }
    return table

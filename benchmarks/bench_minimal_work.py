"""The minimal-work metric per grasp with cached profiles and limit surfaces (the budget:
"≤ 5 ms per grasp").

One grasp is evaluated as ``workbench/grasp/work_table.py`` (``grasp_row``) does, minus the
wall FEM and the simulated truth: REACH profiles of both jaws at 10 N, the ellipsoidal
6DLS of each (``contact_sets(..., "6dls", M)``) — built once per grasp, outside the timing
— then, per grasp,

(a) ``q_work`` for both tasks (lifting: one pose; lift-and-rotate: 0/45/90°): the
    minimal forces over ``C_outer`` (Eq. 4.4, an LP; ``a_model``: over the 6DLS itself, second-order
    cones, as the experiment now computes them) and their work (Eq. 4.5) at every
    pose, the worst pose, ``q_work = 1 − W/W_max`` (Eq. 4.6), by three paths of the same
    numbers: ``reference`` (the same LP per pose through ``scipy.optimize.linprog``, as
    ``min_grasp_force`` solved it before it held one highspy model), ``per_pose``
    (``minimal_work`` per pose per task: one LP build and a cold solve per pose) and
    ``poses`` (``minimal_work_poses`` on both tasks' wrenches, as the experiment calls
    it: one assembly, warm solves after the first, the shared 0° pose solved once);
(b) ``q_force = 1 − Σf/f_max``: the same LPs give ``Σf``, so its own cost is the
    normalisation (its cost standing alone is that of (a));
(c) ``q_robust`` (Eq. 2.101; N_r = 30 per pose, min over poses, as the experiment);
(d) the stiffness-map lookup at the two contact points;

and the totals: ``metric`` = (d) + (a) + (b) (the minimal-work metric the acceptance
item is about) and ``all_metrics`` = also (c).  Each time is the median of ``repeats``
runs after a warm-up, per grasp, then the median (and max) over the grasps; one cProfile
pass names the dominant function.  Scenes: a synthetic cylinder (R = 35 mm) with a
synthetic stiffness map, always; the measured plastic cup
(``../shared/data/deformable_objects``) when present, else skipped.

Writes results/benchmarks/minimal_work.json.  Run: python benchmarks/bench_minimal_work.py [--quick]
"""

from __future__ import annotations

import argparse
import cProfile
import inspect
import io
import json
import os
import pstats
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from bench_wrench import machine_roofline  # the sibling benchmark's FMA roofline
from scipy.optimize import linprog

from workbench import config
from workbench.grasp import StiffnessMap, contact_sets
from workbench.grasp.models import ModelParameters
from workbench.grasp.resistance.program import assemble
from workbench.grasp.resistance.solvers import _slack_form
from workbench.grasp.robust import Perturbation, q_robust
from workbench.grasp.sampling import horizontal_grasps
from workbench.grasp.tasks import TASKS, task_wrenches
from workbench.grasp.work import minimal_work, minimal_work_poses, q_force, q_work, work
from workbench.limit_surface import LimitSurfaceCache
from workbench.runner.results import versions, write_json
from workbench.sources.reach import jaw_profiles

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data" / "deformable_objects"
BUDGET_MS = 5.0  # the budget: the metric per grasp
MU, F0, PAD, CLOSING = 0.5, 10.0, (0.02, 0.04), 1e-3  # workbench/experiments/minimal_work.py DEFAULT_CONFIG
ROBUST_SAMPLES = 30  # its robust_samples (N_r)
M_DEFAULT = inspect.signature(contact_sets).parameters["M"].default  # 200, also the experiment's "M"
# normalisers only scale the qualities (fitted on training grasps in the experiment); any > 0 times the same
W_MAX, F_MAX = 0.05, 20.0
POSES = {t: len(a) for t, a in TASKS.items()}  # {"vertical_lifting": 1, "lift_and_rotate": 3}


def _times(fn, repeats: int, warmup: int = 1) -> list[float]:
    """Wall times [s] of ``repeats`` calls of ``fn`` after ``warmup`` calls."""
    for _ in range(warmup):
        fn()
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def cylinder_scene() -> dict:
    """A closed cylinder, R = 35 mm, 120 mm tall, and a synthetic stiffness map on its side
    wall: 400 N/m at mid-height rising to ~2e4 N/m towards the rims (a hollow wall is
    stiffest near its ends), measured on 6 heights × 6 angles."""
    import trimesh

    R, H = 0.035, 0.12
    mesh = trimesh.creation.cylinder(radius=R, height=H, sections=96)
    z, a = np.meshgrid(np.linspace(-0.045, 0.045, 6), np.linspace(0, 2 * np.pi, 6, endpoint=False))
    pts = np.c_[R * np.cos(a.ravel()), R * np.sin(a.ravel()), z.ravel()]
    s = 400.0 * np.exp(4.0 * (pts[:, 2] / 0.045) ** 2)
    return {"mesh": mesh, "smap": StiffnessMap(pts, s), "mass": 0.2, "com": np.zeros(3)}


def cup_scene() -> dict | str:
    """The measured plastic cup (mesh and stiffness map, read by path), or why not."""
    import trimesh

    mesh_path, map_path = DATA / "meshes" / "plastic_cup.obj", DATA / "stiffness_maps" / "plastic_cup.json"
    if not mesh_path.exists() or not map_path.exists():
        return f"{mesh_path} or {map_path} not found"
    mesh = trimesh.load(mesh_path, force="mesh")
    data = json.loads(map_path.read_text())
    smap = StiffnessMap.from_measured(data["stiffness_locations"], data["stiffness_map"])
    # the experiment's filled-cup mass and centre (mass_kg, convex-hull centre)
    return {"mesh": mesh, "smap": smap, "mass": 0.18, "com": mesh.convex_hull.center_mass}


class Grasp:
    """One candidate grasp with its cached profiles and 6DLS contact sets, and every
    way of evaluating its metrics."""

    def __init__(self, scene: dict, g: dict, cache: LimitSurfaceCache, M: int = M_DEFAULT) -> None:
        self.scene, self.g, self.M = scene, g, M
        t0 = time.perf_counter()
        self.profiles = jaw_profiles(scene["mesh"], g, F0, pad=PAD, closing=CLOSING, allow_scale=True)
        t1 = time.perf_counter()
        params = ModelParameters(M=M)
        self.contacts = [contact_sets(p, "6dls", params, seed=0, cache=cache)[0] for p in self.profiles]
        t2 = time.perf_counter()
        self.build_ms = {"profiles": (t1 - t0) * 1e3, "limit_surfaces": (t2 - t1) * 1e3}
        self.points = np.array([g["p1"], g["p2"]])

    def tasks(self, only: tuple[str, ...] = tuple(TASKS)) -> dict[str, np.ndarray]:
        """Each task's gravity wrenches at its poses (timed with the metric: they depend on
        the grasp axis)."""
        sc = self.scene
        return {t: task_wrenches(t, sc["mass"], sc["com"], self.g["axis"]) for t in only}

    # (d)
    def stiffness(self) -> np.ndarray:
        return self.scene["smap"](self.points)

    # (a), three paths to the same numbers
    def works_reference(self, s) -> dict:
        """The former path: the LP of ``min_grasp_force`` (objective "sum", "outer")
        assembled per pose and solved by ``scipy.optimize.linprog`` (HiGHS), then Eq. 4.5."""
        out = {}
        for t, ws in self.tasks().items():
            res = []
            for w in ws:
                prog = assemble(self.contacts, w, MU, "outer", None, minforce="sum")
                cost = prog.Phi.sum(axis=0) * prog.S
                A_eq, b_eq, G, h, lb, ub = _slack_form(prog)
                bounds = np.column_stack([lb, ub])
                band = np.r_[np.zeros(prog.n), np.ones(12)][None]
                lp = linprog(
                    np.r_[cost, np.zeros(12)],
                    A_ub=sp.csr_matrix(np.vstack([G, band])),
                    b_ub=np.r_[h, config.TOL.resist_rtol],
                    A_eq=sp.csr_matrix(A_eq),
                    b_eq=b_eq,
                    bounds=bounds,
                    method="highs",
                )
                if lp.status != 0:
                    res.append((np.inf, np.inf))
                    continue
                f = np.maximum(prog.contact_solution(self.contacts, lp.x[: prog.n])[1], 0.0)
                res.append((float(f.sum()), work(f, s)))
            out[t] = (max(r[0] for r in res), max(r[1] for r in res))
        return out

    def works_per_pose(self, s) -> dict:
        """``minimal_work`` per pose per task over ``C_outer`` (the reference's LP)."""
        out = {}
        for t, ws in self.tasks().items():
            mw = [minimal_work(self.contacts, w, MU, s, representation="outer") for w in ws]
            out[t] = (max(m.f_sum for m in mw), max(m.W for m in mw))
        return out

    def works_poses(self, s, only: tuple[str, ...] = tuple(TASKS), representation: str = "outer") -> dict:
        """``minimal_work_poses`` on both tasks' poses at once (or the tasks ``only``), over
        ``C_outer`` (the reference's LP) or, ``representation="model"``, the 6DLS itself (the
        experiment's default)."""
        tasks = self.tasks(only)
        mw = minimal_work_poses(
            self.contacts, np.vstack(list(tasks.values())), MU, s, representation=representation
        )
        out, k = {}, 0
        for t, ws in tasks.items():
            part = mw[k : k + len(ws)]
            k += len(ws)
            out[t] = (max(m.f_sum for m in part), max(m.W for m in part))
        return out

    @staticmethod
    def q_work_of(works: dict) -> dict:
        return {t: q_work(W, W_MAX) for t, (_, W) in works.items()}

    # (b)
    @staticmethod
    def q_force_of(works: dict) -> dict:
        return {t: q_force(f, F_MAX) for t, (f, _) in works.items()}

    # (c)
    def q_robust(self) -> dict:
        p = Perturbation(n_samples=ROBUST_SAMPLES)
        return {
            t: min(q_robust(self.contacts, MU, w, p, seed=0) for w in ws) for t, ws in self.tasks().items()
        }

    # totals
    def metric(
        self, only: tuple[str, ...] = tuple(TASKS), representation: str = "outer"
    ) -> tuple[dict, dict]:
        """(d) + (a) + (b): the minimal-work metric of one grasp (q_work, q_force per task)."""
        works = self.works_poses(self.stiffness(), only, representation)
        return self.q_work_of(works), self.q_force_of(works)

    def all_metrics(self) -> tuple[dict, dict, dict]:
        return (*self.metric(), self.q_robust())


def _summary(per_grasp: list[list[float]]) -> dict:
    """ms: median over grasps of each grasp's median, the max of those, and the run spread."""
    med = np.array([np.median(t) for t in per_grasp]) * 1e3
    allt = np.concatenate(per_grasp) * 1e3
    return {
        "median_ms": float(np.median(med)),
        "max_over_grasps_ms": float(med.max()),
        "runs_p10_p90_ms": [float(np.percentile(allt, 10)), float(np.percentile(allt, 90))],
    }


def _profile(fn, n: int, top: int = 6) -> dict:
    """cProfile of ``n`` calls: the top functions by own time, with their share."""
    prof = cProfile.Profile()
    prof.enable()
    for _ in range(n):
        fn()
    prof.disable()
    st = pstats.Stats(prof, stream=io.StringIO())
    total = st.total_tt
    rows = sorted(st.stats.items(), key=lambda kv: kv[1][2], reverse=True)[:top]  # (cc, nc, tt, ct, callers)

    def name(k):
        f, line, fn_ = k
        return fn_ if f == "~" else f"{Path(f).parent.name}/{Path(f).name}:{line}({fn_})"

    cum = sorted(st.stats.items(), key=lambda kv: kv[1][3], reverse=True)
    return {
        "dominant": name(rows[0][0]),
        "top_own_time": [
            {"function": name(k), "share": v[2] / total, "ms_per_call": v[2] / n * 1e3} for k, v in rows
        ],
        "top_cumulative_in_workbench": [
            {"function": name(k), "ms_per_call": v[3] / n * 1e3} for k, v in cum if "/workbench/" in k[0]
        ][:top],
    }


def time_grasp(G: Grasp, repeats: int, robust_repeats: int) -> dict[str, list[float]]:
    """Run times [s] of every part and total on one grasp."""
    s = G.stiffness()
    works = G.works_poses(s)
    return {
        "d_stiffness": _times(G.stiffness, repeats),
        "a_reference": _times(lambda: G.q_work_of(G.works_reference(s)), repeats),
        "a_per_pose": _times(lambda: G.q_work_of(G.works_per_pose(s)), repeats),
        "a_poses": _times(lambda: G.q_work_of(G.works_poses(s)), repeats),
        "a_model": _times(lambda: G.q_work_of(G.works_poses(s, representation="model")), repeats),
        "b_q_force": _times(lambda: G.q_force_of(works), repeats),
        "c_q_robust": _times(G.q_robust, robust_repeats),
        "metric": _times(G.metric, repeats),
        "metric_model": _times(lambda: G.metric(representation="model"), repeats),
        "metric_lifting_only": _times(lambda: G.metric(("vertical_lifting",)), repeats),
        "all_metrics": _times(G.all_metrics, robust_repeats),
    }


def breakdown(G: Grasp, repeats: int) -> dict:
    """Where (a) goes, ms (median of ``repeats``): the task wrenches, the one LP build
    per grasp (assembly and the HiGHS model), a cold HiGHS solve per distinct pose, and
    the warm solves of the poses after the first (each from the one before)."""
    import importlib

    work_mod = importlib.import_module("workbench.grasp.work")  # `work` the function shadows it
    tasks = G.tasks()
    W = np.vstack(list(tasks.values()))
    lp = work_mod._MinForceLP.build(G.contacts, MU, "outer", None)
    ms = {
        "task_wrenches": _times(G.tasks, repeats),
        "lp_build_per_grasp": _times(
            lambda: work_mod._MinForceLP.build(G.contacts, MU, "outer", None), repeats
        ),
        "solve_cold_per_pose": [
            t for w in W[1:] for t in _times(lambda w=w: lp.lp.solve(w * lp.prog.w), repeats)
        ],
    }
    distinct = list({w.tobytes(): w for w in W}.values())

    def warm_chain():  # the first pose cold, then each later one from the one before
        lp.lp.solve(distinct[0] * lp.prog.w)
        t0 = time.perf_counter()
        for w in distinct[1:]:
            lp.lp.solve(w * lp.prog.w, warm=True)
        return (time.perf_counter() - t0) / max(len(distinct) - 1, 1)

    warm_chain()
    ms["solve_warm_per_pose"] = [warm_chain() for _ in range(repeats)]
    out = {k: float(np.median(v) * 1e3) for k, v in ms.items()}
    n = len({w.tobytes() for w in W})
    out["distinct_poses"] = n
    return out


def bench_scene(scene: dict, n_grasps: int, repeats: int, robust_repeats: int) -> dict:
    mesh = scene["mesh"]
    lo, hi = mesh.bounds[:, 2]
    cands = horizontal_grasps(mesh, np.linspace(lo, hi, 10)[1:-1], 6, MU, pad=None)  # the experiment's grid
    cache = LimitSurfaceCache()
    # spread over the candidates (every k-th first), skipping any whose jaw would pull
    step = max(1, len(cands) // n_grasps)
    order = list(range(0, len(cands), step)) + [i for i in range(len(cands)) if i % step]
    grasps = []
    for i in order:
        if len(grasps) == n_grasps:
            break
        try:
            grasps.append(Grasp(scene, cands[i], cache))
        except ValueError:  # the experiment would fail on it too; not a timing question
            continue
    parts = {
        k: []
        for k in ("d_stiffness", "a_reference", "a_per_pose", "a_poses", "a_model", "b_q_force", "c_q_robust")
    }
    totals = {"metric": [], "metric_model": [], "metric_lifting_only": [], "all_metrics": []}
    worst, roundoff = 0.0, 0.0
    for G in grasps:
        for k, v in time_grasp(G, repeats, robust_repeats).items():
            (parts if k in parts else totals)[k].append(v)
        # minimal_work per pose and minimal_work_poses give the same numbers (to round-off:
        # warm solves); the former linprog path, the same optimum (relative differences)
        s = G.stiffness()
        ref, per, poses = G.works_reference(s), G.works_per_pose(s), G.works_poses(s)
        for t in TASKS:
            roundoff = max(roundoff, *(abs(per[t][i] - poses[t][i]) / abs(per[t][i]) for i in (0, 1)))
            if np.isfinite(ref[t][1]):
                worst = max(worst, *(abs(poses[t][i] - ref[t][i]) / ref[t][i] for i in (0, 1)))
    out = {
        "n_grasps": len(grasps),
        "n_candidates": len(cands),
        "build_ms_per_grasp_median": {
            k: float(np.median([G.build_ms[k] for G in grasps])) for k in ("profiles", "limit_surfaces")
        },
        "parts": {k: _summary(v) for k, v in parts.items()},
        "totals": {k: _summary(v) for k, v in totals.items()},
        "paths_per_pose_vs_poses_max_rel_diff": roundoff,  # cold vs warm solves: round-off
        "paths_max_rel_diff": worst,  # poses vs the linprog reference, (Σf, W)
        "lp_rows_per_contact": M_DEFAULT,
        "resisted_fraction": {
            t: float(np.mean([np.isfinite(G.works_poses(G.stiffness())[t][1]) for G in grasps]))
            for t in TASKS
        },
    }
    a = out["parts"]
    out["speedup_a_reference_over_poses"] = a["a_reference"]["median_ms"] / a["a_poses"]["median_ms"]
    out["speedup_a_reference_over_per_pose"] = a["a_reference"]["median_ms"] / a["a_per_pose"]["median_ms"]
    out["metric_within_budget"] = out["totals"]["metric"]["median_ms"] <= BUDGET_MS
    G = grasps[len(grasps) // 2]
    out["breakdown_a_poses_ms"] = breakdown(G, repeats)
    G.metric()
    out["profile_metric"] = _profile(G.metric, 30)
    out["profile_q_work_reference"] = _profile(lambda: G.works_reference(G.stiffness()), 10)
    out["profile_q_robust"] = _profile(G.q_robust, 2)
    return out


def m_sweep(scene: dict, Ms, repeats: int) -> dict:
    """ms of (a) by ``minimal_work_poses`` against the linearisation size M, on one grasp."""
    mesh = scene["mesh"]
    lo, hi = mesh.bounds[:, 2]
    g = horizontal_grasps(mesh, [0.5 * (lo + hi)], 1, MU, pad=None)[0]
    cache = LimitSurfaceCache()
    out = {}
    for M in Ms:
        G = Grasp(scene, g, cache, M=M)
        s = G.stiffness()
        out[str(M)] = float(np.median(_times(lambda G=G, s=s: G.q_work_of(G.works_poses(s)), repeats)) * 1e3)
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "results" / "benchmarks" / "minimal_work.json"))
    args = parser.parse_args()
    n_grasps, repeats, robust_repeats = (3, 7, 3) if args.quick else (8, 15, 7)
    t0 = time.perf_counter()
    load_before = os.getloadavg()
    scenes = {"cylinder_r35mm": cylinder_scene(), "plastic_cup": cup_scene()}
    results = {}
    for name, scene in scenes.items():
        if isinstance(scene, str):
            results[name] = {"skipped": scene}
            print(f"{name}: skipped ({scene})")
            continue
        results[name] = bench_scene(scene, n_grasps, repeats, robust_repeats)
    sweep = m_sweep(scenes["cylinder_r35mm"], (50, 100, 200, 400), repeats)
    load_after = os.getloadavg()
    head = results["plastic_cup"] if "parts" in results["plastic_cup"] else results["cylinder_r35mm"]
    out = {
        "benchmark": "minimal-work metric per grasp, cached profiles and limit surfaces",
        "budget_ms": BUDGET_MS,
        "headline_scene": "plastic_cup" if head is results["plastic_cup"] else "cylinder_r35mm",
        "metric_ms_per_grasp": head["totals"]["metric"]["median_ms"],
        "metric_model_ms_per_grasp": head["totals"]["metric_model"]["median_ms"],
        "all_metrics_ms_per_grasp": head["totals"]["all_metrics"]["median_ms"],
        "metric_within_budget": head["metric_within_budget"],
        "setup": (
            f"horizontal antipodal grasps (the experiment's 8 heights x 6 angles), REACH profiles at "
            f"{F0} N (pad {PAD} m, closing {CLOSING} m), ellipsoidal 6DLS (SDP fit) per jaw, C_outer with "
            f"M = {M_DEFAULT} directions per contact (LP: {2 * M_DEFAULT} + 7 rows, 26 columns; HiGHS "
            f"solves its dual, 26 rows, by the primal simplex), mu = {MU}; "
            f"poses per task {POSES}; q_robust N_r = {ROBUST_SAMPLES} per pose on the 6DLS cones (Clarabel)"
        ),
        "default_M": M_DEFAULT,
        "parts_legend": {
            "d_stiffness": "StiffnessMap at the two contact points",
            "a_reference": "q_work both tasks, the same LP per pose through scipy linprog (the former path)",
            "a_per_pose": "q_work both tasks, minimal_work per pose per task (a build and a cold solve each)",
            "a_poses": "q_work both tasks, minimal_work_poses on the 4 poses, 3 distinct, over C_outer",
            "a_model": "q_work both tasks, minimal_work_poses over the 6DLS (the experiment default)",
            "b_q_force": "q_force from (a)'s minimal forces (standing alone it costs (a))",
            "c_q_robust": f"q_robust, N_r = {ROBUST_SAMPLES} per pose, 4 poses (as the experiment)",
            "metric": "(d) + a_poses + (b): the minimal-work metric per grasp over C_outer",
            "metric_model": "(d) + a_model + (b): the metric as the experiment computes it (the 6DLS itself)",
            "metric_lifting_only": "metric for the lifting task alone (one pose, one LP)",
            "all_metrics": "metric + (c)",
        },
        "scenes": results,
        "m_sweep_a_poses_ms": sweep,
        "machine": {
            **machine_roofline(quick=True),
            "cpu_count": os.cpu_count(),
            "loadavg_1_5_15_before": load_before,
            "loadavg_1_5_15_after": load_after,
        },
        "tolerances": {"resist_rtol": config.TOL.resist_rtol, "work_eps": config.DEFAULTS.work_eps},
        "method": (
            f"one process; per grasp the median of {repeats} runs ({robust_repeats} with q_robust) after a "
            "warm-up, then the median and max over grasps; p10/p90 over all runs show the noise"
        ),
        "versions": versions(),
        "wall_time_s": time.perf_counter() - t0,
    }
    write_json(Path(args.out), out)
    print(f"wrote {args.out}")
    for name, r in results.items():
        if "parts" not in r:
            continue
        diff = r["paths_per_pose_vs_poses_max_rel_diff"]
        print(f"{name} ({r['n_grasps']} grasps, per-pose vs poses: {diff:.1e}):")
        for k, v in {**r["parts"], **r["totals"]}.items():
            print(
                f"  {k:>12}: {v['median_ms']:8.3f} ms (max {v['max_over_grasps_ms']:.3f}, p10-p90 "
                f"{v['runs_p10_p90_ms'][0]:.3f}-{v['runs_p10_p90_ms'][1]:.3f})"
            )
        print(f"  breakdown of a_poses [ms]: {r['breakdown_a_poses_ms']}")
        print(
            f"  dominant (metric): {r['profile_metric']['dominant']}; "
            f"(q_robust): {r['profile_q_robust']['dominant']}"
        )
    print(f"  M sweep (a_poses ms): {sweep}")
    print(
        f"  FMA {out['machine']['fma_gflops_measured']:.1f} GFLOP/s, {os.cpu_count()} cores, "
        f"load {load_before[0]:.2f} -> {load_after[0]:.2f}"
    )


if __name__ == "__main__":
    main()

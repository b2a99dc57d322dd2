"""Grasp-analysis runtimes and cross-checks.

* ``ms_per_grasp``: wrench resistance per grasp from cached contact sets, each
  model, on the elliptic-cylinder parallel-jaw grasp (median over random
  disturbances and grasp forces after a warm-up): the exact path of
  :func:`wrench_resistance` — the ellipsoid itself as a second-order cone for
  6DLS/6DFC/planar, half-spaces for point, soft point and REACH; ``6dls_linearized``
  is the fixed outer polytope (M = 200) for comparison.  The one-off build of
  each model's contact sets is reported separately.
* ``build_plus_solve_ms``: the thesis's per-grasp measure (Tables 4.2 / 4.3) — each model
  built from the contact profiles with an empty limit-surface cache, plus one solve.
* ``lp_vs_hull``: membership of ``−w_ext`` in the 6DLS ``W_L∞`` by the LP over
  vertex weights and by the Qhull facets, on 1,000 random disturbances.
* ``qp_solvers``: every installed qpsolvers backend (and the default "auto") on
  two sizes of the same outer QPs — two 6DLS contacts (12 variables) and REACH
  (32 soft contacts, 66 variables): median time and agreement with an exact LP
  on the same constraints.  They decided ``config.DEFAULTS.qp_solver``.

Writes results/benchmarks/grasp.json.  Run: python benchmarks/bench_grasp.py [--quick]
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from bench_wrench import machine_roofline  # the sibling benchmark's roofline

from workbench import config
from workbench.grasp import build_gws, resists, resists_lp
from workbench.grasp.models import ModelParameters, contact_sets
from workbench.grasp.resistance.program import assemble
from workbench.grasp.resistance.solvers import solve_min_lp
from workbench.grasp.tasks import lever_disturbances
from workbench.limit_surface import LimitSurfaceCache
from workbench.runner.results import versions, write_json
from workbench.sources.scenes import elliptic_cylinder_grasp

ROOT = Path(__file__).resolve().parents[1]
MU = 0.3
#: thesis Tables 4.2/4.3, last column (QP-based grasp analysis per grasp)
THESIS_MS = {"6dls": "236-252", "6dfc": "236-252", "point": "13-14"}


def compare_solvers(sets, W, ref) -> dict:
    """Median time, agreement with the exact decisions ``ref`` and failures of every
    installed qpsolvers backend (and "auto") on the outer QPs of ``sets`` for ``W``."""
    import qpsolvers

    out = {}
    for solver in ["auto", *sorted(qpsolvers.available_solvers)]:
        times, dec, failed = [], [], 0
        for w in W:
            t0 = time.perf_counter()
            # backends' status/conversion warnings are the results counted here, not news
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = resists(sets, w, MU, representation="outer", solver=solver)
            # a backend failing is a result too: counted, decided "no" (the recorded
            # fallback answered instead)
            failed += bool(r.fallbacks)
            dec.append(bool(r) and not r.fallbacks)
            times.append(time.perf_counter() - t0)
        out[solver] = {
            "median_ms": float(np.median(times[1:]) * 1e3),  # the first call imports the backend
            "agree_with_exact_lp": float((np.array(dec) == np.array(ref)).mean()),
            "failures": failed,
        }
    return out


def outer_lp(contacts, w, mu) -> bool:
    """Exact feasibility of the outer program's constraints with zero residual (reference)."""
    prog = assemble(contacts, np.asarray(w, float), mu, "outer", None)
    _, status = solve_min_lp(prog, np.zeros(prog.n))
    return status == "optimal"


def evaluate_one_call(quick: bool) -> dict:
    """ms per :func:`evaluate_grasp` call (verdict + minimal force) with cached profiles and
    limit surfaces, per model, on antipodal grasps of thesis bottle 0014 (skipped when the
    dataset is absent); the one-off profile and model costs are reported beside."""
    import trimesh

    from workbench.grasp import MODELS, CutStore, Jaws, ModelOptions, Task, antipodal_grasps, evaluate_grasp
    from workbench.sources.reach import jaw_profiles

    path = ROOT.parent / "shared/data/thesis_objects/0014_bottle-gen_bottle_100x030x030-03.obj"
    if not path.exists():
        return {"skipped": f"{path} not found"}
    mesh = trimesh.load(path, force="mesh")
    grasps = antipodal_grasps(mesh, 3 if quick else 8, 0.5, seed=1)
    t0 = time.perf_counter()
    profiles = [jaw_profiles(mesh, g, 10.0) for g in grasps]
    profile_ms = (time.perf_counter() - t0) / len(grasps) * 1e3
    cache, cuts = LimitSurfaceCache(), CutStore()
    out = {"grasps": len(grasps), "profiles_ms_per_grasp": profile_ms, "ms_per_call": {}, "first_call_ms": {}}
    for model in MODELS:
        if quick and model == "6dls_quartic":
            continue
        times = []
        for i, (g, prof) in enumerate(zip(grasps, profiles, strict=True)):
            kw = dict(jaws=Jaws(force=10.0), options=ModelOptions(model, 0.5), profiles=prof, cache=cache)
            task = Task(mass=0.3, com=[0, 0, 0])
            t1 = time.perf_counter()
            evaluate_grasp(mesh, g, task, cuts=cuts, **kw)  # first call fits the limit surfaces
            first = (time.perf_counter() - t1) * 1e3
            if i == 0:
                out["first_call_ms"][model] = first
            for _ in range(3):
                t1 = time.perf_counter()
                evaluate_grasp(mesh, g, task, cuts=cuts, **kw)
                times.append(time.perf_counter() - t1)
        out["ms_per_call"][model] = float(np.median(times) * 1e3)
    return out


def time_models(profiles, cache, rng, n_grasps: int) -> tuple[dict, dict, dict]:
    """(ms per grasp, build ms, resisted fraction) per model from cached contact sets, on
    ``n_grasps`` random disturbances and grasp forces drawn from ``rng``."""
    ms, build_ms, resisted = {}, {}, {}
    W = lever_disturbances(rng, n_grasps)
    forces = rng.uniform(20.0, 35.0, n_grasps)
    for name in ("point", "soft_point", "planar", "reach", "6dls", "6dls_quartic", "6dfc", "6dls_linearized"):
        t0 = time.perf_counter()
        base = "6dls" if name == "6dls_linearized" else name
        sets = [c for p in profiles for c in contact_sets(p, base, cache=cache)]
        kw = {"representation": "outer"} if name == "6dls_linearized" else {}
        build_ms[name] = (time.perf_counter() - t0) * 1e3
        scaled = [[c.with_force(c.force * f / 25.0) for c in sets] for f in forces]
        resists(scaled[0], W[0], MU, **kw)  # warm-up (imports)
        times, hits = [], 0
        for i in range(n_grasps):
            t0 = time.perf_counter()
            hits += bool(resists(scaled[i], W[i], MU, **kw))
            times.append(time.perf_counter() - t0)
        ms[name] = float(np.median(times) * 1e3)
        resisted[name] = hits / n_grasps
    return ms, build_ms, resisted


#: the models of Tables 4.2 / 4.3 (their "Point" is the soft point contact, §4.1.4.3)
BUILD_SOLVE_MODELS = ("soft_point", "planar", "6dls", "6dfc")


def time_build_solve(profiles, rng, repeats: int) -> dict:
    """Per model, what the thesis's per-grasp runtime measures: the contact models built from
    the grasp's contact profiles with an empty limit-surface cache (so 6DFC fits its own
    ellipsoid, as 6DLS does, rather than reading 6DLS's) plus one resistance solve — median,
    min and max over ``repeats`` after a warm-up build; the build's share of the median."""
    w = lever_disturbances(rng, 1)[0]
    out = {}
    for name in BUILD_SOLVE_MODELS:
        sets = [c for p in profiles for c in contact_sets(p, name, cache=LimitSurfaceCache())]
        resists(sets, w, MU)  # warm-up: JIT, imports, the solver's first call
        build, total = [], []
        for _ in range(repeats):
            t0 = time.perf_counter()
            sets = [c for p in profiles for c in contact_sets(p, name, cache=LimitSurfaceCache())]
            t1 = time.perf_counter()
            resists(sets, w, MU)
            t2 = time.perf_counter()
            build.append((t1 - t0) * 1e3)
            total.append((t2 - t0) * 1e3)
        out[name] = {
            "median_ms": float(np.median(total)),
            "min_ms": float(np.min(total)),
            "max_ms": float(np.max(total)),
            "build_median_ms": float(np.median(build)),
            "repeats": repeats,
        }
    return out


def lp_vs_hull(profiles, cache, rng, n_hull: int) -> tuple[dict, bool]:
    """Membership of ``-w`` in the 6DLS ``W_L∞`` (inner vertices) by the LP and by the hull's
    facets on ``n_hull`` random disturbances: (agreement and times, whether all agree)."""
    model_sets = [c for p in profiles for c in contact_sets(p, "6dls", ModelParameters(M=40), cache=cache)]
    t0 = time.perf_counter()
    hull = build_gws(model_sets, MU)
    hull_build_s = time.perf_counter() - t0
    Wh = lever_disturbances(rng, n_hull)
    t0 = time.perf_counter()
    lp = np.array([bool(resists_lp(model_sets, w, MU)) for w in Wh])
    lp_ms = (time.perf_counter() - t0) / n_hull * 1e3
    t0 = time.perf_counter()
    hl = hull.contains(-Wh)
    hull_batch_ms = (time.perf_counter() - t0) / n_hull * 1e3
    t_single = []
    for w in Wh[:200]:
        t1 = time.perf_counter()
        hull.contains(-w)
        t_single.append(time.perf_counter() - t1)
    hull_single_ms = float(np.median(t_single) * 1e3)
    return {
        "n": n_hull,
        "agreement": float((lp == hl).mean()),
        "resisted_fraction": float(lp.mean()),
        "minkowski_points": int(len(model_sets[0].friction) * len(model_sets[1].friction)),
        "hull_facets": int(len(hull.equations)),
        "hull_build_s": hull_build_s,
        "lp_ms_per_query": lp_ms,
        "hull_ms_per_query_batched": hull_batch_ms,
        "hull_ms_per_query_single": hull_single_ms,
        "lp_over_hull_time_ratio_single": lp_ms / hull_single_ms,
        "queries_to_amortise_hull": hull_build_s * 1e3 / max(lp_ms - hull_single_ms, 1e-9),
    }, bool(np.array_equal(lp, hl))


def qp_solvers(profiles, cache, rng, quick: bool) -> dict:
    """QP solvers on two sizes of the outer QP vs an exact LP of the same constraints:
    two 6DLS contacts (14 variables) and REACH (32 soft contacts in two force groups,
    2 variables each on their affine hulls + one σ per jaw)."""
    sets6 = [c for p in profiles for c in contact_sets(p, "6dls", cache=cache)]
    sets_reach = [c for p in profiles for c in contact_sets(p, "reach", cache=cache)]
    Wq = lever_disturbances(rng, 100 if quick else 300)
    n6 = assemble(sets6, Wq[0], MU, "outer", None).n
    nr = assemble(sets_reach, Wq[0], MU, "outer", None).n
    return {
        f"6dls_{n6}_variables": compare_solvers(sets6, Wq, [outer_lp(sets6, w, MU) for w in Wq]),
        f"reach_{nr}_variables": compare_solvers(
            sets_reach, Wq[:100], [outer_lp(sets_reach, w, MU) for w in Wq[:100]]
        ),
    }


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "results" / "benchmarks" / "grasp.json"))
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    n_grasps = 60 if args.quick else 300
    n_hull = 200 if args.quick else 1000
    profiles = elliptic_cylinder_grasp(force=25.0)
    cache = LimitSurfaceCache()

    # in this order: each draws its disturbances from rng
    ms, build_ms, resisted = time_models(profiles, cache, rng, n_grasps)
    hull_table, hull_agree = lp_vs_hull(profiles, cache, rng, n_hull)
    solvers = qp_solvers(profiles, cache, rng, args.quick)
    build_solve = time_build_solve(profiles, rng, 3 if args.quick else 7)

    # the one-call evaluation (evaluate_grasp): a thesis bottle, REACH profiles computed once,
    # then per model the verdict + minimal force from cached profiles and limit surfaces
    one_call = evaluate_one_call(quick=args.quick)

    out = {
        "setup": (
            f"elliptic-cylinder parallel-jaw grasp (a=30, b=20 mm, half angle 0.6 rad, length 30 mm, "
            f"power law k=2.4), mu={MU}, forces 20-35 N, {n_grasps} disturbances; outer QP with "
            f"{config.DEFAULTS.qp_solver} via qpsolvers; known forces in [F(1-r), F], "
            f"r = {config.TOL.known_force_rtol}"
        ),
        "ms_per_grasp": ms,
        # one build each in the order above, sharing one cache: 6dfc and 6dls_linearized read
        # the ellipsoid 6dls fitted (build + solve from an empty cache: build_plus_solve_ms)
        "build_ms": build_ms,
        "build_plus_solve_ms": build_solve,
        "resisted_fraction": resisted,
        "thesis_ms_per_grasp": THESIS_MS,
        "lp_vs_hull_agree": hull_agree,
        "lp_vs_hull": hull_table,
        "qp_solvers": solvers,
        "evaluate_grasp": one_call,
        "default_solver": (
            f"{config.DEFAULTS.qp_solver}: quadprog up to {config.DEFAULTS.qp_auto_large} variables, "
            "DAQP above"
        ),
        # this machine's measured FMA throughput beside the timings (machines differ ~7x)
        "machine": machine_roofline(quick=True),
        "versions": versions(),
    }
    write_json(Path(args.out), out)
    print(f"wrote {args.out}")
    for k, v in ms.items():
        print(f"  {k:>11}: {v:.3f} ms per grasp (build {build_ms[k]:.0f} ms, resisted {resisted[k]:.2f})")
    print(
        f"  LP vs hull agree: {out['lp_vs_hull_agree']} ({hull_table['lp_ms_per_query']:.2f} ms vs "
        f"{hull_table['hull_ms_per_query_single']:.3f} ms per query)"
    )
    for k, v in build_solve.items():
        print(f"  build + solve {k:>11}: {v['median_ms']:.1f} ms (build {v['build_median_ms']:.1f})")
    for k, v in one_call.get("ms_per_call", {}).items():
        print(f"  evaluate_grasp {k:>14}: {v:.2f} ms per call (cached profiles and limit surfaces)")
    for size, table in solvers.items():
        for k, v in table.items():
            print(f"  {size} {k:>9}: {v}")


if __name__ == "__main__":
    main()

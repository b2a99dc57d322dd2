"""minimal_work_poses and minimal_work's LP path (benchmarks/bench_minimal_work.py) give
the numbers of min_grasp_force (objective="sum") on every pose, resisted or not, shared
or not, in any order of the poses — the first pose (a cold solve) bit for bit, the later
ones (warm solves, kept only when the optimum is unique) to round-off; and that LP (one
highspy model) has the optimum scipy's linprog finds for the same rows."""

import numpy as np
import pytest

from workbench.grasp import contact_sets, gravity_wrench, min_grasp_force, minimal_work, point_contact
from workbench.grasp.models import ModelParameters
from workbench.grasp.tasks import TASKS, lever_disturbances, task_wrenches
from workbench.grasp.work import displacements, minimal_work_poses
from workbench.sources.scenes import elliptic_cylinder_grasp


def _reference(contacts, w, mu, s, eps=None, representation="outer"):
    """(f_sum, forces, W) as minimal_work computed them: min_grasp_force, then Eq. 4.5."""
    mf = min_grasp_force(contacts, w, mu, objective="sum", representation=representation)
    if not mf.feasible:
        return np.inf, None, np.inf
    f = np.maximum(mf.forces, 0.0)
    return float(f.sum()), f, float(f @ displacements(f, s, eps))


# two factorisations of one optimal basis differ by round-off: ~1e-13 N seen on these
# scenes; 1e-9 relative is four decades above that and two below HiGHS's 1e-7 tolerances
ROUNDOFF = 1e-9


def _same(res, ref, exact: bool = True) -> bool:
    """``res`` (a MinimalWork) is ``ref`` (from _reference): bit for bit, or to round-off."""
    f_sum, f, W = ref
    if f is None:
        return not res.feasible and res.f_sum == np.inf and res.W == np.inf and np.isnan(res.forces).all()
    if exact:
        return res.feasible and res.f_sum == f_sum and res.W == W and np.array_equal(res.forces, f)
    scale = f_sum + 1e-300
    return (
        res.feasible
        and abs(res.f_sum - f_sum) <= ROUNDOFF * scale
        and abs(res.W - W) <= ROUNDOFF * abs(W)
        and np.abs(res.forces - f).max() <= ROUNDOFF * scale
    )


@pytest.fixture(scope="module")
def jaws():
    profiles = elliptic_cylinder_grasp(force=10.0)
    return {
        "6dls": [contact_sets(p, "6dls", ModelParameters(M=60))[0] for p in profiles],
        "point": [
            point_contact([0.03, 0, 0], [1, 0, 0], 10.0),
            point_contact([-0.03, 0, 0], [-1, 0, 0], 10.0),
        ],
    }


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
@pytest.mark.parametrize("model", ["6dls", "point"])
@pytest.mark.parametrize("representation", ["outer", "inner"])
def test_every_pose_is_bitwise_the_min_grasp_force_answer(jaws, model, representation):
    rng = np.random.default_rng(7)
    contacts = jaws[model]
    # lever disturbances (some out of reach) and the two tasks' gravity poses
    W = np.vstack(
        [lever_disturbances(rng, 12) * rng.uniform(0.05, 3.0, (12, 1))]
        + [task_wrenches(t, 0.4, [0.0, 0.0, 0.01], [1.0, 0.0, 0.0]) for t in TASKS]
    )
    s = np.array([600.0, np.inf])
    for mu in (0.3, 0.7):
        refs = [_reference(contacts, w, mu, s, 1e-4, representation) for w in W]
        assert any(r[1] is None for r in refs) or model == "6dls"
        poses = minimal_work_poses(contacts, W, mu, s, eps=1e-4, representation=representation)
        for k, (w, res, ref) in enumerate(zip(W, poses, refs, strict=True)):
            assert _same(res, ref, exact=k == 0), k
            assert _same(minimal_work(contacts, w, mu, s, eps=1e-4, representation=representation), ref)
            assert res.solver == "highs" and res.converged and res.fallbacks == ()
        # the answer does not depend on the poses solved before it
        backwards = minimal_work_poses(contacts, W[::-1], mu, s, eps=1e-4, representation=representation)
        for k, (res, ref) in enumerate(zip(backwards[::-1], refs, strict=True)):
            assert _same(res, ref, exact=k == len(W) - 1), k


def _min_lps(contacts, mu=0.5):
    from workbench import config
    from workbench.grasp.resistance.program import assemble
    from workbench.grasp.resistance.solvers import MinLP

    prog = assemble(contacts, np.ones(6), mu, "outer", None, minforce="sum")
    cost = prog.Phi.sum(axis=0) * prog.S
    return prog, MinLP(prog, cost, config.TOL.resist_rtol), MinLP(prog, cost, config.TOL.resist_rtol)


def _four_points():
    """Two point contacts per jaw: against a pure force the jaws' pairs share the load
    in a one-parameter family of equal Σf — a tie."""
    return [point_contact([0.03, y, 0.0], [1, 0, 0], 10.0) for y in (-0.01, 0.01)] + [
        point_contact([-0.03, y, 0.0], [-1, 0, 0], 10.0) for y in (-0.01, 0.01)
    ]


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_warm_solves_keep_only_unique_optima(jaws):
    """A warm solve returns the cold answer: to round-off when it kept its basis (the
    optimum is unique), bit for bit when it re-solved cold.  On the 6DLS jaws every
    optimum is unique; on four point contacts against a force every one ties."""
    rng = np.random.default_rng(3)
    levers = lever_disturbances(rng, 40) * rng.uniform(0.05, 3.0, (40, 1))
    forces = np.c_[rng.normal(size=(40, 3)), np.zeros((40, 3))]
    for contacts, W, ties in ((jaws["6dls"], levers, False), (_four_points(), forces, True)):
        prog, warm, cold = _min_lps(contacts)
        kept = 0
        for w in W:
            resolves = warm.cold_resolves
            yw, sw = warm.solve(w * prog.w, warm=True)
            yc, sc = cold.solve(w * prog.w)
            assert sw == sc
            if yc is None:
                continue
            if resolves == warm.cold_resolves:  # kept: the same vertex
                kept += 1
                assert np.abs(yw - yc).max() <= ROUNDOFF * np.abs(yc).max()
            else:  # re-solved cold: the cold answer itself
                assert np.array_equal(yw, yc)
        # 6DLS: every warm solve kept (40 of 40 here); points: nearly all re-solved (38 of 40)
        assert warm.cold_resolves == 0 if not ties else warm.cold_resolves >= len(W) // 2
        assert kept >= 10 if not ties else kept < len(W) // 2


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_uniqueness_check_against_a_search_for_other_optima(jaws):
    """MinLP's dual-nondegeneracy test against an independent search: with Σf held at
    its optimum, linprog pushes each variable up and down; a unique optimum moves none."""
    import scipy.sparse as sp
    from scipy.optimize import linprog

    from workbench import config
    from workbench.grasp.resistance.program import assemble
    from workbench.grasp.resistance.solvers import _slack_form

    rng = np.random.default_rng(5)
    cases = [(jaws["6dls"], w) for w in lever_disturbances(rng, 4) * 0.5] + [
        (_four_points(), np.r_[rng.normal(size=3), np.zeros(3)]) for _ in range(3)
    ]
    verdicts = []
    for contacts, w in cases:
        prog, lp, _ = _min_lps(contacts)
        y, status = lp.solve(w * prog.w)
        assert status == "optimal"
        at_w = assemble(contacts, w, 0.5, "outer", None, minforce="sum")
        A_eq, b_eq, G, h, lb, ub = _slack_form(at_w)
        bounds = np.column_stack([lb, ub])
        cost = np.r_[prog.Phi.sum(axis=0) * prog.S, np.zeros(12)]
        band = np.r_[np.zeros(prog.n), np.ones(12)]
        A_ub = sp.csr_matrix(np.vstack([G, cost, band]))
        b_ub = np.r_[h, (cost[: prog.n] @ y) * (1 + 1e-9), config.TOL.resist_rtol]
        moved = 0.0
        for j in range(prog.n):
            for sign in (1.0, -1.0):
                c = np.zeros(prog.n + 12)
                c[j] = sign
                r = linprog(
                    c,
                    A_ub=A_ub,
                    b_ub=b_ub,
                    A_eq=sp.csr_matrix(A_eq),
                    b_eq=b_eq,
                    bounds=bounds,
                    method="highs",
                )
                assert r.status == 0
                moved = max(moved, abs(r.x[j] - y[j]) / max(np.abs(y).max(), 1e-12))
        unique = lp._unique()
        verdicts.append(unique)
        # unique: nothing moves beyond the 1e-9 slack in Σf; a tie moves by O(1)
        assert (moved < 1e-6) == unique, (unique, moved)
    assert any(verdicts) and not all(verdicts)


def _linprog_min_force(prog):
    """(cost, tol, linprog result) of the minimal-force LP of ``prog``, built independently
    of MinLP from _slack_form's rows and solved by scipy's linprog (HiGHS dual simplex)."""
    import scipy.sparse as sp
    from scipy.optimize import linprog

    from workbench import config
    from workbench.grasp.resistance.solvers import _slack_form

    cost, tol = prog.Phi.sum(axis=0) * prog.S, config.TOL.resist_rtol
    A_eq, b_eq, G, h, lb, ub = _slack_form(prog)
    bounds = np.column_stack([lb, ub])
    band = np.r_[np.zeros(prog.n), np.ones(12)][None]
    ref = linprog(
        np.r_[cost, np.zeros(12)],
        A_ub=sp.csr_matrix(np.vstack([G, band])),
        b_ub=np.r_[h, tol],
        A_eq=sp.csr_matrix(A_eq),
        b_eq=b_eq,
        bounds=bounds,
        method="highs-ds",
        # HiGHS's tightest (1e-10, the facets' check): at linprog's default 1e-7 the
        # reference itself broke a facet by 4e-8 and undercut the optimum by 3e-4
        options={"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10},
    )
    return cost, tol, ref


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_min_lp_optimum_is_linprogs(jaws):
    """The highspy model against an independent construction of the same LP through
    scipy.optimize.linprog (dual simplex): the same feasibility and Σf to 1e-9 relative."""
    from workbench.grasp.resistance.program import assemble
    from workbench.grasp.resistance.solvers import solve_min_lp

    rng = np.random.default_rng(11)
    W = np.vstack(
        [lever_disturbances(rng, 12) * rng.uniform(0.05, 3.0, (12, 1))]
        + [task_wrenches(t, 0.4, [0.0, 0.0, 0.01], [1.0, 0.0, 0.0]) for t in TASKS]
    )
    answers = []
    for model in ("6dls", "point"):
        for w in W:
            prog = assemble(jaws[model], w, 0.5, "outer", None, minforce="sum")
            cost, tol, ref = _linprog_min_force(prog)
            y, status = solve_min_lp(prog, cost, tol)
            assert (y is not None) == (ref.status == 0), (status, ref.message)
            answers.append(y is not None)
            if y is not None:
                assert cost @ y == pytest.approx(ref.fun, rel=1e-9, abs=1e-12)
    assert any(answers) and not all(answers)  # both answers occur


@pytest.mark.jit_only("over 15 s as pure Python")
def test_min_lp_meets_the_facets_for_a_light_object():
    """A light object's gravity (50 g) against 10 N jaws on a cylinder (R = 30 mm): the LP's
    facet rows G y <= h are the dual-feasibility conditions of the dual HiGHS solves, and
    unscaled at HiGHS's default tolerance (1e-7) they were violated by ~1e-7 — enough to
    move Σf by 5e-5 relative on these poses (5e-3 on the measured shampoo bottle).  The
    facets must hold to 1e-10 and Σf be linprog's to 1e-9."""
    import trimesh

    from workbench.grasp.resistance.program import assemble
    from workbench.grasp.resistance.solvers import solve_min_lp
    from workbench.grasp.sampling import horizontal_grasps
    from workbench.sources.reach import jaw_profiles

    mesh = trimesh.creation.cylinder(radius=0.03, height=0.2, sections=96)
    lo, hi = mesh.bounds[:, 2]
    g = horizontal_grasps(mesh, np.linspace(lo, hi, 10)[1:-1], 6, 0.5, pad=None)[2]
    profiles = jaw_profiles(mesh, g, 10.0, pad=(0.02, 0.04), closing=1e-3, allow_scale=True)
    contacts = [contact_sets(p, "6dls", ModelParameters(M=200), seed=0)[0] for p in profiles]
    for w in task_wrenches("lift_and_rotate", 0.05, [0.002, 0.0, -0.02], g["axis"]):
        prog = assemble(contacts, w, 0.5, "outer", None, minforce="sum")
        cost, tol, ref = _linprog_min_force(prog)
        y, status = solve_min_lp(prog, cost, tol)
        assert y is not None and ref.status == 0, (status, ref.message)
        G, h = prog.rows("ineq")
        assert (G @ y - h).max() <= 1e-10
        assert cost @ y == pytest.approx(ref.fun, rel=1e-9)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_a_repeated_pose_is_solved_once_and_copied(jaws):
    # lifting and lift-and-rotate share the 0 deg pose
    W = np.vstack([task_wrenches(t, 0.3, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]) for t in TASKS])
    assert np.array_equal(W[0], W[1])
    a, b, *_ = minimal_work_poses(jaws["6dls"], W, 0.5, [500.0, 800.0])
    assert a.W == b.W and np.array_equal(a.forces, b.forces)
    assert a.forces is not b.forces and a.stiffness is not b.stiffness


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_model_representation_is_minimal_work_per_pose(jaws):
    W = np.vstack([gravity_wrench(0.2, [0.0, 0.0, 0.0]), gravity_wrench(0.3, [0.0, 0.0, 0.01])])
    s = [500.0, 800.0]
    got = minimal_work_poses(jaws["6dls"], W, 0.5, s, representation="model")
    for w, res in zip(W, got, strict=True):
        one = minimal_work(jaws["6dls"], w, 0.5, s, representation="model")
        assert res.W == one.W and res.solver == one.solver == "clarabel"


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_minimal_work_poses_rejects_bad_input(jaws):
    with pytest.raises(ValueError, match=r"\(k, 6\)"):
        minimal_work_poses(jaws["6dls"], np.zeros(6), 0.5, [500.0, 500.0])
    with pytest.raises(ValueError, match="w_ext must be finite"):
        minimal_work_poses(jaws["6dls"], np.full((2, 6), np.nan), 0.5, [500.0, 500.0])
    with pytest.raises(ValueError, match="representation"):
        minimal_work_poses(jaws["6dls"], np.zeros((1, 6)), 0.5, [500.0, 500.0], representation="exact")
    assert minimal_work_poses(jaws["6dls"], np.zeros((0, 6)), 0.5, [500.0, 500.0]) == []

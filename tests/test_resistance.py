"""workbench.grasp.resistance: one meaning of "resisted" (Eq. 2.100) by LP, QP and hull, the
minimal grasp force (Eq. 4.4), the cone-solver fallback, bad input."""

import contextlib
from dataclasses import replace

import numpy as np
import pytest
from grasp_helpers import MU, F, antipodal

from workbench import config
from workbench.grasp import (
    build_gws,
    gravity_wrench,
    limit_surface_contact,
    min_grasp_force,
    resists,
    resists_lp,
    wrench_resistance,
)


@pytest.mark.parametrize("method", ["lp", "qp", "hull"])
def test_antipodal_point_contacts_hold_iff_2_mu_F_ge_mg(method):
    n = 64
    for kind, lo, hi in (("inner", np.cos(np.pi / n), 1.0), ("outer", 1.0, 1 / np.cos(np.pi / n))):
        grasp = antipodal(kind, n)
        hull = build_gws(grasp, MU) if method == "hull" else None
        # LP and QP decide by the same relative residual (config.TOL.resist_rtol, in units
        # of the largest contact force ~F): a band of 10x it; the hull's facets to 1e-9
        eps = 10 * config.TOL.resist_rtol if method != "hull" else 1e-6
        for factor, expect in ((lo * (1 - eps), True), (hi * (1 + eps), False)):
            w = gravity_wrench(factor * 2 * MU * F / 9.81, [0, 0, 0])
            if method == "lp":
                got = bool(resists_lp(grasp, w, MU))
            elif method == "qp":
                got = bool(wrench_resistance(grasp, w, MU))
            else:
                got = bool(hull.contains(-w)[0])
            assert got is expect or got == expect, (kind, factor, method)


def test_lp_hull_and_qp_agree_on_random_disturbances():
    grasp = antipodal(soft=0.004, n=8)
    hull = build_gws(grasp, MU)
    rng = np.random.default_rng(3)
    W = rng.normal(size=(150, 6)) * [4, 4, 4, 0.05, 0.1, 0.1]
    lp = np.array([bool(resists_lp(grasp, w, MU)) for w in W])
    qp = np.array([bool(wrench_resistance(grasp, w, MU)) for w in W])
    qp_in = np.array([bool(wrench_resistance(grasp, w, MU, representation="inner")) for w in W])
    hl = hull.contains(-W)
    assert 0.1 < lp.mean() < 0.9  # both outcomes are exercised
    # polygons: the half-spaces describe exactly the vertex polytope, so all four agree
    assert np.array_equal(lp, hl) and np.array_equal(lp, qp) and np.array_equal(lp, qp_in)


def test_min_grasp_force_two_antipodal_points():
    grasp = antipodal(n=64)
    m = min_grasp_force(grasp, gravity_wrench(1.0, [0, 0, 0]), MU, objective="sum")
    # inner 64-gon aligned with gravity: mg / (2 μ) per jaw, less the residual band that
    # "resisted" allows (config.TOL.resist_rtol, relative to the contact force)
    band = 2 * config.TOL.resist_rtol
    assert m.forces == pytest.approx([9.81, 9.81], rel=band)
    assert m.total == pytest.approx(2 * 9.81, rel=band)
    # the common-scale objective: the same forces here (symmetric jaws), as a factor on F
    s = min_grasp_force(grasp, gravity_wrench(1.0, [0, 0, 0]), MU)
    assert s.scale == pytest.approx(9.81 / F, rel=band) and s.total == pytest.approx(2 * 9.81, rel=band)
    m = min_grasp_force(grasp, np.array([0, 0, 0, 1.0, 0, 0]), MU)
    assert m.total == np.inf and not m.feasible  # point contacts cannot resist torque about the axis


def test_bad_input():
    grasp = antipodal()
    with pytest.raises(ValueError, match="at least one contact"):
        resists_lp([], np.zeros(6), MU)
    with pytest.raises(ValueError, match="finite"):
        resists_lp(grasp, np.array([0, 0, np.nan, 0, 0, 0]), MU)
    with pytest.raises(ValueError, match=r"\(6,\)"):
        wrench_resistance(grasp, np.zeros(3), MU)
    # a single point contact cannot hold a weight: a clear False, not an error
    assert not resists_lp(grasp[:1], gravity_wrench(0.1, [0, 0, 0]), MU)
    # a contact with zero force transmits nothing (fixed-force model at F = 0)
    zero = [c.with_force(0.0) for c in grasp]
    assert not resists_lp([replace_cone(c) for c in zero], gravity_wrench(0.01, [0, 0, 0]), MU)
    assert resists_lp(zero, np.zeros(6), MU)
    with pytest.raises(ValueError, match="normal force"):
        grasp[0].with_force(-1.0)


def replace_cone(c):
    from dataclasses import replace

    return replace(c, cone=False)


@contextlib.contextmanager
def _cone_solver_failing():
    """Clarabel "fails" on every resistance cone program (the fallback route runs)."""
    import workbench.grasp.resistance.api as api

    real = api.solve_conic

    def failing(prog, cost=None):
        return (None, "simulated failure") if cost is None else real(prog, cost)

    api.solve_conic = failing
    try:
        yield
    finally:
        api.solve_conic = real


@pytest.mark.jit_only("over 15 s as pure Python")
def test_ellipsoid_socp_matches_the_cutting_planes_and_lies_inside_the_outer_qp():
    from workbench.grasp.models import ModelParameters, contact_sets
    from workbench.sources.scenes import elliptic_cylinder_grasp

    profiles = elliptic_cylinder_grasp(force=25.0, n_elements=200)
    sets = [c for p in profiles for c in contact_sets(p, "6dls", ModelParameters(M=100, n_wrenches=400))]
    rng = np.random.default_rng(4)
    W = np.zeros((40, 6))
    W[:, 1] = -rng.uniform(2, 14, 40)
    W[:, 3] = rng.uniform(-0.025, 0.025, 40) * -W[:, 1]
    W[:, 5] = rng.uniform(-0.04, 0.04, 40) * W[:, 1]
    loose = np.array([bool(wrench_resistance(sets, w, 0.3, representation="outer")) for w in W])
    socp = np.array([bool(wrench_resistance(sets, w, 0.3)) for w in W])
    with _cone_solver_failing():  # the recorded fallback: cutting planes on the ellipsoids
        res = [wrench_resistance(sets, w, 0.3) for w in W]
    assert all(r.fallbacks and r.solver != "clarabel" for r in res)
    assert np.array_equal(socp, [bool(r) for r in res])  # two exact routes to the model's own answer
    # low-rank (flat) ellipsoids: the cone acts in the model's subspace, equalities pin the rest
    for name in ("planar", "3dls_nonplanar"):
        flat = [c for p in profiles for c in contact_sets(p, name, ModelParameters(M=100, n_wrenches=400))]
        a = np.array([bool(wrench_resistance(flat, w, 0.3)) for w in W[:15]])
        with _cone_solver_failing():
            b = np.array([bool(wrench_resistance(flat, w, 0.3)) for w in W[:15]])
        assert np.array_equal(a, b), name
        assert not bool(wrench_resistance(flat, np.array([0, -10 * 25.0, 0, 0, 0, 0]), 0.3))
    assert (loose | ~socp).all() and loose.sum() > socp.sum()  # the fixed outer polytope over-predicts
    assert 0 < socp.mean() < 1


@pytest.mark.jit_only("over 15 s as pure Python")
@pytest.mark.parametrize("model", ["ellipsoid", "quartic"])
def test_single_6dls_contact_resists_exactly_its_own_limit_surface(model, monkeypatch):
    """One 6DLS contact alone: ``w_ext`` is resisted iff ``f_{μF}(-w_ext - F ŵ⊥) <= 1``
    (Eq. 3.26).  Points 3% inside / outside the fitted surface along random
    directions decide the QP (second-order cone for the ellipsoid, cutting planes
    on the quartic) against the model's own value."""
    from workbench import mesh_profile
    from workbench.limit_surface import LimitSurfaceCache, ModelSpec
    from workbench.sources.surface_catalog import S4

    prof = mesh_profile(S4, 600)
    spec = ModelSpec(model="quartic") if model == "quartic" else ModelSpec(method="sdp")
    cm = LimitSurfaceCache().contact_model(prof, 1.0, spec=spec)
    mu, F = 0.4, prof.F
    contact = limit_surface_contact(cm, np.zeros(3), F, M=200)
    ls = cm.limit_surface.scaled(mu * F)
    u = np.random.default_rng(3).standard_normal((30, 6)) * ls.scale
    if model == "quartic":
        # with no cutting-plane round allowed the outer polytope alone would call points
        # just outside the model resisted; unconverged refinement must defer to the inner LP
        fresh = limit_surface_contact(cm, np.zeros(3), F, M=200)
        outside = [-(F * cm.normal_wrench + 1.03 * ls.value(ui) ** -0.25 * ui) for ui in u]
        loose = sum(bool(wrench_resistance([fresh], w, mu, representation="outer")) for w in outside)
        assert loose > 0  # the M = 200 outer polytope is loose in 6D
        monkeypatch.setattr(config, "TOL", replace(config.TOL, max_cut_rounds=0))
        res = [wrench_resistance([fresh], w, mu) for w in outside]
        assert not any(res)
        # exactly the points the outer polytope over-predicted needed the inner-LP fallback
        assert sum(any("did not converge" in f for f in r.fallbacks) for r in res) == loose
        monkeypatch.undo()
    for rho in (0.97, 1.03):
        for ui in u:
            w_ext = -(F * cm.normal_wrench + rho * ls.value(ui) ** (-1 / ls.degree) * ui)
            assert bool(resists([contact], w_ext, mu)) == (rho < 1), (rho, ui)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_highs_lp_equals_scipy_linprog_with_its_duals(seed):
    """The direct HiGHS call (workbench.grasp.resistance.solvers.highs_lp) against scipy's
    linprog(method="highs") on random feasible LPs with equality, inequality and bound rows:
    the same optimum, primal point and equality/inequality marginals (the column generation of
    resists_exact reads the equality duals as its separating direction)."""
    import scipy.sparse as sp
    from scipy.optimize import linprog

    from workbench.grasp.resistance.solvers import highs_lp

    rng = np.random.default_rng(seed)
    n, m_eq, m_ub = 30, 6, 8
    A_eq = rng.standard_normal((m_eq, n))
    A_ub = rng.standard_normal((m_ub, n))
    x0 = rng.uniform(0.1, 1.0, n)  # strictly feasible: every row and bound holds at x0
    c = rng.uniform(0.5, 2.0, n)  # positive costs with x >= 0: bounded
    ub = np.where(rng.random(n) < 0.3, 2.0, np.inf)
    M = np.vstack([A_eq, A_ub])
    M[rng.random(M.shape) < 0.2] = 0.0  # zeros the compressed columns leave out
    M[:, 3] = 0.0  # and an empty column
    b_eq, b_ub = M[:m_eq] @ x0, M[m_eq:] @ x0 + rng.uniform(0.1, 1.0, m_ub)
    ref = linprog(
        c,
        A_ub=M[m_eq:],
        b_ub=b_ub,
        A_eq=M[:m_eq],
        b_eq=b_eq,
        bounds=list(zip([0] * n, ub, strict=True)),
        method="highs",
    )
    assert ref.status == 0
    got = [
        highs_lp(c, form, np.r_[b_eq, np.full(m_ub, -np.inf)], np.r_[b_eq, b_ub], np.zeros(n), ub)
        for form in (M, sp.csc_matrix(M), sp.csr_matrix(M))  # dense or sparse: one model
    ]
    for x, duals, fun in got:
        assert fun == pytest.approx(ref.fun, rel=1e-12)
        np.testing.assert_allclose(x, ref.x, atol=1e-9)
        np.testing.assert_allclose(duals[:m_eq], ref.eqlin.marginals, atol=1e-9)
        np.testing.assert_allclose(duals[m_eq:], ref.ineqlin.marginals, atol=1e-9)
        np.testing.assert_array_equal(x, got[0][0])  # HiGHS got the same arrays
    # an infeasible LP (x >= 0 and Σ x = -1) is no answer
    assert (
        highs_lp(np.ones(3), sp.csc_matrix(np.ones((1, 3))), [-1.0], [-1.0], np.zeros(3), np.full(3, np.inf))
        is None
    )


def test_csc_arrays_of_a_dense_matrix_are_scipys():
    """The compressed columns highs_lp builds from a dense matrix in NumPy: scipy's csc_matrix
    arrays exactly (zeros and negative zeros left out, empty columns, sorted rows)."""
    import scipy.sparse as sp

    from workbench.grasp.resistance.solvers import _csc, _csc_arrays

    rng = np.random.default_rng(3)
    M = rng.standard_normal((7, 12))
    M[rng.random(M.shape) < 0.4] = 0.0
    M[2, 5] = -0.0
    M[:, [0, 9]] = 0.0
    ref = sp.csc_matrix(M)
    for got, want in zip(_csc_arrays(M), (ref.indptr, ref.indices, ref.data), strict=True):
        np.testing.assert_array_equal(got, want)
    # the conic solve's objective: the upper triangle as scipy's triu gives it
    S = M.T @ M
    got, ref = _csc(np.triu(S)), sp.triu(sp.csc_matrix(S)).tocsc()
    for a in ("indptr", "indices", "data"):
        np.testing.assert_array_equal(getattr(got, a), getattr(ref, a))
    assert got.shape == ref.shape


def test_cut_store_rows_follow_every_add_and_eviction():
    """The stacked rows are cached between adds: each add (and the eviction beyond
    config.TOL.max_stored_cuts) shows in the next rows(), which callers cannot modify."""
    from workbench import config
    from workbench.grasp.resistance.cuts import CutStore

    store, model, other = CutStore(), object(), object()
    A, b = store.rows(model)
    assert A.shape == (0, 6) and b.shape == (0,)
    with config.override(max_stored_cuts=3):
        for k in range(5):
            store.add(model, np.full(6, float(k)), float(k))
            A, b = store.rows(model)
            kept = list(range(max(0, k - 2), k + 1))  # the newest three
            np.testing.assert_array_equal(A, np.array([np.full(6, float(j)) for j in kept]))
            np.testing.assert_array_equal(b, np.array(kept, dtype=float))
            assert np.shares_memory(store.rows(model)[0], A)  # a view: no re-stacking
    assert not A.flags.writeable and not b.flags.writeable
    assert store.rows(other)[0].shape == (0, 6) and len(store) == 3


def test_cut_store_rows_handed_out_never_change():
    """rows() are views of the store's buffers: later adds, evictions and the buffer's
    replacement when full leave every view handed out before as it was (against a list
    reference of the newest max_stored_cuts cuts)."""
    from workbench import config
    from workbench.grasp.resistance.cuts import CutStore

    rng = np.random.default_rng(0)
    store, model, ref, held = CutStore(), object(), [], []
    with config.override(max_stored_cuts=40):
        for _ in range(500):
            a, b = rng.standard_normal(6), float(rng.standard_normal())
            store.add(model, a, b)
            ref = (ref + [(a, b)])[-40:]
            A, B = store.rows(model)
            np.testing.assert_array_equal(A, np.array([x for x, _ in ref]))
            np.testing.assert_array_equal(B, np.array([y for _, y in ref]))
            held.append((A, B, A.copy(), B.copy()))
    for A, B, A0, B0 in held:
        np.testing.assert_array_equal(A, A0)
        np.testing.assert_array_equal(B, B0)
    assert len(store) == 40


def test_a_qp_answer_just_outside_the_band_is_redecided_by_the_exact_lp(monkeypatch):
    """An active-set QP stopping at its own tolerance can leave a residual a few times the band on
    a wrench the contacts resist (DAQP: 4.2x on a thesis-bottle grasp that quadprog, proxqp,
    Clarabel and HiGHS all resist).  Simulated here by moving the QP's answer so it leaves 4x the
    band: the residual LP re-decides (resisted, residual at round-off) and the fallback is recorded;
    a QP answer 1000x outside the band is kept (not resisted, no second solve); a genuine "not
    resisted" within the factor is confirmed by the LP and stays the QP's, with no fallback."""
    from workbench import config
    from workbench.grasp import resists
    from workbench.grasp.contacts import soft_point_contact
    from workbench.grasp.resistance import api

    sets = [
        soft_point_contact([0.0, -0.02, 0], [0, -1.0, 0], 10.0, 0.005),
        soft_point_contact([0.0, 0.02, 0], [0, 1.0, 0], 10.0, 0.005),
    ]
    w = np.array([0.0, 0.0, -2.0, 0.0, 0.0, 0.0])  # 2 N down against 2 μ F = 10 N: resisted
    tol = config.TOL.resist_rtol
    honest = resists(sets, w, 0.5, representation="outer")
    assert honest.resisted and not honest.fallbacks
    original = api.solve_l2_qp

    def off_by(factor):
        def solve(prog, solver):
            y = original(prog, solver)
            # a step whose residual is factor * tol: along A6's first column, scaled
            col = prog.A6[:, 0]
            return y + factor * tol / np.linalg.norm(col) * np.eye(len(y))[0]

        return solve

    monkeypatch.setattr(api, "solve_l2_qp", off_by(4.0))
    redecided = resists(sets, w, 0.5, representation="outer")
    assert redecided.resisted and redecided.residual <= 1e-9 and redecided.solver == "highs"
    assert any("the LP decides" in f for f in redecided.fallbacks)
    monkeypatch.setattr(api, "solve_l2_qp", off_by(1000.0))
    kept = resists(sets, w, 0.5, representation="outer")
    assert not kept.resisted and kept.residual == pytest.approx(1000.0 * tol, rel=1e-6)
    assert not kept.fallbacks
    monkeypatch.setattr(api, "solve_l2_qp", original)
    # 11 N down against 2 μ F = 10 N: not resisted whatever the solver; the QP's answer stands
    heavy = resists(sets, [0.0, 0.0, -11.0, 0.0, 0.0, 0.0], 0.5, representation="outer")
    assert not heavy.resisted and not heavy.fallbacks and heavy.solver != "highs"

"""Grasp analysis (workbench.grasp): analytic grasps, GWS inclusions and symmetry,
LP vs hull vs QP agreement, robust metric, bad input."""

import contextlib
from dataclasses import replace

import numpy as np
import pytest

from workbench import config
from workbench.grasp import (
    Perturbation,
    build_gws,
    grasp_map,
    gravity_wrench,
    gws_points,
    limit_surface_contact,
    min_grasp_force,
    point_contact,
    q_robust,
    reach_contacts,
    resists,
    resists_lp,
    soft_point_contact,
    wrench_resistance,
)
from workbench.grasp.gws import WrenchHull

MU, F, A = 0.5, 10.0, 0.03


def _antipodal(kind="inner", n=64, soft=None):
    if soft is None:
        return [
            point_contact([A, 0, 0], [1, 0, 0], F, n_edges=n, kind=kind),
            point_contact([-A, 0, 0], [-1, 0, 0], F, n_edges=n, kind=kind),
        ]
    return [
        soft_point_contact([A, 0, 0], [1, 0, 0], F, soft, n_edges=n, kind=kind),
        soft_point_contact([-A, 0, 0], [-1, 0, 0], F, soft, n_edges=n, kind=kind),
    ]


def test_contact_wrenches_are_forces_at_the_contact_point():
    """Independent reference for Eq. (4.1): a force f at p gives [f, p × f]."""
    p = np.array([0.01, -0.02, 0.03])
    c = point_contact(p, [0.0, 0.6, 0.8], F, n_edges=5)
    V = c.vertices(MU)
    np.testing.assert_allclose(V[:, 3:], np.cross(p, V[:, :3]), atol=1e-14)
    # every vertex on the cone's edge: normal part F, tangential part μF
    n_in = -np.array([0.0, 0.6, 0.8])
    fn = V[:, :3] @ n_in
    np.testing.assert_allclose(fn, F, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(V[:, :3] - fn[:, None] * n_in, axis=1), MU * F, rtol=1e-12)
    G = grasp_map([c, c])
    assert G.shape == (6, 12)


@pytest.mark.parametrize("method", ["lp", "qp", "hull"])
def test_antipodal_point_contacts_hold_iff_2_mu_F_ge_mg(method):
    n = 64
    for kind, lo, hi in (("inner", np.cos(np.pi / n), 1.0), ("outer", 1.0, 1 / np.cos(np.pi / n))):
        grasp = _antipodal(kind, n)
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


def test_soft_point_torsion_limit_is_gamma_F():
    ell = 0.004  # γ = μ ℓ
    grasp = _antipodal(soft=ell, n=8)
    # one contact's largest torque about its normal
    tau_n = grasp[0].vertices(MU)[:, 3:] @ np.array([-1.0, 0, 0])
    assert tau_n.max() == pytest.approx(MU * ell * F, rel=1e-12)
    # one tolerance for both routes: a band of 10x config.TOL.resist_rtol
    band = 10 * config.TOL.resist_rtol
    for factor, expect in ((1 - band, True), (1 + band, False)):
        w = np.array([0, 0, 0, factor * 2 * MU * ell * F, 0, 0])  # torque about the grasp axis
        assert bool(resists_lp(grasp, w, MU)) == expect
        assert bool(wrench_resistance(grasp, w, MU)) == expect


def _three_finger():
    pts = [np.array([np.cos(a), np.sin(a), 0.0]) * A for a in (0.0, 2.1, 4.0)]
    return [soft_point_contact(p, p / A + [0, 0, 0.2], F, 0.003, n_edges=6) for p in pts]


def test_l1_inside_linf_and_strictly_smaller():
    grasp = _three_finger()
    l1 = gws_points(grasp, MU, "l1")
    linf = build_gws(grasp, MU, "linf")
    assert linf.dim == 6
    assert linf.contains(l1, tol=1e-9).all()
    # and not the other way round: some Minkowski-sum points lie outside W_L1
    l1_hull = WrenchHull.from_points(l1)
    assert not l1_hull.contains(gws_points(grasp, MU, "linf")).all()
    # LP membership says the same for the union vertices
    assert all(resists_lp(grasp, -w, MU, "linf") for w in l1[::7])


def test_gws_of_mirror_symmetric_contacts_is_symmetric():
    grasp = _antipodal(soft=0.004, n=8)
    hull = build_gws(grasp, MU)
    pts = gws_points(grasp, MU)
    # mirror x -> -x swaps the two contacts; forces reflect, torques are pseudovectors
    Mx = np.diag([-1.0, 1, 1, 1, -1, -1])
    My = np.diag([1.0, -1, 1, -1, 1, -1])
    for M in (Mx, My):
        assert hull.contains(pts @ M.T, tol=1e-9).all()
    # gravity up or down is resisted alike
    w = gravity_wrench(0.8, [0.0, 0.0, 0.0])
    assert bool(resists_lp(grasp, w, MU)) == bool(resists_lp(grasp, w * [1, 1, -1, 1, 1, -1], MU))


def test_lp_hull_and_qp_agree_on_random_disturbances():
    grasp = _antipodal(soft=0.004, n=8)
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


def test_epsilon_metric_of_a_symmetric_grasp():
    grasp = _three_finger()
    hull = build_gws(grasp, MU, torque_length=A)
    eps = hull.epsilon()
    assert eps > 0
    # the ball of radius ε is inside: random directions at 0.999 ε are members
    rng = np.random.default_rng(0)
    d = rng.normal(size=(200, 6))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    assert hull.contains(0.999 * eps * d).all()
    assert build_gws(_antipodal(), MU).epsilon() == 0.0  # 5-dimensional GWS: no ball fits


def test_min_grasp_force_two_antipodal_points():
    grasp = _antipodal(n=64)
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


def test_q_robust_deterministic_and_bounded():
    grasp = _antipodal(soft=0.004, n=16)
    none = Perturbation(n_samples=5, sigma_trans=0, sigma_rot=0, sigma_mu=0, sigma_mass=0, sigma_com=0)
    assert q_robust(grasp, MU, 0.9 * 2 * MU * F / 9.81, [0, 0, 0], none) == 1.0
    assert q_robust(grasp, MU, 1.1 * 2 * MU * F / 9.81, [0, 0, 0], none) == 0.0
    p = Perturbation(n_samples=40)
    m = 1.0 * 2 * MU * F / 9.81  # at the limit: perturbations split the outcomes
    q1 = q_robust(grasp, MU, m, [0, 0, 0.005], p, seed=7)
    assert q1 == q_robust(grasp, MU, m, [0, 0, 0.005], p, seed=7)
    assert 0.0 < q1 < 1.0
    assert q_robust(grasp, MU, 0.5 * m, [0, 0, 0.005], p, seed=7) >= q1


def test_q_robust_rotations_are_rodrigues_of_the_sampled_vectors():
    # q_robust perturbs the contacts by scipy's Rotation.from_rotvec; Rodrigues' formula
    # written out (tests/naive.py, what it used before) gives the same matrices to round-off
    from naive import rodrigues
    from scipy.spatial.transform import Rotation

    v = np.vstack([np.zeros(3), np.random.default_rng(3).normal(0.0, 0.2, (200, 3)), [[0, 0, np.pi - 1e-9]]])
    R = Rotation.from_rotvec(v).as_matrix()
    assert np.abs(R - rodrigues(v)).max() < 5e-15 and np.array_equal(R[0], np.eye(3))


def test_six_dls_contact_vertices_lie_on_the_model():
    from workbench.limit_surface import LimitSurfaceCache
    from workbench.sources.surface_catalog import S2
    from workbench.sources.surfaces import mesh_profile

    prof = mesh_profile(S2, 300, pressure_scale=1e4)
    model = LimitSurfaceCache().contact_model(prof, mu=1.0)
    c = limit_surface_contact(model, prof.pressure_center, prof.F, M=100)
    local = c.local_vertices(1.0)
    np.testing.assert_allclose(model.value(local, prof.F), 1.0, atol=1e-9)
    # object frame: the pressure centre is the torque reference
    V = c.vertices(1.0)
    np.testing.assert_allclose(
        V[:, 3:] - local[:, 3:], np.cross(prof.pressure_center, local[:, :3]), atol=1e-12
    )


def test_six_dls_outer_qp_contains_the_inner_gws():
    """Outer half-spaces (Eq. 3.28) contain the inner vertices (Eq. 3.27): whatever the
    inner LP resists, the outer QP resists; the 6DFC (force up to F) contains the 6DLS."""
    from workbench.limit_surface import LimitSurfaceCache
    from workbench.sources.surface_catalog import S2
    from workbench.sources.surfaces import mesh_profile

    prof = mesh_profile(S2, 300, pressure_scale=1e4)
    # the other jaw: a half-turn about an axis normal to the net contact force, through a
    # point beyond the pressure centre, so the two normal forces oppose (a parallel-jaw grasp)
    n = prof.normal_wrench[:3] / np.linalg.norm(prof.normal_wrench[:3])  # the force on the object
    axis = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    axis /= np.linalg.norm(axis)
    R = 2 * np.outer(axis, axis) - np.eye(3)
    # object centre inside: along the normal force, which points into the object (an
    # earlier version went the other way and built a pulling grasp; the check now warns)
    centre = prof.pressure_center + 0.5 * n
    mirror = prof.transformed(R, centre - R @ centre)
    cache = LimitSurfaceCache()
    grasp, cones = [], []
    for p in (prof, mirror):
        m = cache.contact_model(p, mu=1.0)
        grasp.append(limit_surface_contact(m, p.pressure_center, p.F, M=150))
        cones.append(limit_surface_contact(m, p.pressure_center, p.F, M=150, cone=True, name="6DFC"))
    rng = np.random.default_rng(1)
    Fs = grasp[0].force
    W = rng.normal(size=(60, 6)) * np.r_[np.full(3, 0.6 * Fs), np.full(3, 0.3 * Fs)]
    inner = np.array([bool(resists_lp(grasp, w, 1.0)) for w in W])
    outer = np.array([bool(wrench_resistance(grasp, w, 1.0)) for w in W])
    cone = np.array([bool(wrench_resistance(cones, w, 1.0)) for w in W])
    assert 0 < inner.sum() and not outer.all()
    assert (outer | ~inner).all() and (cone | ~outer).all()


def test_reach_clusters_keep_the_normal_wrench():
    """Merging a curved profile's elements keeps its normal wrench exactly (force and
    moment, reference: the profile's own Eq. 3.2 wrench moved to the origin); the
    scalar forces then sum to between |net force| and Σ p a (normals spread)."""
    from workbench.sources.surface_catalog import S3
    from workbench.sources.surfaces import mesh_profile

    prof = mesh_profile(S3, 400, pressure_scale=1e4)
    subs = reach_contacts(prof, max_triangles=32)
    assert 1 <= len(subs) <= 32
    assert all(not s.cone for s in subs) and len({s.group for s in subs}) == 1
    wn = prof.normal_wrench
    ref = np.r_[wn[:3], wn[3:] + np.cross(prof.pressure_center, wn[:3])]  # about the origin
    got = sum(s.G @ (s.force * s.normal) for s in subs)
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * prof.F)
    total = sum(s.force for s in subs)
    assert np.linalg.norm(wn[:3]) <= total <= prof.F
    assert total < 0.99 * prof.F  # S3 is curved: the scalar sum would overstate the force
    # a second call is a second jaw: its own force group
    assert reach_contacts(prof, max_triangles=32)[0].group != subs[0].group


def test_bad_input():
    grasp = _antipodal()
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


def test_every_model_on_the_elliptic_cylinder_grasp():
    from workbench.grasp.models import MODELS, contact_sets, planar_profile
    from workbench.limit_surface import LimitSurfaceCache
    from workbench.sources.scenes import elliptic_cylinder_grasp

    profiles = elliptic_cylinder_grasp(force=25.0, n_elements=200)
    # the force-sensor convention: the grasp-axis normal force of each jaw is F
    assert -profiles[0].normal_wrench[0] == pytest.approx(25.0, rel=1e-12)
    flat = planar_profile(profiles[0])
    assert flat.F == pytest.approx(profiles[0].F, rel=1e-12)
    assert np.allclose(np.abs(flat.normals[:, 0]), 1.0)  # projected onto the yz-plane
    cache = LimitSurfaceCache()
    mu = 0.3
    lift = np.array([0, -0.9 * 2 * mu * 25.0, 0, 0, 0, 0])  # a weight along -y
    twist = np.array([0, 0, 0, 0.02, 0, 0])  # torque about the grasp axis
    for name in MODELS:
        sets = [c for p in profiles for c in contact_sets(p, name, cache=cache, M=100, n_wrenches=400)]
        # outer QP where the model has half-spaces (the thesis's QP), else the exact LP
        assert resists(sets, lift, mu), name  # friction force ~2μF > 0.9·2μF
        assert resists(sets, np.zeros(6), mu), name
        if name == "point":
            assert not resists(sets, twist, mu)  # no torsional friction
        else:
            assert resists(sets, twist, mu), name
    with pytest.raises(ValueError, match="model must be one of"):
        contact_sets(profiles[0], "ellipsoid")


def _disc(R=0.01, x=0.03, n_r=12, n_t=36, p=1e4, outward=1.0):
    """Flat disc contact in the plane x = ±x0 (normal ±x outward), uniform pressure."""
    from workbench.profile import ContactProfile

    r_edges = np.linspace(0, R, n_r + 1)
    rc = 0.5 * (r_edges[1:] + r_edges[:-1])
    th = (np.arange(n_t) + 0.5) * 2 * np.pi / n_t
    Rr, Th = np.meshgrid(rc, th, indexing="ij")
    area = (np.pi * (r_edges[1:] ** 2 - r_edges[:-1] ** 2) / n_t)[:, None] * np.ones(n_t)
    centers = np.column_stack(
        [np.full(Rr.size, outward * x), (Rr * np.cos(Th)).ravel(), (Rr * np.sin(Th)).ravel()]
    )
    normals = np.tile([outward, 0.0, 0.0], (Rr.size, 1))
    return ContactProfile(centers, normals, area.ravel(), np.full(Rr.size, p))


def test_exact_resistance_of_two_flat_discs():
    """Column generation with the exact support: the friction force limit 2μF and the
    torsion limit 2μ Σ p a |r| of the discretised discs, to 10x the resistance tolerance
    (config.TOL.resist_rtol) — no polygon, no sampling."""
    from workbench.grasp.exact import ExactContacts, resists_exact

    discs = [_disc(), _disc(outward=-1.0)]
    ex = ExactContacts(discs, n_start=60)
    Fd = discs[0].F
    torsion = MU * float((discs[0].forces * np.linalg.norm(discs[0].centers[:, 1:], axis=1)).sum())
    band = 10 * config.TOL.resist_rtol
    for factor, expect in ((1 - band, True), (1 + band, False)):
        assert resists_exact(ex, np.array([0, 0, -factor * 2 * MU * Fd, 0, 0, 0]), MU)[0] == expect
        assert resists_exact(ex, np.array([0, 0, 0, factor * 2 * torsion, 0, 0]), MU)[0] == expect
    # the sampled 6DFW hull is an inner approximation of the same set
    from workbench.grasp.models import contact_sets

    rng = np.random.default_rng(2)
    W = rng.normal(size=(40, 6)) * np.r_[np.full(3, 0.8 * MU * Fd), np.full(3, 1.2 * torsion)]
    W[:, 0] = 0.0  # nothing along the grasp axis
    hull = [c for d in discs for c in contact_sets(d, "6dfw", n_wrenches=300)]
    dense = np.array([bool(resists_lp(hull, w, MU)) for w in W])
    exact = np.array([resists_exact(ex, w, MU)[0] for w in W])
    assert (exact | ~dense).all() and 0 < exact.mean() < 1


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


def test_ellipsoid_socp_matches_the_cutting_planes_and_lies_inside_the_outer_qp():
    from workbench.grasp.models import contact_sets
    from workbench.sources.scenes import elliptic_cylinder_grasp

    profiles = elliptic_cylinder_grasp(force=25.0, n_elements=200)
    sets = [c for p in profiles for c in contact_sets(p, "6dls", M=100, n_wrenches=400)]
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
        flat = [c for p in profiles for c in contact_sets(p, name, M=100, n_wrenches=400)]
        a = np.array([bool(wrench_resistance(flat, w, 0.3)) for w in W[:15]])
        with _cone_solver_failing():
            b = np.array([bool(wrench_resistance(flat, w, 0.3)) for w in W[:15]])
        assert np.array_equal(a, b), name
        assert not bool(wrench_resistance(flat, np.array([0, -10 * 25.0, 0, 0, 0, 0]), 0.3))
    assert (loose | ~socp).all() and loose.sum() > socp.sum()  # the fixed outer polytope over-predicts
    assert 0 < socp.mean() < 1


def test_reach_profile_of_a_sphere_is_winkler():
    """Flat pad closing δ on a sphere: F = π R k δ² (Winkler, δ ≪ R), contact on the axis."""
    import trimesh

    from workbench.sources.reach import reach_profile

    R, k, d = 0.03, 2e8, 1e-3
    s = trimesh.creation.icosphere(subdivisions=5, radius=R)
    p = reach_profile(s, [0, R, 0], [0, -1, 0], [0, 0, 1], closing=d, stiffness=k, max_edge=0.5e-3)
    assert p.F == pytest.approx(np.pi * R * k * d**2, rel=0.01)
    np.testing.assert_allclose(p.pressure_center[[0, 2]], 0.0, atol=1e-4)
    assert np.sqrt(np.hypot(p.centers[:, 0], p.centers[:, 2]).max() ** 2) == pytest.approx(
        np.sqrt(2 * R * d), rel=0.05
    )
    open_mesh = trimesh.Trimesh(s.vertices, s.faces[:-10])
    with pytest.raises(ValueError, match="watertight"):
        reach_profile(open_mesh, [0, R, 0], [0, -1, 0])
    with pytest.raises(ValueError, match="covers no part"):
        reach_profile(s, [0.5, R, 0], [0, -1, 0])


def test_antipodal_grasps_on_a_sphere_and_a_standing_cylinder():
    import trimesh

    from workbench.grasp.sampling import antipodal_grasps

    R, mu = 0.03, 0.3
    g = antipodal_grasps(trimesh.creation.icosphere(subdivisions=4, radius=R), 30, mu, seed=0, pad=None)
    assert len(g) == 30
    half = np.arctan(mu)
    for x in g:
        assert np.arccos(-x["n1"] @ x["axis"]) <= half + 1e-9
        assert np.arccos(x["n2"] @ x["axis"]) <= half + 1e-9
        # a chord within the friction cone passes within R sin(atan μ) of the centre
        assert np.linalg.norm(x["center"]) <= R * np.sin(half) + 1e-3
    cyl = trimesh.creation.cylinder(radius=R, height=0.1)  # z from -0.05 to 0.05
    g = antipodal_grasps(cyl, 20, mu, seed=1, table_z=-0.05, clearance=0.02, max_width=0.07, pad=None)
    assert len(g) == 20
    assert all(min(x["p1"][2], x["p2"][2]) >= -0.03 and x["width"] <= 0.07 for x in g)
    again = antipodal_grasps(cyl, 20, mu, seed=1, table_z=-0.05, clearance=0.02, max_width=0.07, pad=None)
    assert all(np.array_equal(a["p1"], b["p1"]) for a, b in zip(g, again, strict=True))  # seeded


def test_grasp_pipeline_on_a_thesis_object_if_available():
    """Antipodal sampling -> REACH profiles -> 6DLS -> resistance of the bottle's own weight."""
    from pathlib import Path

    import trimesh

    from workbench.grasp.models import contact_sets
    from workbench.grasp.sampling import antipodal_grasps
    from workbench.sources.jaws import with_axis_force
    from workbench.sources.reach import reach_profile

    path = (
        Path(__file__).resolve().parents[2]
        / "shared/data/thesis_objects/0006_bottle-gen_smoothie_150x040x040-04.obj"
    )
    if not path.exists():
        pytest.skip("thesis objects not available")
    mesh = trimesh.load(path, force="mesh")
    grasps = antipodal_grasps(mesh, 3, 0.5, seed=0, table_z=0.0, clearance=0.03, max_width=0.1)
    assert grasps
    g = grasps[0]
    # both jaws press with the same grasp-axis force (a force-sensor reading, §4.1.3.2)
    F = 10.0
    profiles = [
        with_axis_force(reach_profile(mesh, g["p1"], g["axis"], closing=1e-3, max_edge=1e-3), g["axis"], F),
        with_axis_force(reach_profile(mesh, g["p2"], -g["axis"], closing=1e-3, max_edge=1e-3), g["axis"], F),
    ]
    assert all(len(p) > 10 for p in profiles)
    sets = [c for p in profiles for c in contact_sets(p, "6dls", M=100, n_wrenches=400)]
    light = gravity_wrench(0.2 * 0.5 * F / 9.81, mesh.center_mass)
    heavy = gravity_wrench(5 * 0.5 * F / 9.81, mesh.center_mass)
    assert resists(sets, light, 0.5) and not resists(sets, heavy, 0.5)


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


def test_force_group_hull_matches_the_program():
    """The GWS of force-grouped contacts (one Minkowski block per group, at full force and
    at (1 − r)) holds exactly the wrenches the grouped program resists (inner vertices):
    two jaws of two point elements each, known forces, one reading per jaw."""
    jaws = []
    for side, g in ((1.0, "jaw-a"), (-1.0, "jaw-b")):
        for dz in (-0.01, 0.01):
            c = point_contact([side * A, 0, dz], [side, 0, 0], F / 2, n_edges=4)
            jaws.append(replace(c, cone=False, group=g))
    hull = build_gws(jaws, MU)
    rng = np.random.default_rng(5)
    W = np.c_[rng.normal(0, 0.25 * F, (300, 3)), rng.normal(0, 0.25 * F * A, (300, 3))]
    W[:, 0] *= 0.05  # along the grasp axis only the force mismatch (1 %) is reachable
    inside = hull.contains(-W)
    lp = np.array([bool(resists(jaws, w, MU, representation="inner")) for w in W])
    qp = np.array([bool(resists(jaws, w, MU)) for w in W])
    assert 20 < inside.sum() < 280
    assert (inside == lp).mean() >= 0.99 and (lp == qp).mean() >= 0.99  # boundary cases aside (measured: 1.0)
    with pytest.raises(ValueError, match="max_points"):
        gws_points(jaws, MU, max_points=100)

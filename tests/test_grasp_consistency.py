"""One meaning of "resisted": resists, min_grasp_force and q_robust agree on
every contact model; known-force models tolerate jaw-force mismatch; the one-call
evaluation reaches the same verdict; edge contacts are filtered.  evaluate_grasp's own
behaviour (force scaling, profile checks, closed forms) is tested in test_evaluate.py."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from workbench import config
from workbench.grasp import (
    MODELS,
    CutStore,
    Jaws,
    ModelOptions,
    Perturbation,
    Task,
    antipodal_grasps,
    contact_sets,
    evaluate_grasp,
    gravity_wrench,
    min_grasp_force,
    q_robust,
    resists,
)
from workbench.grasp.exact import ExactContacts, resists_exact
from workbench.grasp.models import ModelParameters
from workbench.limit_surface import LimitSurfaceCache
from workbench.sources.scenes import elliptic_cylinder_grasp

MU = 0.5
BOTTLE = (
    Path(__file__).resolve().parents[2]
    / "shared/data/thesis_objects/0014_bottle-gen_bottle_100x030x030-03.obj"
)
NO_NOISE = Perturbation(n_samples=2, sigma_trans=0, sigma_rot=0, sigma_mu=0, sigma_mass=0, sigma_com=0)


@pytest.fixture(scope="module")
def scene():
    """Elliptic-cylinder grasp, 10 N per jaw, jaw 2's pressures × 1.0002 (a 0.02 % force
    mismatch, as every real pair of profiles has), and a cache shared by the models."""
    profiles = elliptic_cylinder_grasp(force=10.0, n_elements=200)
    profiles[1] = profiles[1].with_pressures(profiles[1].pressures * 1.0002)
    return profiles, LimitSurfaceCache()


def _scaled(sets, s):
    return [c.with_force(c.force * s) for c in sets]


def _agree(sets, w, cuts):
    """min_grasp_force's scale s*: resists (and q_robust without noise) is True at
    1.03 s* and False at 0.97 s*."""
    m = min_grasp_force(sets, w, MU, cuts=cuts)
    assert m.feasible and m.converged and not m.fallbacks
    for factor, expect in ((1.03, True), (0.97, False)):
        grasp = _scaled(sets, factor * m.scale)
        r = resists(grasp, w, MU, cuts=cuts)
        assert bool(r) is expect, (factor, r)
        assert q_robust(grasp, MU, w, NO_NOISE, cuts=cuts) == float(expect)
    return m


@pytest.mark.jit_only("over 15 s as pure Python")
@pytest.mark.parametrize("model", [m for m in MODELS if m != "point"])
def test_three_grasp_functions_agree_on_the_elliptic_cylinder(scene, model):
    profiles, cache = scene
    params = ModelParameters(M=100, n_wrenches=400)
    sets = [c for p in profiles for c in contact_sets(p, model, params, cache=cache)]
    w = gravity_wrench(0.3, [0.0, 0.0, 0.01])
    m = _agree(sets, w, CutStore())
    # friction carries the weight: Coulomb gives μ Σ f >= mg, so Σ f >= mg / μ — exactly for
    # the unfitted models (polygons, sampled 6DFWs, REACH); a fitted limit surface may exceed
    # the true wrench set by its fitting error (measured: the 6DLS ellipsoid 0.6 % below)
    fitted = model in ("planar", "3dls_nonplanar", "6dls", "6dls_quartic", "6dfc")
    assert m.total >= 0.3 * 9.81 / MU * (1 - (0.02 if fitted else 1e-6)), m.total
    assert m.scale <= 1.0  # the grasp holds at the scene's 10 N


def test_point_contacts_never_resist_torsion_about_the_grasp_axis(scene):
    """Two hard point contacts on the grasp axis have no torque about it: the gravity
    wrench at a COM off the axis is out of reach at any force — all three functions say so."""
    profiles, cache = scene
    sets = [c for p in profiles for c in contact_sets(p, "point", cache=cache)]
    w = gravity_wrench(0.3, [0.0, 0.01, 0.0])  # τ_x = −0.01 · mg about the grasp axis x
    assert not min_grasp_force(sets, w, MU).feasible
    assert not resists(_scaled(sets, 100.0), w, MU)
    assert q_robust(_scaled(sets, 100.0), MU, w, NO_NOISE) == 0.0


@pytest.mark.jit_only("over 15 s as pure Python")
@pytest.mark.parametrize("model", ["planar", "3dls_nonplanar", "6dls", "6dfc"])
def test_known_force_models_are_continuous_in_the_jaw_forces(model):
    """With jaw 2 × 1.0002 the planar 3DLS used to be False at every force from
    3 to 50 N.  Within the sensor interval (config.TOL.known_force_rtol) the verdict is the
    same as for exactly equal forces; beyond it a force-known planar contact, which has no
    normal freedom, cannot balance the axis force (the documented limit)."""
    w = gravity_wrench(0.3, [0.0, 0.0, 0.01])
    cache = LimitSurfaceCache()
    r = config.TOL.known_force_rtol
    for force in (2.0, 10.0, 50.0):  # 0.3 kg at μ = 0.5 needs ~2.9 N per jaw
        verdicts = []
        for mismatch in (1.0, 1.0002, 1 + 0.5 * r):
            prof = elliptic_cylinder_grasp(force=force, n_elements=150)
            prof[1] = prof[1].with_pressures(prof[1].pressures * mismatch)
            params = ModelParameters(M=100, n_wrenches=300)
            sets = [c for p in prof for c in contact_sets(p, model, params, cache=cache)]
            verdicts.append(bool(resists(sets, w, MU)))
        assert verdicts == [force >= 10.0] * 3, (force, verdicts)  # the same at every mismatch
    if model in ("planar", "3dls_nonplanar"):
        prof = elliptic_cylinder_grasp(force=10.0, n_elements=150)
        prof[1] = prof[1].with_pressures(prof[1].pressures * (1 + 3 * r))
        params = ModelParameters(M=100, n_wrenches=300)
        sets = [c for p in prof for c in contact_sets(p, model, params, cache=cache)]
        assert not resists(sets, w, MU)


@pytest.mark.jit_only("over 15 s as pure Python")
def test_min_grasp_force_of_the_sampled_6dfw_bounds_the_exact_one_from_above(scene):
    """Independent reference: the exact 6DFW set (column generation on the true profile's
    support function) contains the hull of any sample of its wrenches, so the sampled
    6DFW's minimal force is at least the exact one — and the ellipsoid's is close to both."""
    profiles, cache = scene
    w = gravity_wrench(0.3, [0.0, 0.0, 0.01])
    ex = ExactContacts(profiles, n_start=200)
    lo, hi = 0.05, 1.0  # bisection on the common force scale with the exact solver
    assert resists_exact(ex, w, MU, forces=ex.F * hi)[0] and not resists_exact(ex, w, MU, forces=ex.F * lo)[0]
    for _ in range(14):
        mid = np.sqrt(lo * hi)
        lo, hi = (lo, mid) if resists_exact(ex, w, MU, forces=ex.F * mid)[0] else (mid, hi)
    s_exact = hi
    params = ModelParameters(n_wrenches=600)
    sampled = min_grasp_force([c for p in profiles for c in contact_sets(p, "6dfw", params)], w, MU)
    ell = min_grasp_force([c for p in profiles for c in contact_sets(p, "6dls", cache=cache)], w, MU)
    assert sampled.scale >= s_exact * (1 - 2e-3)
    assert sampled.scale <= 1.15 * s_exact  # 600 samples miss little of this set
    assert abs(ell.scale / s_exact - 1) < 0.15, (ell.scale, s_exact)


def test_thesis_objective_sum_over_independent_forces():
    """Eq. 4.4 as published (objective="sum", C_outer by name): per-contact forces are free;
    for two symmetric soft point contacts it equals the common-scale answer."""
    profiles = elliptic_cylinder_grasp(force=10.0, n_elements=150)
    sets = [c for p in profiles for c in contact_sets(p, "soft_point")]
    w = gravity_wrench(0.3, [0.0, 0.0, 0.0])
    a = min_grasp_force(sets, w, MU, objective="sum", representation="outer")
    b = min_grasp_force(sets, w, MU)
    # one is an LP (L1 residual band), the other a cone program (L2 band): equal to 10 tol
    assert a.total == pytest.approx(b.total, rel=10 * config.TOL.resist_rtol)
    # the inner 8-gon (local x = object z for a normal along x) has a vertex along −z:
    # mg along it needs exactly mg / (2 μ) per jaw
    # (to the residual band, config.TOL.resist_rtol of the contacts' capacity ~F (1 + μ))
    band = 2 * config.TOL.resist_rtol * 10.0 * (1 + MU)
    assert a.forces == pytest.approx([0.3 * 9.81 / (2 * MU)] * 2, abs=band)


def test_bad_inputs_raise_with_a_fix():
    profiles = elliptic_cylinder_grasp(force=10.0, n_elements=100)
    sets = [c for p in profiles for c in contact_sets(p, "soft_point")]
    w = gravity_wrench(0.3, [0, 0, 0])
    for bad in (-1.0, np.nan, np.inf, True):
        for fn in (resists, min_grasp_force):
            with pytest.raises(ValueError, match="mu"):
                fn(sets, w, bad)
        with pytest.raises(ValueError, match="mu"):
            q_robust(sets, bad, Task(mass=0.3, com=[0, 0, 0]))
    with pytest.raises(ValueError, match="mass"):
        gravity_wrench(-1.0, [0, 0, 0])  # pointed up before
    with pytest.raises(ValueError, match="com"):
        gravity_wrench(1.0, [0, 0])  # only warned before
    with pytest.raises(ValueError, match="representation"):
        resists(sets, w, MU, representation="exact")
    with pytest.raises(ValueError, match="ContactSet"):
        resists(profiles, w, MU)


@pytest.mark.jit_only("over 15 s as pure Python")
@pytest.mark.skipif(not BOTTLE.exists(), reason="thesis objects not available")
def test_one_call_evaluation_on_a_thesis_bottle_agrees_across_functions():
    """Mesh → antipodal grasp → REACH profiles → every model: the verdict, the minimal
    force and q_robust agree (1.03 / 0.97 × the minimal force); the sampled 6DFW's minimal
    force bounds the exact 6DFW's from above (the exact set contains the samples' hull)."""
    import trimesh

    mesh = trimesh.load(BOTTLE, force="mesh")
    grasps = antipodal_grasps(mesh, 3, MU, seed=1)
    assert grasps
    cache, cuts = LimitSurfaceCache(), CutStore()
    task, jaws = Task(mass=0.3, com=[0, 0, 0]), Jaws(force=4.0)
    first = evaluate_grasp(mesh, grasps[0], task, jaws=jaws, options=ModelOptions("soft_point", MU))
    per_jaw = {}
    for model in MODELS:
        ev = evaluate_grasp(
            mesh,
            grasps[0],
            task,
            jaws=jaws,
            options=ModelOptions(model, MU),
            profiles=first.profiles,
            cache=cache,
            cuts=cuts,
        )
        if model == "point":  # the COM is off the grasp axis: torsion no point pair resists
            assert not ev.min_force.feasible and not ev.resisted
            assert not resists(_scaled(ev.contacts, 100.0), ev.w_ext, MU, cuts=cuts)
            continue
        m = _agree(ev.contacts, ev.w_ext, cuts)
        assert bool(ev.resistance) == (m.scale <= 1.0)
        per_jaw[model] = 4.0 * m.scale
    ex = ExactContacts(first.profiles, n_start=200)
    w = gravity_wrench(0.3, [0, 0, 0])
    s_6dfw = per_jaw["6dfw"] / 4.0
    assert resists_exact(ex, w, MU, forces=ex.F * s_6dfw * 1.001)[0]  # exact ⊇ sampled
    # the models do differ on this tilted grasp (per_jaw holds their minimal
    # forces); polygonal soft points and REACH are the most conservative
    assert per_jaw["soft_point"] >= per_jaw["6dfw"] and per_jaw["reach"] >= per_jaw["6dfw"], per_jaw


def test_antipodal_grasps_drop_edge_contacts():
    """A flat jaw tilted against a cylinder wall presses it with the pad's edge: such
    grasps are dropped (pressure centre in the outer quarter of the face); kept ones have
    their REACH pressure centres within the face's inner 3/4."""
    import trimesh

    from workbench.sources.jaws import jaw_frame
    from workbench.sources.reach import WinklerPress, reach_profile

    cyl = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=96)
    everything = antipodal_grasps(cyl, 20, 0.5, jaws=None, seed=3)
    kept = antipodal_grasps(cyl, 20, 0.5, seed=3)
    tilts = [abs(g["axis"][2]) for g in kept]
    assert len(kept) >= 10 and max(tilts) < max(abs(g["axis"][2]) for g in everything)
    for g in kept[:5]:
        for p, a in ((g["p1"], g["axis"]), (g["p2"], -g["axis"])):
            prof = reach_profile(cyl, p, a, press=WinklerPress(closing=1e-3))
            _, e1, e2 = jaw_frame(a, (0, 0, 1))
            off = prof.pressure_center - p
            assert abs(off @ e1) < 0.75 * 0.01 and abs(off @ e2) < 0.75 * 0.02


# --- regressions from a new-user trial ---------------------------------------------------


def test_reach_profile_area_does_not_depend_on_the_triangulation():
    """A 20 × 40 mm pad lying on the 60 × 100 mm face of a box: 8 cm² of contact whatever
    the triangulation (faces with no vertex under the pad used to be dropped: 'covers no
    part of the object' on the 2-triangle face, −10 % area after two subdivisions), and no
    pressure on the side walls parallel to the approach."""
    import trimesh

    from workbench.sources.reach import WinklerPress, reach_profile

    box = trimesh.creation.box(extents=(0.04, 0.06, 0.10))
    for level in range(4):
        mesh = box
        for _ in range(level):
            mesh = mesh.subdivide()
        prof = reach_profile(mesh, (-0.02, 0.0, 0.0), (1.0, 0.0, 0.0), press=WinklerPress(closing=1e-3))
        # elements are kept by their centres on a 1 mm grid: 8 cm² to half an element row
        assert prof.areas.sum() == pytest.approx(8e-4, rel=0.01), level
        assert np.allclose(prof.normals, [-1.0, 0.0, 0.0])  # only the face under the pad
        # a flat face pressed 1 mm: uniform Winkler pressure k δ over the area
        assert prof.F == pytest.approx(1e6 / 0.005 * 1e-3 * prof.areas.sum(), rel=1e-9)


@pytest.mark.jit_only("over 15 s as pure Python")
@pytest.mark.parametrize("model", MODELS)
def test_frictionless_contacts_resist_only_what_normal_forces_can(model):
    """μ = 0 used to raise 'every solver failed' for the ellipsoid models: without friction
    each contact wrench is its normal wrench; two opposing jaws balance each other but no
    weight."""
    profiles = elliptic_cylinder_grasp(force=10.0, n_elements=150)
    sets = [c for p in profiles for c in contact_sets(p, model, ModelParameters(M=60, n_wrenches=200))]
    assert resists(sets, np.zeros(6), 0.0)
    assert not resists(sets, gravity_wrench(0.1, [0, 0, 0]), 0.0)
    assert not min_grasp_force(sets, gravity_wrench(0.1, [0, 0, 0]), 0.0).feasible


def test_point_contacts_agree_under_a_tiny_misalignment():
    """Jaw 1 offset by 1e-7 m: resists is True within the residual band, so the minimal force
    must be finite (it was inf); offset 1e-5 m: all three say no."""
    from workbench.grasp import point_contact

    for dy, expect in ((1e-7, True), (1e-5, False)):
        sets = [
            point_contact([0.02, dy, 0.0], [1.0, 0, 0], 10.0, n_edges=64),
            point_contact([-0.02, 0.0, 0.0], [-1.0, 0, 0], 10.0, n_edges=64),
        ]
        w = gravity_wrench(0.9, [0, 0, 0])
        m = min_grasp_force(sets, w, MU)
        assert bool(resists(sets, w, MU)) is expect and m.feasible is expect
        assert q_robust(sets, MU, w, NO_NOISE) == float(expect)
        if expect:
            assert m.scale == pytest.approx(0.9 * 9.81 / (2 * MU * 10.0), rel=1e-3)


def test_careless_inputs_name_the_fix():
    import trimesh

    box = trimesh.creation.box(extents=(0.04, 0.06, 0.10))
    g = {"p1": np.array([-0.02, 0.0, 0.0]), "p2": np.array([0.02, 0.0, 0.0]), "axis": np.array([1.0, 0, 0])}
    task, opts = Task(mass=0.3, com=[0, 0, 0]), ModelOptions(mu=MU)
    with pytest.raises(ValueError, match="'axis'"):
        evaluate_grasp(box, {"p1": g["p1"], "p2": g["p2"]}, task, options=opts)
    with pytest.raises(ValueError, match=r"in millimetres\? pass \[0.0, 0.01, 0.0\]"):  # refused when made
        evaluate_grasp(box, g, Task(mass=0.3, com=[0, 10.0, 0]), options=opts)  # COM in mm on a metre mesh
    with pytest.raises(ValueError, match="another unit"):  # within any object's reach, off this one
        evaluate_grasp(box, g, Task(mass=0.3, com=[0, 0.9, 0]), options=opts)
    with pytest.raises(ValueError, match="p1 and p2 swapped"):
        evaluate_grasp(box, {**g, "axis": -g["axis"]}, task, options=opts)
    for force in (True, "10", np.nan, 0.0):  # a bool is a slip, not 1 N (as fem_jaw_profile says)
        with pytest.raises(
            ValueError, match=r"force \(each jaw's reading \[N\]\) must be a (jaw force in|number)"
        ):
            evaluate_grasp(box, g, task, jaws=Jaws(force=force), options=opts)
    for pad in ((-0.02, 0.04), (0.02,), "0.02"):  # on the REACH path, before the footprint is cast
        with pytest.raises(
            ValueError, match=r"pad must be the jaw face \(width, length\) \[m\], two numbers > 0"
        ):
            evaluate_grasp(box, g, task, jaws=Jaws(pad=pad), options=opts)
    sets = [c for p in elliptic_cylinder_grasp(force=10.0, n_elements=100) for c in contact_sets(p, "point")]
    with pytest.raises(ValueError, match="list of ContactSet"):
        resists(sets[0], np.zeros(6), MU)
    with pytest.raises(ValueError, match="sigma_mu"):
        Perturbation(sigma_mu=-0.1)
    task = Task(mass=0.1, com=[0, 0, 0])
    assert 0.0 <= q_robust(sets, MU, task, None) <= 1.0  # None: the default perturbation


def _reference_residual(sets, w, mu, grouped):
    """Independent reference (cvxpy, vertex form, object frame, no scaling): the smallest
    ‖Σ_i G_i Σ_m α_im F_i(μ s_m + ŵ⊥) + w‖ with Σ_m α_im = σ_g(i) (grouped: one σ per
    force group) or σ_i (each contact its own), every σ in [1 − r, 1]."""
    import cvxpy as cp

    r = config.TOL.known_force_rtol
    keys = [c.group if grouped else k for k, c in enumerate(sets)]
    sig = {k: cp.Variable() for k in dict.fromkeys(keys)}
    total, cons = 0, []
    for c, k in zip(sets, keys, strict=True):
        V = c.vertices(mu)  # (M, 6) object frame at the contact's force
        a = cp.Variable(len(V), nonneg=True)
        cons.append(cp.sum(a) == sig[k])
        total = total + V.T @ a
    cons += [s >= 1 - r for s in sig.values()] + [s <= 1 for s in sig.values()]
    prob = cp.Problem(cp.Minimize(cp.norm(total + w)), cons)
    prob.solve(solver="CLARABEL")
    return prob.value


def test_reach_jaw_is_one_force_group(scene):
    """A REACH jaw's elements share its sensor reading: they scale together by one
    σ ∈ [1 − r, 1] (ContactSet.group).  resists (half-spaces on each element's affine
    hull) and its vertex form agree with an independent cvxpy program of the grouped
    vertex sets, and the solution's forces keep each jaw's distribution."""
    profiles, _ = scene
    sets = [c for p in profiles for c in contact_sets(p, "reach", ModelParameters(n_edges=6))]
    assert len({c.group for c in sets}) == 2
    rng = np.random.default_rng(3)
    W = np.c_[rng.normal(0, 3.0, (24, 3)), rng.normal(0, 0.03, (24, 3))]
    cap = sum(c.force for c in sets)
    decided = 0
    for w in W:
        ref = _reference_residual(sets, w, MU, grouped=True) / cap
        res = resists(sets, w, MU)
        inner = resists(sets, w, MU, representation="inner")
        if ref < 1e-9 or ref > 1e-3:  # clear cases (the solvers' bands differ in scaling)
            decided += 1
            assert bool(res) == bool(inner) == bool(ref < 1e-9), (ref, res.residual, inner.residual)
        if res:
            for g in {c.group for c in sets}:
                idx = [i for i, c in enumerate(sets) if c.group == g]
                sigma = res.forces[idx] / np.array([sets[i].force for i in idx])
                np.testing.assert_allclose(sigma, sigma[0], rtol=1e-6)
                r = config.TOL.known_force_rtol
                assert 1 - r - 1e-6 <= sigma[0] <= 1 + 1e-6
    assert decided >= 20
    # grouping is a real constraint: frictionless, a per-element interval reaches a
    # pressure redistribution inside a jaw (half its elements at F(1 − r)); one
    # reading per jaw cannot — the reference and resists (group equality rows) agree
    r = config.TOL.known_force_rtol
    f = np.array([c.force * (1 - r if k % 2 else 1.0) for k, c in enumerate(sets)])
    w = -sum(fi * (c.G @ c.normal) for fi, c in zip(f, sets, strict=True))
    assert _reference_residual(sets, w, 0.0, grouped=False) < 1e-9 * cap
    assert _reference_residual(sets, w, 0.0, grouped=True) > 0.5 * abs(w[5])  # its torque stays
    assert not resists(sets, w, 0.0)
    ungrouped = [dataclasses.replace(c, group=None) for c in sets]
    assert resists(ungrouped, w, 0.0)


def test_a_mirrored_jaw_needs_its_own_force_group(scene):
    """Trial finding: jaw 2 built by moving jaw 1's REACH contacts kept jaw 1's group, so
    both jaws silently shared one reading.  A group whose normal forces cancel is now
    rejected; ``moved(..., group=)`` gives the copy its own reading, and then the
    mirrored grasp decides like the grasp built from both profiles."""
    profiles, _ = scene
    jaw1 = contact_sets(profiles[0], "reach")
    Rz = np.diag([-1.0, -1.0, 1.0])  # the scene is symmetric under a half turn about z
    w = gravity_wrench(0.3, [0.0, 0.0, 0.01])
    with pytest.raises(ValueError, match="spans opposing jaws"):
        resists(jaw1 + [c.moved(Rz, np.zeros(3)) for c in jaw1], w, MU)
    mirrored = jaw1 + [c.moved(Rz, np.zeros(3), group="jaw-2") for c in jaw1]
    both = jaw1 + contact_sets(profiles[1], "reach")
    m1 = min_grasp_force(mirrored, w, MU)
    m2 = min_grasp_force(both, w, MU)
    assert m1.feasible and m1.scale == pytest.approx(m2.scale, rel=2e-3)  # jaw 2 is 0.02 % stronger


def test_reach_defaults_are_one_model_and_bad_sizes_are_refused(scene):
    from workbench.grasp import reach_contacts

    profiles, _ = scene
    a = contact_sets(profiles[0], "reach")
    b = reach_contacts(profiles[0])
    assert len(a) == len(b) and len(a[0].friction) == len(b[0].friction)
    np.testing.assert_allclose([c.force for c in a], [c.force for c in b])
    with pytest.raises(ValueError, match="max_triangles"):
        reach_contacts(profiles[0], max_triangles=0)

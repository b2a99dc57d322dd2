"""Careless inputs of the seventh new-user trial ("no silent nonsense") to the contact
profile, the contact models, grasp resistance, the evaluation and the minimal work: each was
accepted without a word (a wrong verdict, a meaningless number) or crashed with an exception
naming something the user never passed.  Each is refused now (a ValueError saying what was
expected, what came and the fix) or warned about where the input may be meant, and the
corrected call gives the right number."""

import warnings

import numpy as np
import pytest
import trimesh

from workbench import ContactProfile
from workbench.plausible import ImplausibleWarning

G = 9.81
MU, F, A = 0.5, 10.0, 0.03


def _patch() -> ContactProfile:
    """A flat 20 x 40 mm patch of 1 mm elements at 10 kPa (F = 8 N), normal +x, in metres."""
    y, z = np.meshgrid(np.arange(-9.5, 10, 1.0) * 1e-3, np.arange(-19.5, 20, 1.0) * 1e-3)
    c = np.c_[np.zeros(y.size), y.ravel(), z.ravel()]
    return ContactProfile(c, np.tile([1.0, 0, 0], (y.size, 1)), np.full(y.size, 1e-6), np.full(y.size, 1e4))


def _small() -> ContactProfile:
    """A 5 x 5 patch of 5 mm elements (20 mm across), normal +x: cheap limit surfaces."""
    y, z = np.meshgrid(np.linspace(-0.01, 0.01, 5), np.linspace(-0.01, 0.01, 5))
    c = np.c_[np.zeros(25), y.ravel(), z.ravel()]
    return ContactProfile(c, np.tile([1.0, 0, 0], (25, 1)), np.full(25, 2.5e-5), np.full(25, 4e4))


def _box() -> trimesh.Trimesh:
    """A 60 x 40 x 80 mm box standing on z = 0 (the trial's object, without its rounding)."""
    box = trimesh.creation.box((0.06, 0.04, 0.08))
    box.apply_translation([0, 0, 0.04])
    return box


def _grasp(z=0.04) -> dict:
    return {"p1": np.array([-A, 0, z]), "p2": np.array([A, 0, z]), "axis": np.array([1.0, 0, 0])}


def _least_sum() -> float:
    """The least Σ f of two contacts (force scale F) holding 0.3 kg by friction at MU: m g / MU,
    less the residual band "resisted" accepts (config.TOL.resist_rtol of the force scale F)."""
    from workbench import config

    return (0.3 * G - config.TOL.resist_rtol * F) / MU * (1 - 1e-9)


def _points():
    """Two hard point contacts at ±A on the x axis, each pressed with F."""
    from workbench.grasp import point_contact

    return [point_contact([A, 0, 0], [1, 0, 0], F), point_contact([-A, 0, 0], [-1, 0, 0], F)]


# ------------------------------------------------------------------ A. profile and sampler


def test_a08_areas_in_square_millimetres_beside_centres_in_metres_are_refused():
    """A08: ``ContactProfile(c, n, a_mm2, p)`` — 1 mm² elements given as 1.0 (m²) beside centres
    in metres: 800 m² on a 20 x 40 mm patch (F = 8 MN) was accepted."""
    p = _patch()
    with pytest.raises(
        ValueError,
        match=r"areas: the 800 elements' total area 800 m² is 4\.\d+e\+05 x the surface area .* config\.TOL\."
        r"profile_area_box_ratio = 10: .* areas in mm² beside centres in metres\? pass areas x 1e-06",
    ):
        ContactProfile(p.centers, p.normals, p.areas * 1e6, p.pressures)
    # in cm² (1e-2 each: 8 m² on the same patch) it is named as such
    with pytest.raises(ValueError, match=r"areas in cm² beside centres in metres\? pass areas x 0\.0001"):
        ContactProfile(p.centers, p.normals, p.areas * 1e4, p.pressures)
    # the corrected call: 800 x 10 kPa x 1 mm² = 8 N
    assert ContactProfile(p.centers, p.normals, p.areas * 1e6 * 1e-6, p.pressures).F == pytest.approx(8.0)
    # the bound is sound for curved contacts: a sphere's whole surface (the most a convex patch
    # can wrap) of 40 mm diameter, 4 pi r² = 5.03e-3 m² in a box of surface 24 r² = 9.6e-3 m²
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.02)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ImplausibleWarning)  # its normal forces cancel: warned
        whole = ContactProfile.from_trimesh(sphere, 1e4)
    assert whole.areas.sum() == pytest.approx(4 * np.pi * 0.02**2, rel=2e-2)
    # one element, or elements at one point, have no extent to judge their areas by
    ContactProfile([[0.0, 0, 0]], [[1.0, 0, 0]], [1.0], [1.0])


def test_a29_a_reversed_pitch_range_is_refused_by_its_config_rule():
    """A29: ``sample_twists_thesis(10, patch, pitch_range=(2, -2))`` — numpy's "high - low < 0"."""
    from workbench.twists import plucker_from_twists, sample_twists_thesis

    p = _patch()
    with pytest.raises(
        ValueError,
        match=r"pitch_range must be a tuple of 2 finite numbers \(lo, hi\) \[l_s\] with lo <= hi; "
        r"got \(2, -2\) \(tuple\)\. Pass such a value, e.g. its default pitch_range=\(-1\.0, 1\.0\)",
    ):
        sample_twists_thesis(10, p, seed=0, pitch_range=(2, -2))
    with pytest.raises(ValueError, match=r"radius_factor must be a finite number >= 0; got -0\.25"):
        sample_twists_thesis(10, p, seed=0, radius_factor=-0.25)
    # the corrected call: pitches h in [-2, 2] l_s (l_s = 39 mm, the patch's longest side)
    _, _, h, trans = plucker_from_twists(sample_twists_thesis(200, p, seed=0, pitch_range=(-2, 2)))
    assert trans.sum() == 200 and p.length_scale == pytest.approx(0.039)
    assert np.abs(h[~trans]).max() <= 2 * 0.039 and np.abs(h[~trans]).max() > 1.9 * 0.039


# ------------------------------------------------------------------ B. contact models


def test_b01_a_contact_point_in_millimetres_is_refused():
    """B01: ``point_contact([30, 0, 40], [1, 0, 0], 10)`` — a point in mm, 50 m from the origin."""
    from workbench.grasp import point_contact, soft_point_contact

    with pytest.raises(
        ValueError,
        match=r"point must be in metres, in the object's frame; got \[30\.0, 0\.0, 40\.0\], 50 m from the "
        r"origin, beyond the largest object \(config\.TOL\.max_object_extent_m = 2 m\) — in millimetres\? "
        r"pass \[0\.03, 0\.0, 0\.04\]",
    ):
        point_contact([30.0, 0, 40.0], [1.0, 0, 0], 10.0)
    with pytest.raises(ValueError, match=r"point must be in metres"):
        soft_point_contact([30.0, 0, 40.0], [1.0, 0, 0], 10.0, 0.005)
    # the same rule as gravity_wrench's com
    from workbench.grasp import gravity_wrench

    with pytest.raises(ValueError, match=r"com must be in metres, in the object's frame; got \[30\.0"):
        gravity_wrench(0.3, [30.0, 0, 40.0])
    c = point_contact([0.03, 0, 0.04], [1.0, 0, 0], 10.0)
    np.testing.assert_array_equal(c.t, [0.03, 0, 0.04])
    # the jaw pushes the object along -x (the inward normal) with up to 10 N
    np.testing.assert_allclose(c.R @ c.normal[:3] * c.force, [-10.0, 0, 0], atol=1e-12)


def test_b09_an_odd_or_too_small_6dfw_count_is_refused_naming_n_wrenches():
    """B09: ``contact_sets(jaw, '6dfw', n_wrenches=0)`` (and 1, 3) — refused as "n must be an
    integer >= 1 (a number of twists)", a parameter never passed; 3 silently gave 2 wrenches."""
    from workbench.grasp import contact_sets
    from workbench.grasp.models import ModelParameters

    p = _patch()
    for n in (0, 1):
        with pytest.raises(
            ValueError,
            match=r"n_wrenches must be an even integer >= 2 \(the number of 6DFW samples: the thesis "
            r"sampler draws n screw motions and the n translations along the same axes, 2n wrenches, "
            rf"so an odd count cannot be met\); got {n} — pass e\.g\. the default 600",
        ):
            contact_sets(p, "6dfw", ModelParameters(n_wrenches=n))
    with pytest.raises(ValueError, match=r"got 3 — pass 2 or 4"):
        contact_sets(p, "6dfw", ModelParameters(n_wrenches=3))
    with pytest.raises(ValueError, match=r"n_wrenches must be an even integer >= 2"):
        contact_sets(p, "3dls_nonplanar", ModelParameters(n_wrenches=101))
    (s,) = contact_sets(p, "6dfw", ModelParameters(n_wrenches=4))
    assert s.friction.shape == (4, 6)
    # rows 3 and 4 are the translations along the two Fibonacci axes ±(0.87, 0, ∓0.5)... of a
    # flat patch normal to x: pure forces, |f_t| = μ F = 1 at μ = 1 and unit force, no torque
    np.testing.assert_allclose(np.linalg.norm(s.friction[2:, :3], axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(s.friction[2:, 3:], 0.0, atol=1e-12)


def test_b11_a_dict_for_the_profile_is_refused_naming_contact_profile():
    """B11: ``contact_sets({'centers': ..., 'normals': ..., 'areas': ..., 'pressures': ...}, '6dls')``
    — AttributeError: 'dict' object has no attribute 'F'."""
    from workbench.grasp import contact_sets

    p = _patch()
    d = {"centers": p.centers, "normals": p.normals, "areas": p.areas, "pressures": p.pressures}
    with pytest.raises(
        ValueError,
        match=r"profile must be a ContactProfile \(one jaw's contact: element centres, normals, areas and "
        r"pressures\); got dict — build one with ContactProfile\(\*\*profile\)",
    ):
        contact_sets(d, "6dls")
    with pytest.raises(ValueError, match=r"got list — build one with ContactProfile\(centers, normals"):
        contact_sets([p.centers], "point")
    # the fix: a point contact at the pressure centre (the patch's middle), 8 N along -x
    (c,) = contact_sets(ContactProfile(**d), "point")
    np.testing.assert_allclose(c.t, [0, 0, 0], atol=1e-15)
    assert c.force == pytest.approx(8.0)


# ------------------------------------------------------------------ C. resistance


def test_c05_a_negative_tol_is_refused_by_the_rule_of_resist_rtol():
    """C05: ``resists(sets, w, mu=0.5, tol=-1)`` — 0.3 kg, easily held, came out not resisted."""
    from workbench.grasp import gravity_wrench, resists

    w = gravity_wrench(0.3, [0, 0, 0])
    with pytest.raises(
        ValueError,
        match=r"tol \(the residual band of 'resisted': relative to the contacts' capacity, not in newtons\) "
        r"must be a finite number > 0 and <= 0\.1; got -1\.0 \(float\)\. Pass such a value, e\.g\. its "
        r"default resist_rtol=1e-05",
    ):
        resists(_points(), w, MU, tol=-1.0)
    # the same rule as config.configure(resist_rtol=...)
    from workbench import config

    with pytest.raises(ValueError, match=r"config field resist_rtol must be a finite number > 0 and <= 0\.1"):
        config.configure(resist_rtol=-1.0)
    # held: 2.94 N against the two contacts' friction, up to 2 mu F = 10 N
    assert resists(_points(), w, MU, tol=1e-5).resisted


def test_c22_a_tol_in_newtons_is_refused():
    """C22: ``resists(sets, [0, 0, -60, 0, 0, 0], 0.5, tol=10)`` — tol taken for newtons: 60 N
    against a 10 N capacity came out resisted."""
    from workbench.grasp import resists
    from workbench.grasp.resistance import resists_lp

    w = np.array([0, 0, -60.0, 0, 0, 0])
    with pytest.raises(
        ValueError, match=r"tol \(.*not in newtons\) must be a finite number > 0 and <= 0\.1; got 10"
    ):
        resists(_points(), w, MU, tol=10)
    with pytest.raises(ValueError, match=r"tol \(.*\) must be a finite number > 0 and <= 0\.1; got 10"):
        resists_lp(_points(), w, MU, norm="l1", tol=10)
    # 60 N is six times what two 10 N contacts hold at mu = 0.5; 9 N is within it
    assert not resists(_points(), w, MU).resisted
    assert resists(_points(), [0, 0, -9.0, 0, 0, 0], MU).resisted


def test_c10_a_force_cap_with_the_scale_objective_is_refused():
    """C10: ``min_grasp_force(sets, w, mu=0.5, f_max=1.0)`` — the 1 N cap was ignored by the
    default objective='scale' (forces 2.94 N each)."""
    from workbench.grasp import gravity_wrench, min_grasp_force

    w = gravity_wrench(0.3, [0, 0, 0])
    with pytest.raises(
        ValueError,
        match=r"f_max caps each contact's force under objective='sum' only .*; got f_max=1\.0 with "
        r"objective='scale', .* pass objective='sum' to cap them, or drop f_max",
    ):
        min_grasp_force(_points(), w, MU, f_max=1.0)
    # the cap honoured by "sum": 1 N a contact holds 2 mu = 1 N < 2.94 N (infeasible); 5 N holds it,
    # at Σ f = m g / mu = 5.886 N (the 8-gon's inner friction polygon: up to 1 / cos(22.5°) more)
    capped = min_grasp_force(_points(), w, MU, objective="sum", f_max=1.0)
    assert not capped.feasible and capped.total == np.inf
    ok = min_grasp_force(_points(), w, MU, objective="sum", f_max=5.0)
    assert _least_sum() <= ok.total <= 0.3 * G / MU / np.cos(np.pi / 8) * (1 + 1e-9)
    assert ok.forces.max() <= 5.0 + 1e-9


def test_c07_c23_an_unknown_qp_solver_is_refused_by_name_before_solving():
    """C23 / C07: ``resists(sets, w, 0.5, solver='quadprogg')`` — reported as a solver that
    "returned no solution; retrying with 'clarabel'" (polygonal contacts) or ignored without a
    word (6DLS, decided by the cone solver)."""
    from workbench.grasp import contact_sets, gravity_wrench, resists

    w = gravity_wrench(0.3, [0, 0, 0])
    msg = (
        r"solver \(the dense QP solver of polyhedral programs\) must be one of \['auto', .*'quadprog'.*\]; "
        r"got 'quadprogg' \(str\)\. Pass such a value, e\.g\. its default qp_solver='auto'"
    )
    with pytest.raises(ValueError, match=msg):
        resists(_points(), w, MU, solver="quadprogg")  # C23: polygonal, a QP
    six = [
        c
        for s in (1, -1)
        for c in contact_sets(_small().transformed(np.diag([s, s, 1.0]), [s * A, 0, 0]), "6dls")
    ]
    with pytest.raises(ValueError, match=msg):
        resists(six, w, MU, solver="quadprogg")  # C07: ellipsoids, the cone program
    r = resists(_points(), w, MU, solver="quadprog")
    assert r.resisted and r.solver == "quadprog" and r.fallbacks == ()


# ------------------------------------------------------------------ D. evaluation


def test_d16_a_dict_for_the_task_wrench_is_refused():
    """D16: ``evaluate_grasp(box, g, w_ext={'fz': -2.9})`` — TypeError: float() argument must
    be ... not 'dict'."""
    from workbench.grasp import Task, evaluate_grasp
    from workbench.grasp.gws import check_wrench

    with pytest.raises(
        ValueError,
        match=r"w_ext must be a \(6,\) wrench \[f_x, f_y, f_z, τ_x, τ_y, τ_z\] of numbers \[N, N·m\]; got "
        r"dict \{'fz': -2\.9\} — pass an array, e\.g\. np\.array\(\[0, 0, -2\.9, 0, 0, 0\]\)",
    ):
        evaluate_grasp(_box(), _grasp(), Task(w_ext={"fz": -2.9}))
    np.testing.assert_array_equal(check_wrench([0, 0, -2.9, 0, 0, 0]), [0, 0, -2.9, 0, 0, 0])


def test_d43_a_centre_of_mass_outside_the_object_is_refused():
    """D43: ``evaluate_grasp(box, g, mass=0.3, com=[0, 0.05, 0.04])`` — a com 30 mm outside the
    box (it reaches y = 0.02) was accepted."""
    from workbench.grasp import Task, evaluate_grasp
    from workbench.grasp.robust import check_com

    box = _box()
    with pytest.raises(
        ValueError,
        match=r"com \[0\.0, 0\.05, 0\.04\] lies 30 mm outside the object's convex hull .* more than "
        r"config\.TOL\.com_hull_rtol = 0\.05 x its size 80 mm: a centre of mass is a weighted mean of the "
        r"object's points and lies inside their hull — .* pass mesh\.center_mass = \[0\.0, 0\.0, 0\.04\]",
    ):
        evaluate_grasp(box, _grasp(), Task(mass=0.3, com=[0, 0.05, 0.04]))
    # within 5 % of 80 mm (4 mm) of the hull: a faceted mesh or a measured com; a com in mm: its unit
    np.testing.assert_array_equal(check_com([0, 0.023, 0.04], box), [0, 0.023, 0.04])
    with pytest.raises(ValueError, match=r"lies 5 mm outside the object's convex hull"):
        check_com([0, 0.025, 0.04], box)
    with pytest.raises(ValueError, match=r"far outside the object's bounding box .* in another unit"):
        check_com([0, 0, 40.0], box)
    # a corner's edge: 3 mm past both faces is 4.2 mm from the hull, measured as 3 mm (a lower bound)
    np.testing.assert_array_equal(check_com([0.033, 0.023, 0.04], box), [0.033, 0.023, 0.04])


def test_d53_a_torque_half_a_metre_off_the_force_is_warned_about():
    """D53: ``evaluate_grasp(box, g, w_ext=[0, 0, -10, 5, 0, 0])`` — a 5 N·mm torque typed as
    5 N·m puts the 10 N load 0.5 m off the origin (an 80 mm box): accepted without a word."""
    from workbench.grasp import ModelOptions, Task, evaluate_grasp
    from workbench.grasp.robust import check_task_wrench

    with pytest.warns(
        ImplausibleWarning,
        match=r"w_ext's lever \|τ\|/\|f\| \(\|τ\| = 5 N·m over \|f\| = 10 N: a torque in N·mm, or an origin "
        r"off the object\?\) = 0\.5 m is above the usual 0\.3 m of a lever arm",
    ):
        ev = evaluate_grasp(
            _box(),
            _grasp(),
            Task(w_ext=[0, 0, -10.0, 5.0, 0, 0]),
            options=ModelOptions(model="soft_point", min_force=False),
        )
    # still answered for the wrench as given: not resisted — each jaw's friction (mu F = 5 N) acts
    # 50 mm from the origin and its torsion lever is a few mm, under 1 N·m together
    assert not ev.resisted
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        check_task_wrench([0, 0, -10.0, 0.5, 0, 0])  # 50 mm: a usual lever
    with pytest.raises(ValueError, match=r"at least 1\.5 m from the object origin .* probably in N·mm"):
        check_task_wrench([0, 0, -10.0, 15.0, 0, 0])


def test_c24_a_path_for_the_cache_is_refused_naming_limit_surface_cache(tmp_path):
    """C24: ``evaluate_grasp(box, g, model='6dls', cache='some/dir')`` — AttributeError: 'str'
    object has no attribute 'contact_model' (after the jaws' profiles were made)."""
    from workbench.grasp import ModelOptions, Task, contact_sets, evaluate_grasp
    from workbench.limit_surface import LimitSurfaceCache

    d = str(tmp_path / "lscache")
    with pytest.raises(
        ValueError,
        match=rf"cache must be a LimitSurfaceCache or None; got str '{d}' — pass "
        rf"LimitSurfaceCache\('{d}'\) to keep the limit surfaces in that directory",
    ):
        evaluate_grasp(_box(), _grasp(), Task(mass=0.3, com=[0, 0, 0.04]), options=ModelOptions(), cache=d)
    with pytest.raises(ValueError, match=r"cache must be a LimitSurfaceCache or None; got dict"):
        contact_sets(_small(), "6dls", cache={})
    # the fix keeps the fitted surface there: one file, read back by a second cache
    cache = LimitSurfaceCache(d)
    contact_sets(_small(), "6dls", cache=cache)
    assert len(list((tmp_path / "lscache").glob("*.npz"))) == 1
    again = LimitSurfaceCache(d)
    contact_sets(_small(), "6dls", cache=again)
    assert again.stats["disk_hits"] == 1 and again.stats["solves"] == 0


def test_c25_a_file_for_the_cache_directory_is_refused_when_the_cache_is_made(tmp_path):
    """C25: ``LimitSurfaceCache('afile.txt')`` (a file, not a directory) — FileExistsError from
    mkdir after the first limit surface was fitted."""
    from workbench.limit_surface import LimitSurfaceCache

    f = tmp_path / "afile.txt"
    f.write_text("x")
    with pytest.raises(
        ValueError,
        match=rf"LimitSurfaceCache directory must be a directory path; got '{f}', which is a file, not a "
        r"directory — pass a directory",
    ):
        LimitSurfaceCache(str(f))
    with pytest.raises(ValueError, match=rf"which cannot be made: '{f}' is a file, not a directory"):
        LimitSurfaceCache(f / "sub")
    with pytest.raises(
        ValueError, match=r"directory must be a path \(str or pathlib\.Path\) or None; got int"
    ):
        LimitSurfaceCache(3)
    LimitSurfaceCache(tmp_path / "new")  # made when the first surface is written
    assert not (tmp_path / "new").exists()


# ------------------------------------------------------------------ G. work


def test_g13_forces_in_millinewtons_are_refused_by_the_jaw_force_range():
    """G13: ``work([5000, 5000], [2e4, 2e4])`` — 5 N given in mN: W = 2500 J without a word."""
    from workbench import config
    from workbench.grasp.work import work

    with pytest.raises(
        ValueError,
        match=r"forces\[0\] \(a contact's normal force \[N\]\) must be a jaw force in \(0, 500\] N; got "
        r"5000\.0: probably in millinewtons — pass 5 \[N\]",
    ):
        work([5000.0, 5000.0], [2e4, 2e4])
    eps = config.DEFAULTS.work_eps
    # W = Σ f (f / s + ε) = 2 x 5 N x (0.25 mm + ε)
    assert work([5.0, 5.0], [2e4, 2e4]) == pytest.approx(2 * 5.0 * (5.0 / 2e4 + eps), rel=1e-12)
    assert work([0.0, 5.0], [2e4, np.inf]) == pytest.approx(5.0 * eps, rel=1e-12)  # a contact without force


def test_g14_a_stiffness_map_is_evaluated_at_the_contacts():
    """G14: ``minimal_work(sets, w, 0.5, stiffness=StiffnessMap(...))`` — the map itself, not its
    values: TypeError: float() argument must be ... not 'StiffnessMap'."""
    from workbench import config
    from workbench.grasp import gravity_wrench, soft_point_contact
    from workbench.grasp.stiffness_map import StiffnessMap
    from workbench.grasp.work import minimal_work, work

    sm = StiffnessMap(
        np.array([[A, 0, 0.04], [-A, 0, 0.04], [0, 0.02, 0.04], [0, -0.02, 0.04], [0, 0, 0.0]]),
        np.array([1e4, 1e4, 2e4, 2e4, 3e4]),
    )
    sets = [
        soft_point_contact([A, 0, 0.04], [1, 0, 0], F, 0.005),
        soft_point_contact([-A, 0, 0.04], [-1, 0, 0], F, 0.005),
    ]
    w = gravity_wrench(0.3, [0, 0, 0.04])
    res = minimal_work(sets, w, MU, sm)
    # the map is exact at its measured points: 1e4 N/m at both jaws
    np.testing.assert_allclose(res.stiffness, [1e4, 1e4], rtol=1e-9)
    eps = config.DEFAULTS.work_eps
    f = res.forces
    assert res.W == pytest.approx(float(f @ (f / 1e4 + eps)), rel=1e-9)
    # Σ f holds m g at mu: 2.943 N / 0.5 (up to the inner 8-gon's 1 / cos(22.5°))
    assert _least_sum() <= res.f_sum <= 0.3 * G / MU / np.cos(np.pi / 8) * (1 + 1e-9)
    # work() has no contacts to evaluate a map at: refused naming the fix
    with pytest.raises(ValueError, match=r"stiffness must be \(n,\) = \(2,\) numbers, one value per contact"):
        work([5.0, 5.0], sm)


def test_a_force_cap_in_millinewtons_is_refused_naming_them():
    """A new-user trial: ``min_grasp_force(..., objective="sum", f_max=1e4)`` was taken as a
    10 kN cap; a contact's cap is a jaw's force (the one rule of every jaw force)."""
    from workbench.grasp import gravity_wrench, min_grasp_force

    w = gravity_wrench(0.3, [0, 0, 0])
    with pytest.raises(
        ValueError, match=r"f_max \(each contact's force cap .* probably in millinewtons — pass 10"
    ):
        min_grasp_force(_points(), w, MU, objective="sum", f_max=1e4)

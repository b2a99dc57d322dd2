"""Plausible ranges of the physical inputs (workbench.plausible): the rule of each quantity,
and the library entry points that apply it — each fed the careless inputs new users gave
(a wall E in MPa, a force in millinewtons, μ as a percentage, a pad in mm ...)."""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from workbench import plausible
from workbench.plausible import RANGES, ImplausibleWarning, check, check_each

DOCS = Path(__file__).resolve().parents[1] / "docs" / "inputs.md"


def _usual(r) -> float:
    """A value well inside the usual range (its geometric middle when both ends are > 0)."""
    lo, hi = r.usual
    return math.sqrt(lo * hi) if lo > 0 else (lo + hi) / 2


@pytest.mark.parametrize("key", sorted(RANGES))
def test_each_range_passes_usual_values_silently_and_refuses_beyond_its_limits(key):
    r = RANGES[key]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a usual value: no warning
        assert check(key, _usual(r)) == pytest.approx(_usual(r))
        assert check(key, r.usual[0]) == r.usual[0] and check(key, r.usual[1]) == r.usual[1]
    hi = r.upper()
    for bad in (hi * 1.01 + 1e-12, r.lo - abs(r.lo) * 0.01 - 1e-12, np.nan, np.inf):
        with pytest.raises(ValueError, match=f"must be an? {re.escape(r.name)} in"):
            check(key, bad)
    if r.lo_open:
        with pytest.raises(ValueError, match="must be a"):
            check(key, r.lo)
    for slip in (True, "1.0", None, [1.0]):
        with pytest.raises(ValueError, match="must be a number"):
            check(key, slip)


@pytest.mark.parametrize("key", sorted(RANGES))
def test_each_unit_slip_is_named_with_the_value_to_pass(key):
    """A usual value given in each slip unit is refused or warned, and the message names the
    first slip (in the range's order) that makes it usual, with the SI value back — unless it
    is still a usual value (then nothing can tell)."""
    r = RANGES[key]
    si = _usual(r)
    for slip_factor in (f for _, f in r.slips):
        given = si / slip_factor
        if r.usual[0] / 2 <= given <= 2 * r.usual[1]:  # usual, or too near it to suspect a unit
            continue
        unit, factor = next((u, f) for u, f in r.slips if r.usual[0] <= given * f <= r.usual[1])
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            try:
                check(key, given)
                text = " ".join(str(w.message) for w in seen if issubclass(w.category, ImplausibleWarning))
            except ValueError as exc:
                text = str(exc)
        assert f"in {unit}" in text, (key, unit, given, text)
        named = float(re.search(r"pass ([-+0-9.e]+)", text).group(1))
        assert named == pytest.approx(given * factor, rel=1e-5)


def test_the_issues_mistakes_get_the_likely_unit():
    cases = [
        ("wall_modulus", 2500.0, "MPa — pass 2.5e+09"),  # E=2500 meant as MPa (a new user's input)
        ("wall_modulus", 2.5, "GPa — pass 2.5e+09"),
        ("pad_modulus", 1.0, "MPa — pass 1e+06"),
        ("poisson", 45.0, "per cent — pass 0.45"),
        ("mu", 30.0, "per cent — pass 0.3"),
        ("mu", 50.0, "per cent — pass 0.5"),
        ("wall_thickness", 0.5, "millimetres — pass 0.0005"),
        ("pad_thickness", 3.0, "millimetres — pass 0.003"),
        ("pad_size", 20.0, "millimetres — pass 0.02"),
        ("jaw_force", 1e4, "millinewtons — pass 10"),
        ("closing", 2.0, "millimetres — pass 0.002"),
        ("mass", 270.0, "grams — pass 0.27"),
        ("density", 1e6, "more than any real mean density"),
        ("opening", 50.0, "millimetres — pass 0.05"),
    ]
    for key, value, words in cases:
        with pytest.raises(ValueError) as exc:
            check(key, value, "x")
        assert words in str(exc.value), (key, str(exc.value))
        assert re.match("x must be an? ", str(exc.value))


def test_unusual_values_warn_and_say_why():
    with pytest.warns(ImplausibleWarning, match=r"below the usual 5e\+07 Pa .*MPa"):
        assert check("wall_modulus", 2e5) == 2e5  # 0.2 MPa: rubber, or 200 GPa in MPa?
    with pytest.warns(ImplausibleWarning, match="above the usual 1.5 of a friction coefficient"):
        check("mu", 1.8)
    with pytest.warns(ImplausibleWarning, match="results may not describe a real gripper"):
        check("jaw_force", 400.0)
    with pytest.warns(ImplausibleWarning, match="below the usual 0.0001 m"):
        check("wall_thickness", 5e-5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check("mu", 0) == 0.0  # frictionless: an idealisation, not a slip
    # a real but large noise names no unit: 0.03 m was suggested as "millimetres — pass 3e-05"
    # (a new-user trial); the same noise typed in millimetres is refused naming them
    with pytest.warns(ImplausibleWarning, match=r"above the usual 0.01 m .*results may not describe"):
        check("pose_noise_trans", 0.03)
    with pytest.raises(ValueError, match=r"got 3.0: probably in millimetres — pass 0.003 \[m\]"):
        check("pose_noise_trans", 3.0)


def test_a_config_tolerance_sets_the_mass_limit_at_call_time():
    from workbench import config

    with pytest.raises(ValueError, match="max_plausible_mass_kg"):
        check("mass", 30.0)
    with config.override(max_plausible_mass_kg=50.0):
        with pytest.warns(ImplausibleWarning):
            assert check("mass", 30.0) == 30.0


def test_check_each_keeps_shape_and_names_the_bad_element():
    np.testing.assert_array_equal(check_each("pad_size", [[0.02, 0.04]]), [[0.02, 0.04]])
    with pytest.raises(ValueError, match="got 40.0: probably in millimetres"):
        check_each("pad_size", np.array([0.02, 40.0]))


def test_the_docs_table_is_the_code_table():
    assert plausible.markdown_table() in DOCS.read_text(), "regenerate docs/inputs.md's table"


# ---------------------------------------------------------------- entry points


def test_library_entry_points_apply_the_ranges():
    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry, condense_pad
    from workbench.fem.wall import build_wall, circle_surface
    from workbench.grasp.robust import check_mass
    from workbench.sources.gripper import PadShape, yumi
    from workbench.sources.jaws import check_jaw_force, check_pad
    from workbench.wrench import check_mu

    with pytest.raises(ValueError, match="MPa — pass 2.5e\\+09"):
        build_wall(circle_surface(0.03), Material(2500.0, 0.4), n_theta=16, n_z=4)
    with pytest.raises(ValueError, match="millimetres — pass 0.0005"):
        build_wall(circle_surface(0.03), Material(2.5e9, 0.4), thickness=0.5, n_theta=16, n_z=4)
    with pytest.raises(ValueError, match="MPa — pass 1e\\+06"):
        condense_pad(PadGeometry(nx=2, ny=2, nz=1), Material(1.0, 0.45), cache_dir=False)
    with pytest.raises(ValueError, match="grams — pass 0.03"):
        check_mass(30.0)
    with pytest.raises(ValueError, match="per cent — pass 0.5"):
        check_mu(50)
    with pytest.raises(ValueError, match="millinewtons — pass 10"):
        check_jaw_force(1e4)
    with pytest.raises(ValueError, match="millimetres — pass 0.02"):
        check_pad((20, 40))
    with pytest.raises(ValueError, match="pad width .* millimetres — pass 0.02"):
        PadShape.rectangle(20, 8)
    with pytest.raises(ValueError, match="millimetres — pass 0.003"):
        PadShape.rectangle(0.02, 0.008, thickness=3)
    with pytest.raises(ValueError, match="MPa — pass 1e\\+06"):
        PadShape.rectangle(0.02, 0.008, modulus=1.0)
    import dataclasses

    with pytest.raises(ValueError, match="millimetres — pass 0.05"):
        dataclasses.replace(yumi(), opening=50.0)


def test_evaluate_grasp_refuses_the_issues_force_and_friction():
    """evaluate_grasp(force=1e4) and mu=50 used to run silently."""
    import trimesh

    from workbench.grasp.evaluate import evaluate_grasp
    from workbench.grasp.inputs import Jaws, ModelOptions, Task

    box = trimesh.creation.box((0.04, 0.04, 0.04))
    g = {"p1": np.array([-0.02, 0, 0.0]), "p2": np.array([0.02, 0, 0.0]), "axis": np.array([1.0, 0, 0])}
    task = Task(mass=0.05, com=[0, 0, 0])
    with pytest.raises(ValueError, match="millinewtons — pass 10"):
        evaluate_grasp(box, g, task, jaws=Jaws(force=1e4), options=ModelOptions(model="point"))
    with pytest.raises(ValueError, match="per cent — pass 0.5"):
        evaluate_grasp(box, g, task, options=ModelOptions(model="point", mu=50))


# ---------------------------------------------------------------- impossible derived quantities


@pytest.mark.jit_only(
    "~60 s as pure Python (three walls' sparse factors); the factor's kernels run JIT-off in test_fem_wall"
)
def test_an_impossible_closing_is_flagged_not_reported_as_a_stiffness():
    """A 0.2 MPa 'bottle' (2.5e9 meant, a slip of 10^4 the range lets through with a warning)
    closes by metres at 10 N on a 60 mm tube: squeeze flags it, stiffness_at reports no number."""
    from workbench.fem.material import Material
    from workbench.fem.wall import PET, build_wall, circle_surface, squeeze
    from workbench.fem.wall_grasps import stiffness_at

    surface = circle_surface(0.03)
    kw = {"n_theta": 16, "n_z": 6, "z_range": (0.0, 0.06), "clamp_top": True}
    c, ax = np.array([0.0, 0.0, 0.03]), np.array([1.0, 0.0, 0.0])
    pet = squeeze(build_wall(surface, PET, **kw), c, ax, force=10.0)
    assert pet.width == pytest.approx(0.06, rel=1e-9)  # the tube's outer diameter
    assert not pet.implausible and pet.delta < 0.01 * pet.width
    with pytest.warns(ImplausibleWarning, match="wall Young's modulus"):
        soft_wall = build_wall(surface, Material(2e5, 0.4), **kw)
    soft = squeeze(soft_wall, c, ax, force=10.0)
    # not exactly 1/E-proportional (the jaws' gaps to the footprint are metres, not scaled), but
    # orders of magnitude beyond the tube: more nodes reach a jaw
    assert soft.delta > 1e3 * pet.delta
    assert soft.implausible and soft.delta > soft.width
    import trimesh

    from workbench.fem.object_wall import wall_geometry

    cup = trimesh.creation.cylinder(radius=0.03, height=0.08, sections=64)
    cup.apply_translation((0, 0, 0.04))
    geo = wall_geometry(cup, thickness=0.5e-3, n_z=8, top="clamped")
    with pytest.warns(ImplausibleWarning):
        wall = geo.build(Material(2e5, 0.4), n_theta=16)
    L = np.array([[0.03, 0.0, 0.04], [-0.03, 0.0, 0.04]])
    (row,) = stiffness_at(wall, geo, L, force=10.0)
    assert row["implausible"] and row["failed"] and np.isnan(row["stiffness"])
    assert "impossible" in row["reason"] and "60 mm width" in row["reason"]


# ---------------------------------------------------------------- the second new-user trial's silent accepts


def test_the_trials_silent_accepts_are_refused():
    """Each of these used to run silently (a new-user trial): a mass of 33,000 kg/m³, a pad
    in millimetres given to the FEM adapter (4 m² of contact after 100 s), pose noise of metres,
    a REACH press 30 mm deep, a sampler's opening in mm, a string modulus."""
    import trimesh

    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry
    from workbench.grasp.evaluate import evaluate_grasp
    from workbench.grasp.inputs import ModelOptions, Task
    from workbench.grasp.robust import Perturbation
    from workbench.grasp.sampling import GraspSampling, antipodal_grasps
    from workbench.sources.fem_jaw import fem_jaw_profiles
    from workbench.sources.reach import WinklerPress, reach_profile

    box = trimesh.creation.box((0.06, 0.04, 0.1))  # 240 mL
    g = {"p1": np.array([0, -0.02, 0.0]), "p2": np.array([0, 0.02, 0.0]), "axis": np.array([0, 1.0, 0])}
    with pytest.raises(ValueError, match="240 cm³ object: its mean density.*got 33333.*grams\\? pass 0.008"):
        evaluate_grasp(box, g, Task(mass=8.0, com=[0, 0, 0]), options=ModelOptions("soft_point", 0.5))
    with pytest.raises(ValueError, match="PadGeometry.width .* millimetres — pass 0.02"):
        fem_jaw_profiles(box, g, 10.0, geometry=PadGeometry(width=20, length=40))
    with pytest.raises(ValueError, match="PadGeometry.thickness .* millimetres — pass 0.005"):
        fem_jaw_profiles(box, g, 10.0, geometry=PadGeometry(thickness=5))
    with pytest.raises(ValueError, match="Perturbation.sigma_trans .* millimetres — pass 0.002"):
        Perturbation(sigma_trans=2.0)
    with pytest.raises(ValueError, match="Perturbation.sigma_rot .* degrees — pass 0.0872665"):
        Perturbation(sigma_rot=5.0)
    with pytest.raises(ValueError, match="Perturbation.sigma_mu .* per cent — pass 0.1"):
        Perturbation(sigma_mu=10)
    with pytest.raises(ValueError, match=r"pad compression in \[0, 0.02\] m; got 0.03"):
        reach_profile(box, [0, -0.02, 0], [0, 1.0, 0], press=WinklerPress(closing=0.03))
    with pytest.raises(ValueError, match="max_width .* millimetres — pass 0.1"):
        antipodal_grasps(box, 5, mu=0.5, sampling=GraspSampling(max_width=100))
    with pytest.raises(ValueError, match="E must be a Young's modulus .* got '1e6' \\(str\\)"):
        Material("1e6", 0.45)


@pytest.mark.jit_only(
    "~40 s as pure Python (three walls' sparse factors); the factor's kernels run JIT-off in test_fem_wall"
)
def test_a_closing_beyond_small_deflections_is_warned(caplog):
    """The linear wall squeezed by more than a tenth of the object's width (a new user's 400 N on a
    70 mm bottle: 19 mm) logs that the small-deflection model is stretched — exactly then."""
    import logging

    from workbench.fem.material import Material
    from workbench.fem.wall import build_wall, circle_surface, squeeze

    kw = {"n_theta": 16, "n_z": 6, "z_range": (0.0, 0.06), "clamp_top": True}
    c, ax = np.array([0.0, 0.0, 0.03]), np.array([1.0, 0.0, 0.0])
    seen = []
    for E in (2.5e9, 5e7, 1e7):  # 1e7 Pa: a rubber-soft wall, warned as unusual
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ImplausibleWarning)
            wall = build_wall(circle_surface(0.03), Material(E, 0.4), **kw)
        caplog.clear()
        with caplog.at_level(logging.WARNING, logger="workbench.fem.wall"):
            r = squeeze(wall, c, ax, force=10.0)
        warned = any("beyond the small deflections" in m for m in caplog.messages)
        assert warned == (0.1 * r.width < r.delta < r.width), (E, r.delta)
        seen.append(warned)
    assert seen[0] is False and any(seen)  # PET is small; a soft enough wall is not


def test_the_second_trials_silent_accepts_are_refused_or_warned():
    """A density in the unusual band warns; a 25 kN scene, a 20 cm pose noise, a centre of mass
    20 cm off a 3 cm cube, a 20 m pad condensed directly are refused (a second new-user trial)."""
    import trimesh

    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry, condense_pad
    from workbench.grasp.pose_robust import PoseNoise
    from workbench.grasp.robust import check_com, check_object_mass
    from workbench.sources.scenes import elliptic_cylinder_grasp

    box = trimesh.creation.box((0.06, 0.04, 0.1))  # 240 mL
    with pytest.warns(ImplausibleWarning, match="above the usual 20000 kg/m³"):
        check_object_mass(5.0, box)  # 20,800 kg/m³
    with pytest.warns(ImplausibleWarning, match="below the usual 30 kg/m³"):
        check_object_mass(0.005, box)  # 21 kg/m³
    with pytest.raises(ValueError, match="lighter than any object"):
        check_object_mass(0.0011, box)  # 4.6 kg/m³
    with pytest.raises(ValueError, match=r"jaw force in \(0, 500\] N; got 25000"):
        elliptic_cylinder_grasp(force=25000.0)
    with pytest.raises(ValueError, match=r"PoseNoise.sigma_trans .* got 0.2"):
        PoseNoise(3, 0.2, 0.003)
    cube = trimesh.creation.box((0.03, 0.03, 0.03))
    with pytest.raises(ValueError, match="far outside the object's bounding box"):
        check_com([0.2, 0, 0], cube)
    np.testing.assert_array_equal(check_com([0.01, 0, 0], cube), [0.01, 0, 0])
    with pytest.raises(ValueError, match=r"PadGeometry.width .* millimetres — pass 0.02"):
        condense_pad(PadGeometry(width=20, length=40, nx=2, ny=2, nz=1), Material(), cache_dir=False)


@pytest.mark.parametrize(
    "sets, words",
    [
        ({"height_fractions": [30, 70]}, "per cent? pass [0.3, 0.7]"),
        ({"n_angles": 0}, "n_angles must be >= 1"),
        ({"mesh": [48]}, "two integers >= 1"),
    ],
)
def test_wall_stiffness_refuses_map_settings_before_any_work(tmp_path, sets, words):
    """These crashed after partial outputs (n_angles=0: 'zero-size array') or blamed the geometry
    ('the grasp axis misses the object' for heights in per cent) — a second new-user trial."""
    from workbench.runner.experiment_config import build_config

    with pytest.raises(SystemExit) as exc:
        build_config("wall-stiffness", True, str(tmp_path / "o"), None, sets)
    assert words in str(exc.value.code)
    assert not (tmp_path / "o").exists()


def test_press_pad_stiffness_offset_and_task_load_are_judged():
    """A Winkler modulus in Pa/m given as 200, a refinement length of 1 m, a pad offset in mm and
    a 1 MN task load ran silently (a second new-user trial)."""
    import trimesh

    from workbench.grasp.evaluate import evaluate_grasp
    from workbench.grasp.inputs import ModelOptions, Task
    from workbench.sources.gripper import PadShape
    from workbench.sources.reach import WinklerPress, reach_profile

    box = trimesh.creation.box((0.06, 0.04, 0.1))
    with pytest.raises(ValueError, match=r"stiffness \(the pad's Winkler modulus \[Pa/m\]\)"):
        reach_profile(box, [0, -0.02, 0], [0, 1.0, 0], press=WinklerPress(stiffness=200.0))
    with pytest.raises(ValueError, match=r"max_edge .* got 1.0"):
        reach_profile(box, [0, -0.02, 0], [0, 1.0, 0], press=WinklerPress(max_edge=1.0))
    with pytest.raises(ValueError, match="pad offset .* millimetres — pass 0.01"):
        PadShape.rectangle(0.02, 0.008, offset=(10.0, 0.0))
    g = {"p1": np.array([0, -0.02, 0.0]), "p2": np.array([0, 0.02, 0.0]), "axis": np.array([0, 1.0, 0])}
    with pytest.raises(ValueError, match=r"w_ext's force \|f\| \[N\] must be a weight"):
        evaluate_grasp(box, g, Task(w_ext=[0, 0, -1e6, 0, 0, 0]), options=ModelOptions("point", 0.5))


def test_the_third_trials_silent_accepts_are_refused():
    """FEM-level calls a researcher also uses: jaws in mm and a vertical axis in squeeze, a ring
    radius in mm or negative, a non-rigid obstacle transform, a negative condensation patch, an
    obstacle placed 25 m away, a 50 m jaw stroke (a third new-user trial)."""
    import trimesh

    from workbench.fem.material import Material
    from workbench.fem.obstacles import MeshObstacle, Sphere
    from workbench.fem.pad import PadGeometry, condense_pad
    from workbench.fem.wall import build_wall, circle_surface, ring_pinch, ring_wall, squeeze
    from workbench.sources.gripper import Jaw

    wall = build_wall(circle_surface(0.03), n_theta=16, n_z=6, z_range=(0.0, 0.06))
    c = np.array([0.0, 0.0, 0.03])
    with pytest.raises(ValueError, match="millimetres — pass 0.02"):
        squeeze(wall, c, np.array([1.0, 0, 0]), jaw=(20, 40))
    with pytest.raises(ValueError, match="is not horizontal"):
        squeeze(wall, c, np.array([0, 0, 1.0]))
    with pytest.raises(
        ValueError, match=r"radius \(the ring's mid-surface radius \[m\]\).*millimetres — pass 0.035"
    ):
        ring_pinch(35.0, 0.0005, n_theta=16)
    with pytest.raises(ValueError, match="radius"):
        ring_wall(-0.035, 0.0005, n_theta=16)
    with pytest.raises(ValueError, match="not orthonormal|scaled|reflection"):
        MeshObstacle(trimesh.creation.box((0.04, 0.04, 0.04)), transform=np.diag([1000.0, 1000, 1000, 1]))
    with pytest.raises(ValueError, match="patch_radius"):
        condense_pad(PadGeometry(nx=2, ny=2, nz=1), Material(), patch_radius=-0.01, cache_dir=False)
    with pytest.raises(ValueError, match="center's distance from the pad .* millimetres — pass 0.025"):
        Sphere((0, 0, 25.0), 0.02)
    outline = np.array([[-0.01, -0.004], [0.01, -0.004], [0.01, 0.004], [-0.01, 0.004]])
    with pytest.raises(ValueError, match=r"Jaw.stroke .* got 50.0"):
        Jaw(
            np.zeros(3),
            np.array([1.0, 0, 0]),
            np.array([0, 1.0, 0]),
            np.array([0, 0, 1.0]),
            outline,
            50.0,
            3e8,
        )

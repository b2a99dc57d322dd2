"""workbench.grasp.evaluate: the one-call grasp evaluation (thesis §4.1.4, §4.2) — the
given profiles scaled to the reading, the minimal force of two point-like jaws against its
closed form, torsion no point pair resists, the task given either way, and bad input.
(evaluate_grasp's agreement with the separate entry points is in test_grasp_consistency.py,
the FEM pad's profiles through it in test_fem_jaw.py.)"""

import numpy as np
import pytest

from workbench import config
from workbench.grasp import (
    Jaws,
    ModelOptions,
    Perturbation,
    Task,
    contact_sets,
    evaluate_grasp,
    gravity_wrench,
    resists,
)
from workbench.sources.scenes import elliptic_cylinder_grasp

MU = 0.5
G_ACC = 9.81  # workbench.grasp.robust.G_ACC
NO_NOISE = Perturbation(n_samples=2, sigma_trans=0, sigma_rot=0, sigma_mu=0, sigma_mass=0, sigma_com=0)


@pytest.mark.jit_only("over 15 s as pure Python")
def test_evaluate_grasp_applies_force_and_checks_given_profiles():
    """Given profiles are scaled to ``force`` (it was ignored), must lie at their jaws, and
    must push: flipped normals raise on the evaluation path and warn in resists."""
    import trimesh

    box = trimesh.creation.box(extents=(0.04, 0.06, 0.10))
    g = {"p1": np.array([-0.02, 0.0, 0.0]), "p2": np.array([0.02, 0.0, 0.0]), "axis": np.array([1.0, 0, 0])}
    task, opts = Task(mass=0.3, com=[0, 0, 0]), ModelOptions(model="6dls", mu=MU)
    base = evaluate_grasp(box, g, task, jaws=Jaws(force=10.0), options=opts)
    for force in (2.0, 10.0, 100.0):
        ev = evaluate_grasp(box, g, task, jaws=Jaws(force=force), options=opts, profiles=base.profiles)
        # the minimal reading does not depend on the reading the profiles came with, up to
        # the residual band (config.TOL.resist_rtol of the capacity ~force (1 + μ) per jaw)
        band = 2 * config.TOL.resist_rtol * max(force, 10.0) * (1 + MU)
        assert force * ev.min_force.scale == pytest.approx(10.0 * base.min_force.scale, abs=band)
        assert ev.contacts[0].force == pytest.approx(force * base.contacts[0].force / 10.0, rel=1e-9)
    # q_robust without noise is the verdict itself, for the gravity task and a given wrench
    robust = ModelOptions(model="6dls", mu=MU, robust=NO_NOISE)
    for kw in ({"mass": 0.3, "com": [0, 0, 0]}, {"w_ext": gravity_wrench(0.3, [0, 0, 0])}):
        for force in (0.9 * 10.0 * base.min_force.scale, 1.1 * 10.0 * base.min_force.scale):
            ev = evaluate_grasp(box, g, Task(**kw), jaws=Jaws(force=force), options=robust)
            assert ev.q_robust == float(ev.resisted) and ev.resisted == (force > 10.0 * base.min_force.scale)
    flipped = [p.__class__(p.centers, -p.normals, p.areas, p.pressures) for p in base.profiles]
    with pytest.raises(ValueError, match="pull"):
        evaluate_grasp(box, g, task, options=opts, profiles=flipped)
    far = [p.transformed(None, [0.5, 0, 0]) for p in base.profiles]
    with pytest.raises(ValueError, match="pressure centre"):
        evaluate_grasp(box, g, task, options=opts, profiles=far)
    sets = [c for p in flipped for c in contact_sets(p, "soft_point")]
    with pytest.warns(UserWarning, match="push away"):
        resists(sets, gravity_wrench(0.3, [0, 0, 0]), MU)


# --- added: closed forms on the elliptic-cylinder scene ------------------------------------

GRASP = {"p1": [0.03, 0.0, 0.0], "p2": [-0.03, 0.0, 0.0], "axis": [-1.0, 0.0, 0.0]}


@pytest.fixture(scope="module")
def cylinder_jaws():
    """The two jaws of the elliptic-cylinder scene, jaw 1 at +x pushing along −x."""
    return elliptic_cylinder_grasp(force=10.0, n_elements=150)


@pytest.mark.parametrize("model", ["point", "soft_point"])
def test_minimal_force_of_two_opposing_jaws_holding_a_weight(cylinder_jaws, model):
    """Both contacts at the pressure centres on the x axis, normals ±x, friction cones as
    inscribed 8-gons with a vertex along −z (friction along gravity exactly μ f): holding
    m g needs 2 μ f = m g, so Σ f = m g / μ.  A contact's force bound f is the profile's
    Σ p a, larger than the axial reading |Σ p a n_x| on a curved contact, so the minimal
    reading is (m g / 2 μ) |Σ p a n_x| / Σ p a (both sums by hand from the profiles)."""
    mass, force = 0.3, 10.0
    task, opts = Task(mass=mass, com=[0, 0, 0]), ModelOptions(model=model, mu=MU)
    ev = evaluate_grasp(None, GRASP, task, jaws=Jaws(force=force), options=opts, profiles=cylinder_jaws)
    assert ev.model == model and ev.resisted
    np.testing.assert_allclose(ev.w_ext, [0, 0, -mass * G_ACC, 0, 0, 0], atol=1e-15)
    for prof in ev.profiles:  # each scaled to the reading along the grasp axis
        fa = prof.pressures * prof.areas
        assert abs(fa @ prof.normals[:, 0]) == pytest.approx(force, rel=1e-12)
    prof = ev.profiles[0]
    ratio = abs((prof.pressures * prof.areas) @ prof.normals[:, 0]) / (prof.pressures * prof.areas).sum()
    band = 2 * config.TOL.resist_rtol * prof.F * (1 + MU)  # the residual band of "resisted"
    assert ev.min_force.feasible and ev.min_force.total == pytest.approx(mass * G_ACC / MU, abs=band)
    assert force * ev.min_force.scale == pytest.approx(mass * G_ACC / (2 * MU) * ratio, abs=band)
    assert set(ev.timings_ms) == {"profiles", "contact_model", "resists", "min_grasp_force"}
    # below the minimal reading the same grasp slips, and the minimal reading stays
    low = 0.9 * force * ev.min_force.scale
    weak = evaluate_grasp(None, GRASP, task, jaws=Jaws(force=low), options=opts, profiles=cylinder_jaws)
    assert not weak.resisted and low * weak.min_force.scale == pytest.approx(
        force * ev.min_force.scale, abs=band
    )


def test_point_jaws_cannot_hold_a_weight_off_their_axis(cylinder_jaws):
    """A centre of mass at y = 1 cm loads a torque m g y about the grasp axis x (com × m g d
    = (−m g y, 0, 0)); two point contacts on that axis have no moment about it (Eq. 2.100)
    at any force, while soft points resist it with torsional friction."""
    mass, y = 0.3, 0.01
    task, kw = Task(mass=mass, com=[0, y, 0]), {"jaws": Jaws(force=10.0), "profiles": cylinder_jaws}
    ev = evaluate_grasp(None, GRASP, task, options=ModelOptions("point", MU), **kw)
    np.testing.assert_allclose(ev.w_ext, [0, 0, -mass * G_ACC, -mass * G_ACC * y, 0, 0], atol=1e-15)
    assert not ev.resisted and not ev.min_force.feasible
    assert evaluate_grasp(None, GRASP, task, options=ModelOptions("soft_point", MU), **kw).min_force.feasible
    # the same task as w_ext gives the same verdict; no minimal force asked: None
    no_min = ModelOptions(model="point", mu=MU, min_force=False)
    same = evaluate_grasp(None, GRASP, Task(w_ext=ev.w_ext), options=no_min, profiles=cylinder_jaws)
    assert not same.resisted and same.min_force is None and same.q_robust is None


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"model": "6d"}, r"model must be one of \('point', "),
        ({"mu": -0.5}, "mu"),
        ({"mass": None}, "give the task as w_ext"),
        ({"com": None}, r"give the task as w_ext .*evaluate_grasp takes no default centre of mass"),
        ({"w_ext": np.zeros(6)}, "either as w_ext or as mass and com, not both"),
        ({"profiles": None}, "give the object mesh"),
        ({"profiles": "jaws"}, "profiles must be a list of the two jaws' ContactProfiles"),
        ({"pad": (0.02, np.nan)}, "pad must be the jaw face"),
        ({"force": -1.0}, r"force \(each jaw's reading \[N\]\) must be a jaw force in \(0, 500\] N"),
        ({"grasp": {"p1": [0, 0, 0], "p2": [1, 0, 0], "axis": [0, 0, 0]}}, "axis non-zero"),
    ],
)
def test_careless_arguments_are_refused_before_any_work(cylinder_jaws, kw, match):
    args = {"profiles": cylinder_jaws, "mu": MU, "mass": 0.3, "com": [0, 0, 0], **kw}
    grasp = args.pop("grasp", GRASP)
    with pytest.raises(ValueError, match=match):
        _evaluate(None, grasp, **args)
    with pytest.raises(ValueError, match="got a list of 1"):
        _evaluate(None, GRASP, profiles=cylinder_jaws[:1], mu=MU, mass=0.3, com=[0, 0, 0])


#: the group of each flat keyword argument of the old call
_GROUP = {"w_ext": "task", "mass": "task", "com": "task", "down": "task", "force": "jaws", "pad": "jaws"}
_GROUP |= {"model": "options", "mu": "options"}


def _evaluate(mesh, grasp, **kw):
    """evaluate_grasp with its Task, Jaws and ModelOptions made from flat keyword arguments inside
    the caller's ``pytest.raises`` (a careless value is refused where its group is made)."""
    groups: dict = {"task": {}, "jaws": {}, "options": {}}
    rest = {k: v for k, v in kw.items() if k not in _GROUP}
    for k in kw.keys() & _GROUP.keys():
        groups[_GROUP[k]][k] = kw[k]
    task = Task(**groups["task"])
    jaws, opts = Jaws(**groups["jaws"]), ModelOptions(**groups["options"])
    return evaluate_grasp(mesh, grasp, task, jaws=jaws, options=opts, **rest)


def test_gravity_takes_a_direction(cylinder_jaws):
    """``down=`` turns the task: gravity along −y instead of −z loads the same weight along −y
    (w_ext = [0, −m g, 0, 0, 0, 0] about a centre of mass at the origin), and the minimal force
    of two soft points is the same by symmetry of the friction circle (their friction is a
    polygon: within its 8-gon's in/out radius ratio cos(π/8))."""
    mass = 0.3
    kw = dict(profiles=cylinder_jaws, jaws=Jaws(force=10.0), options=ModelOptions("soft_point", MU))
    z = evaluate_grasp(None, GRASP, Task(mass=mass, com=[0, 0, 0]), **kw)
    y = evaluate_grasp(None, GRASP, Task(mass=mass, com=[0, 0, 0], down=(0, -2.0, 0)), **kw)
    np.testing.assert_allclose(y.w_ext, [0, -mass * G_ACC, 0, 0, 0, 0], atol=1e-15)
    assert y.resisted
    assert np.cos(np.pi / 8) - 1e-9 <= z.min_force.scale / y.min_force.scale <= 1 / np.cos(np.pi / 8) + 1e-9


def test_an_unusual_mass_is_warned_once_per_call():
    # the new-user trial saw each ImplausibleWarning twice: the Task checked the mass, then the
    # evaluation checked it again against the mesh's volume
    import warnings

    import trimesh

    from workbench.grasp import ModelOptions, Task, evaluate_grasp
    from workbench.plausible import ImplausibleWarning

    box = trimesh.creation.box((0.3, 0.08, 0.3))
    grasp = {"p1": [0, 0.04, 0], "p2": [0, -0.04, 0], "axis": [0, -1, 0]}
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        task = Task(mass=15.0, com=box.center_mass)  # above the usual object mass, 2,083 kg/m³
        evaluate_grasp(box, grasp, task, options=ModelOptions(model="point", min_force=False))
    unusual = [w for w in seen if issubclass(w.category, ImplausibleWarning)]
    assert len(unusual) == 1, [str(w.message)[:60] for w in unusual]
    assert "15 kg is above the usual" in str(unusual[0].message)


def test_an_unusual_jaw_force_warns_once_per_call():
    """Found by a new-user trial: Jaws(force=0.5) warned when made and again inside
    evaluate_grasp; the group's warning is the one (the value is the same)."""
    import warnings

    import trimesh

    from workbench.plausible import ImplausibleWarning

    box = trimesh.creation.box([0.06, 0.04, 0.1])
    grasp = {"p1": np.array([0, -0.02, 0.0]), "p2": np.array([0, 0.02, 0.0]), "axis": np.array([0, 1.0, 0])}
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        jaws = Jaws(force=0.5)
        ev = evaluate_grasp(
            box, grasp, Task(mass=0.01, com=[0, 0, 0]), jaws=jaws, options=ModelOptions("6dls", 0.5)
        )
    assert [w.category for w in got] == [ImplausibleWarning] and "0.5 N is below" in str(got[0].message)
    assert ev.resisted  # 0.1 N of weight against 2 x 0.5 x 0.5 N of friction


def test_a_large_pad_warns_once_and_a_numpy_mass_is_stored_as_a_float():
    """Second new-user trial: Jaws(pad=(0.15, 0.15)) warned once per side; Task kept a float32 mass."""
    import warnings

    from workbench.plausible import ImplausibleWarning

    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        Jaws(pad=(0.15, 0.15))
    assert [w.category for w in got] == [ImplausibleWarning] and "0.15 m is above the usual 0.1 m" in str(
        got[0].message
    )
    task = Task(mass=np.float32(0.3), com=(0, 0, 0))
    assert type(task.mass) is float and task.mass == pytest.approx(0.3, rel=1e-7)

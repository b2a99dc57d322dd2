"""The engine-trial simulator (MuJoCo) validated against closed forms before it judges any
grasp: Coulomb friction of a pulled block and a tilted plane, the creep of a held block, the
torsion of a flat flex pad (μ Σ N_i |r_i| of its own contact forces), and a box held squarely
by two flex pads, which must hold above the Coulomb load 2 μ F = m (g + a) and drop below it."""

from dataclasses import replace

import numpy as np
import pytest
import trimesh

mujoco = pytest.importorskip("mujoco")

from workbench import config  # noqa: E402
from workbench.engine_trials import (  # noqa: E402
    EngineObject,
    EnginePad,
    TrialPhases,
    probes,
    simulate_grasp,
    simulate_grasp_tasks,
)

G_ACC = 9.81


@pytest.mark.parametrize(("mu", "angle"), [(0.2, 0.0), (0.5, 45.0), (1.0, 0.0)])
def test_a_pulled_block_slides_at_mu_m_g(mu, angle):
    # a slowly ramped pull (any direction: elliptic cones are isotropic) starts the block at
    # μ m g; the onset is late by the ramp's threshold bias (≤ 3.2 % here), never early
    r = probes.pulled_block(mu, angle_deg=angle)
    assert r["coulomb"] == pytest.approx(mu * 0.2 * G_ACC)
    assert 1.0 <= r["ratio"] <= 1.05


@pytest.mark.parametrize("mu", [0.2, 0.5, 1.0])
def test_a_tilted_plane_starts_the_block_at_atan_mu(mu):
    r = probes.tilted_block(mu)
    assert r["coulomb"] == pytest.approx(np.degrees(np.arctan(mu)))
    assert 1.0 <= r["ratio"] <= 1.05


def test_a_block_held_below_its_slip_load_creeps_less_than_a_tenth_of_a_millimetre_per_second():
    # MuJoCo's soft contacts let a held object creep (no true stiction); the default settings
    # (elliptic cone, impratio 100, stiff contacts) bound it — at half and at 90 % of the load
    for fraction in (0.5, 0.9):
        assert abs(probes.held_block_creep(0.5, fraction)["speed"]) < 1e-4


def test_a_flat_flex_pad_spins_at_its_contact_forces_torsion_capacity():
    # τ = μ Σ N_i |r_i| (μ∫p|r|dA of the engine's own pressure) within 10 %; for a flat pad that
    # pressure is near uniform, so μ F mean|r| (11.86 mm for 20 x 40 mm) is within 10 % too
    # the closed form of a 20 x 40 mm face's mean radius against a midpoint-rule integral
    x = (np.arange(400) + 0.5) / 400 * 0.02 - 0.01
    y = (np.arange(800) + 0.5) / 800 * 0.04 - 0.02
    r_mean = float(np.hypot(*np.meshgrid(x, y)).mean())
    assert probes.rectangle_mean_radius(0.02, 0.04) == pytest.approx(r_mean, rel=1e-5)
    r = probes.spun_pad(0.5)
    assert r["uniform"] == pytest.approx(0.5 * 10.0 * r_mean, rel=1e-5)
    assert abs(r["ratio"] - 1.0) < 0.10
    assert abs(r["measured"] / r["uniform"] - 1.0) < 0.10
    assert r["penetration"] < 1e-4  # the tips' contacts are stiff: < 0.1 mm into the plane


BOX = trimesh.creation.box(extents=(0.05, 0.04, 0.06))
GRASP = {"p1": [0.0, -0.02, 0.0], "p2": [0.0, 0.02, 0.0], "axis": [0.0, 1.0, 0.0]}


def _peak_lift_acceleration(phases: TrialPhases) -> float:
    return 6.0 * phases.lift_height / phases.lift**2  # smoothstep's peak


@pytest.mark.slow
def test_a_box_held_at_ten_times_its_weight_holds_and_a_slippery_heavy_one_drops():
    light = simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=0.1, mu=0.5))  # 2 μ F = 10 m g
    assert light.held and light.drift < 2e-4 and light.turn_deg < 0.5
    heavy = simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=2.0, mu=0.05))  # 2 μ F = m g / 20
    # it stays on the table while the gripper rises the lift height without it
    lift = TrialPhases().lift_height
    assert not heavy.held and heavy.drift == pytest.approx(lift, rel=0.05)


@pytest.mark.slow
def test_the_box_drops_where_coulomb_says():
    # friction 2 μ F against m (g + a_max), a_max the lift's peak acceleration: held with a 10 %
    # margin, dropped 5 % short of it
    a = _peak_lift_acceleration(TrialPhases())
    for ratio, held in ((1.10, True), (0.95, False)):
        mass = 2 * 0.5 * 10.0 / (G_ACC + a) / ratio
        assert simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=mass, mu=0.5)).held is held


@pytest.mark.slow
def test_lift_and_rotate_turns_the_gripper_and_a_held_box_with_it():
    r = simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=0.1, mu=0.5), task="lift_and_rotate")
    assert r.held and r.turn_deg < 0.5
    p = TrialPhases()
    assert r.times[-1] == pytest.approx(
        p.gravity_ramp + p.close + p.settle + p.lift + p.rotate + p.hold, abs=2e-3
    )


@pytest.mark.slow
def test_a_grasps_tasks_stepped_together_are_each_the_trial_stepped_alone_bit_for_bit():
    # a slipping grasp (2 mu F = 3.6 N against m g = 2.9 N plus the lift): its record moves
    phases = TrialPhases(close=0.2, settle=0.1, lift=0.4, rotate=0.4, hold=0.3)
    obj = EngineObject(mass=0.3, mu=0.18)
    both = simulate_grasp_tasks(BOX, GRASP, force=10.0, obj=obj, phases=phases)
    assert list(both) == ["vertical_lifting", "lift_and_rotate"]
    n_fork = round((phases.gravity_ramp + phases.close + phases.settle + phases.lift) / 1e-3) - 1
    for k, (task, together) in enumerate(both.items()):
        alone = simulate_grasp(BOX, GRASP, force=10.0, obj=obj, task=task, phases=phases)
        assert alone.shared_steps == 0 and together.shared_steps == (n_fork if k else 0)
        assert together.steps == alone.steps and together.held == alone.held
        for a, b in ((alone.times, together.times), (alone.rel_pos, together.rel_pos)):
            assert np.array_equal(a, b)
        assert np.array_equal(alone.rel_turn_deg, together.rel_turn_deg)
        assert together.drift == alone.drift > 1e-5  # it moved: the record is not trivially equal
    with pytest.raises(ValueError, match="tasks must be distinct names.* e.g. tasks="):
        simulate_grasp_tasks(BOX, GRASP, force=10.0, obj=obj, tasks=("vertical_lifting", "vertical_lifting"))
    with pytest.raises(ValueError, match="'lift' is not a task"):
        simulate_grasp_tasks(BOX, GRASP, force=10.0, obj=obj, tasks=("lift",))
    with pytest.raises(ValueError, match=r"not one name.* pass tasks=\('vertical_lifting',\)"):
        simulate_grasp_tasks(BOX, GRASP, force=10.0, obj=obj, tasks="vertical_lifting")
    with pytest.raises(ValueError, match="a list or tuple of task names .*an ordered sequence"):
        simulate_grasp_tasks(BOX, GRASP, force=10.0, obj=obj, tasks={"vertical_lifting"})


@pytest.mark.slow
def test_a_trial_stopped_once_lost_has_every_verdict_of_the_whole_trial_and_its_record_is_a_prefix():
    from workbench.engine_trials.trial import VERDICT_LIMITS

    phases = TrialPhases(close=0.2, settle=0.1, lift=0.4, hold=0.3)
    obj = EngineObject(mass=2.0, mu=0.05)  # 2 mu F = g m / 20: it stays on the table
    whole = simulate_grasp(BOX, GRASP, force=10.0, obj=obj, phases=phases)
    stopped = simulate_grasp(BOX, GRASP, force=10.0, obj=obj, phases=replace(phases, stop_when_lost=True))
    assert whole.stopped_at is None and stopped.stopped_at is not None
    k = stopped.times.size
    assert stopped.steps < whole.steps and k < whole.times.size
    assert np.array_equal(stopped.times, whole.times[:k])
    assert np.array_equal(stopped.rel_pos, whole.rel_pos[:k])
    assert stopped.stopped_at == stopped.times[-1]
    assert stopped.drift > 9e-3 and np.isnan(stopped.slip_speed)  # past the largest drift limit
    assert stopped.held is whole.held is False
    assert stopped.reason.split(" slid")[0] == whole.reason.split(" slid")[0] == "the object"
    for d_mm, t_deg in VERDICT_LIMITS:  # every re-read limit gives the same verdict
        for r in (whole, stopped):
            assert not (r.drift * 1e3 <= d_mm and r.turn_deg <= t_deg)
    with pytest.raises(ValueError, match="stop_when_lost must be True or False"):
        TrialPhases(stop_when_lost="yes")


def test_careless_trial_input_is_refused():
    with pytest.raises(ValueError, match="probably in grams"):
        simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=100.0, mu=0.5))
    obj = EngineObject(mass=0.1, mu=0.5)
    with pytest.raises(ValueError, match="task must be one of"):
        simulate_grasp(BOX, GRASP, force=10.0, obj=obj, task="lift")
    inside_out = BOX.copy()
    inside_out.invert()
    with pytest.raises(ValueError, match="inside out"):
        simulate_grasp(inside_out, GRASP, force=10.0, obj=obj)
    # a friction left to a gripper's (None) is refused where no gripper gives it
    with pytest.raises(ValueError, match=r"EngineObject.mu \(the pad–object friction\) must be given"):
        simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=0.1))


def test_careless_engine_settings_are_refused():
    from workbench.engine_trials import EngineSettings

    for kwargs, match in (
        ({"cone": "pyr"}, "cone must be"),
        ({"tip_radius": 0.3}, r"in metres \(0.3 mm = 3e-4\)"),
        ({"pad_grid": (5, 9, 1)}, "three integers >= 2"),
        ({"timestep": 0}, "timestep must be a positive"),
        # trial 7: 0 iterations read as "both jaws touched nothing"; a mixed-sign solref fell
        # back to MuJoCo's own (0.02, 1) with 170k console lines and no warning in the outcome
        ({"iterations": 0}, r"iterations must be an integer in \[1, 100000\]"),
        ({"contact_solref": (-0.002, 1.0)}, r"contact_solref must be \(time constant"),
        ({"contact_solref": (0.001, 1.0)}, "below 2 time steps"),
        ({"contact_solimp": (0.99, 0.999, 1e-4, 0.5, 0.0)}, "contact_solimp must be"),
        # accepted, then MuJoCo's XML parser said "invalid keyword: 'rk4'"
        ({"integrator": "rk4"}, r"integrator must be one of MuJoCo's .*got 'rk4' — pass 'RK4'"),
        ({"integrator": "bogus"}, r"integrator must be one of MuJoCo's .*got 'bogus' \(the probes"),
    ):
        with pytest.raises(ValueError, match=match):
            EngineSettings(**kwargs)


def test_every_integrator_engine_settings_accept_is_one_mujocos_parser_takes():
    # the neighbours of 'rk4': each accepted spelling compiles in MuJoCo itself, and its enum has
    # no integrator the settings would refuse
    from workbench.engine_trials.settings import INTEGRATORS, EngineSettings

    for name in INTEGRATORS:
        m = mujoco.MjModel.from_xml_string(f"<mujoco>{EngineSettings(integrator=name).option_xml()}</mujoco>")
        assert mujoco.mjtIntegrator(m.opt.integrator).name.lower() == f"mjint_{name.lower()}"
    assert len(INTEGRATORS) == len([k for k in dir(mujoco.mjtIntegrator) if k.startswith("mjINT_")])


def test_careless_pads_phases_and_timesteps_are_refused():
    # each was accepted and decided a verdict: 20 m pads (mm), a 1 Pa pad (MPa), a 5 m drift
    # limit (mm), a 0.1 s step whose flex MuJoCo calls ill-conditioned, a negative lift time
    from workbench.engine_trials import EngineSettings

    cases = (
        ({"size": (20, 40, 5)}, r"pad width .*probably in millimetres — pass 0.02"),
        ({"E": 1.0}, r"pad_E .*probably in MPa — pass 1e\+06"),
        ({"nu": 45}, r"pad_nu .*per cent — pass 0.45"),
        ({"up": (0, 0, 0)}, "up must be a non-zero finite"),
    )
    for extra, match in cases:
        with pytest.raises(ValueError, match=match):
            EnginePad(**extra)
    with pytest.raises(ValueError, match=r"com must be in metres.* in millimetres\? pass \[0.0, 0.0, 0.03\]"):
        simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=0.1, mu=0.5, com=(0, 0, 30)))
    with pytest.raises(
        ValueError, match="far outside the object's bounding box"
    ):  # within reach, off the box
        simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=0.1, mu=0.5, com=(0, 0, 0.9)))
    with pytest.raises(
        ValueError,
        match=r"pad must be a workbench\.engine_trials\.EnginePad"
        r" .*got tuple — pass EnginePad\(size=\(width, ",
    ):
        simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=0.1, mu=0.5), pad=(0.02, 0.04, 0.005))
    with pytest.raises(ValueError, match=r"max_drift .*probably in millimetres — pass 0.005"):
        TrialPhases(max_drift=5)
    with pytest.raises(ValueError, match=r"TrialPhases.lift must be a duration in \(0, 60\] s"):
        TrialPhases(lift=-1)
    with pytest.raises(ValueError, match="validated at 1e-3 s"):
        EngineSettings(timestep=0.1)


def test_a_turn_limit_in_radians_and_record_every_zero_are_refused():
    from workbench.engine_trials import DisturbancePhases

    # trial 7: 5 degrees given as 0.0873 rad failed a held grasp "turned 0.358 deg (limit 0.0873)"
    with pytest.raises(ValueError, match=r"probably in radians — pass 5 \[deg\]"):
        TrialPhases(max_turn_deg=0.0873)
    with pytest.raises(ValueError, match="probably in radians"):
        DisturbancePhases(max_turn_deg=0.0873)
    # trial 7: record_every=0 was a ZeroDivisionError seconds into the run
    with pytest.raises(ValueError, match="record_every must be an integer >= 1"):
        TrialPhases(record_every=0)


def test_a_record_every_too_coarse_for_the_verdict_is_refused_and_the_bound_holds():
    """Trial 11 D17-D19: record_every=10**7 recorded one pose, and a box that slid the whole
    lift height read held=True, drift 0; 1000 read a 50 mm slide as 32.7 mm."""
    from workbench.engine_trials import DisturbancePhases, check_record_every, simulate_disturbance
    from workbench.engine_trials.trial import _judged

    kw = {"force": 10.0, "obj": EngineObject(mass=2.0, mu=0.05)}  # slides: 2 μ F = m g / 20
    coarse = r"TrialPhases.hold \(0.5 s = 500 steps.*at least 20 of them — pass record_every <= 25"
    for every in (10**7, 1000, 26):
        with pytest.raises(ValueError, match=coarse):
            simulate_grasp(BOX, GRASP, **kw, phases=TrialPhases(record_every=every))
    with pytest.raises(ValueError, match=r"DisturbancePhases.hold .* pass record_every <= 15"):
        simulate_disturbance(
            BOX, GRASP, [0.0] * 6, force=10.0, obj=kw["obj"], phases=DisturbancePhases(record_every=16)
        )
    # the bound: the shortest judged phase over 20 records, counted in steps (round, not floor,
    # so 0.3 s / 1 ms is 300 steps); lift_and_rotate adds its 1 s turn, not a shorter phase
    p = TrialPhases()
    assert check_record_every(25, _judged(p, "lift_and_rotate"), 1e-3) == 25
    assert check_record_every(10, {"hold": DisturbancePhases().hold}, 1e-3) == 10
    # a phase under 20 steps still takes record_every=1: every step is all there is to read
    assert check_record_every(1, {"hold": 0.01}, 1e-3) == 1
    with pytest.raises(ValueError, match="TrialPhases.hold"):
        check_record_every(10, _judged(TrialPhases(hold=0.1), "vertical_lifting"), 1e-3)
    # the fewest records a phase needs is config's, read at call time: at 10 the bound doubles
    with config.override(engine_min_samples_per_phase=10):
        assert check_record_every(50, _judged(p, "lift_and_rotate"), 1e-3) == 50
        with pytest.raises(ValueError, match=r"at least 10 of them — pass record_every <= 50"):
            check_record_every(51, _judged(p, "lift_and_rotate"), 1e-3)
    # the neighbour at the bound judges the slide as the default does: the box stays on the
    # table while the gripper rises the lift height
    r = simulate_grasp(BOX, GRASP, **kw, phases=TrialPhases(record_every=25))
    assert not r.held and r.drift == pytest.approx(p.lift_height, rel=0.05)
    assert r.reason.startswith("the object slid")
    assert np.diff(r.times)[:-1] == pytest.approx(0.025)


def test_gravity_along_the_pads_up_is_refused_and_across_or_against_it_runs():
    """Trial 11 C11: down=(0, 0, 1) with up=(0, 0, 1) was simulated as an ordinary lift."""
    from workbench.engine_trials.trial import _check_up_down

    along = (
        r"down \[0.0, 0.0, 1.0\] \(gravity\) is 0 deg from up .*at least 90 deg"
        r".*pass down = \[0.0, 0.0, -1.0\], or.* up = \[0.0, 0.0, -1.0\]"
    )
    with pytest.raises(ValueError, match=along):
        simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=0.1, mu=0.5, down=(0.0, 0.0, 1.0)))
    with pytest.raises(ValueError, match="is 80 deg from up"):
        _check_up_down((0.0, 0.0, 1.0), np.array([np.cos(np.radians(10)), 0.0, np.sin(np.radians(10))]))
    # across the pads (a pad lying flat under gravity) and against up pass
    for down in ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.6, 0.0, -0.8)):
        _check_up_down((0.0, 0.0, 1.0), np.array(down))
    # an object upside down in its frame, the pads' up flipped with it: the box is held as upright
    upside_down = EngineObject(mass=0.1, mu=0.5, down=(0.0, 0.0, 1.0))
    r = simulate_grasp(BOX, GRASP, force=10.0, obj=upside_down, pad=EnginePad(up=(0.0, 0.0, -1.0)))
    assert r.held and r.drift < 2e-4 and r.turn_deg < 0.5


def test_a_zero_axis_is_named_by_the_pad_and_scene_builders():
    """Trial 11 K02: a zero axis read as "up is parallel to the grasp axis (0, 0, 0)", with a
    numpy divide warning (an error under this suite's filterwarnings)."""
    from workbench.engine_trials.pad import pad_rotation
    from workbench.engine_trials.trial import open_pad_depth

    with pytest.raises(
        ValueError, match=r"approach must be a non-zero finite \(3,\) direction .*zero vector"
    ):
        pad_rotation(np.zeros(3), np.array([0.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match=r"axis must be a non-zero finite \(3,\) direction"):
        open_pad_depth(BOX, ([0, -0.0205, 0], [0, 0.0205, 0]), [0, 0, 0], [0, 0, 1], (0.02, 0.04, 5e-3))
    with pytest.raises(ValueError, match=r"up .* is parallel to the jaw's approach"):
        pad_rotation(np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 1.0]))
    # the neighbour: the pad frame of a y-axis grasp, its face along −y, its length along z
    R = pad_rotation(np.array([0.0, 2.0, 0.0]), np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(R, [[1, 0, 0], [0, 0, -1], [0, 1, 0]], atol=1e-15)  # x = y × z


def test_open_pads_that_start_inside_the_object_are_a_miss_not_a_hold():
    """Trial 7: a 74 mm cup in a 50 mm YuMi opening was 'held' by the engine (the open pads
    started inside it); the same pose judged by evaluate_gripper was a miss."""
    from workbench.engine_trials import simulate_gripper
    from workbench.engine_trials.trial import open_pad_depth
    from workbench.sources.gripper import yumi

    wide = trimesh.creation.cylinder(radius=0.037, height=0.09)
    pose = np.eye(4)
    pose[:3, :3] = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1.0]]).T
    pose[:3, 3] = [0.0, 0.0, 0.160098]  # the tooltips at the cylinder's mid-height
    r = simulate_gripper(wide, yumi(), pose, obj=EngineObject(mass=0.2))
    assert not r.held and r.steps == 0 and "inside the object" in r.reason
    # the depth is the cylinder's radius beyond the half-opening (25 mm), ~12 mm on each side
    jaws = yumi().jaws(pose)
    lo, hi = jaws[0].outline.min(axis=0), jaws[0].outline.max(axis=0)
    c, size = (lo + hi) / 2, hi - lo
    faces = [j.origin + c[0] * j.e1 + c[1] * j.e2 for j in jaws]
    depth = open_pad_depth(wide, faces, jaws[0].closing, jaws[0].e2, (size[0], size[1], 3e-3))
    half_open = 0.5 * abs((jaws[1].origin - jaws[0].origin) @ jaws[0].closing)
    # the faces' corners sit at the pad's half-width off the axis: deepest at the face centre
    assert depth == pytest.approx(np.full(2, 0.037 - half_open), abs=2e-4)
    # the box's squarely placed pads start clear of it
    assert np.all(
        open_pad_depth(BOX, ([0, -0.0205, 0], [0, 0.0205, 0]), [0, 1, 0], [0, 0, 1], (0.02, 0.04, 5e-3)) == 0
    )


@pytest.mark.slow
def test_a_trial_says_why_it_failed():
    import warnings

    from workbench.engine_trials import EngineWarning

    slip = simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=2.0, mu=0.05))
    assert not slip.held and slip.reason.startswith("the object slid")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ok = simulate_grasp(BOX, GRASP, force=10.0, obj=EngineObject(mass=0.1, mu=0.5))
    assert ok.held and ok.reason == "" and ok.engine_warnings == {}
    assert not [w for w in caught if issubclass(w.category, EngineWarning)]


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::workbench.plausible.ImplausibleWarning")  # the 50 mm pad, on purpose
def test_mujocos_warnings_are_recorded_and_raised_as_an_engine_warning():
    """Trial 11 C14: a 50 mm pad made MuJoCo warn (mjWARN_INERTIA) 1921 times and the library
    only logged 'the verdict may not be reliable'."""
    from workbench.engine_trials import EngineWarning

    with pytest.warns(EngineWarning, match=r"MuJoCo warned \{'mjWARN_INERTIA': \d+\} .*may not be reliable"):
        obj, pad = EngineObject(mass=0.1, mu=0.5), EnginePad(size=(0.02, 0.04, 0.05))
        r = simulate_grasp(BOX, GRASP, force=10.0, obj=obj, pad=pad)
    assert r.engine_warnings.get("mjWARN_INERTIA", 0) > 0
    assert r.row()["engine_warnings"] == r.engine_warnings


@pytest.mark.slow
def test_a_yumi_trial_at_its_recorded_pose_and_a_gripper_that_misses():
    # the first REACH cube grasp (held in 5 of 5 real repeats) at its recorded pose: the cube on
    # the table, the jaws closing by the YuMi's 20 N, lifting; and the same pose 10 cm to the side
    from workbench.engine_trials import simulate_gripper
    from workbench.sources.gripper import yumi
    from workbench.sources.trials import default_mesh_path, default_trials_path, read_trials

    trials = read_trials(default_trials_path())
    cube = trimesh.load(default_mesh_path(), force="mesh")
    pose, down = trials.gripper_pose[0], trials.down[0]
    assert trials.success[trials.grasp_index == 0].all()
    r = simulate_gripper(cube, yumi(), pose, obj=EngineObject(mass=trials.mass, down=down))
    assert r.held and r.drift < 1e-3 and r.reason == ""
    away = pose.copy()
    away[:3, 3] += 0.1 * np.cross(down, pose[:3, 0])  # sideways, across gravity and the jaw axis
    miss = simulate_gripper(cube, yumi(), away, obj=EngineObject(mass=trials.mass, down=down))
    assert not miss.held and "touched nothing" in miss.reason


def test_a_mesh_in_millimetres_is_refused_with_a_remedy_the_trials_take():
    """simulate_grasp has no units= argument: the refusal names the scaling, not an option
    it would refuse as a TypeError."""
    import trimesh

    from workbench.engine_trials import simulate_grasp

    box = trimesh.creation.box((40.0, 40.0, 80.0))  # a 40 x 40 x 80 mm block given in mm
    grasp = {"p1": [-20.0, 0, 0], "p2": [20.0, 0, 0], "axis": [1.0, 0, 0]}
    with pytest.raises(ValueError, match=r"apply_scale\(0.001\)") as err:
        simulate_grasp(box, grasp, force=10.0, obj=EngineObject(mass=0.1, mu=0.5))
    assert "units=" not in str(err.value) and "allow_scale" not in str(err.value)

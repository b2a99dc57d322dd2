"""Careless inputs a new user gave that were accepted silently or crashed unhelpfully: each public
entry point now refuses them with a ValueError naming what it expected, what came and the fix (by
the library's one rule of that quantity), or accepts the reasonable form with the right number."""

import numpy as np
import pytest

from workbench.plausible import ImplausibleWarning

# ---------------------------------------------------------------- peers: mu, modulus, pad lengths

R, DELTA, E, NU = 0.02, 1e-3, 1.0e6, 0.45


def test_a_peer_refuses_a_friction_coefficient_in_per_cent_as_the_core_does():
    from workbench.peers.hertz import hertz_torsion_capacity
    from workbench.wrench import check_mu

    with pytest.raises(ValueError, match="probably in per cent — pass 0.5") as peer:
        hertz_torsion_capacity(R, DELTA, E, NU, mu=50)
    with pytest.raises(ValueError) as core:
        check_mu(50)
    assert str(peer.value) == str(core.value)  # one rule: the same words
    with pytest.raises(ValueError, match="no torsion capacity to compute; pass the contact's friction"):
        hertz_torsion_capacity(R, DELTA, E, NU, mu=0.0)
    # a plausible mu still gives Johnson's 3 pi mu F a / 16, F = 4/3 E* sqrt(R) d^1.5, a = sqrt(R d)
    e_star = E / (1 - NU**2)
    f = 4.0 / 3.0 * e_star * np.sqrt(R) * DELTA**1.5
    expected = 3 * np.pi * 0.5 * f * np.sqrt(R * DELTA) / 16
    assert hertz_torsion_capacity(R, DELTA, E, NU, mu=0.5) == pytest.approx(expected, rel=1e-12)


def test_a_peer_names_the_unit_slip_of_a_pad_modulus_thickness_and_width():
    from workbench.fem.obstacles import Sphere
    from workbench.peers.elastic_foundation import PadGrid, foundation_modulus, foundation_profile

    with pytest.raises(ValueError, match=r"probably in MPa — pass 1e\+06.*1 MPa = 1e6"):
        foundation_modulus(1.0, 0.005)  # E in MPa
    with pytest.raises(ValueError, match="pad thickness .* probably in millimetres — pass 0.005"):
        foundation_modulus(E, 5.0)  # h in mm
    with pytest.raises(ValueError, match="pad size .* probably in millimetres — pass 0.04"):
        foundation_profile(Sphere((0.0, 0.0, 0.005 + R), R), DELTA, E, 0.005, grid=PadGrid(width=40.0))
    with pytest.raises(ValueError, match=r"Poisson ratio in \(-1, 0.5\); got 0.5"):
        foundation_modulus(E, 0.005, 0.5, "confined")


# ---------------------------------------------------------------- a parametric surface in mm


def _disc(radius, **kw):
    from workbench.sources.surfaces import ParametricSurface

    return ParametricSurface(
        "disc",
        lambda r, t: np.stack([r * np.cos(t), r * np.sin(t), 0 * r], axis=-1),
        (0.0, radius),
        (0.0, 2 * np.pi),
        lambda r, t: np.stack([np.cos(t), np.sin(t), 0 * r], axis=-1),
        lambda r, t: np.stack([-r * np.sin(t), r * np.cos(t), 0 * r], axis=-1),
        **kw,
    )


def test_a_surface_given_in_millimetres_is_refused_by_the_contact_size_rule():
    from workbench import config
    from workbench.sources.surfaces import mesh_profile, surface_w_max

    big = _disc(10.0)  # a 10 mm disc written in millimetres: 20 m across
    fix = r"spans 20 m .*TOL.max_object_extent_m = 2 m; it is probably in millimetres: give sigma in metres"
    with pytest.raises(ValueError, match=fix + r" \(scale its points by 0.001.*allow_scale=True"):
        surface_w_max(big, mu=0.5)
    with pytest.raises(ValueError, match=fix):
        mesh_profile(big, 50)
    # the limit is the ContactProfile's, read at call time
    with config.override(max_object_extent_m=25.0):
        assert surface_w_max(big, mu=0.5, rtol=1e-6)[0] > 0


def test_a_large_surface_is_accepted_on_purpose_with_its_right_torsion():
    from workbench.sources.surfaces import mesh_profile, surface_w_max

    big = _disc(10.0, allow_scale=True)
    # uniform 1 Pa: torsion mu * int r dA = mu 2 pi R^3 / 3 (the 1047 N m the trial saw), forces mu pi R^2
    w = surface_w_max(big, mu=0.5, rtol=1e-6)
    assert w[5] == pytest.approx(0.5 * 2 * np.pi * 10.0**3 / 3, rel=1e-5)
    assert w[0] == pytest.approx(0.5 * np.pi * 10.0**2, rel=1e-5)
    assert mesh_profile(big, 50).allow_scale


# ---------------------------------------------------------------- a twist length scale in mm


def test_a_length_scale_in_millimetres_is_refused():
    from workbench.twists import sample_twists_6dfc, sample_twists_thesis

    fix = r"spans 20 m .*probably in millimetres: pass it in metres \(length_scale=20 x 0.001\)"
    with pytest.raises(ValueError, match=fix):
        sample_twists_6dfc(5, 0, 20)
    with pytest.raises(ValueError, match=fix):
        sample_twists_thesis(5, 20)
    # in metres: every rotation axis passes within radius_factor * l_s of the pressure centre
    xi = sample_twists_6dfc(50, 0, 0.02, seed=1, radius_factor=0.25)
    assert np.linalg.norm(xi[:, :3], axis=1).max() <= 0.25 * 0.02


def test_a_profile_built_large_on_purpose_keeps_its_length_scale():
    from workbench import ContactProfile
    from workbench.twists import sample_twists_6dfc

    c = np.array([[-1.5, -0.15, 0], [1.5, -0.15, 0], [1.5, 0.15, 0], [-1.5, 0.15, 0]])  # 3 m long
    prof = ContactProfile(c, np.tile([0.0, 0, 1], (4, 1)), np.ones(4), np.ones(4), allow_scale=True)
    assert prof.length_scale == pytest.approx(3.0)
    xi = sample_twists_6dfc(20, 0, prof, seed=0, radius_factor=0.25)
    assert np.linalg.norm(xi[:, :3], axis=1).max() <= 0.25 * 3.0


# ---------------------------------------------------------------- friction arrows of an array


def test_friction_arrows_of_a_twist_array_are_refused_before_rendering(tmp_path):
    from workbench.runner.viz import render_friction_arrows

    path = tmp_path / "arrows.png"
    with pytest.raises(
        ValueError, match=r"twists must be a dict \{label: \(6,\) twist .*got ndarray of shape \(6, 6\)"
    ):
        render_friction_arrows(None, np.eye(6), path)
    with pytest.raises(ValueError, match=r"enumerate\(array\)"):
        render_friction_arrows(None, np.eye(6), path)
    with pytest.raises(
        ValueError, match=r"twists\['all'\] must be one \(6,\) twist .*split a \(K, 6\) array"
    ):
        render_friction_arrows(None, {"all": np.eye(6)}, path)
    with pytest.raises(ValueError, match="profile must be a ContactProfile; got NoneType"):
        render_friction_arrows(None, {"slide": np.eye(6)[0]}, path)
    assert not path.exists()


# ---------------------------------------------------------------- the grasp scene in mm and degrees


def test_a_scene_in_millimetres_or_degrees_names_the_slip_at_the_top():
    from workbench.sources.scenes import elliptic_cylinder_grasp

    with pytest.raises(
        ValueError, match=r"^a \(ellipse semi-axis .*got 30: probably in millimetres — pass 0.03"
    ) as e:
        elliptic_cylinder_grasp(a=30, b=20)
    assert "from_mesh" not in str(e.value) and "allow_scale" not in str(e.value)
    with pytest.raises(ValueError, match=r"^b \(ellipse .*got 20: probably in millimetres — pass 0.02"):
        elliptic_cylinder_grasp(b=20)
    with pytest.raises(ValueError, match=r"half_angle .*got 34: probably in degrees — pass 0.593412"):
        elliptic_cylinder_grasp(half_angle=34)
    with pytest.raises(ValueError, match=r"half_angle must be < π/2 \(one jaw's side"):
        elliptic_cylinder_grasp(half_angle=1.7)


# ---------------------------------------------------------------- sensitivity --set in mm / degrees


@pytest.mark.parametrize(
    "sets, match",
    [
        ({"a": 30}, r"--set a=30.0: a \[m\] must be a lever arm .*probably in millimetres — pass 0.03"),
        ({"b": 20}, r"--set b=20.0: b \[m\] .*probably in millimetres — pass 0.02"),
        (
            {"half_angle": 34},
            r"--set half_angle=34.0: half_angle \[rad\] .*probably in degrees — pass 0.593412",
        ),
        ({"half_angle": 1.7}, r"half_angle must be < π/2"),
        ({"margin_steps": 0}, r"margin_steps must be an integer >= 1 .*e.g. margin_steps=12"),
    ],
)
def test_sensitivity_refuses_a_scene_slip_before_any_work(tmp_path, sets, match):
    import contextlib

    from workbench.runner.experiment_config import build_config

    # 1.7 rad is a plausible wrap (warned as unusual) but not one jaw's side of this scene
    unusual = sets.get("half_angle") == 1.7
    with pytest.warns(ImplausibleWarning) if unusual else contextlib.nullcontext():
        with pytest.raises(SystemExit, match=match) as e:
            build_config("sensitivity", True, str(tmp_path / "out"), None, sets)
    assert "from_mesh" not in str(e.value)
    assert not (tmp_path / "out").exists()


def test_sensitivity_defaults_pass_the_new_quantities_silently(tmp_path):
    import warnings

    from workbench.runner.experiment_config import build_config

    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        cfg = build_config("sensitivity", False, str(tmp_path), None, {"a": 0.035, "half_angle": 1.0})
    assert (cfg["a"], cfg["half_angle"]) == (0.035, 1.0)


# ---------------------------------------------------------------- wall stiffness with a WallGeometry


@pytest.fixture(scope="module")
def cup_wall():
    import trimesh

    from workbench.fem.object_wall import object_wall

    cup = trimesh.creation.cylinder(radius=0.03, height=0.08, sections=64)
    cup.apply_translation((0, 0, 0.04))
    return object_wall(cup, n_theta=16, n_z=8, top="clamped")


@pytest.mark.jit_only("about 40 s as pure Python (the wall squeeze)")
def test_wall_stiffness_takes_the_geometry_object_wall_returns(cup_wall):
    from workbench.fem.wall import squeeze
    from workbench.fem.wall_grasps import stiffness_at

    geo, wall = cup_wall
    L = np.array([[0.03, 0.0, 0.04], [-0.03, 0.0, 0.04]])
    (row,) = stiffness_at(wall, geo, L, force=10.0)
    ref = squeeze(wall, np.array([0.0, 0.0, 0.04]), np.array([-1.0, 0.0, 0.0]), force=10.0).stiffness
    assert row["stiffness"] == pytest.approx(ref, rel=1e-9) and not row["failed"]
    (side_wall,) = stiffness_at(wall, geo.surface, L, force=10.0)  # no lip: the same heights
    assert side_wall["stiffness"] == row["stiffness"]


def test_wall_stiffness_refuses_another_surface_type_or_swapped_arguments(cup_wall):
    import trimesh

    from workbench.fem.wall_grasps import stiffness_at

    geo, wall = cup_wall
    L = np.array([[0.03, 0.0, 0.04], [-0.03, 0.0, 0.04]])
    with pytest.raises(ValueError, match=r"a RadialSurface .* or the WallGeometry .*got Trimesh — pass geo"):
        stiffness_at(wall, trimesh.creation.box(), L)
    with pytest.raises(
        ValueError, match=r"wall must be the Wall .*got WallGeometry — geo, wall = object_wall"
    ):
        stiffness_at(geo, wall, L)


# ---------------------------------------------------------------- a GWS with a zero or mm torque length


def test_build_gws_refuses_a_torque_length_that_is_no_length_in_metres():
    from workbench.grasp import build_gws, point_contact

    sets = [point_contact([s * 0.03, 0, 0], [s, 0, 0], 10.0, n_edges=8) for s in (1.0, -1.0)]
    fix = "pass the grasp's size in metres"
    with pytest.raises(ValueError, match=rf"torque_length must be a lever arm .* got 0 .*{fix}"):
        build_gws(sets, 0.5, torque_length=0)
    with pytest.raises(ValueError, match=r"got 30: probably in millimetres — pass 0.03"):
        build_gws(sets, 0.5, torque_length=30)
    with pytest.raises(ValueError, match=rf"got nan .*{fix}"):
        build_gws(sets, 0.5, torque_length=float("nan"))
    # in metres: torques divided by it.  Two point contacts (mu 0.5, 10 N, 8-edge cones through
    # +-z) at +-30 mm hold a pure torque about y of 2 x 0.03 m x 5 N = 0.3 N m: 10 in units of 0.03 m
    hull = build_gws(sets, 0.5, torque_length=0.03)
    assert hull.dim == 5
    assert hull.contains(np.array([[0.0, 0, 0, 0, 9.99, 0], [0.0, 0, 0, 0, -9.99, 0]])).all()
    assert not hull.contains(np.array([[0.0, 0, 0, 0, 10.01, 0], [0.0, 0, 0, 0, -10.01, 0]])).any()


# ---------------------------------------------------------------- a margin with no bisection step


def test_a_margin_of_zero_bisection_steps_is_refused():
    from workbench.grasp.margin import margin_vs_truth, resistance_margin

    w = np.array([0.0, -1.0, 0, 0, 0, 0])

    def ball(v):  # resists every wrench up to 3.4 times the disturbance: margin 3.4
        return bool(np.linalg.norm(v) <= 3.4)

    for steps in (0, 2.5, True):
        with pytest.raises(
            ValueError, match=r"steps must be an integer >= 1 .*pass a whole number of steps, e.g. steps=12"
        ):
            resistance_margin(ball, w, steps=steps)
    s = resistance_margin(ball, w, steps=20)  # resolution 12 / 2^20 in log2 s
    assert 3.4 * 2 ** (-12 / 2**20) <= s <= 3.4
    with pytest.raises(ValueError, match="resisted must be a callable"):
        resistance_margin(np.ones(6), w, steps=20)
    with pytest.raises(ValueError, match=r"span must be a number > 1"):
        margin_vs_truth(np.ones(3), np.ones(3), span=0.5)

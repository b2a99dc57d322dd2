"""The lever scene of thesis §4.1.3 (workbench.grasp.lever_scene): the seeded grasps are the
lever draw followed by the sensor forces and the noise, the profiles are both jaws at a unit reading,
and a model's plain prediction follows Coulomb friction — two hard points at 20 N, μ 0.3 carry
a weight of up to 2 μ f = 12 N along the jaws but no torsion about the grasp axis, whether the
grasps share unit-force profiles (predict_resisted) or one grasp has its own at its reading
(predict_grasp)."""

import numpy as np
import pytest

from workbench.grasp.lever_scene import (
    predict_grasp,
    predict_resisted,
    scene_inputs,
    scene_profiles,
    scene_sets,
)
from workbench.grasp.models import ModelParameters
from workbench.grasp.resistance import CutStore
from workbench.grasp.tasks import lever_disturbances
from workbench.limit_surface import LimitSurfaceCache
from workbench.sources.scenes import elliptic_cylinder_grasp

CONFIG = {
    "seed": 3,
    "n_disturbances": 6,
    "weight_range": [2.0, 14.0],
    "lever_x": 0.04,
    "lever_z": 0.025,
    "force_range": [20.0, 35.0],
    "mu": 0.3,
    "noise_mu": 0.05,
    "noise_force": 0.03,
    "a": 0.03,
    "b": 0.02,
    "half_angle": 0.6,
    "n_elements": 60,
    "M": 50,
}


def test_the_draw_is_the_lever_disturbances_then_the_forces_then_the_noise():
    W, forces, mu_true, f_true = scene_inputs(CONFIG)
    again = scene_inputs(dict(CONFIG))
    for a, b in zip((W, forces, mu_true, f_true), again, strict=True):
        np.testing.assert_array_equal(a, b)  # same seed, same grasps
    rng = np.random.default_rng(3)
    np.testing.assert_array_equal(W, lever_disturbances(rng, 6, [2.0, 14.0], 0.04, 0.025))
    np.testing.assert_array_equal(forces, rng.uniform(20.0, 35.0, 6))
    assert W.shape == (6, 6) and ((forces >= 20.0) & (forces <= 35.0)).all()
    # noise-free: the truth is the nominal μ and the sensor's force, exactly
    W0, forces0, mu0, f0 = scene_inputs({**CONFIG, "noise_mu": 0.0, "noise_force": 0.0})
    np.testing.assert_array_equal(W0, W)
    np.testing.assert_array_equal(mu0, np.full(6, 0.3))
    np.testing.assert_array_equal(f0, forces0)
    assert not np.array_equal(mu_true, mu0) and np.abs(mu_true / 0.3 - 1).max() < 0.05 * 5


def test_the_profiles_are_both_jaws_at_a_unit_reading_mirrored_across_the_grasp_axis():
    right, left = scene_profiles(CONFIG, 2.4, 0.03)
    # a unit force-sensor reading along the grasp axis x: on the curved patch the normal forces'
    # magnitudes sum to more than their x components
    for p, sign in ((right, -1), (left, 1)):
        assert p.normal_wrench[0] == pytest.approx(sign * 1.0, rel=1e-12)
        assert p.F > 1.0
    # the −x jaw is the +x one turned by π about z
    np.testing.assert_allclose(left.pressure_center, right.pressure_center * [-1, -1, 1], atol=1e-15)
    assert right.pressure_center[0] > 0.02  # on the ellipse's +x side (a = 3 cm)


def test_two_hard_points_carry_a_weight_up_to_two_mu_f_and_no_torsion():
    sets = scene_sets(scene_profiles(CONFIG, 2.4, 0.03), "point", LimitSurfaceCache(), CONFIG)
    assert len(sets) == 2
    W = np.array(
        [
            [0.0, -5.0, 0.0, 0.0, 0.0, 0.0],  # well below 2 μ f = 12 N
            [0.0, -20.0, 0.0, 0.0, 0.0, 0.0],  # well above
            [0.0, 0.0, 0.0, 0.01, 0.0, 0.0],  # a little torsion about the grasp axis x
        ]
    )
    pred, ms = predict_resisted(sets, W, np.full(3, 20.0), 0.3, CutStore())
    assert pred.dtype == bool and pred.tolist() == [True, False, False]
    assert ms >= 0
    # the lever draw always twists about the grasp axis (τ_x = r_z m g): no hard-point grasp holds it
    W, forces, _, _ = scene_inputs(CONFIG)
    assert (np.abs(W[:, 3]) > 0).all()
    assert not predict_resisted(sets, W, forces, 0.3, CutStore())[0].any()


def test_one_grasp_with_its_own_profiles_at_its_reading_is_the_same_coulomb_limit():
    """The profiles made at the 20 N reading, not rescaled: the two hard points hold 5 N along
    the jaws (< 2 μ f = 12 N), not 20 N, nor torsion; the same verdicts as predict_resisted's
    unit profiles scaled by 20 N, and the build and decision timed."""
    profiles = elliptic_cylinder_grasp(0.03, 0.02, 0.6, 0.03, 2.4, 20.0, n_elements=60)
    params, cache = ModelParameters(M=50), LimitSurfaceCache()
    W = [[0.0, -5.0, 0, 0, 0, 0], [0.0, -20.0, 0, 0, 0, 0], [0.0, 0, 0, 0.01, 0, 0]]
    got = [predict_grasp(profiles, "point", np.array(w), 0.3, params, cache) for w in W]
    assert [held for held, _ in got] == [True, False, False]
    assert all(isinstance(held, bool) and ms > 0 for held, ms in got)
    unit = scene_sets(scene_profiles(CONFIG, 2.4, 0.03), "point", LimitSurfaceCache(), CONFIG)
    pred, _ = predict_resisted(unit, np.array(W), np.full(3, 20.0), 0.3, CutStore())
    assert pred.tolist() == [held for held, _ in got]
    # a limit-surface model too: the 6DLS of the curved patch holds the 5 N weight
    assert predict_grasp(profiles, "6dls", np.array(W[0]), 0.3, params, cache)[0] is True

"""Careless inputs a new user fed the samplers, the success-threshold fits, a Hertz peer and a
profile's rigid move, each accepted silently or refused with a message naming the wrong thing:
a fractional seed (numpy's bare TypeError) and an int where a generator was wanted (an
AttributeError), a negative quality threshold, trials of one outcome only scored as if they
told successes from failures, a modulus passed where the sphere radius goes (read as a radius in
micrometres) and a rotation matrix scaled by 2 (refused as if its shape were wrong).  Each is
refused or warned about now, the message naming the fix; the corrected call gives the right
number."""

import warnings

import numpy as np
import pytest

from workbench import ContactProfile
from workbench.plausible import ImplausibleWarning

# ------------------------------------------------------------------ seeds


def test_a_fractional_seed_is_refused_by_the_twist_samplers_naming_an_integer():
    from workbench.twists import fibonacci_sphere, sample_twists_6dfc, sample_twists_thesis

    with pytest.raises(
        ValueError,
        match=r"seed must be an integer >= 0 or a numpy.random.Generator; got 1.5 — "
        r"pass an integer, e.g. seed=0",
    ):
        sample_twists_thesis(10, 0.02, seed=1.5)
    with pytest.raises(ValueError, match=r"got 3.0 — pass seed=3"):
        sample_twists_6dfc(4, 2, 0.02, seed=3.0)
    with pytest.raises(ValueError, match=r"got -1 — pass an integer"):
        sample_twists_thesis(10, 0.02, seed=-1)
    xi = sample_twists_thesis(10, 0.02, seed=3)
    # the translations are [e; 0] along the Fibonacci directions, whatever the seed
    assert xi.shape == (20, 6)
    np.testing.assert_allclose(xi[10:], np.hstack([fibonacci_sphere(10), np.zeros((10, 3))]), atol=1e-15)
    # an int seed and a Generator of that seed draw the same twists
    np.testing.assert_array_equal(xi, sample_twists_thesis(10, 0.02, seed=np.random.default_rng(3)))


def test_an_int_seed_for_the_lever_disturbances_draws_as_its_generator():
    from workbench.grasp.tasks import lever_disturbances

    with pytest.raises(
        ValueError,
        match=r"rng must be an integer >= 0 or a numpy.random.Generator; got 1.5 — pass an integer",
    ):
        lever_disturbances(1.5, 4)
    got = lever_disturbances(0, 4, weight_range=(2.0, 3.0), lever_x=0.05, lever_z=0.07)
    # the same draws, by hand, from the generator of seed 0
    rng = np.random.default_rng(0)
    mg = rng.uniform(2.0, 3.0, 4)
    rx = rng.uniform(-0.05, 0.05, 4)
    rz = rng.uniform(-0.07, 0.07, 4)
    noise = rng.normal(0.0, 1.0, (4, 6)) * [0.0, 0.3, 0.3, 0.003, 0.003, 0.003]
    want = np.zeros((4, 6))
    want[:, 1], want[:, 3], want[:, 5] = -mg, rz * mg, -rx * mg
    np.testing.assert_allclose(got, want + noise, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(
        got, lever_disturbances(np.random.default_rng(0), 4, (2.0, 3.0), lever_x=0.05, lever_z=0.07)
    )


def test_a_bad_seed_is_refused_by_every_sampler_before_it_draws():
    import trimesh

    from workbench.grasp.sampling import antipodal_grasps
    from workbench.limit_surface.cache import SamplerSpec
    from workbench.limit_surface.linearize import sample_directions

    box = trimesh.creation.box(extents=(0.04, 0.04, 0.04))
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0 .*got 0.5 — pass an integer"):
        antipodal_grasps(box, 2, 0.5, seed=0.5)
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0 .*got '7' — pass an integer"):
        sample_directions(5, 3, seed="7")
    # a cache key: the same draw every time, so a Generator is refused too
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0 here .*got a numpy.random.Generator"):
        SamplerSpec(kind="thesis", seed=np.random.default_rng(0))
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0; got -2 — pass an integer"):
        SamplerSpec(kind="thesis", seed=-2)
    s = sample_directions(50, 3, seed=2)
    # "cube": every direction on the surface ||s||_inf = 1
    np.testing.assert_allclose(np.abs(s).max(axis=1), 1.0, rtol=0, atol=0)
    np.testing.assert_array_equal(s, sample_directions(50, 3, seed=np.random.default_rng(2)))


def test_the_peer_metric_takes_its_seed_by_the_one_rule():
    from workbench.peers import metrics
    from workbench.peers.hertz import hertz_profile

    ref = hertz_profile(0.015, 0.001, 1.0e6, 0.45, center=np.array([0.0, 0.0, 0.02]))
    # its truth points must be the same for every peer compared: an int, not a Generator
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0 here .*pass an integer, e.g. seed=0"):
        metrics.fitted_ls_error(ref, ref, 0.5, n_twists=40, seed=np.random.default_rng(0))
    with pytest.raises(ValueError, match=r"seed must be an integer >= 0; got 2.0 — pass seed=2"):
        metrics.fitted_ls_error(ref, ref, 0.5, n_twists=40, seed=2.0)


# ------------------------------------------------------------------ success thresholds


def test_a_negative_quality_threshold_is_refused_naming_the_sign_slip():
    from workbench.grasp.threshold import fit_normaliser

    values, truth = [1.0, 2.0, 3.0, 4.0], [True, True, False, False]
    with pytest.raises(
        ValueError,
        match=r"sigma must be a finite quality threshold < 1 and >= 0 \(0.5 in the thesis\); got -0.5 — "
        r"a negative threshold predicts success beyond X_max; sign slip\? pass 0.5",
    ):
        fit_normaliser(values, truth, sigma=-0.5)
    with pytest.raises(ValueError, match=r"got -3 — pass e.g. 0.5"):
        fit_normaliser(values, truth, sigma=-3)
    # the cut t = 2.5 between the successes and the failures: X_max = t / (1 - σ)
    assert fit_normaliser(values, truth, sigma=0.5) == pytest.approx(5.0, rel=1e-15)
    assert fit_normaliser(values, truth, sigma=0.0) == pytest.approx(2.5, rel=1e-15)


@pytest.mark.parametrize("outcome", [True, False])
def test_trials_of_one_outcome_only_warn_that_the_scores_tell_nothing_apart(outcome):
    from workbench.grasp.crossval import crossval_scores

    q, group = np.linspace(0.0, 1.0, 6), np.repeat(np.arange(3), 2)
    kind = "successes" if outcome else "failures"
    with pytest.warns(ImplausibleWarning) as record:
        got = crossval_scores(q, np.full(6, outcome), group)
    assert len(record) == 1  # one warning for the call, not one per score
    msg = str(record[0].message)
    assert msg.startswith(
        f"all 6 trials are {kind}: balanced_accuracy 1 is the recall of the {kind} alone and roc_auc is NaN"
    )
    assert "score trials with both outcomes" in msg
    # the documented values are kept
    assert got["balanced_accuracy"] == 1.0 and np.isnan(got["roc_auc"])
    assert got["n_success"] == (6 if outcome else 0)


def test_the_threshold_free_scorers_warn_on_one_outcome_and_not_on_both():
    from workbench.grasp.crossval import average_precision, average_recall, roc_auc

    q = [0.1, 0.4, 0.35, 0.8]
    with pytest.warns(ImplausibleWarning, match=r"all 4 trials are successes: roc_auc is NaN"):
        assert np.isnan(roc_auc(q, [1, 1, 1, 1]))
    with pytest.warns(
        ImplausibleWarning, match=r"all 4 trials are successes: average_precision is 1 whatever"
    ):
        assert average_precision(q, [1, 1, 1, 1]) == 1.0
    with pytest.warns(ImplausibleWarning, match=r"all 4 trials are failures: average_recall is NaN"):
        assert np.isnan(average_recall(q, [0, 0, 0, 0]))
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        # 3 of the 4 (success, failure) pairs ranked right: 0.35 < 0.4 is the miss
        assert roc_auc(q, [0, 0, 1, 1]) == pytest.approx(0.75, rel=1e-15)
        # precision 1 at recall 1/2 (0.8), 2/3 at recall 1 (0.8, 0.4, 0.35)
        assert average_precision(q, [0, 0, 1, 1]) == pytest.approx(0.5 * 1 + 0.5 * 2 / 3, rel=1e-15)


# ------------------------------------------------------------------ peers


def test_a_modulus_in_the_radius_place_names_the_swapped_arguments():
    from workbench.peers.elastic_foundation import foundation_modulus
    from workbench.peers.hertz import hertz_force

    # meant hertz_force(0.02, 1e-3, 1e6, 0.45): the unit reading alone ("micrometres") would be
    # the wrong fix, so the refusal also names the swap
    with pytest.raises(ValueError) as exc:
        hertz_force(1e6, 0.45, 0.02, 1e-3)
    msg = str(exc.value)
    assert msg.startswith("R (sphere radius)")
    assert "or arguments swapped: 1e+06 is the size of a modulus [Pa]" in msg
    # a modulus the size of a length: its unit reading and the swap
    with pytest.raises(
        ValueError, match=r"E \(Young's modulus\).*or arguments swapped: 0.005 is the size of a length"
    ):
        foundation_modulus(0.005, 1e6)
    # a radius in millimetres is read as one, with no swap named (20 m is no modulus)
    with pytest.raises(ValueError, match=r"probably in millimetres") as exc:
        hertz_force(20.0, 1e-3, 1e6, 0.45)
    assert "swapped" not in str(exc.value)
    # F = (4/3) E/(1 - ν²) √R δ^1.5 (Johnson §4.2)
    want = 4.0 / 3.0 * 1e6 / (1.0 - 0.45**2) * np.sqrt(0.02) * 1e-3**1.5
    assert hertz_force(0.02, 1e-3, 1e6, 0.45) == pytest.approx(want, rel=1e-14)
    assert foundation_modulus(1e6, 0.005) == pytest.approx(2e8, rel=1e-15)


def test_a_length_too_large_keeps_its_unit_reading():
    from workbench.peers.mujoco_cone import torsion_coefficient

    # 5000 is read as a radius in micrometres first (the swap is named after it)
    with pytest.raises(ValueError, match=r"a \(patch radius\) spans 5000 m .*probably in micrometres"):
        torsion_coefficient(5000.0, 0.5)


# ------------------------------------------------------------------ profile


def test_a_scaled_rotation_is_refused_as_not_orthogonal_naming_the_factor():
    x, y = np.meshgrid(np.linspace(-0.01, 0.01, 5), np.linspace(-0.01, 0.01, 5))
    c = np.column_stack([x.ravel(), y.ravel(), np.zeros(25)])
    p = ContactProfile(c, np.tile([0.0, 0, 1], (25, 1)), np.full(25, 1e-5), np.full(25, 4e4))
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # 90° about x
    with pytest.raises(
        ValueError,
        match=r"rotation must be orthogonal \(R Rᵀ = I\); got R Rᵀ differing from I by up to 3: "
        r"a rotation scaled by 2\? pass rotation / 2",
    ):
        p.transformed(rotation=2 * Rx)
    with pytest.raises(ValueError, match=r"differing from I by up to 0.1: not a rotation — build it with"):
        p.transformed(rotation=[[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    with pytest.raises(
        ValueError, match=r"rotation must be a \(3, 3\) orthogonal matrix; got shape \(2, 2\)"
    ):
        p.transformed(rotation=np.eye(2))
    moved = p.transformed(rotation=2 * Rx / 2)
    np.testing.assert_allclose(moved.normals, np.tile([0.0, -1.0, 0.0], (25, 1)), atol=1e-15)
    assert moved.F == pytest.approx(p.F, rel=1e-15)

"""stiffness_at / grasp_pairs on a meshed tube: the same stiffness as a direct squeeze,
rigid and failed flags with their reasons, careless locations."""

import numpy as np
import pytest
import trimesh

from workbench.fem.mesh_wall import radial_surface
from workbench.fem.wall import build_wall, squeeze
from workbench.fem.wall_grasps import RIGID_STIFFNESS, grasp_pairs, stiffness_at


@pytest.fixture(scope="module")
def tube():
    m = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=128)
    m.apply_translation([0, 0, 0.05])
    surf = radial_surface(m, z_range=(0.005, 0.08))  # the top 20 mm left out: "rigid" there
    return surf, build_wall(surf, thickness=0.5e-3, n_theta=32, n_z=8, z_range=surf.z_range)


def _pair(z, r=0.03):
    return np.array([[r, 0.0, z], [-r, 0.0, z]])


@pytest.mark.jit_only("over 15 s as pure Python")
def test_stiffness_is_the_squeeze_at_the_midpoint(tube):
    surf, wall = tube
    a, b = _pair(0.06), _pair(0.04)
    locs = np.vstack([a[:1], b[:1], a[1:], b[1:]])  # points i and i + n form grasp i
    rows = stiffness_at(wall, surf, locs)
    for row, z in zip(rows, (0.06, 0.04), strict=True):
        ref = squeeze(wall, np.array([0.0, 0.0, z]), np.array([-1.0, 0.0, 0.0]))["stiffness"]
        assert row["stiffness"] == pytest.approx(ref, rel=1e-9)
        assert not row["rigid"] and not row["failed"] and row["reason"] is None


def test_rigid_and_failed_grasps_are_flagged_not_fatal(tube):
    surf, wall = tube
    top = _pair(0.09)  # above the modelled wall
    tilted = np.array([[0.03, 0.0, 0.05], [-0.03, 0.0, 0.06]])
    base = _pair(0.01)  # the jaw footprint reaches the clamped rim: the jaw rests on it
    locs = np.vstack([top[:1], tilted[:1], base[:1], top[1:], tilted[1:], base[1:]])
    rows = stiffness_at(wall, surf, locs)
    assert rows[0]["rigid"] and rows[0]["stiffness"] == RIGID_STIFFNESS
    assert rows[1]["failed"] and "not horizontal" in rows[1]["reason"]
    assert (
        rows[2]["rigid"] and "clamped edge" in rows[2]["reason"] and rows[2]["stiffness"] == RIGID_STIFFNESS
    )
    assert not rows[2]["failed"]


@pytest.mark.jit_only("over 15 s as pure Python")
def test_non_antipodal_pairs_are_flagged_with_the_chord_angle(tube, caplog):
    """On a circle, a chord between points φ apart makes (180° − φ)/2 with both normals:
    φ = 180° is antipodal (0°), φ = 100° gives 40° (kept), φ = 60° gives 60° (> 45°: flagged,
    still squeezed, and logged)."""
    from workbench.fem.wall_grasps import axis_normal_angles

    surf, wall = tube
    r, z = 0.03, 0.05
    phis = np.radians([180.0, 100.0, 60.0])
    a = np.tile([r, 0.0, z], (3, 1))
    b = np.column_stack([r * np.cos(phis), r * np.sin(phis), np.full(3, z)])
    np.testing.assert_allclose(axis_normal_angles(surf, a, b), [0.0, 40.0, 60.0], atol=0.5)
    with caplog.at_level("WARNING", logger="workbench.fem.wall_grasps"):
        rows = stiffness_at(wall, surf, np.vstack([a, b]))
    assert [row["non_antipodal"] for row in rows] == [False, False, True]
    assert rows[2]["axis_normal_deg"] == pytest.approx(60.0, abs=0.5)
    assert not rows[2]["failed"] and np.isfinite(rows[2]["stiffness"])
    assert "grasp 2 is not antipodal" in caplog.text and "grasp 1 " not in caplog.text
    caplog.clear()
    with caplog.at_level("WARNING", logger="workbench.fem.wall_grasps"):  # the caller's grasp numbers
        stiffness_at(wall, surf, np.vstack([a[2:], b[2:]]), grasp_ids=[17])
    assert "grasp 17 is not antipodal" in caplog.text
    # two coincident jaw points: no axis, a failure that says so (not "no wall under a jaw")
    (row,) = stiffness_at(wall, surf, np.vstack([a[:1], a[:1]]))
    assert row["failed"] and "coincide" in row["reason"] and not row["non_antipodal"]


@pytest.mark.parametrize(
    "locs, match",
    [
        (np.zeros((3, 3)), "2n points"),
        (np.zeros((4, 2)), r"\(2n, 3\)"),
        (
            np.vstack([_pair(0.05)[:1] * [0.9, 1, 1], _pair(0.05)[1:]]),
            "location 0 .* off the object's surface.*-3.00 mm off it",
        ),
        (_pair(0.05) * 1000, "locations 0, 1 .2 of 2. lie outside the object.s box.*probably in millimetres"),
        (_pair(0.05) * [0.95, 1, 1], r"locations 0, 1 \(2 of 2\) lie off the object.s surface"),
    ],
)
def test_careless_locations_are_refused(tube, locs, match):
    surf, _ = tube
    with pytest.raises(ValueError, match=match):
        grasp_pairs(locs, surf)


def test_one_factor_calibration_against_a_direct_computation():
    """workbench.fem.calibration: the factor is the median log ratio on the training grasps (exact on
    a model off by a constant), one per group, and the held-out scores are the plain ones."""
    from scipy.stats import spearmanr

    from workbench.fem.calibration import calibrate, held_out, split_scores

    rng = np.random.default_rng(3)
    measured = np.exp(rng.normal(7.0, 0.6, 30))
    model = measured / 4.0  # a model 4x too soft everywhere
    train = np.arange(0, 30, 2)
    np.testing.assert_allclose(calibrate(model, measured, train), 4.0, rtol=1e-12)
    assert held_out(model, measured, train)["median_abs_log_ratio"] < 1e-12
    # off by 2x in the upper half of the grasps: one factor cannot fit, one per half can
    groups = (np.arange(30) >= 15).astype(int)
    model2 = model * np.where(groups == 1, 0.5, 1.0)
    # training: 8 grasps of the lower half (ratio 4) and 7 of the upper (ratio 8): factor 4, so the
    # 8 held-out upper grasps (of 15) are off by log 2
    assert held_out(model2, measured, train)["median_abs_log_ratio"] == pytest.approx(np.log(2), rel=1e-12)
    assert held_out(model2, measured, train, groups)["median_abs_log_ratio"] < 1e-12
    # a noisy model: the held-out score is the direct one
    noisy = measured * np.exp(rng.normal(0.0, 0.3, 30))
    c = np.exp(np.median(np.log(measured[train] / noisy[train])))
    test = np.setdiff1d(np.arange(30), train)
    h = held_out(noisy, measured, train)
    assert h["median_abs_log_ratio"] == pytest.approx(
        np.median(np.abs(np.log(c * noisy[test] / measured[test])))
    )
    assert h["spearman"] == pytest.approx(spearmanr(noisy[test], measured[test]).statistic)
    spread = split_scores(noisy, measured, n_splits=50)
    assert spread["median_abs_log_ratio"]["p10"] <= spread["median_abs_log_ratio"]["median"]
    assert spread["median_abs_log_ratio"]["median"] <= spread["median_abs_log_ratio"]["p90"]
    with pytest.raises(ValueError, match="finite and > 0"):
        calibrate(np.r_[model[:-1], np.inf], measured, train)


def test_missing_physics_measurements_on_constructed_maps():
    """workbench.fem.calibration.missing_physics on maps built with one known defect each: a series
    spring, a closing that levels off at 0.45 of the width, a model too stiff near a clamp."""
    from workbench.fem.calibration import missing_physics

    rng = np.random.default_rng(5)
    n, F = 40, 10.0
    model = np.exp(rng.uniform(np.log(300.0), np.log(3e4), n))
    width = rng.uniform(0.03, 0.08, n)
    far = np.full(n, np.inf)
    # (1) a 2e-5 m/N spring in series with a wall 3x the model: s = 1 / (1/(3 s_m) + c)
    c = 2e-5
    measured = 1.0 / (1.0 / (3.0 * model) + c)
    mp = missing_physics(model, measured, width=width, clamp_distance=far, force=F)
    assert mp["series_compliance_bound_m_per_N"] == pytest.approx(1.0 / measured.max(), rel=1e-12)
    assert mp["series_compliance_bound_m_per_N"] > c  # the bound holds
    k = mp["calibration_factor"]
    s_med = k * np.median(model)
    assert mp["series_effect_at_median"] == pytest.approx(1 - 1 / (1 + s_med / measured.max()), rel=1e-12)
    # (2) the measured closing levels off at 0.45 x width: residuals rise with the predicted closing
    closing = np.minimum(F / (0.5 * model), 0.45 * width)
    measured = F / closing
    mp = missing_physics(model, measured, width=width, clamp_distance=far, force=F)
    cf = mp["closing_fraction"]
    assert cf["measured_closing_over_width_max"] == pytest.approx(0.45, rel=1e-12)
    assert cf["spearman_residual"] > 0.5
    top = [b for b in cf["bins"] if b["predicted_closing_over_width"][1] is None]
    assert not top or top[0]["measured_closing_over_width_max"] <= 0.45 + 1e-12
    assert mp["away_from_clamps"]["scores"] is not None
    # (3) a model 4x too stiff within 10 mm of a clamp, exact elsewhere; two grasps it calls rigid
    d = rng.uniform(0.0, 0.08, n)
    d[:2] = 0.002
    measured = 2.0 * model * np.where(d < 0.01, 0.25, 1.0)
    model_r = model.copy()
    model_r[:2] = np.inf
    mp = missing_physics(model_r, measured, width=width, clamp_distance=d, force=F, near=0.01)
    away = mp["away_from_clamps"]
    assert away["n"] == int(np.sum(d >= 0.01)) and away["n_all"] == n - 2
    assert away["scores"]["median_abs_log_ratio"]["p90"] < 1e-12  # exact away from the clamp
    assert away["model_rigid_near_clamps_measured"] == pytest.approx(measured[:2].tolist())
    with pytest.raises(ValueError, match="width must be finite and > 0"):
        missing_physics(model, measured, width=np.zeros(n), clamp_distance=far)
    with pytest.raises(ValueError, match="one length"):
        missing_physics(model, measured[:-1], width=width, clamp_distance=far)


def test_split_scores_of_any_calibrated_model():
    """split_scores_of with the one-factor fit is split_scores (same halves); a fit that
    predicts NaN on some halves is left out and counted; a model calibrated by a power law
    (s = c * m**2, as no factor can fit) is scored by its own fit."""
    from workbench.fem.calibration import calibrate, split_scores, split_scores_of

    rng = np.random.default_rng(3)
    model = rng.uniform(300, 3000, 30)
    measured = 0.2 * model * np.exp(rng.normal(0, 0.1, 30))
    a = split_scores(model, measured, n_splits=40)
    b = split_scores_of(lambda tr: model * calibrate(model, measured, tr), measured, n_splits=40)
    assert a == b and b["n_failed"] == 0 and b["n_splits"] == 40
    calls = iter(range(10**6))
    flaky = split_scores_of(
        lambda tr: model * (np.nan if next(calls) % 4 == 0 else 0.2), measured, n_splits=40
    )
    assert flaky["n_failed"] == 10
    sq = 1e-4 * model**2

    def power_fit(tr):  # exponent 1/2 and a factor, fitted on the training half
        k, logc = np.polyfit(np.log(sq[tr]), np.log(measured[tr]), 1)
        return np.exp(logc) * sq**k

    fit = split_scores_of(power_fit, measured, n_splits=40)
    assert fit["median_abs_log_ratio"]["median"] < 0.12  # the noise is 0.1 in log


def test_one_factor_validation_on_a_model_off_by_a_constant():
    """workbench.fem.calibration.one_factor_validation: rigid (>= the rigid threshold) and failed
    (NaN) grasps left out and counted; the half drawn as one permutation of the usable grasps; a
    model 4x too soft calibrated to c = 4 exactly (E_effective = 4 E) with a perfect held-out
    score; the two-factor split at the median height."""
    from workbench import config
    from workbench.fem.calibration import one_factor_validation, split_scores

    rng = np.random.default_rng(11)
    n = 24
    measured = np.exp(rng.normal(7.0, 0.6, n))
    model = measured / 4.0
    model[0] = np.nan  # the FEM failed
    model[1] = RIGID_STIFFNESS  # the FEM calls it rigid
    measured[2] = 8e10  # the measured map calls it rigid
    heights = np.linspace(0.01, 0.1, n)
    scores, train, test = one_factor_validation(
        model, measured, np.random.default_rng(5), heights=heights, E=2e9
    )
    usable = np.arange(3, n)
    np.testing.assert_array_equal(train, np.random.default_rng(5).permutation(usable)[: usable.size // 2])
    np.testing.assert_array_equal(np.sort(np.r_[train, test]), usable)
    assert scores["calibrated"]["scale"] == pytest.approx(4.0, rel=1e-12)
    assert scores["calibrated"]["E_effective_Pa"] == pytest.approx(8e9, rel=1e-12)
    assert scores["median_abs_log_ratio"] < 1e-12 and scores["spearman"] == pytest.approx(1.0)
    assert scores["uncalibrated_median_log_ratio"] == pytest.approx(-np.log(4.0), rel=1e-12)
    assert (scores["n_train"], scores["n_test"]) == (10, 11)
    assert (scores["rigid_measured"], scores["rigid_fem"]) == (1, 1)
    groups = (heights[usable] > np.median(heights[usable])).astype(int)
    assert scores["two_factors_by_height"] == split_scores(model[usable], measured[usable], groups=groups)
    # the rigid threshold is config's: raised above 8e10, the rigid grasps count as stiff ones
    with config.override(rigid_stiffness_threshold=1e12):
        s2, _, _ = one_factor_validation(model, measured, np.random.default_rng(5), heights=heights, E=2e9)
    assert s2["n_train"] + s2["n_test"] == n - 1 and s2["rigid_measured"] == 0
    with pytest.raises(ValueError, match="at least 4 grasps"):
        one_factor_validation(model[:6], measured[:6], rng, heights=heights[:6], E=2e9)

"""One-scalar calibration of a simulated stiffness map against a measured one
(workbench.fem.calibration): the factor, the held-out scores and their spread
over random halves, the measurements of what one factor misses, and careless input."""

import numpy as np
import pytest

from workbench.fem.wall_grasps import RIGID_STIFFNESS


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


def test_a_group_without_training_grasps_gets_the_overall_factor():
    """Ratios measured / model = 2, 4, ..., 64 (log ratios k ln 2, k = 1..6) in three groups
    of two; training on the first four grasps: group 0 has log ratios (1, 2) ln 2, median
    1.5 ln 2; group 1 (3, 4) ln 2, median 3.5 ln 2; group 2 none, so the median of all four
    training ratios, 2.5 ln 2."""
    from workbench.fem.calibration import calibrate

    model = np.full(6, 250.0)
    measured = model * 2.0 ** np.arange(1, 7)
    groups = np.array([0, 0, 1, 1, 2, 2])
    c = calibrate(model, measured, np.arange(4), groups)
    np.testing.assert_allclose(c, 2.0 ** np.array([1.5, 1.5, 3.5, 3.5, 2.5, 2.5]), rtol=1e-12)
    # without groups, one factor: 2 ** 2.5 everywhere
    np.testing.assert_allclose(calibrate(model, measured, np.arange(4)), 2.0**2.5, rtol=1e-12)


def _spearman_no_ties(x, y):
    """Pearson correlation of the ranks (valid without ties)."""
    rx, ry = np.argsort(np.argsort(x)), np.argsort(np.argsort(y))
    return float(np.corrcoef(rx, ry)[0, 1])


def test_split_scores_equal_a_loop_over_the_same_random_halves():
    """split_scores against a slow reference: the halves drawn as documented (the first
    n // 2 of one permutation per split from default_rng(seed)), the factor the median log
    ratio of the half, Spearman as the correlation of ranks, then median / 10th / 90th
    percentile of each score; with groups, one median per group (the overall one for a group
    without training grasps)."""
    from workbench.fem.calibration import split_scores

    rng = np.random.default_rng(21)
    n = 17
    measured = np.exp(rng.normal(7.0, 0.8, n))
    model = measured * np.exp(rng.normal(-1.0, 0.4, n))
    groups = (np.arange(n) % 3 == 0).astype(int)
    for g in (None, groups):
        got = split_scores(model, measured, groups=g, n_splits=30, seed=4)
        draw = np.random.default_rng(4)
        rho, mal = [], []
        for _ in range(30):
            train = draw.permutation(n)[: n // 2]
            test = np.setdiff1d(np.arange(n), train)
            labels = np.zeros(n, int) if g is None else g
            log_c = np.full(n, np.median(np.log(measured[train] / model[train])))  # no training grasp
            for label in (0, 1):
                t = train[labels[train] == label]
                if t.size:
                    log_c[labels == label] = np.median(np.log(measured[t] / model[t]))
            pred = model * np.exp(log_c)
            rho.append(_spearman_no_ties(pred[test], measured[test]))
            mal.append(np.median(np.abs(np.log(pred[test] / measured[test]))))
        for key, v in (("spearman", rho), ("median_abs_log_ratio", mal)):
            ref = {"median": np.median(v), "p10": np.percentile(v, 10), "p90": np.percentile(v, 90)}
            for stat, value in ref.items():
                assert got[key][stat] == pytest.approx(value, rel=1e-12, abs=1e-15), (g, key, stat)
        assert got["n_splits"] == 30 and got["n_failed"] == 0


def test_missing_physics_bins_by_the_predicted_closing():
    """A map built so the all-grasp factor is exactly 1 (ratios 0.5, 1, 1, 1, 1, 2: median 1)
    and the predicted closing / width is chosen per grasp, f = 0.10, 0.15, 0.30, 0.50, 0.70,
    0.90 (model = F / (f w)).  By hand: residual ln r, measured closing / width f / r =
    0.20, 0.15, 0.30, 0.50, 0.70, 0.45; bins [0, .2): ln 2 * (-1, 0) median -ln2 / 2, measured
    median 0.175, max 0.20; [.2, .4) and [.4, .6): one grasp each, residual 0; [.6, inf):
    ln 2 * (0, 1), median ln2 / 2, measured median 0.575, max 0.70.  A seventh grasp the model
    calls rigid (>= ``rigid``) 5 mm from a clamp is left out of all of them and listed."""
    from scipy.stats import spearmanr

    from workbench.fem.calibration import missing_physics

    F, w = 10.0, 0.05
    f = np.array([0.10, 0.15, 0.30, 0.50, 0.70, 0.90])
    r = np.array([0.5, 1.0, 1.0, 1.0, 1.0, 2.0])
    model = np.r_[F / (f * w), 5e7]
    measured = np.r_[r * F / (f * w), 3e4]
    clamp = np.r_[np.full(6, np.inf), 0.005]
    mp = missing_physics(
        model, measured, width=np.full(7, w), clamp_distance=clamp, force=F, rigid=1e7, n_splits=10
    )
    assert mp["calibration_factor"] == pytest.approx(1.0, rel=1e-12)
    assert mp["series_compliance_bound_m_per_N"] == pytest.approx(1.0 / measured[:6].max(), rel=1e-12)
    ln2 = np.log(2.0)
    ref = [
        ([0.0, 0.2], 2, -ln2 / 2, 0.175, 0.20),
        ([0.2, 0.4], 1, 0.0, 0.30, 0.30),
        ([0.4, 0.6], 1, 0.0, 0.50, 0.50),
        ([0.6, None], 2, ln2 / 2, 0.575, 0.70),
    ]
    bins = mp["closing_fraction"]["bins"]
    assert [b["predicted_closing_over_width"] for b in bins] == [x[0] for x in ref]
    for b, (_, n, res, med, top) in zip(bins, ref, strict=True):
        assert b["n"] == n
        assert b["median_residual"] == pytest.approx(res, abs=1e-12)
        assert b["measured_closing_over_width_median"] == pytest.approx(med, rel=1e-12)
        assert b["measured_closing_over_width_max"] == pytest.approx(top, rel=1e-12)
    cf = mp["closing_fraction"]
    assert cf["measured_closing_over_width_max"] == pytest.approx(0.70, rel=1e-12)
    assert cf["spearman_residual"] == pytest.approx(spearmanr(np.log(r), f).statistic, rel=1e-12)
    away = mp["away_from_clamps"]
    assert (away["n"], away["n_all"]) == (6, 6)
    assert away["model_rigid_near_clamps_measured"] == [3e4]


@pytest.mark.parametrize(
    "model, measured, match",
    [
        (np.ones(5), np.ones(4), r"\(n,\) stiffness arrays"),
        (np.ones((5, 1)), np.ones((5, 1)), r"\(n,\) stiffness arrays"),
        (np.r_[1.0, 2.0, np.nan, 4.0, 5.0], np.ones(5), "finite and > 0"),
        (np.ones(5), np.r_[1.0, 2.0, 0.0, 4.0, 5.0], "finite and > 0"),
        (np.r_[1.0, -2.0, 3.0, 4.0, 5.0], np.ones(5), "finite and > 0"),
    ],
)
def test_calibration_rejects_bad_stiffness_arrays(model, measured, match):
    from workbench.fem.calibration import calibrate, held_out, split_scores

    train = np.arange(2)
    with pytest.raises(ValueError, match=match):
        calibrate(model, measured, train)
    with pytest.raises(ValueError, match=match):
        held_out(model, measured, train)
    with pytest.raises(ValueError, match=match):
        split_scores(model, measured, n_splits=3)


def test_calibration_rejects_bad_groups_heights_and_all_failed_fits():
    from workbench.fem.calibration import calibrate, missing_physics, one_factor_validation, split_scores_of

    s = np.linspace(100.0, 500.0, 8)
    with pytest.raises(ValueError, match=r"groups must be \(n,\)"):
        calibrate(s, 2 * s, np.arange(4), groups=np.zeros(7, int))
    with pytest.raises(ValueError, match="one length"):
        one_factor_validation(s, 2 * s, np.random.default_rng(0), heights=np.ones(7), E=1e9)
    with pytest.raises(ValueError, match="non-finite stiffness on all 5 halves"):
        split_scores_of(lambda tr: np.full(8, np.nan), 2 * s, n_splits=5)
    # three usable grasps: the rest NaN (failed) or above the rigid threshold
    model = np.r_[s[:3], np.nan, np.nan, RIGID_STIFFNESS, RIGID_STIFFNESS, RIGID_STIFFNESS]
    with pytest.raises(ValueError, match="at least 4 grasps that neither side calls rigid; got 3"):
        missing_physics(model, 2 * s, width=np.full(8, 0.05), clamp_distance=np.full(8, np.inf))
    with pytest.raises(ValueError, match="width must be finite"):
        missing_physics(s, 2 * s, width=np.r_[np.full(7, 0.05), np.nan], clamp_distance=np.full(8, np.inf))


def test_uncalibrated_scores_leave_out_rigid_and_failed_grasps():
    """workbench.fem.calibration.uncalibrated_scores: the model as it comes against the map over
    the grasps neither side calls rigid (the map: >= the rigid threshold) nor the model failed
    at; log ratios by hand."""
    from scipy.stats import spearmanr

    from workbench.fem.calibration import uncalibrated_scores

    measured = np.array([100.0, 200.0, 300.0, 400.0, RIGID_STIFFNESS, 600.0, 50.0])
    model = np.array([25.0, 400.0, np.nan, 1200.0, 1000.0, 1200.0, 60.0])
    rigid = np.array([False, False, False, False, False, True, False])
    failed = np.array([False, False, True, False, False, False, False])
    u = uncalibrated_scores(model, measured, rigid=rigid, failed=failed)
    # grasps 0, 1, 3, 6: ratios 1/4, 2, 3, 1.2
    assert u["n"] == 4
    assert u["median_log_ratio"] == pytest.approx(0.5 * (np.log(1.2) + np.log(2.0)), rel=1e-14)
    assert u["median_abs_log_ratio"] == pytest.approx(0.5 * (np.log(2.0) + np.log(3.0)), rel=1e-14)
    ok = [0, 1, 3, 6]
    assert u["spearman"] == pytest.approx(spearmanr(model[ok], measured[ok]).statistic, rel=1e-14)
    # ranks (measured 2, 3, 4, 1; model 1, 3, 4, 2): 1 - 6 * 2 / (4 * 15)
    assert u["spearman"] == pytest.approx(0.8, rel=1e-14)
    few = uncalibrated_scores(model, measured, rigid=rigid | (measured < 250), failed=failed)
    assert few["n"] == 1 and "fewer than 3 grasps" in few["note"]
    with pytest.raises(ValueError, match="one length, one entry per grasp"):
        uncalibrated_scores(model[:-1], measured, rigid=rigid, failed=failed)


def test_stiffness_scores_by_hand():
    from workbench.fem.calibration import stiffness_scores

    # |log ratio| = ln 2, 0, ln 1.25, ln(8/7): median of the middle two = (ln 1.25 + ln(8/7)) / 2
    s = stiffness_scores(np.array([2.0, 3.0, 5.0, 7.0]), np.array([1.0, 3.0, 4.0, 8.0]))
    assert s["median_abs_log_ratio"] == pytest.approx((np.log(1.25) + np.log(8 / 7)) / 2, rel=1e-14)
    assert s["spearman"] == pytest.approx(1.0, abs=1e-15)  # same order on both sides
    # one swap of neighbours among 4: rho = 1 - 6 * 2 / (4 * 15) = 0.8
    s = stiffness_scores(np.array([1.0, 2.0, 3.0, 4.0]), np.array([1.0, 3.0, 2.0, 4.0]))
    assert s["spearman"] == pytest.approx(0.8, abs=1e-14)
    assert s["median_abs_log_ratio"] == pytest.approx(np.log(1.5) / 2, rel=1e-14)  # 0, 0, ln 1.5, ln 1.5

"""The linear and the nonlinear wall of a measured object (workbench.fem.wall_linearity): each
model's one-scalar calibration recovering a factor chosen here, the nonlinear one through the
f / E scaling of piecewise-linear load curves whose secant stiffness is known in closed form, the
grasps spread over the heights, one grasp's comparison of both models and careless input.  The
FEM steps themselves run in tests/test_experiments.py (wall-nonlinear --quick)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from workbench.fem import wall_grasps
from workbench.fem.calibration import split_scores
from workbench.fem.material import Material
from workbench.fem.wall_linearity import (
    MAX_SCALE,
    calibrate_models,
    grasp_comparison,
    linear_at_grasps,
    measured_object_wall,
    nonlinear_scale,
    nonlinear_stiffness,
    pick_grasps,
)

F, F_STOP = 10.0, 13.0
D1 = 5e-3  # the curves' kink [m]


def _curve(k1: float, k2: float, imbalance: float = 0.0) -> dict:
    """A load curve of stiffness ``k1`` [N/m] up to the closing D1, then ``k2`` up to 1.05 F_STOP
    (a curve runs past the force it was run to), both jaws ``1 ± imbalance`` of the mean force;
    linear between its points, so it is read exactly."""
    f_end = 1.05 * F_STOP
    d = np.array([0.0, D1, D1 + (f_end - k1 * D1) / k2])
    f = np.array([0.0, k1 * D1, f_end])
    return {
        "closing": d.tolist(),
        "jaw_forces": np.column_stack([f * (1 + imbalance), f * (1 - imbalance)]).tolist(),
    }


def _secant(k1: float, k2: float, c: float) -> float:
    """Secant stiffness F / Δ(F) [N/m] of :func:`_curve` with its forces × ``c`` (E × c), by hand:
    on the first leg c k1; past the kink Δ = D1 + (F / c − k1 D1) / k2."""
    if F <= c * k1 * D1:
        return c * k1
    return F / (D1 + (F / c - k1 * D1) / k2)


def test_nonlinear_stiffness_follows_the_f_over_E_scaling_of_a_curve():
    k1, k2 = 1000.0, 250.0
    cv = _curve(k1, k2)
    # E x 1.2: the kink at 6 N is below 10 N, so the second leg: Δ = 5 mm + (8.333 − 5) / 250 m
    assert 1.2 * k1 * D1 < F
    expected = F / (5e-3 + (F / 1.2 - 5.0) / 250.0)
    assert _secant(k1, k2, 1.2) == pytest.approx(expected, rel=1e-15)
    s = nonlinear_stiffness([cv, cv], F, 1.2)
    np.testing.assert_allclose(s, expected, rtol=1e-12)
    # E x 2.5: the 10 N fall on the first leg, stiffness 2.5 k1
    assert nonlinear_stiffness([cv], F, 2.5)[0] == pytest.approx(2500.0, rel=1e-12)
    # E x 0.5: the curve ends at 0.5 x 13.65 N, below 10 N: no stiffness
    assert np.isnan(nonlinear_stiffness([cv], F, 0.5)[0])


def test_both_models_recover_the_factor_the_data_were_made_with():
    """measured = 3 s_linear: the linear model's factor is 3 exactly (E_effective = 3 E_lin); the
    measured values are the nonlinear curves' secant stiffness at E x 1.2: the nonlinear factor is
    1.2 — not 3, since a nonlinear wall's stiffness is not proportional to E."""
    rng = np.random.default_rng(7)
    k1 = rng.uniform(600.0, 1500.0, 4)
    k2 = 0.25 * k1
    curves = [_curve(a, b) for a, b in zip(k1, k2, strict=True)]
    measured = np.array([_secant(a, b, 1.2) for a, b in zip(k1, k2, strict=True)])
    s_linear = measured / 3.0
    cal = calibrate_models(measured, s_linear, curves, E_lin=2e8, force=F, force_stop=F_STOP)
    assert cal.scale_linear == pytest.approx(3.0, rel=1e-14)
    assert cal.scale_nonlinear == pytest.approx(1.2, rel=1e-9)
    assert nonlinear_scale(curves, measured, force=F, force_stop=F_STOP) == cal.scale_nonlinear
    lin, nl = cal.compare["linear"], cal.compare["nonlinear"]
    assert lin["E_effective_Pa"] == pytest.approx(6e8, rel=1e-14)
    assert nl["E_effective_Pa"] == pytest.approx(2.4e8, rel=1e-9)
    assert lin["median_abs_log_ratio"] < 1e-14 and nl["median_abs_log_ratio"] < 1e-9
    assert lin["spearman"] == pytest.approx(1.0) and nl["spearman"] == pytest.approx(1.0)
    assert cal.held_out is None  # 4 grasps: halves of 2 score nothing
    # the secant at E x 1.2 sits on the second leg for every grasp (the nonlinear regime)
    assert (1.2 * k1 * D1 < F).all()


def test_held_out_scores_over_random_halves_of_exact_models():
    """Eight grasps, both models exact up to their factor: every half recovers it, so every
    held-out |log ratio| vanishes; the linear model's scores are split_scores' own."""
    rng = np.random.default_rng(3)
    k1 = rng.uniform(600.0, 2000.0, 8)
    curves = [_curve(a, 0.3 * a) for a in k1]
    measured = np.array([_secant(a, 0.3 * a, 0.8) for a in k1])
    s_linear = measured / 0.5
    cal = calibrate_models(measured, s_linear, curves, E_lin=1e9, force=F, force_stop=F_STOP)
    held = cal.held_out
    assert held["n_grasps"] == 8 and held["linear"] == split_scores(s_linear, measured)
    for model in ("linear", "nonlinear"):
        assert held[model]["n_failed"] == 0 and held[model]["n_splits"] == 200
        assert held[model]["median_abs_log_ratio"]["p90"] < 1e-9
        assert held[model]["spearman"]["median"] == pytest.approx(1.0)
    assert cal.scale_nonlinear == pytest.approx(0.8, rel=1e-9)


def test_no_nonlinear_factor_when_the_curves_cannot_reach_the_measurement():
    """A measured stiffness above what E x MAX_SCALE gives: no factor brackets the zero, the
    nonlinear model has no calibration (None), the linear one still does."""
    curves = [_curve(1000.0, 250.0)] * 3
    measured = np.full(3, 2.0 * MAX_SCALE * 1000.0)
    cal = calibrate_models(measured, np.full(3, 1000.0), curves, E_lin=1e9, force=F, force_stop=F_STOP)
    assert np.isnan(cal.scale_nonlinear) and cal.compare["nonlinear"] is None
    assert cal.scale_linear == pytest.approx(2.0 * MAX_SCALE, rel=1e-14)
    with pytest.raises(ValueError, match="one entry per grasp"):
        calibrate_models(measured[:2], np.full(3, 1000.0), curves, E_lin=1e9, force=F, force_stop=F_STOP)


def test_pick_grasps_spreads_over_the_heights():
    ok = np.array([True, False, True, True, True, False, True])
    z = np.array([0.05, 0.01, 0.02, 0.08, 0.03, 0.0, 0.06])
    # the resolved grasps by height: 2 (0.02), 4, 0, 6, 3 (0.08)
    assert pick_grasps(ok, z, n_grasps=3).tolist() == [2, 0, 3]  # lowest, middle, highest
    assert pick_grasps(ok, z, n_grasps=2).tolist() == [2, 3]
    assert pick_grasps(ok, z, n_grasps=1).tolist() == [0]  # the middle one by height
    assert pick_grasps(ok, z, n_grasps=10).tolist() == [2, 4, 0, 6, 3]  # every one once
    assert pick_grasps(ok, z, n_grasps=3, grasps=[6, 0]).tolist() == [6, 0]
    with pytest.raises(ValueError, match=r"grasps \[1, 9\] of cup .* choose among \[0, 2, 3, 4, 6\]"):
        pick_grasps(ok, z, n_grasps=3, grasps=[1, 9], name="cup")


def test_grasp_comparison_of_a_linear_spring():
    """The nonlinear curve a spring of 800 N/m (jaws at 1 ± 1 % of the mean), the linear wall
    790 N/m: stiffness, closings, work F² / 2s and the jaws' imbalance by hand."""
    d = np.linspace(0.0, 0.02, 11)
    f = 800.0 * d
    curves = {
        "closing": d.tolist(),
        "jaw_forces": np.column_stack([1.01 * f, 0.99 * f]).tolist(),
        "newton_iterations": 17,
        "on_clamp": False,
        "seconds": 1.5,
        "s_linear": 790.0,
        "on_clamp_linear": False,
    }
    row = grasp_comparison(4, curves, z=0.05, measured=600.0, s_linear_all=500.0, force=F)
    assert row["grasp"] == 4 and row["z_m"] == 0.05 and row["measured"] == 600.0
    assert row["linear_residual_log"] == pytest.approx(np.log(600.0 / 500.0), rel=1e-14)
    assert row["s_nonlinear"] == pytest.approx(800.0, rel=1e-12)
    assert row["ratio_nl_lin"] == pytest.approx(800.0 / 790.0, rel=1e-12)
    assert row["closing_linear_mm"] == pytest.approx(1e4 / 790.0, rel=1e-14)
    assert row["closing_nonlinear_mm"] == pytest.approx(12.5, rel=1e-12)
    assert row["work_linear_mJ"] == pytest.approx(0.5 * 100 / 790.0 * 1e3, rel=1e-14)
    assert row["work_nonlinear_mJ"] == pytest.approx(62.5, rel=1e-12)  # F² / 2k = 100 / 1600 J
    assert row["jaw_force_imbalance"] == pytest.approx(0.02, rel=1e-12)
    assert row["load_curve_mm_N"][-1] == pytest.approx([20.0, 16.0])
    assert row["rests_on_base"] == {"linear": False, "nonlinear": False}
    assert (row["newton_iterations"], row["seconds"]) == (17, 1.5)
    # the linear jaw rests on the base: no linear stiffness, the ratio NaN too
    rested = {**curves, "on_clamp_linear": True}
    rested = grasp_comparison(4, rested, z=0.05, measured=600.0, s_linear_all=500.0, force=F)
    assert np.isnan(rested["s_linear"]) and np.isnan(rested["ratio_nl_lin"])


def test_linear_at_grasps_calibrates_on_the_grasps_both_resolve(monkeypatch):
    """The FEM squeeze replaced by known rows: a failed (NaN) and a rigid grasp of each side are
    left out; measured = 3 s on the rest gives the factor 3."""
    s = [100.0, 200.0, np.nan, 2e9, 400.0, 50.0]
    monkeypatch.setattr(wall_grasps, "stiffness_at", lambda wall, geo, L: [{"stiffness": v} for v in s])
    measured = np.array([300.0, 600.0, 500.0, 900.0, 8e10, 150.0])
    lin = linear_at_grasps(None, None, np.zeros((12, 3)), measured)
    assert lin.ok.tolist() == [True, True, False, False, False, True]
    assert lin.scale == pytest.approx(3.0, rel=1e-14)
    np.testing.assert_array_equal(lin.stiffness, s)
    with pytest.raises(ValueError, match="read-only"):
        lin.stiffness[0] = 1.0
    with pytest.raises(ValueError, match=r"measured must be \(n,\) for the n = 6 grasps"):
        linear_at_grasps(None, None, np.zeros((12, 3)), measured[:5])


def test_an_object_without_a_measured_map_is_refused(tmp_path):
    import trimesh

    (tmp_path / "meshes").mkdir()
    (tmp_path / "stiffness_maps").mkdir()
    trimesh.creation.cylinder(radius=0.03, height=0.1).export(tmp_path / "meshes" / "jar.obj")
    locations = {"stiffness_locations": [[0.03, 0.0, 0.0], [-0.03, 0.0, 0.0]]}
    (tmp_path / "stiffness_maps" / "jar.json").write_text(json.dumps(locations))
    with pytest.raises(ValueError, match=r"jar: the map has no 'stiffness_map'.*choose a measured object"):
        measured_object_wall(tmp_path, "jar", Material(2.5e9, 0.4), thickness=0.5e-3, mesh=(12, 6))

"""Careless inputs of a new user, each refused with the fix (or warned) by the one rule of its
quantity, and each corrected call checked against a closed form."""

from __future__ import annotations

import json
import logging
import warnings

import numpy as np
import pytest

from workbench.plausible import ImplausibleWarning


def test_lever_disturbances_refuse_levers_in_mm_weights_in_grams_and_a_swapped_weight_range():
    """Levers in mm gave torques of hundreds of N·m, weights in grams 928 N loads, swapped ends
    numpy's "high - low < 0"; the corrected call keeps |τ_z| = |r_x| m g <= lever_x · max weight."""
    from workbench.grasp.tasks import lever_disturbances

    rng = np.random.default_rng(0)
    with pytest.raises(
        ValueError, match=r"lever_x \[m\] must be a lever arm .*got 60: probably in millimetres — pass 0.06"
    ):
        lever_disturbances(rng, 3, lever_x=60)
    with pytest.raises(ValueError, match=r"lever_z \[m\] .*got 80: probably in millimetres — pass 0.08"):
        lever_disturbances(rng, 3, lever_z=80)
    with pytest.raises(
        ValueError, match=r"weight_range\[1\] \[N\] .*got 1400: probably in grams-force — pass 13.7293"
    ):
        lever_disturbances(rng, 3, weight_range=(100, 1400))
    with pytest.raises(
        ValueError, match=r"lo <= hi \[N\]; got \(14.0, 1.0\): the ends are swapped — pass \(1.0, 14.0\)"
    ):
        lever_disturbances(rng, 3, weight_range=(14.0, 1.0))
    with pytest.raises(ValueError, match=r"weight_range must be \(lo, hi\), two weights"):
        lever_disturbances(rng, 3, weight_range=14.0)

    w = lever_disturbances(
        np.random.default_rng(1), 2000, weight_range=(1.0, 14.0), lever_x=0.06, lever_z=0.08
    )
    # τ_z = −r_x m g, τ_x = r_z m g (+ N(0, 0.003)): bounded by 0.06 · 14 = 0.84 N·m and
    # 0.08 · 14 = 1.12 N·m up to the noise (5 sigma), and 2000 draws come within 10 % of it
    for col, lever in ((5, 0.06), (3, 0.08)):
        assert 0.9 * lever * 14.0 < np.abs(w[:, col]).max() <= lever * 14.0 + 5 * 0.003
    # f_y = −m g + N(0, 0.3), m g ~ U[1, 14]: mean −7.5 within 4 standard errors
    se = np.hypot(13.0 / np.sqrt(12.0), 0.3) / np.sqrt(2000)
    assert abs(w[:, 1].mean() + 7.5) < 4 * se
    assert (w[:, 0] == 0.0).all()  # nothing along the grasp axis


def test_average_recall_refuses_thresholds_in_per_cent():
    """Thresholds 0, 10, 50, 100 on qualities in [0, 1] recalled only at 0 (AR 0.25, silently)."""
    from workbench.grasp.crossval import average_recall

    q, s = [0.2, 0.6, 0.9, 0.05], [True, True, True, False]
    with pytest.raises(
        ValueError, match=r"thresholds must be fractions in \[0, 1\].*per cent\? pass 0.0, 0.1, 0.5, 1.0"
    ):
        average_recall(q, s, thresholds=[0, 10, 50, 100])
    with pytest.raises(ValueError, match=r"got -0.1, 0.5 .*pass fractions in \[0, 1\]"):
        average_recall(q, s, thresholds=[-0.1, 0.5])
    with pytest.raises(ValueError, match=r"a single threshold: pass \[0.5\]"):
        average_recall(q, s, thresholds=0.5)
    # the successes' qualities 0.2, 0.6, 0.9: recalls 1, 1, 2/3, 0 at t = 0, 0.1, 0.5, 1
    assert average_recall(q, s, thresholds=[0.0, 0.1, 0.5, 1.0]) == pytest.approx(
        (1 + 1 + 2 / 3 + 0) / 4, abs=1e-15
    )
    # a quality on another scale (0-90) may mean such a grid: kept, with a warning naming the fix
    with pytest.warns(ImplausibleWarning, match=r"per cent\? pass 0.0, 0.1, 0.5, 1.0"):
        ar = average_recall([0.0, 20.0, 50.0, 90.0], s, thresholds=[0, 10, 50, 100])
    assert ar == pytest.approx((1 + 2 / 3 + 1 / 3 + 0) / 4, abs=1e-15)


def test_fit_normaliser_names_a_quality_threshold_given_in_per_cent():
    from workbench.grasp.threshold import fit_normaliser

    x, truth = [1.0, 2.0, 3.0, 4.0], [True, True, False, False]
    with pytest.raises(
        ValueError, match=r"sigma must be a finite quality threshold < 1 .*got 50 — per cent\? pass 0.5"
    ):
        fit_normaliser(x, truth, sigma=50)
    with pytest.raises(ValueError, match=r"got 'x'$"):
        fit_normaliser(x, truth, sigma="x")
    # the cut x <= 2.5 separates the classes (balanced accuracy 1, the only such candidate):
    # X_max = 2.5 / (1 − σ)
    assert fit_normaliser(x, truth, sigma=0.5) == pytest.approx(5.0, rel=1e-15)


def test_stiffness_validation_figure_refuses_a_list_and_stiffness_in_n_per_mm(tmp_path, caplog):
    from workbench.runner.stiffness_figures import plot_stiffness_validation

    with pytest.raises(ValueError, match=r"panels must be a dict naming at least one object.*got list"):
        plot_stiffness_validation([1, 2, 3], tmp_path / "v.png")
    n = 6
    train = np.arange(n) < 3
    measured_mm = np.linspace(5.0, 8.0, n)  # N/mm
    panel = {"measured": measured_mm, "predicted": measured_mm * 1.1, "train": train, "test": ~train}
    with pytest.raises(
        ValueError, match=r"bottle: measured stiffness at grasp 0 .*probably in N/mm — pass 5000"
    ):
        plot_stiffness_validation({"bottle": panel}, tmp_path / "v.png")
    with pytest.raises(ValueError, match=r"panels\['bottle'\] must be a dict"):
        plot_stiffness_validation({"bottle": [measured_mm]}, tmp_path / "v.png")
    with pytest.raises(ValueError, match=r"band must be a finite width > 0"):
        plot_stiffness_validation({"bottle": panel}, tmp_path / "v.png", band=-1.0)
    assert not (tmp_path / "v.png").exists()
    # in N/m: the prediction 1.1 × measured ranks the grasps alike (Spearman 1) and is off by ln 1.1
    ok = dict(panel, measured=measured_mm * 1e3, predicted=measured_mm * 1.1e3)
    with caplog.at_level(logging.INFO, logger="workbench.runner.stiffness_figures"):
        path = plot_stiffness_validation({"bottle": ok}, tmp_path / "v.png")
    assert path.exists()
    assert f"held-out Spearman 1.000, median |log ratio| {np.log(1.1):.3f}" in caplog.text


def test_mujoco_cone_refuses_a_sliding_coefficient_in_per_cent():
    from workbench.peers.mujoco_cone import cone_support

    with pytest.raises(
        ValueError, match=r"mu\[0\] \(a sliding coefficient.*got 50.0: probably in per cent — pass 0.5"
    ):
        cone_support([0, 1, 0, 0, 0, 0], [50, 0.01, 0])
    with pytest.raises(ValueError, match=r"mu\[1\] .*got 30.0: probably in per cent — pass 0.3"):
        cone_support([0, 1, 0, 0, 0, 0], [0.5, 30, 0.01, 0, 0])
    with pytest.raises(ValueError, match="lengths in metres"):  # a torsional coefficient in mm
        cone_support([0, 1, 0, 0, 0, 0], [0.5, 3.0, 0])
    # f_n (d_1 + sqrt(Σ μ_i² d_i²)): 0.5 along a tangent; 1 + 0.5 · |(0.6, 0.8)| = 1.5
    assert cone_support([0, 1, 0, 0, 0, 0], [0.5, 0.01, 0]) == pytest.approx(0.5, rel=1e-15)
    assert cone_support([1, 0.6, 0.8, 0, 0, 0], [0.5, 0.01, 0], f_n=2.0) == pytest.approx(3.0, rel=1e-15)


def test_reach_profile_refuses_a_zero_approach_before_numpy_divides_by_it():
    import trimesh

    from workbench.sources.reach import WinklerPress, reach_profile

    box = trimesh.creation.box((0.06, 0.06, 0.02))
    top = (0.0, 0.0, 0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy "invalid value in divide" first
        with pytest.raises(
            ValueError, match=r"approach must be a non-zero finite \(3,\) direction .*got \(0, 0, 0\)"
        ):
            reach_profile(box, top, approach=(0, 0, 0))
        with pytest.raises(ValueError, match=r"approach must be .*got \(0, 0, nan\)"):
            reach_profile(box, top, approach=(0, 0, np.nan))
        with pytest.raises(ValueError, match=r"up must be a non-zero finite \(3,\) direction"):
            reach_profile(box, top, approach=(0, 0, -1), up=(0, 0, 0))
        with pytest.raises(ValueError, match=r"up must not be parallel .*e.g. \(1, 0, 0\)"):
            reach_profile(box, top, approach=(0, 0, -1), up=(0, 0, 2))
    # the 20 x 40 mm pad flat on the 60 x 60 mm top face: p = k · closing everywhere, area 8 cm²
    # up to the band of elements its boundary cuts (<= 0.25 · perimeter · max_edge)
    press = WinklerPress(closing=1e-3, stiffness=2e8, max_edge=1e-3)
    p = reach_profile(box, top, approach=(0, 0, -1), up=(0, 1, 0), press=press)
    np.testing.assert_allclose(p.pressures, 2e8 * 1e-3, rtol=1e-12)
    assert abs(p.areas.sum() - 0.02 * 0.04) <= 0.25 * 0.12 * 1e-3
    assert np.linalg.norm(p.pressure_center - top) <= 0.2 * 1e-3


def test_report_of_a_results_directory_that_does_not_exist_is_an_error(tmp_path, capsys):
    from workbench.runner.cli import main

    missing = tmp_path / "nonexistent"
    with pytest.raises(SystemExit) as exc:
        main(["report", "--results", str(missing)])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert str(missing) in err and "does not exist" in err
    assert "`make reproduce`" in err and "`workbench run NAME`" in err
    assert not missing.exists()

    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(SystemExit) as exc:
        main(["report", "--results", str(empty)])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "holds no summary" in err and "`make reproduce`" in err
    assert not (empty / "REPORT.md").exists()

    # one summary is enough: the row reads it (0.0081 → 0.81 %), the rest are missing rows
    (tmp_path / "res" / "discretization").mkdir(parents=True)
    (tmp_path / "res" / "discretization" / "summary.json").write_text(
        json.dumps({"max_error_rate_at_300": 0.0081})
    )
    assert main(["report", "--results", str(tmp_path / "res")]) == 0
    text = (tmp_path / "res" / "REPORT.md").read_text()
    row = next(x for x in text.splitlines() if x.startswith("| largest wrench error rate over S1–S6 at 300"))
    assert "| 0.81 % |" in row


def test_sphere_in_millimetres_is_named_by_its_radius():
    from workbench.fem.obstacles import Cylinder, Sphere

    with pytest.raises(
        ValueError,
        match=r"radius 20\) spans 40 m .*probably in millimetres: give the radius and the center in metres",
    ):
        Sphere((0, 0, 25), 20)
    with pytest.raises(
        ValueError, match=r"radius 20.0\) spans 40 m .*millimetres: give the radius and the point"
    ):
        Cylinder((0, 0, 20), (0, 1, 0), 20.0)
    with pytest.raises(ValueError, match=r"radius must be > 0, a length in metres; got 'a'"):
        Sphere((0, 0, 0.025), "a")
    # in metres: the pad's origin is |(0, 0, −0.025)| − 0.02 = 5 mm outside, the normal −z
    d, n = Sphere((0, 0, 0.025), 0.02).signed_distance(np.zeros((1, 3)))
    assert d[0] == pytest.approx(0.005, abs=1e-15)
    np.testing.assert_allclose(n[0], [0.0, 0.0, -1.0], atol=1e-15)


@pytest.mark.parametrize("fidelity", ["condensed", "linear", "nonlinear"])
def test_press_refuses_a_plane_whose_normal_points_away_from_the_pad(fidelity):
    """Plane((0, 0, h), (0, 0, +1)) has the pad on its solid side: 0 N without a word."""
    from workbench.fem import press
    from workbench.fem.material import Material
    from workbench.fem.obstacles import Plane
    from workbench.fem.pad import PadGeometry

    flipped = Plane((0, 0, 0.005), (0, 0, +1))
    with pytest.raises(
        ValueError, match=r"the normal points out of the obstacle, towards the pad: pass \(0, 0, -1\)"
    ):
        press(PadGeometry(), Material(), flipped, [1e-4], fidelity=fidelity, cache_dir=False)
    with pytest.raises(ValueError, match=r"parallel to the press axis"):
        press(
            PadGeometry(),
            Material(),
            Plane((0, 0, 0.005), (1, 0, 0)),
            [1e-4],
            fidelity=fidelity,
            cache_dir=False,
        )


def test_a_plane_facing_the_pad_presses_it_uniaxially():
    """The corrected plane at nu = 0: F = E δ W L / h (uniaxial, exact for trilinear hexes)."""
    from workbench.fem import press
    from workbench.fem.material import Material
    from workbench.fem.obstacles import Plane
    from workbench.fem.pad import PadGeometry

    geom = PadGeometry(width=0.006, length=0.008, thickness=0.002, nx=3, ny=4, nz=2)
    mat = Material(E=2.0e6, nu=0.0)
    res = press(geom, mat, Plane((0, 0, geom.thickness), (0, 0, -1)), [2e-5], cache_dir=False)
    assert res[2e-5].force == pytest.approx(2.0e6 * 2e-5 / 0.002 * 0.006 * 0.008, rel=1e-9)

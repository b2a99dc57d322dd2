"""stiffness_at / grasp_pairs on a meshed tube: the same stiffness as a direct squeeze,
rigid and failed flags with their reasons, careless locations."""

import numpy as np
import pytest
import trimesh

from fem.mesh_wall import radial_surface
from fem.wall import build_wall, squeeze
from fem.wall_grasps import RIGID_STIFFNESS, grasp_pairs, stiffness_at


@pytest.fixture(scope="module")
def tube():
    m = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=128)
    m.apply_translation([0, 0, 0.05])
    surf = radial_surface(m, z_range=(0.005, 0.08))  # the top 20 mm left out: "rigid" there
    return surf, build_wall(surf, thickness=0.5e-3, n_theta=32, n_z=8, z_range=surf.z_range)


def _pair(z, r=0.03):
    return np.array([[r, 0.0, z], [-r, 0.0, z]])


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


@pytest.mark.parametrize(
    "locs, match",
    [
        (np.zeros((3, 3)), "2n points"),
        (np.zeros((4, 2)), r"\(2n, 3\)"),
        (np.vstack([_pair(0.05)[:1] * [0.9, 1, 1], _pair(0.05)[1:]]), "-3.00 mm off the object's surface"),
        (_pair(0.05) * 1000, "outside the object.s box"),  # millimetres
    ],
)
def test_careless_locations_are_refused(tube, locs, match):
    surf, _ = tube
    with pytest.raises(ValueError, match=match):
        grasp_pairs(locs, surf)


def test_one_factor_calibration_against_a_direct_computation():
    """fem.calibration: the factor is the median log ratio on the training grasps (exact on
    a model off by a constant), one per group, and the held-out scores are the plain ones."""
    from scipy.stats import spearmanr

    from fem.calibration import calibrate, held_out, split_scores

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

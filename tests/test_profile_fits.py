"""Table 3.3's per-profile fits under both protocols and the protocol ablation
(workbench.limit_surface.profile_fits)."""

import numpy as np
import pytest

from workbench import ContactProfile, frictional_wrenches, sample_twists_thesis, w_max
from workbench.coarsen import coarsen_profile
from workbench.limit_surface.fit_score import Scoring, fit_and_score, fit_model
from workbench.limit_surface.profile_fits import (
    ABLATION_VARIANTS,
    MODELS,
    TABLE_MODELS,
    ProfileFitSettings,
    ablation_due,
    code_errors,
    profile_fit_row,
    protocol_ablation,
)
from workbench.limit_surface.thesis_code import thesis_code_sample

SETTINGS = ProfileFitSettings(n_wrenches=300, n_heldout=200, support_directions=60)


def _profile(n: int = 120, seed: int = 0) -> ContactProfile:
    """A rough 30 x 20 mm patch (nonplanar: a 6D wrench set), pressures of a few 10 kPa."""
    rng = np.random.default_rng(seed)
    c = np.c_[rng.uniform(-0.015, 0.015, n), rng.uniform(-0.01, 0.01, n), 0.002 * rng.standard_normal(n)]
    normals = np.tile([0.0, 0.0, 1.0], (n, 1))
    return ContactProfile(c, normals, np.full(n, 5e-6), rng.uniform(1e4, 3e4, n))


def _rotation_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_the_row_holds_both_protocols_errors_as_fitted_directly():
    """Each number of the row is the fit it names, recomputed here from its definition: the
    thesis-text sampler (seed, held-out seed + 10**6) on the normalised profile, and the
    thesis-code sample in the object frame."""
    prof = _profile()
    to_object = (_rotation_z(0.7), np.array([0.01, 0.0, 0.05]))
    row = profile_fit_row(prof, SETTINGS, 5, to_object=to_object)
    pn = prof.normalized()
    W = frictional_wrenches(pn, sample_twists_thesis(150, pn, 5, pitch_range=(-1.0, 1.0)))
    W_test = frictional_wrenches(pn, sample_twists_thesis(100, pn, 5 + 10**6, pitch_range=(-1.0, 1.0)))
    ref = fit_and_score("ellipsoid_lsq", W, w_max=w_max(pn), scoring=Scoring(W_test))
    assert (
        row["ellipsoid_lsq_error"] == ref.test_error and row["ellipsoid_lsq_train_error"] == ref.train_error
    )
    code = thesis_code_sample(pn.transformed(*to_object))
    assert row["code_n_pool"] == len(code.wrenches) and row["code_n_train"] == len(code.train)
    sdp = fit_model("ellipsoid_sdp", code.train_wrenches, w_max=code.w_max)
    assert row["ellipsoid_sdp_code_error"] == sdp.fitting_error(code.wrenches)
    for m in MODELS:
        assert 0 < row[f"{m}_support"] < 1 and row[f"{m}_error"] > 0
    assert not any(k.startswith("abl_") for k in row)
    # the pressure scale does not matter (the profile is normalised), nor does the grid's frame
    # choice for the thesis-text numbers
    jaw = profile_fit_row(
        prof.with_pressures(3 * prof.pressures),
        ProfileFitSettings(n_wrenches=300, n_heldout=200, support_directions=60, code_frame="jaw"),
        5,
        to_object=to_object,
    )
    assert jaw["ellipsoid_lsq_error"] == pytest.approx(row["ellipsoid_lsq_error"], rel=1e-9)
    assert (
        jaw["ellipsoid_sdp_code_error"] != row["ellipsoid_sdp_code_error"]
    )  # the author's grid is axis-aligned


def test_the_ablation_changes_one_thing_each():
    prof = _profile().normalized()
    to_object = (_rotation_z(0.7), np.array([0.01, 0.0, 0.05]))
    p_obj = prof.transformed(*to_object)
    code = thesis_code_sample(p_obj)
    row = protocol_ablation(p_obj, prof, SETTINGS, code)
    assert {k for k in row if k.endswith("_n_train")} == {f"abl_{v}_n_train" for v in ABLATION_VARIANTS}
    # the jaw frame: the thesis-code protocol on the profile as it is
    jaw = code_errors(prof, SETTINGS)
    assert row["abl_jaw_frame_ellipsoid_sdp"] == jaw["ellipsoid_sdp"]
    ref = thesis_code_sample(prof)
    assert jaw["n_train"] == len(ref.train)
    assert jaw["ellipsoid_sdp"] == fit_model(
        "ellipsoid_sdp", ref.train_wrenches, w_max=ref.w_max
    ).fitting_error(ref.wrenches)
    # the coarse elements: the protocol on the coarsened profile
    coarse = thesis_code_sample(coarsen_profile(p_obj, SETTINGS.ablation_cell_mm * 1e-3))
    assert row["abl_coarse_elements_n_train"] == len(coarse.train)
    # the author's objective reuses the given sample: its training set
    assert row["abl_author_objective_n_train"] == len(code.train)
    assert all(row[f"abl_author_objective_{m}"] > 0 for m in TABLE_MODELS)


def test_every_nth_profile_is_ablated_from_the_first():
    assert [i for i in range(10) if ablation_due(i, 4)] == [0, 4, 8]
    assert not any(ablation_due(i, 0) for i in range(10))


@pytest.mark.parametrize(
    "given, match",
    [
        ({"n_wrenches": 10}, "n_wrenches must be >= 126"),
        ({"n_heldout": 0}, "n_heldout >= 1"),
        ({"code_frame": "world"}, "code_frame must be one of"),
        ({"ablation_cell_mm": 0.003}, r"ablation_cell_mm must be a cell size in mm in \[0.1, 100\]"),
        ({"downsample_steps": 1}, "downsample_steps must be >= 2"),
        ({"mu": 0.0}, "mu = 0 has no friction wrench"),
    ],
)
def test_settings_refuse_what_the_fits_cannot_use(given, match):
    with pytest.raises(ValueError, match=match):
        ProfileFitSettings(**given)


def test_settings_from_a_config_take_their_keys_only():
    s = ProfileFitSettings.from_config({"mu": 0.5, "pitch_range": [-0.5, 0.5], "heights": [0.5]})
    assert s == ProfileFitSettings(mu=0.5, pitch_range=(-0.5, 0.5))

"""The two sampling/scoring protocols' building blocks (workbench.limit_surface.protocols)."""

import numpy as np
import pytest

from workbench import ContactProfile, frictional_wrenches, sample_twists_thesis, w_max
from workbench.limit_surface.fit_score import Scoring, fit_and_score
from workbench.limit_surface.protocols import (
    ExactContact,
    fit_score,
    fit_scores,
    thesis_code_sample_of,
    thesis_code_training_draws,
    thesis_text_wrenches,
)
from workbench.limit_surface.thesis_code import thesis_code_sample
from workbench.sources.surface_catalog import THESIS_SURFACES


def _profile(n: int = 80, seed: int = 0) -> ContactProfile:
    """A rough 30 x 20 mm patch of ``n`` elements (nonplanar: a 6D wrench set)."""
    rng = np.random.default_rng(seed)
    c = np.c_[rng.uniform(-0.015, 0.015, n), rng.uniform(-0.01, 0.01, n), 0.002 * rng.standard_normal(n)]
    normals = np.tile([0.0, 0.0, 1.0], (n, 1))
    return ContactProfile(c, normals, np.full(n, 2e-6), rng.uniform(1e4, 2e4, n))


def test_a_profile_contact_gives_the_profiles_exact_wrenches_and_w_max():
    prof = _profile()
    contact = ExactContact.of_profile(prof, 0.5, 50)
    xi = sample_twists_thesis(20, prof, seed=3)
    assert np.array_equal(contact.wrenches(xi), frictional_wrenches(prof, xi, 0.5))
    assert np.array_equal(contact.w_max, w_max(prof, 0.5))
    # the thesis-text sampler: n // 2 rotations + as many translations, scaled by the profile's l_s
    W, twists = thesis_text_wrenches(contact, 41, 3, pitch_range=(-0.5, 0.5))
    ref = sample_twists_thesis(20, prof, 3, pitch_range=(-0.5, 0.5))
    assert np.array_equal(twists, ref) and np.array_equal(W, frictional_wrenches(prof, ref, 0.5))


def test_the_thesis_code_sample_of_a_profile_contact_is_thesis_code_sample():
    """One protocol, two entry points: the contact's author grid and split are those of
    workbench.limit_surface.thesis_code (profile box, or given sides), bit for bit."""
    prof = _profile()
    contact = ExactContact.of_profile(prof, 1.0, 50)
    for sides in (None, np.array([0.03, 0.02, 0.01])):
        mine = thesis_code_sample_of(contact, 0, 2.5, sides=sides)
        ref = thesis_code_sample(prof, 1.0, 0, 2.5, sides=sides)
        assert len(mine.twists) > 40_000 and 0 < len(mine.train) < len(mine.twists)
        for field in ("twists", "wrenches", "w_max", "train"):
            assert np.array_equal(getattr(mine, field), getattr(ref, field)), field


def test_fit_scores_leaves_out_an_underdetermined_quartic():
    """The thesis-code training set can have fewer wrenches than the quartic's 126
    coefficients (121 on a bottle profile): the quartic is left out, not faked."""
    prof = _profile()
    contact = ExactContact.of_profile(prof, 1.0, 50)
    W = frictional_wrenches(prof, sample_twists_thesis(100, prof, seed=1))
    models = ("ellipsoid_sdp", "ellipsoid_lsq", "quartic_values")
    few, enough = (fit_scores(contact, models, W[:k], test=W, support_seed=0) for k in (121, 130))
    assert list(few) == ["ellipsoid_sdp", "ellipsoid_lsq"]
    assert list(enough) == list(models)
    # each is fit_and_score with the contact's exact w_max and support error
    ref = fit_and_score(
        "ellipsoid_lsq",
        W[:130],
        w_max=w_max(prof),
        scoring=Scoring(W, lambda xi: frictional_wrenches(prof, xi), support_directions=50, support_seed=0),
    )
    got = enough["ellipsoid_lsq"]
    assert (got.test_error, got.train_error, got.support.radial_mean) == (
        ref.test_error,
        ref.train_error,
        ref.support.radial_mean,
    )
    assert fit_score(contact, "ellipsoid_lsq", W[:130]).support is None  # no seed, no support error


def test_surface_support_twists_are_integrated_once_per_contact():
    """The support error's twists (its directions and the ±e_i probes) are the same for every
    model of a contact: the second model's support error reuses the first's wrenches (the memo
    held 4,000 twists against 4,000 + 12 asked, so it never hit) — and gets the same error as
    with fresh wrenches."""

    def contact():
        return ExactContact.of_surface(THESIS_SURFACES["S3"], 1.0, 300, source="mesh", mesh_elements=800)

    first = contact()
    W, _ = thesis_text_wrenches(first, 200, 1)
    errs = [
        fit_score(first, k, W, support_seed=0).support.radial_mean for k in ("ellipsoid_sdp", "ellipsoid_lsq")
    ]
    assert first.memo_hits == 1
    fresh = contact()
    again = fit_score(fresh, "ellipsoid_lsq", W, support_seed=0).support.radial_mean
    assert fresh.memo_hits == 0 and again == errs[1]


def test_exact_contact_refuses_what_it_cannot_use():
    prof = _profile()
    with pytest.raises(ValueError, match="profile must be a ContactProfile"):
        ExactContact.of_profile(THESIS_SURFACES["S3"], 1.0, 50)
    with pytest.raises(ValueError, match="support_directions must be a positive integer"):
        ExactContact.of_profile(prof, 1.0, 0)
    with pytest.raises(ValueError, match="mu = 0 has no friction wrench"):
        ExactContact.of_profile(prof, 0.0, 50)
    with pytest.raises(ValueError, match="source must be one of"):
        ExactContact.of_surface(THESIS_SURFACES["S3"], 1.0, 50, source="fem")
    with pytest.raises(ValueError, match="quad_rtol must be a relative tolerance"):
        ExactContact.of_surface(THESIS_SURFACES["S3"], 1.0, 50, quad_rtol=0.0)


def test_thesis_code_training_draws_are_distinct_seeded_and_drawn_in_order():
    sizes = [5, 20, 50]
    draws = thesis_code_training_draws(60, sizes, 7)
    assert [len(d) for d in draws] == sizes
    for d in draws:  # without replacement, inside the pool
        assert len(np.unique(d)) == len(d) and d.min() >= 0 and d.max() < 60
    # one generator, the sizes in order: the draws of rng.choice one after the other
    rng = np.random.default_rng(7)
    for d, K in zip(draws, sizes, strict=True):
        np.testing.assert_array_equal(d, rng.choice(60, K, replace=False))
    # the same seed, the same sets; a generator is taken as it is
    again = thesis_code_training_draws(60, sizes, np.random.default_rng(7))
    assert all(np.array_equal(a, b) for a, b in zip(draws, again, strict=True))
    assert not np.array_equal(thesis_code_training_draws(60, sizes, 8)[0], draws[0])
    # the whole pool: a permutation of it
    assert sorted(thesis_code_training_draws(60, [60], 0)[0].tolist()) == list(range(60))


@pytest.mark.parametrize("sizes", [[61], [0], [10, 2.5], [True]])
def test_thesis_code_training_draws_refuse_sizes_outside_the_pool(sizes):
    with pytest.raises(ValueError, match="sizes must be training set sizes"):
        thesis_code_training_draws(60, sizes, 0)

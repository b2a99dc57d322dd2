"""workbench.limit_surface.thesis_code: the "thesis-code" protocol's wrench set and its
training split — one wrench per occupied cell, the frame dependence, μ cancelled
by the normalisation, a hand-counted split, and the protocol settings refused by name."""

import numpy as np
import pytest
from naive import fw_vectorized, random_profile

from workbench import ContactProfile, w_max
from workbench.limit_surface.thesis_code import check_protocol_config, thesis_code_sample, thesis_code_split


@pytest.mark.jit_only("18 s as pure Python (48 483 twists); its kernels run in test_wrench.py")
def test_thesis_code_sample_trains_on_one_wrench_per_cell(rng):
    c, n, a, p = random_profile(rng, 60)
    prof = ContactProfile(c, n, a, p)
    s = thesis_code_sample(prof, 0.5)
    assert s.wrenches.shape == s.twists.shape == (len(s.twists), 6)
    np.testing.assert_allclose(s.w_max, w_max(prof, 0.5))
    np.testing.assert_allclose(s.wrenches[:50], fw_vectorized(c, n, a, p, s.twists[:50], 0.5), atol=1e-12)
    x = s.wrenches / s.w_max
    lo, width = x.min(0), (x.max(0) - x.min(0)) / 2.5
    cells = {tuple(np.minimum(np.floor((row - lo) / width), 2).astype(int)) for row in x}
    assert len(s.train) == len(cells)  # one per occupied cell
    assert 100 < len(s.train) < 729


@pytest.mark.jit_only(
    "70 s as pure Python (48 483 twists, three wrench sets); its kernels run in test_wrench.py"
)
def test_thesis_code_sample_depends_on_the_frame_and_takes_sides(rng):
    """The author's grid is axis-aligned: the same contact rotated gives another wrench
    set (why fem-fitting fixes the frame); ``sides`` replaces the profile's box."""
    c, n, a, p = random_profile(rng, 60)
    prof = ContactProfile(c, n, a, p)
    base = thesis_code_sample(prof, 1.0)
    same = thesis_code_sample(prof, 1.0, sides=np.ptp(prof.centers, axis=0))
    np.testing.assert_array_equal(same.wrenches, base.wrenches)
    bigger = thesis_code_sample(prof, 1.0, sides=2 * np.ptp(prof.centers, axis=0))
    assert not np.allclose(bigger.twists, base.twists)
    R = np.array([[0.0, 0, 1], [1, 0, 0], [0, 1, 0]])  # axes permuted: the box sides permute too
    turned = thesis_code_sample(prof.transformed(R), 1.0)
    # a rotated copy of the same wrench set would have the rotated norms of forces/torques
    norms = lambda W: np.sort(np.linalg.norm(W[:, :3], axis=1))  # noqa: E731
    assert len(turned.wrenches) == len(base.wrenches)
    assert not np.allclose(norms(turned.wrenches), norms(base.wrenches), rtol=1e-3)


# --- added ---------------------------------------------------------------------------------


def test_mu_scales_the_wrenches_and_cancels_in_the_split(rng):
    """Coulomb friction is linear in μ: the wrench set at μ = 0.5 is 0.5 × the set at μ = 1,
    and the normalisation by w_max (also ∝ μ) leaves the same training indices (the author's
    code hard-codes μ = 1 for that reason).  μ = 0.5 scales exactly in binary floating point,
    so the normalised wrenches agree to the last bit and no cell boundary can flip (another
    μ moves a few wrenches lying within rounding of a boundary: 4 of 158 at μ = 0.3, level 0)."""
    prof = ContactProfile(*random_profile(rng, 60))
    one, half = thesis_code_sample(prof, 1.0, fine_level=-1), thesis_code_sample(prof, 0.5, fine_level=-1)
    assert len(one.twists) == 46 and 10 < len(one.train) < 46  # the coarse level: 46 twists
    np.testing.assert_array_equal(half.twists, one.twists)
    np.testing.assert_allclose(half.wrenches, 0.5 * one.wrenches, rtol=1e-15, atol=0)
    np.testing.assert_allclose(half.w_max, 0.5 * one.w_max, rtol=1e-15)
    np.testing.assert_array_equal(half.train, one.train)
    np.testing.assert_array_equal(one.train_twists, one.twists[one.train])
    np.testing.assert_array_equal(one.train_wrenches, one.wrenches[one.train])
    with pytest.raises(ValueError, match="mu"):
        thesis_code_sample(prof, -0.5)


def test_split_normalises_by_w_max_and_counts_cells():
    """Force x in [0, 2] N with w_max 2 N, the other components zero (their w_max 0 is
    guarded, Eq. 3.10: no division by zero): normalised to [0, 1], steps 2.5 cut it at 0,
    0.4, 0.8 — {0, 0.1, 0.3} keeps 0.1, {0.5}, {0.85, 0.9, 1.0} keeps 0.9 (the nearest to
    its cell's mean); steps 1: two cells, {1.0} alone and 0.5 nearest the mean 0.442."""
    W = np.zeros((7, 6))
    W[:, 0] = 2.0 * np.array([0.0, 0.1, 0.3, 0.5, 0.85, 0.9, 1.0])
    wm = np.array([2.0, 0, 0, 0, 0, 0])
    np.testing.assert_array_equal(thesis_code_split(W, wm), [1, 3, 5])
    np.testing.assert_array_equal(thesis_code_split(W, wm, steps=1.0), [3, 6])
    for bad in (wm[:5], wm[None], 2.0):
        with pytest.raises(ValueError, match=r"wm must be the \(6,\) w_max"):
            thesis_code_split(W, bad)
    with pytest.raises(ValueError, match="finite"):
        thesis_code_split(np.where(W == 0.2, np.nan, W), wm)


GOOD = {"fine_level": 0, "downsample_steps": 2.5, "support_directions": 500}


@pytest.mark.parametrize(
    "key, value, match",
    [
        ("fine_level", 7, r"fine_level must be one of \[-1, 0, 1, .*\]; got 7"),
        ("fine_level", "0", "fine_level must be one of .*; got '0'"),
        ("downsample_steps", 1.5, "downsample_steps must be >= 2 .*got 1.5"),
        ("downsample_steps", float("nan"), "downsample_steps must be >= 2 .*got nan"),
        ("support_directions", 0, "support_directions must be a positive number of directions; got 0"),
        ("support_directions", 2.5, "support_directions must be .*got 2.5"),
        ("support_directions", True, "support_directions must be .*got True"),
    ],
)
def test_protocol_settings_are_refused_by_name(key, value, match):
    check_protocol_config(GOOD)  # the defaults pass
    with pytest.raises(ValueError, match=match):
        check_protocol_config({**GOOD, key: value})

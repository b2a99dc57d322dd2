"""Training and scoring wrenches of the "thesis-code" protocol.

The author's code (``computewrenchtwistfitls.m``) samples twists on a grid
(:func:`workbench.twists_author.sample_twists_author`), computes every wrench,
normalises them, keeps one wrench per occupied cell of a coarse grid for the fit
(:func:`.downsample.grid_downsample`) and scores Eq. 3.18 on *all* of them.
:func:`thesis_code_sample` does the sampling and the split; the fit is the
caller's (the same fitters as the other protocol, so only the distribution
differs).

Departures that change a number: the wrenches are normalised by the exact
``w_max`` (canonical twists), not by the sampled maxima (they agree to 1e-4 on
the FEM profiles and parametric surfaces); wrenches are never NaN here, so none
are dropped; μ is the caller's (the code hard-codes 1, which normalisation
cancels anyway).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..profile import ContactProfile
from ..twists_author import AUTHOR_LEVELS, sample_twists_author
from ..wrench import _check_profile, _frictional_wrenches, check_mu, w_max
from .downsample import _grid_downsample, check_steps
from .normalize import check_wrenches, wrench_scale


@dataclass(frozen=True)
class ThesisCodeSample:
    """The author's wrench set of one contact and its training subset."""

    twists: np.ndarray  # (N, 6) the grid's twists about o
    wrenches: np.ndarray  # (N, 6) their raw friction wrenches (the scoring set)
    w_max: np.ndarray  # (6,) exact maxima used for normalisation
    train: np.ndarray  # (n,) int indices of the grid-downsampled training wrenches

    @property
    def train_twists(self) -> np.ndarray:
        return self.twists[self.train]

    @property
    def train_wrenches(self) -> np.ndarray:
        return self.wrenches[self.train]


def thesis_code_split(wrenches: np.ndarray, wm: np.ndarray, steps: float = 2.5) -> np.ndarray:
    """(n,) training indices: grid downsampling of ``wrenches`` (N, 6) normalised by
    ``wm`` (6,) (degenerate components guarded as in Eq. 3.10)."""
    wm = np.asarray(wm, float)
    if wm.shape != (6,):
        raise ValueError(f"wm must be the (6,) w_max of the wrenches' contact; got shape {wm.shape}")
    return _split(check_wrenches(wrenches), wm, check_steps(steps))


def _split(W: np.ndarray, wm: np.ndarray, steps: float) -> np.ndarray:
    """:func:`thesis_code_split` of checked wrenches W (N, 6), w_max (6,) and steps."""
    return _grid_downsample(W / wrench_scale(wm), steps)


def thesis_code_sample(
    profile: ContactProfile,
    mu: float = 1.0,
    fine_level: int = 0,
    steps: float = 2.5,
    *,
    sides: np.ndarray | None = None,
) -> ThesisCodeSample:
    """Author's twist grid (``fine_level``) on ``profile``, its wrenches, and the
    grid-downsampled training indices (``steps`` cell widths per range).

    The grid is axis-aligned in the profile's own frame (its box sides, offsets on
    its coordinate axes, a golden-angle sphere about its z axis), so the same
    contact in two frames gives two different wrench sets and errors: pass the
    profile in the frame the comparison calls for (the author's: the object frame).
    sides : optional (3,) box sides [m] to use instead of the profile's (e.g. to
        measure the effect of a different box).
    Level 0 (the FEM study) gives 48 483 twists and, on the bottle profiles, a few
    hundred training wrenches (the author reports 122-294).
    """
    mu = check_mu(mu, what="thesis-code wrench set")
    steps = check_steps(steps)
    xi = sample_twists_author(profile if sides is None else sides, fine_level)
    # the grid's own unit twists: finite and nonzero by construction, so not checked again
    W = _frictional_wrenches(_check_profile(profile), xi, mu)
    wm = w_max(profile, mu)
    # the kernel's wrenches of checked inputs are finite: thesis_code_split without its checks
    return ThesisCodeSample(xi, W, wm, _split(W, wm, steps))


def check_protocol_config(config: dict) -> None:
    """Raise ``ValueError`` naming the key if an experiment's thesis-code settings
    (``fine_level``, ``downsample_steps``, ``support_directions``) would fail — so an
    experiment refuses them before its first solve, not after it."""
    if config["fine_level"] not in AUTHOR_LEVELS:
        raise ValueError(f"fine_level must be one of {sorted(AUTHOR_LEVELS)}; got {config['fine_level']!r}")
    if not config["downsample_steps"] >= 2:
        # below 2 cells per range the 6D grid has at most 2^6 cells and the training set a
        # handful of wrenches (steps 1: 7 on a 60-element contact) — fewer than any fit needs
        raise ValueError(
            "downsample_steps must be >= 2 cell widths per range (the author's 2.5 gives ~3 cells per "
            f"dimension); got {config['downsample_steps']!r}"
        )
    n_dir = config["support_directions"]
    if isinstance(n_dir, bool) or not (isinstance(n_dir, int) and n_dir > 0):
        raise ValueError(
            "support_directions must be a positive number of directions; "
            f"got {config['support_directions']!r}"
        )


__all__ = ["ThesisCodeSample", "check_protocol_config", "thesis_code_sample", "thesis_code_split"]

"""The two sampling/scoring protocols of the fitting experiments (thesis §3.3.2, §3.5).

The fitters are the same under both; only the wrenches differ:

* "thesis-text" — the sampler the thesis describes (§3.3.2: ``n/2`` Fibonacci rotations
  plus ``n/2`` translations, pitch ``h ∈ pitch_range·l_s``):
  :func:`thesis_text_wrenches`;
* "thesis-code" — the author's code: the twist grid of
  :func:`workbench.twists_author.sample_twists_author`, every wrench of it as the scoring
  set and one wrench per occupied cell of a coarse wrench grid as the training set:
  :func:`thesis_code_sample_of` (:mod:`.thesis_code`).

Both draw their wrenches from an :class:`ExactContact` — a normalised contact's exact
wrenches for any twists (a FEM contact profile, or a parametric surface by quadrature or
on a fine mesh), its exact ``w_max`` (Eq. 3.10) and the box the author's grid is sized
by — and score fits with :func:`fit_score` / :func:`fit_scores`: Eq. 3.18 on test
wrenches and, given ``support_seed``, the sampler-independent support error
(:mod:`.support_error`) on the same contact's exact wrenches.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from functools import partial
from typing import Any

import numpy as np

from ..profile import ContactProfile
from ..seeds import check_seed
from ..sources.surfaces import ParametricSurface, check_rtol, mesh_profile, surface_w_max, surface_wrenches
from ..twists import sample_twists_thesis
from ..twists_author import box_sides, sample_twists_author
from ..wrench import check_mu, frictional_wrenches, w_max
from .fit_score import FitScore, Scoring, fit_and_score, min_wrenches
from .support_error import SharedWrenches
from .thesis_code import ThesisCodeSample, thesis_code_split

#: where a parametric surface's exact wrenches come from (:meth:`ExactContact.of_surface`)
WRENCH_SOURCES = ("continuous", "mesh")


def _count(value: Any, name: str, what: str) -> int:
    if isinstance(value, bool) or not (isinstance(value, int | np.integer) and value > 0):
        raise ValueError(f"{name} must be a positive integer ({what}); got {value!r}")
    return int(value)


class ExactContact:
    """One contact's exact wrenches for any twists, its exact ``w_max`` and its box.

    Twist sets of up to ``support_directions + 12`` rows are memoised by their bytes
    (:class:`~.support_error.SharedWrenches`): every model of the contact draws the same
    support-error twists, which are then integrated once.  Build it with
    :meth:`of_profile` or :meth:`of_surface`.

    shape : the contact whose ``length_scale`` ``l_s`` scales the thesis-text sampler
        (a ContactProfile or a ParametricSurface).
    wrenches_of : ``(K, 6) twists -> (K, 6)`` exact raw wrenches of ``shape``.
    w_max : (6,) its exact maxima (Eq. 3.10).
    box : what sizes the author's twist grid: a ContactProfile (its box sides) or (3,)
        sides [m] (:func:`workbench.twists_author.box_sides`).
    support_directions : normals of the support error (:func:`fit_score`).
    """

    def __init__(
        self,
        shape: Any,
        wrenches_of: Callable[[np.ndarray], np.ndarray],
        w_max: np.ndarray,
        box: Any,
        support_directions: int,
    ) -> None:
        self.shape = shape
        self.w_max = np.asarray(w_max, float)
        if self.w_max.shape != (6,):
            raise ValueError(f"w_max must be the contact's (6,) maxima; got shape {self.w_max.shape}")
        self.box = box
        self.support_directions = _count(
            support_directions, "support_directions", "normals of the support error"
        )
        self._wrenches = SharedWrenches(wrenches_of, self.support_directions)

    @classmethod
    def of_profile(cls, profile: ContactProfile, mu: float, support_directions: int) -> ExactContact:
        """The contact profile as given (normalise it first for a "profile pair"):
        :func:`workbench.wrench.frictional_wrenches` with friction ``mu``."""
        if not isinstance(profile, ContactProfile):
            raise ValueError(
                f"profile must be a ContactProfile; got {type(profile).__name__} "
                "(a parametric surface: use ExactContact.of_surface)"
            )
        mu = check_mu(mu, what="limit surface")
        fn = partial(frictional_wrenches, profile, mu=mu)
        return cls(profile, fn, w_max(profile, mu), profile, support_directions)

    @classmethod
    def of_surface(
        cls,
        surface: ParametricSurface,
        mu: float,
        support_directions: int,
        *,
        source: str = "continuous",
        mesh_elements: int = 2000,
        quad_rtol: float | None = None,
    ) -> ExactContact:
        """The normalised surface: its wrenches by adaptive quadrature to ``quad_rtol``
        (``source="continuous"``, :func:`workbench.sources.surfaces.surface_wrenches`) or
        on its mesh of ``mesh_elements`` triangles (``"mesh"``).  The author's box is the
        mesh's element-centre extent either way (their ``lengthArray``)."""
        if source not in WRENCH_SOURCES:
            raise ValueError(f"source must be one of {WRENCH_SOURCES}; got {source!r}")
        _count(mesh_elements, "mesh_elements", "triangles of the surface's mesh")
        mu = check_mu(mu, what="limit surface")
        normalized = surface.normalized()
        prof = mesh_profile(surface, mesh_elements).normalized()
        sides = box_sides(prof)
        if source == "continuous":
            rtol = check_rtol(quad_rtol, "quad_rtol") if quad_rtol is not None else None
            fn = partial(surface_wrenches, normalized, mu=mu, rtol=rtol)
            return cls(normalized, fn, surface_w_max(normalized, mu), sides, support_directions)
        fn = partial(frictional_wrenches, prof, mu=mu)
        return cls(normalized, fn, w_max(prof, mu), sides, support_directions)

    @property
    def memo_hits(self) -> int:
        """Twist sets answered from the memo without computing them again."""
        return self._wrenches.hits

    def wrenches(self, twists: np.ndarray) -> np.ndarray:
        """(K, 6) exact raw wrenches of ``twists`` (K, 6)."""
        return self._wrenches(twists)

    def support_args(self, seed: int) -> dict:
        """:class:`~.fit_score.Scoring`'s arguments of the support error on this contact,
        its normals drawn with ``seed``."""
        return {
            "wrenches_of": self.wrenches,
            "support_directions": self.support_directions,
            "support_seed": seed,
        }


def thesis_text_wrenches(
    contact: ExactContact,
    n_wrenches: int,
    seed: int,
    *,
    pitch_range: tuple[float, float] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Raw wrenches (K, 6) of the thesis-text sampler (§3.3.2) on ``contact`` and their
    twists (K, 6), ``K = 2·(n_wrenches // 2)``: ``n_wrenches // 2`` Fibonacci rotations
    plus as many translations, pitch ``h ~ U(pitch_range)·l_s`` (``None``: the config's
    default), drawn with ``seed``."""
    n = _count(n_wrenches, "n_wrenches", "wrenches of the thesis-text sampler")
    xi = sample_twists_thesis(n // 2, contact.shape, seed, pitch_range=pitch_range)
    return contact.wrenches(xi), xi


def thesis_code_sample_of(
    contact: ExactContact, fine_level: int = 0, steps: float = 2.5, *, sides: Any = None
) -> ThesisCodeSample:
    """The thesis-code protocol's wrenches on ``contact``: the author's twist grid of
    ``fine_level`` sized by the contact's box (or ``sides``, (3,) [m], in its place), every
    wrench of it (the scoring set) and the grid-downsampled training indices (``steps``
    cell widths per range; :func:`~.thesis_code.thesis_code_split`), normalised by the
    exact ``w_max``."""
    xi = sample_twists_author(contact.box if sides is None else sides, fine_level)
    W = contact.wrenches(xi)
    return ThesisCodeSample(xi, W, contact.w_max, thesis_code_split(W, contact.w_max, steps))


def thesis_code_training_draws(
    n_pool: int, sizes: Sequence[int], seed: int | np.random.Generator
) -> list[np.ndarray]:
    """Fig 3.9's training sets under the thesis-code protocol: for each ``K`` of ``sizes``, in
    order, ``K`` distinct indices (K,) into the ``n_pool`` wrenches of the author's grid
    (:func:`thesis_code_sample_of`), drawn without replacement from one generator seeded with
    ``seed`` — so a set depends on the sizes drawn before it, and one ``seed`` and ``sizes`` give
    the same sets."""
    n = _count(n_pool, "n_pool", "wrenches of the author's grid drawn from")
    sizes = list(sizes)
    bad = [K for K in sizes if isinstance(K, bool) or not isinstance(K, int | np.integer) or not 0 < K <= n]
    if bad:
        raise ValueError(
            f"sizes must be training set sizes K in [1, n_pool = {n}] (drawn without replacement from "
            f"the author's grid); got {bad!r} among {sizes!r} — lower K or use a finer grid (fine_level)"
        )
    rng = np.random.default_rng(check_seed(seed))
    return [rng.choice(n, K, replace=False) for K in sizes]


def fit_score(
    contact: ExactContact,
    model: str,
    wrenches: np.ndarray,
    *,
    test: Any = None,
    support_seed: int | None = None,
    **fit: Any,
) -> FitScore:
    """:func:`~.fit_score.fit_and_score` of ``model`` on raw ``wrenches`` (K, 6) of
    ``contact``, normalised by its exact ``w_max``, scored on ``test`` (N, 6) wrenches (None:
    not) and with ``support_seed`` also by the support error at the contact's exact surface
    points.  ``fit``: ``twists``, ``solver``, ``alpha``, ``repeats`` of fit_and_score."""
    support = {} if support_seed is None else contact.support_args(support_seed)
    return fit_and_score(model, wrenches, w_max=contact.w_max, scoring=Scoring(test, **support), **fit)


def fit_scores(
    contact: ExactContact,
    models: Iterable[str],
    wrenches: np.ndarray,
    *,
    support_seed: int | None = None,
    repeats: int | Mapping[str, int] = 1,
    **fit: Any,
) -> dict[str, FitScore]:
    """{model: :func:`fit_score`} of ``models`` on ``wrenches`` (K, 6), in the given order.
    A model is left out (absent key) when K is below its unknowns
    (:func:`~.fit_score.min_wrenches`): the thesis-code training set can hold fewer
    wrenches than the quartic's 126 (the author's code regularises instead; we do not
    fake a fit).  ``repeats``: timed fits per model, one number or ``{model: n}``."""
    out = {}
    for m in models:
        if len(wrenches) < min_wrenches(m):
            continue
        n = repeats[m] if isinstance(repeats, Mapping) else repeats
        out[m] = fit_score(contact, m, wrenches, support_seed=support_seed, repeats=n, **fit)
    return out


__all__ = [
    "WRENCH_SOURCES",
    "ExactContact",
    "fit_score",
    "fit_scores",
    "thesis_code_sample_of",
    "thesis_code_training_draws",
    "thesis_text_wrenches",
]

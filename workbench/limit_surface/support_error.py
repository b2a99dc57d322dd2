"""Sampler-independent error of a fitted 6D limit surface.

Eq. 3.18 averages ``|f(ŵ) − 1|`` over *sampled* wrenches, so its value depends
on where the sampler puts them: a sampler that crowds wrenches where the surface
is easy to fit (e.g. near-translations) reports a small error for the same model.
This metric fixes the test points by the geometry instead.

By maximum dissipation (thesis §2.3.4) the friction wrench of a twist ``ξ`` is the
point of the exact 6DFW set whose outward normal is ``−ξ``; in normalised
coordinates ``x̂ = w ⊘ s`` (Eq. 3.10) the power is ``w·ξ = x̂·(s ⊙ ξ)``, so the
normalised outward normal is ``d = −s ⊙ ξ``.  Drawing ``d`` uniformly on the unit
sphere of the model's subspace (all six dimensions for a nonplanar contact, three
for a planar one) and computing ``ξ = −d ⊘ s`` gives exact surface points spread
by *normal direction* — every facet of the exact set is visited in proportion to
its share of directions, whichever sampler trained the model.  The error at each
point is the radial one, ``|f(x̂)^(1/deg) − 1|``: the relative distance from the
exact surface point to the model surface along the ray through the origin, the
same for an ellipsoid and a quartic (Eq. 3.18 charges a quartic ``≈ 2×`` for the
same geometric miss).  It is 0 exactly when every exact point lies on the model.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .. import config
from ..seeds import check_seed
from .base import LimitSurfaceModel

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SupportError:
    """Errors of a model at the exact surface points of uniform normal directions."""

    radial_mean: float  # mean |f(x̂)^(1/deg) − 1| — the number to quote
    radial_p95: float  # its 95th percentile
    radial_max: float
    eq318_mean: float  # mean |f(x̂) − 1| at the same points (Eq. 3.18's form)
    n_directions: int
    dim: int  # dimension of the sphere the normals were drawn on


def uniform_normals(model: LimitSurfaceModel, n: int, seed: int = 0) -> np.ndarray:
    """(n, 6) unit normals ``d``, uniform on the unit sphere of the model's subspace
    (normalised coordinates): ``d = B u / |u|``, ``u ~ N(0, I_r)``.  A full (6D)
    subspace uses ``B = I``, so models of one contact with the same ``scale`` get
    the same twists for a seed (their exact wrenches can be computed once)."""
    if isinstance(n, bool) or not (isinstance(n, int | np.integer) and n > 0):
        raise ValueError(f"n must be a positive integer number of directions; got {n!r}")
    B = model.subspace.basis  # (6, r), orthonormal
    u = np.random.default_rng(check_seed(seed)).standard_normal((int(n), B.shape[1]))
    d = u if B.shape[1] == 6 else u @ B.T
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def twists_for_normals(model: LimitSurfaceModel, normals: np.ndarray) -> np.ndarray:
    """(n, 6) twists ``ξ = −d ⊘ s`` whose friction wrenches have normalised outward
    normal ``d`` (n, 6) — the maximum-dissipation map, inverted."""
    return -np.asarray(normals, float) / model.scale


class SharedWrenches:
    """``wrenches_of`` for :func:`support_error` that computes each of its twist sets once.

    The models of one contact with the same ``scale`` get the same twists for a seed
    (:func:`uniform_normals`, plus the ±e_i probes), so the second and later models' support
    errors reuse the first's exact wrenches — the same function on the same twists, so the same
    bits.  Twist sets of up to ``n_directions + 12`` rows (the support error's) are kept, keyed by
    their bytes; larger ones (training or test sets) are computed afresh and not kept.

    fn : ``(K, 6) twists -> (K, 6)`` exact wrenches of the contact, e.g.
        ``partial(frictional_wrenches, profile, mu=mu)``.
    n_directions : the support error's ``n_directions``.
    """

    def __init__(self, fn: Callable[[np.ndarray], np.ndarray], n_directions: int) -> None:
        self._fn = fn
        self._max_rows = int(n_directions) + 12  # the directions and the ±e_i probes of 6 components
        self._kept: dict[bytes, np.ndarray] = {}
        self.hits = 0  # calls answered from a kept set

    def __call__(self, twists: np.ndarray) -> np.ndarray:
        """(K, 6) wrenches of ``twists`` (K, 6), a fresh array each call."""
        if len(twists) > self._max_rows:
            return self._fn(twists)
        key = np.ascontiguousarray(twists, dtype=float).tobytes()
        if key in self._kept:
            self.hits += 1
        else:
            self._kept[key] = np.asarray(self._fn(twists), float)
        return self._kept[key].copy()


def support_error(
    model: LimitSurfaceModel,
    wrenches_of: Callable[[np.ndarray], np.ndarray],
    n_directions: int = 2000,
    seed: int = 0,
) -> SupportError:
    """Radial error of ``model`` at exact 6DFW surface points of uniform normals.

    model : a fitted limit surface (raw wrenches in, :meth:`value`).
    wrenches_of : ``(K, 6) twists -> (K, 6)`` exact raw friction wrenches of the same
        contact, e.g. ``lambda xi: frictional_wrenches(profile, xi, mu)`` with the
        profile the model was fitted to (same normalisation, same μ).
    n_directions : directions d uniform on the model subspace's unit sphere.
    """
    d = uniform_normals(model, n_directions, seed)
    # plus ±e_i of the non-degenerate components: their exact points reach w_max_i exactly,
    # so a wrench set of another μ, force or normalisation than the model's shows here
    live = np.flatnonzero(model.w_max > config.TOL.degenerate_wmax_rtol * model.w_max.max())
    probe = np.zeros((2 * len(live), 6))
    probe[np.arange(len(live)), live] = 1.0
    probe[len(live) + np.arange(len(live)), live] = -1.0
    W_all = np.asarray(wrenches_of(twists_for_normals(model, np.vstack([d, probe]))), float)
    K = len(d) + len(probe)
    if W_all.shape != (K, 6):
        raise ValueError(
            f"wrenches_of must map (K, 6) twists to (K, 6) wrenches; got shape {W_all.shape} for K = {K} "
            "(pass e.g. lambda xi: frictional_wrenches(profile, xi, mu))"
        )
    if not np.isfinite(W_all).all():
        raise ValueError(
            f"wrenches_of returned NaN/inf in {int((~np.isfinite(W_all).all(axis=1)).sum())} of {K} rows: "
            "it must give the finite friction wrenches of the model's contact"
        )
    W, W_probe = W_all[: len(d)], W_all[len(d) :]
    reach = np.abs(W_probe[np.arange(len(probe)), np.r_[live, live]]) / model.w_max[np.r_[live, live]]
    if reach.max() > 1 + config.TOL.support_wmax_mismatch:  # legitimate for sampled maxima, so a warning
        log.warning(
            "the contact's exact maxima exceed the model's w_max by up to %.0f %% (a model normalised "
            "by sampled maxima, or wrenches_of of a larger μ or force): the radial error includes that",
            100 * (reach.max() - 1),
        )
    if reach.min() < 1 - config.TOL.support_wmax_mismatch:  # below the model's own maxima: another contact
        raise ValueError(
            f"wrenches_of does not reproduce the model's w_max: |w_i| / w_max_i at the twists of the "
            f"canonical normals ±e_i range over [{reach.min():.3g}, {reach.max():.3g}], expected ≈ 1 — pass "
            "the wrenches of the contact the model was fitted to, with the same μ and force (e.g. the "
            "normalised profile for a model from LimitSurfaceCache.get(..., force=1.0))"
        )
    f = np.asarray(model.value(W), float)
    r = np.abs(np.maximum(f, 0.0) ** (1.0 / model.degree) - 1.0)
    return SupportError(
        radial_mean=float(r.mean()),
        radial_p95=float(np.percentile(r, 95)),
        radial_max=float(r.max()),
        eq318_mean=float(np.mean(np.abs(f - 1.0))),
        n_directions=int(n_directions),
        dim=model.dim,
    )


__all__ = ["SharedWrenches", "SupportError", "support_error", "twists_for_normals", "uniform_normals"]

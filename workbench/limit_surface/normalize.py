"""Normalisation of frictional wrenches (Eq. 3.10), the PCA subspace of
§3.3.4.2 / 6DFC §IV-C.2 and Table 3.2's PCA of a contact's wrenches (:func:`wrench_pca`).

Degenerate components (``w_max,i <= config.TOL.degenerate_wmax_rtol * max w_max``,
e.g. ``f_z`` of a planar contact in the xy-plane) are scaled by ``max w_max``
instead of ``w_max,i`` — never divided by ~0 — and the PCA then drops them.  Such an
entry computed from wrench sums may land a round-off below 0: :func:`check_w_max`, the
one rule of ``w_max``, sets it to 0 (``config.TOL.wrench_roundoff_rtol``) and refuses more.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import config

log = logging.getLogger(__name__)


def check_wrenches(wrenches: Any, name: str = "wrenches") -> np.ndarray:
    """Validate raw wrenches: finite (K, 6) float, not all zero."""
    try:
        W = np.asarray(wrenches, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a numeric (K, 6) array; got {type(wrenches).__name__}") from None
    if W.ndim != 2 or W.shape[1] != 6:
        hint = (
            " — a planar contact's (f_x, f_y, τ_z)? give them as 6D wrenches [f_x, f_y, 0, 0, 0, τ_z] "
            "(the fit keeps the 3 dimensions they span)"
            if W.ndim == 2 and W.shape[1] == 3
            else " — one row [f_x, f_y, f_z, τ_x, τ_y, τ_z] per wrench"
        )
        raise ValueError(f"{name} must have shape (K, 6); got {W.shape}{hint}")
    bad = ~np.isfinite(W)
    if bad.any():
        raise ValueError(f"{name} must be finite; row {int(np.argwhere(bad)[0][0])} has NaN/inf")
    if len(W) == 0:
        raise ValueError(f"{name} has no rows: give at least one (K, 6) wrench")
    if not np.any(W):
        raise ValueError(f"{name} are all zero: there is no friction to model (check mu and pressures)")
    return W


def check_twists(
    W: np.ndarray, twists: Any, *, nonzero: bool = False, friction_sign: bool = True
) -> np.ndarray:
    """Validate the twists (K, 6) ``[v; ω]`` that validated wrenches ``W`` (K, 6) were
    computed from: same shape, finite, non-zero rows if ``nonzero``, and — if
    ``friction_sign`` — friction opposing motion, ``w·ξ <= 0`` in every row (the
    author's code uses ``+ξ``; such twists would fit a wrong surface)."""
    xi = np.asarray(twists, dtype=np.float64)
    if xi.shape != W.shape:
        raise ValueError(
            f"twists must have the wrenches' shape {W.shape} (one twist [v; ω] per wrench); got shape "
            f"{xi.shape} — pass the twists the wrenches were computed from"
        )
    bad = ~np.isfinite(xi).all(axis=1)
    if nonzero:
        bad |= ~np.any(xi, axis=1)
    if bad.any():
        what = "NaN/inf or zero" if nonzero else "NaN/inf"
        raise ValueError(
            f"twist {int(np.argmax(bad))} is {what} ({int(bad.sum())} such rows): every wrench needs the "
            f"finite{', non-zero' if nonzero else ''} twist it was computed from"
        )
    if friction_sign:
        power = np.einsum("ij,ij->i", W, xi)
        # friction dissipates: w·xi <= 0 up to round-off of the products' norms
        wrong = power > 1e-9 * np.linalg.norm(W, axis=1) * np.linalg.norm(xi, axis=1)
        if wrong.any():
            raise ValueError(
                f"twist {int(np.argmax(wrong))} is not a friction twist of its wrench: friction opposes "
                f"motion (w·ξ <= 0) but w·ξ > 0 there ({int(wrong.sum())} of {len(W)} rows) — pass the "
                "twists the wrenches were computed from, unchanged in sign and order (not the author's "
                "+ξ convention)"
            )
    return xi


def check_w_max(w_max: Any) -> np.ndarray:
    """The (6,) maximal wrench magnitudes ``w_max`` validated: finite, a positive largest
    entry, and no entry below 0 beyond round-off.

    ``w_max,i = −w(e_i)_i >= 0`` in exact arithmetic (friction dissipates), but a degenerate
    entry (a planar contact's normal force or tilting torque) comes out of the wrench sums a
    little below 0; entries down to ``−config.TOL.wrench_roundoff_rtol · max(w_max)`` (read now)
    are returned as 0 — degenerate, as they are — and anything further below raises.
    Returns a new (6,) float array."""
    try:
        wm = np.array(w_max, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"w_max must be a numeric (6,) array; got {type(w_max).__name__}") from None
    if wm.shape != (6,) or not np.all(np.isfinite(wm)):
        raise ValueError(f"w_max must be a finite (6,) array of maximal wrench magnitudes; got {wm}")
    top = float(wm.max())
    if not top > 0:
        raise ValueError(
            f"w_max must have a positive entry; got {wm} — are the wrenches all zero, or of the opposite "
            "sign (friction opposes motion: pass the twists' own wrenches, not the author's +ξ)?"
        )
    floor = -config.TOL.wrench_roundoff_rtol * top
    if (wm < floor).any():
        i = int(np.argmin(wm))
        raise ValueError(
            f"w_max component {i} is {wm[i]:.6g}, below 0 by more than round-off "
            f"(config.TOL.wrench_roundoff_rtol = {config.TOL.wrench_roundoff_rtol:g} of the largest, "
            f"{top:.6g}): w_max,i = −w(e_i)_i >= 0 since friction dissipates — these are not a contact's "
            "maxima (wrenches of the opposite sign, another contact's?): pass workbench.w_max(profile, mu) "
            "or omit w_max to use the sampled maxima"
        )
    return np.maximum(wm, 0.0)


def wrench_scale(w_max: np.ndarray) -> np.ndarray:
    """(6,) divisor per component: ``w_max`` (checked by :func:`check_w_max`) with degenerate
    entries replaced by ``max(w_max)`` (Eq. 3.10 without dividing by ~0)."""
    w_max = check_w_max(w_max)
    top = float(w_max.max())
    return np.where(w_max > config.TOL.degenerate_wmax_rtol * top, w_max, top)


@dataclass(frozen=True)
class Subspace:
    """Orthonormal basis of the subspace the normalised wrenches span.

    basis : (6, r) columns; complement : (6, 6 - r); std : (6,) PCA std devs.
    """

    basis: np.ndarray
    complement: np.ndarray
    std: np.ndarray

    @property
    def dim(self) -> int:
        return self.basis.shape[1]


def pca_subspace(w_hat: np.ndarray, rtol: float | None = None) -> Subspace:
    """PCA about the origin (limit surfaces are centered at 0): keep directions
    whose std is > ``rtol`` (default ``config.TOL.subspace_rtol``, read now) times the
    largest (§3.3.4.2)."""
    rtol = config.TOL.subspace_rtol if rtol is None else rtol
    # second-moment (not covariance) eigenvectors: the set is symmetric about 0;
    # the 6x6 moment matrix avoids a K x K SVD factor
    lam, vec = np.linalg.eigh(w_hat.T @ w_hat / max(len(w_hat), 1))
    order = np.argsort(lam)[::-1]
    std = np.sqrt(np.clip(lam[order], 0.0, None))
    vec = vec[:, order]
    r = int((std > rtol * std[0]).sum())
    return Subspace(vec[:, :r].copy(), vec[:, r:].copy(), std)


def explained_variance_ratio(w_hat: np.ndarray, *, center: bool = True) -> np.ndarray:
    """(6,) fractions of the variance of normalised wrenches ``w_hat`` (K, 6) along their
    principal directions, largest first — Table 3.2's PCA (the thesis's: about the mean).

    Two conventions live here on purpose: this one centers (``center=True``), as a PCA of a
    sample does; :func:`pca_subspace` takes moments about the origin, because a limit
    surface is centered at 0 by construction and its fit must not move it.  For a set
    symmetric about 0 (``w`` and ``-w`` both sampled) they agree.
    """
    w_hat = np.asarray(w_hat, dtype=np.float64)
    if w_hat.ndim != 2 or w_hat.shape[1] != 6 or len(w_hat) < 2 or not np.isfinite(w_hat).all():
        raise ValueError(f"w_hat must be finite normalised wrenches (K >= 2, 6); got shape {w_hat.shape}")
    x = w_hat - w_hat.mean(axis=0) if center else w_hat
    var = np.linalg.svd(x, compute_uv=False) ** 2 / (len(x) - 1)
    return var / var.sum()


def n_components_retaining(ratio: np.ndarray, retained_variance: float) -> int:
    """The smallest ``k`` whose first ``k`` components of ``ratio`` (6,) (explained variance
    fractions, largest first, summing to 1) retain ``retained_variance`` of the variance; a
    cumulative fraction short of it by round-off only (a relative 1e-12) counts as reaching it."""
    return int(np.searchsorted(np.cumsum(ratio), retained_variance * (1 - 1e-12)) + 1)


def n_components_above(ratio: np.ndarray, fraction: float) -> int:
    """How many components of ``ratio`` (6,) each explain at least ``fraction`` of the variance."""
    return int((ratio >= fraction).sum())


@dataclass(frozen=True)
class WrenchPCA:
    """PCA of one contact's normalised wrenches (Table 3.2, §3.5.1.1)."""

    explained_variance_ratio: np.ndarray  # (6,) variance fractions, largest first
    n_retained: int  # the smallest k retaining the asked fraction of the variance
    n_above_fraction: int  # the components each explaining at least the asked fraction


def wrench_pca(
    wrenches: Any, w_max: Any, *, retained_variance: float, significant_fraction: float
) -> WrenchPCA:
    """PCA of the wrenches (K, 6) of a contact normalised by its exact ``w_max`` (6,)
    (Eq. 3.10, degenerate components guarded by :func:`wrench_scale`): the explained variance
    ratio about the mean (:func:`explained_variance_ratio`), the component count retaining
    ``retained_variance`` in (0, 1] of the variance (:func:`n_components_retaining`) and the
    count of components each explaining at least ``significant_fraction`` in [0, 1]
    (:func:`n_components_above`); e.g. ``config.TOL.pca_retained_variance`` and
    ``config.TOL.pca_significant_fraction``."""
    for name, v, lo_open in (
        ("retained_variance", retained_variance, True),
        ("significant_fraction", significant_fraction, False),
    ):
        ok = not isinstance(v, bool) and isinstance(v, int | float | np.floating | np.integer)
        if not (ok and (0 < v <= 1 if lo_open else 0 <= v <= 1)):
            raise ValueError(
                f"{name} must be a fraction of the variance in {'(0' if lo_open else '[0'}, 1]; got {v!r} "
                "— a percentage? 99 % is 0.99"
            )
    W = check_wrenches(wrenches)
    ratio = explained_variance_ratio(W / wrench_scale(w_max))
    return WrenchPCA(
        ratio,
        n_components_retaining(ratio, retained_variance),
        n_components_above(ratio, significant_fraction),
    )


def _check_centred(x: np.ndarray) -> None:
    """Log a warning when normalised wrenches x (K, 6) are not centred on 0: the mean's norm
    over their RMS norm above ``config.TOL.wrench_offset_warn`` (a frictional wrench set is
    symmetric about 0; a total contact wrench also holds the normal force)."""
    rms = float(np.sqrt(np.mean(np.einsum("ij,ij->i", x, x))))
    offset = float(np.linalg.norm(x.mean(axis=0))) / rms if rms > 0 else 0.0
    if offset > config.TOL.wrench_offset_warn:
        log.warning(
            "the wrenches are not centred on 0: their mean is %.2g of their RMS size (> "
            "TOL.wrench_offset_warn = %g), but a limit surface is symmetric about 0 — are they total "
            "contact wrenches? fit the frictional part only: subtract workbench.normal_wrench(profile), "
            "or sample workbench.frictional_wrenches(profile, twists, mu)",
            offset,
            config.TOL.wrench_offset_warn,
        )


def prepare(
    wrenches: Any, w_max: Any = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Subspace]:
    """Common preamble of the fitters: validated raw wrenches W (K, 6), w_max
    (given, or the sampled maxima of Algorithm 1), the guarded scale,
    normalised wrenches x̂ (Eq. 3.10) and their PCA subspace.  A given ``w_max`` passes
    :func:`check_w_max` (round-off negatives of degenerate entries become 0), the wrenches may
    exceed it by ``config.TOL.given_wmax_rtol`` relative plus ``wrench_roundoff_rtol ·
    max(w_max)``, and its degenerate components are the exact zeros of the contact: the
    wrenches' round-off there is set to 0 (W returned so)."""
    W = check_wrenches(wrenches)
    # the sampled maxima are >= 0 by construction; given ones may hold round-off negatives
    wm = np.abs(W).max(axis=0) if w_max is None else check_w_max(w_max)
    if w_max is not None:
        reach = np.abs(W).max(axis=0)
        # the kernel's round-off may take a component a little past its exact maximum
        slack = config.TOL.wrench_roundoff_rtol * wm.max()
        over = reach > wm * (1 + config.TOL.given_wmax_rtol) + slack
        if over.any():
            i = int(np.argmax(np.where(over, reach / np.maximum(wm, 1e-300), 0)))
            raise ValueError(
                f"the wrenches exceed the given w_max in component {i} ({reach[i]:.6g} > {wm[i]:.6g}): "
                "w_max must be the exact maxima of these wrenches' contact (same μ, force and units, "
                "e.g. workbench.w_max(profile, mu)) — or omit it to use the sampled maxima"
            )
    scale = wrench_scale(wm)
    if w_max is not None:
        # exact maxima: a degenerate component is 0 for every wrench of the contact, and what the
        # samples hold there is round-off (bounded by the check above) that the PCA would keep
        W = np.where(wm <= config.TOL.degenerate_wmax_rtol * wm.max(), 0.0, W)
    x = W / scale
    _check_centred(x)
    sub = pca_subspace(x)
    if sub.dim >= len(W):
        raise ValueError(
            f"{len(W)} wrenches span {sub.dim} dimensions: too few to tell the contact's wrench space "
            "from the sample (a fit would be flat in every direction not sampled) — sample at least "
            "21 for an ellipsoid, 126 for a quartic (their unknowns in 6D; the thesis uses 100-1,000)"
        )
    return W, wm, scale, x, sub

"""The twist grid of the thesis author's code ("thesis-code" protocol).

The thesis (§3.3.2) describes its motion sampling in words; the author's public
MATLAB code (``martinajingyixu/non-planar-surface-contact``,
``generateTwistSamples.m`` and ``samplesphere.m``) fixes the numbers.  Taken from
it as facts (no code copied):

* instantaneous axes of rotation (IARs) along ``n_axes`` near-uniform directions
  (a golden-angle sphere whose points nearest the six ± coordinate axes are
  replaced by those axes);
* each axis offset from the pressure centre ``o`` on a grid perpendicular to it:
  two offset coordinates ``d1, d2`` (on the two coordinate axes other than the
  axis's dominant component; the third solves ``p·ω = 0``) from
  ``{0, ±c·min(L), ±c·max(L)}``, ``c`` in the level's coefficient list, ``L`` the
  contact's axis-aligned box sides — up to 1.0 × the longest side;
* ``n_through`` more axes through ``o`` itself, and 36 near-translations (the code
  rotates about the six coordinate axes at offsets ``(d1, d2) ∈ {0, ±10⁷}²``,
  ``d1 ≠ d2``: translations along the six ± axes and six face diagonals);
* every axis with every pitch of ``{0, ±p·mean(L)}``.

Departures, on purpose (reproduce the method, not its quirks): the code floors the
offsets to 1e-4 *in its length unit* (0.1 µm in its millimetre FEM data, 0.1 mm in
metres) — not done here; the near-translations are exact translations (a rotation
10⁷ units away, whose twist the code then normalises).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from ._kernels import _author_grid
from .twists import translation_twists
from .units import check_extent


@dataclass(frozen=True)
class AuthorLevel:
    """One ``fineLevel`` of ``generateTwistSamples.m``."""

    coeffs: tuple[float, ...]  # offset coefficients c (× min and × max box side)
    n_through: int  # axes through o ("numPointsAngle")
    pitch_factors: tuple[float, ...]  # positive pitches / mean box side ("pitchSamples")
    n_axes: int  # offset-axis directions ("numAngles")


def _r(lo: float, hi: float, step: float) -> tuple[float, ...]:
    return tuple(np.round(np.arange(lo, hi + step / 2, step), 10))


#: the author's levels; the FEM example (Table 3.3) uses level 0
AUTHOR_LEVELS: dict[int, AuthorLevel] = {
    -1: AuthorLevel((0.0,), 10, (0.0,), 0),
    0: AuthorLevel((0.01, 0.05, 0.1, 0.2, 0.3, 1.0), 500, (0.25,), 25),
    1: AuthorLevel((0.01, 0.05, *_r(0.1, 0.5, 0.1), 1.0), 5000, (0.25,), 30),
    2: AuthorLevel((0.01, 0.05, *_r(0.1, 0.5, 0.1), 1.0), 5000, (0.125, 0.25, 0.5, 1.0, 2.0), 16),
    3: AuthorLevel((0.01, 0.05, 0.1, 0.2, 0.3, *_r(0.3, 0.4, 0.025), 0.5, 1.0), 5000, (0.25, 0.5), 16),
    4: AuthorLevel((0.01, 0.05, 0.1, 0.2, *_r(0.3, 0.4, 0.02), 0.5, 1.0), 10000, (0.25,), 50),
    5: AuthorLevel(
        (*_r(0.0, 0.1, 0.05), *_r(0.1, 0.5, 0.025), 0.2, 0.3, 1.0, *_r(0.3, 0.4, 0.01)), 10000, (0.25,), 50
    ),
    6: AuthorLevel((0.01, 0.05, 0.1, 0.2, 0.3, 1.0), 500, (0.25, 0.5), 25),
}


def author_sphere(n: int) -> np.ndarray:
    """(n, 3) unit vectors: a golden-angle sphere of n points whose points nearest
    the six ± coordinate axes are replaced by those axes (``samplesphere.m``)."""
    if n <= 0:
        return np.zeros((0, 3))
    i = np.arange(n) + 0.5
    phi = np.arcsin(1.0 - 2.0 * i / n)
    theta = np.pi * (1.0 + np.sqrt(5.0)) * i
    pts = np.column_stack([np.cos(theta) * np.cos(phi), np.sin(theta) * np.cos(phi), np.sin(phi)])
    axes = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
    keep = np.ones(n, dtype=bool)
    for a in axes[: min(6, n)]:  # nearest remaining point to each axis, in turn
        d = np.linalg.norm(pts - a, axis=1)
        d[~keep] = np.inf
        keep[int(np.argmin(d))] = False
    return np.vstack([pts[keep], axes[: min(6, n)]])


def box_sides(profile_or_sides: Any, *, allow_scale: bool = False) -> np.ndarray:
    """(3,) axis-aligned box sides ``L`` [m] of a contact (``lengthArray``): the extent
    of a ContactProfile's element *centres* (slightly under the surface's own extent;
    the profile's own unit check applies), or given directly — then the longest side
    must be a plausible size in metres (:func:`workbench.units.check_extent`, no lower
    limit; ``allow_scale=True`` accepts any)."""
    centers = getattr(profile_or_sides, "centers", None)
    L = (
        np.ptp(np.asarray(centers, float), axis=0)
        if centers is not None
        else np.asarray(profile_or_sides, float)
    )
    if L.shape != (3,) or not np.isfinite(L).all() or (L < 0).any() or L.max() <= 0:
        what = (
            "the profile's element centres span no box (one element or coincident centres): "
            "the author's grid needs a contact with extent"
            if centers is not None
            else "pass a ContactProfile or its axis-aligned extents"
        )
        raise ValueError(
            f"box sides must be three non-negative lengths [m], not all zero; got {L.tolist()} ({what})"
        )
    if centers is None:
        check_extent(
            L.max(),
            "box sides passed to sample_twists_author",
            allow_scale=allow_scale,
            check_lower=False,
            fix="scale them by {factor:g}",
        )
    return L


def _offsets(omega: np.ndarray, d1: np.ndarray, d2: np.ndarray) -> np.ndarray:
    """(K, 3) offset p ⊥ ω with coordinates (d1, d2) on the two axes other than ω's
    dominant component (the author's parametrisation of the perpendicular plane)."""
    k = np.argmax(np.abs(omega), axis=1)
    j1 = np.where(k == 0, 1, 0)
    j2 = np.where(k == 2, 1, 2)
    rows = np.arange(len(omega))
    p = np.zeros_like(omega)
    p[rows, j1], p[rows, j2] = d1, d2
    p[rows, k] = -(d1 * omega[rows, j1] + d2 * omega[rows, j2]) / omega[rows, k]
    return p


@lru_cache(maxsize=1)
def _near_translations() -> np.ndarray:
    """(36, 3) directions of the code's 36 far-axis rotations: axis e_k, offset
    p = 10⁷ (d1, d2) on the other two axes, twist ≈ [p × e_k; 0]."""
    axes = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
    pairs = [(a, b) for b in (0, 1, -1) for a in (0, 1, -1) if a != b]
    omega = np.repeat(axes, len(pairs), axis=0)
    d = np.tile(np.array(pairs, float), (6, 1))
    m = np.cross(_offsets(omega, d[:, 0], d[:, 1]), omega)
    out = m / np.linalg.norm(m, axis=1, keepdims=True)
    out.flags.writeable = False  # made once a process (lru_cache), shared by every grid
    return out


def sample_twists_author(
    profile_or_sides: Any, fine_level: int = 0, *, allow_scale: bool = False
) -> np.ndarray:
    """Unit twists about the pressure centre ``o`` on the author's grid (module docstring).

    profile_or_sides : ContactProfile (its box sides) or (3,) box sides ``L`` [m]
        (``allow_scale``: see :func:`box_sides`).
    fine_level : the code's ``fineLevel`` (:data:`AUTHOR_LEVELS`; 0: the FEM study).
    Returns (K, 6) ``[v; ω]``: offset axes, axes through ``o`` and 36 translations,
    each with every pitch (rotations with ``|ω| = 1``, translations ``|v| = 1``);
    level 0 gives ``(25·25² + 500 + 36) · 3 = 48 483`` for a box whose 12 offsets
    ``c·min(L)``, ``c·max(L)`` are distinct (offsets that coincide, e.g. 0.05 × 20 mm = 0.2 × 5 mm,
    are one: 41 283 twists on a 20 × 10 × 5 mm box).  A flat contact (one side 0) has fewer
    distinct offsets: a 20 mm square patch gives 14 283 twists (and, downsampled, a few dozen training
    wrenches — its wrench set is 3D).
    """
    if fine_level not in AUTHOR_LEVELS:
        raise ValueError(f"fine_level must be one of {sorted(AUTHOR_LEVELS)}; got {fine_level!r}")
    lv = AUTHOR_LEVELS[fine_level]
    L = box_sides(profile_or_sides, allow_scale=allow_scale)
    c = np.asarray(lv.coeffs)
    half = np.r_[c * L.min(), c * L.max()]
    d = np.unique(np.r_[-half, 0.0, half])
    pitches = np.unique(np.r_[-np.asarray(lv.pitch_factors), 0.0, lv.pitch_factors]) * L.mean()

    # one compiled pass writes the (K, 6) grid, each value rounded as the NumPy expressions of
    # tests/naive.py's author_grid round it (bit for bit)
    return _author_grid(_sphere(lv.n_axes), d, _sphere(lv.n_through), pitches, _translations())


@lru_cache(maxsize=1)
def _translations() -> np.ndarray:
    """(36, 6) the near-translations' unit twists (:func:`_near_translations`), made once a process
    (read-only: shared by every grid)."""
    out = translation_twists(_near_translations())
    out.flags.writeable = False
    return out


@lru_cache(maxsize=8)
def _sphere(n: int) -> np.ndarray:
    """:func:`author_sphere` of ``n``, made once a process (read-only: shared by every grid)."""
    pts = author_sphere(n)
    pts.flags.writeable = False
    return pts


__all__ = ["AUTHOR_LEVELS", "AuthorLevel", "author_sphere", "box_sides", "sample_twists_author"]

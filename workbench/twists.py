"""Unit twists ``ξ = [v; ω]`` about the pressure center, Plücker form and samplers.

A unit twist (Eq. 2.30) is ``[h e + m; e]`` for a motion with rotation
(``|ω| = 1``) and ``[e; 0]`` for a pure translation (``|v| = 1``), where the
screw axis has direction ``e`` and moment ``m = q × e`` (Eq. 2.21) about the
reference point (the pressure center ``o``, so ``q`` is relative to ``o``).

Samplers (all seeded):

* :func:`sample_twists_thesis` — thesis §3.3.2: Fibonacci ``e``, ``q`` uniform
  in a ball of radius ``0.25 l_s``, ``h ~ U[-1, 1] l_s`` (the thesis's
  ``U[-2, 2]`` m/rad for its surfaces with ``l_s = 2``, made scale covariant),
  plus the pure translations along the same ``e``.
* :func:`sample_twists_6dfc` — 6DFC paper §IV-C.1: ``k1`` pure rotations about
  random axes through random centers plus ``k2`` random pure translations.
* :func:`canonical_twists` — the six axis twists that give ``w_max`` exactly.
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

from . import config
from .seeds import check_seed

SeedLike = int | np.random.Generator | None


def _rng(seed: SeedLike) -> np.random.Generator:
    """The generator of ``seed`` (an int >= 0 or a Generator, :func:`workbench.seeds.check_seed`)."""
    return np.random.default_rng(check_seed(seed))


def _unit_rows(name: str, e: Any) -> np.ndarray:
    e = np.atleast_2d(np.asarray(e, dtype=np.float64))
    if e.ndim != 2 or e.shape[1] != 3:
        raise ValueError(f"{name} must have shape (K, 3) or (3,); got {np.shape(e)}")
    norm = np.linalg.norm(e, axis=1)
    if not np.all(np.isfinite(e)) or (norm == 0).any():
        raise ValueError(f"{name} must be finite non-zero directions")
    return e / norm[:, None]


def twists_from_plucker(e: Any, m: Any, h: Any) -> np.ndarray:
    """Unit twists with rotation, Eqs. 2.28, 2.30 with ``|ω| = 1``.

    e : (K, 3) axis directions (normalised here); m : (K, 3) moments about the
    reference point, must satisfy ``e·m = 0`` (Eq. 2.22); h : (K,) pitches.
    Returns (K, 6) ``[h e + m; e]``.
    """
    e = _unit_rows("e", e)
    m = np.atleast_2d(np.asarray(m, dtype=np.float64))
    h = np.broadcast_to(np.asarray(h, dtype=np.float64), (e.shape[0],))
    if m.shape != e.shape:
        raise ValueError(f"m must have the shape of e {e.shape}; got {m.shape}")
    scale = np.maximum(np.linalg.norm(m, axis=1), 1.0)
    # Plücker coordinates: e·m = 0 exactly, up to round-off of their magnitudes
    if (np.abs(np.einsum("ij,ij->i", e, m)) > 1e-9 * scale).any():
        raise ValueError("Plücker coordinates need e·m = 0 (Eq. 2.22); build m as q × e")
    return np.hstack([h[:, None] * e + m, e])


def translation_twists(e: Any) -> np.ndarray:
    """Pure-translation unit twists ``[e; 0]`` (Eq. 2.30, ``|ω| = 0``); e : (K, 3)."""
    e = _unit_rows("e", e)
    return np.hstack([e, np.zeros_like(e)])


def plucker_from_twists(twists: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Inverse of :func:`twists_from_plucker` / :func:`translation_twists`.

    twists : (K, 6) ``[v; ω]`` of any magnitude.  Returns ``(e, m, h,
    is_translation)`` with shapes (K, 3), (K, 3), (K,), (K,) bool.  For pure
    translations ``e = v/|v|``, ``m = 0`` and ``h = inf`` (Eq. 2.28 remark).
    """
    xi = np.atleast_2d(np.asarray(twists, dtype=np.float64))
    if xi.ndim != 2 or xi.shape[1] != 6:
        raise ValueError(f"twists must have shape (K, 6); got {np.shape(twists)}")
    v, w = xi[:, :3], xi[:, 3:]
    wn = np.linalg.norm(w, axis=1)
    vn = np.linalg.norm(v, axis=1)
    trans = wn <= config.TOL.translation_omega_atol * np.maximum(vn, 1.0)
    if ((wn == 0) & (vn == 0)).any():
        raise ValueError("twists contains a zero row: a unit twist needs |ω| = 1 or |v| = 1")
    e = np.where(
        trans[:, None], v / np.where(vn > 0, vn, 1.0)[:, None], w / np.where(wn > 0, wn, 1.0)[:, None]
    )
    safe_wn = np.where(trans, 1.0, wn)
    h = np.where(trans, np.inf, np.einsum("ij,ij->i", v, w) / safe_wn**2)  # h = v·ω/|ω|², Eq. 2.26
    v_unit = v / safe_wn[:, None]
    m = np.where(trans[:, None], 0.0, v_unit - np.where(trans, 0.0, h)[:, None] * e)  # Eq. 2.27
    return e, m, h, trans


def fibonacci_sphere(n: int) -> np.ndarray:
    """(n, 3) near-uniform unit vectors by the Fibonacci (golden-angle) lattice."""
    if n < 1:
        raise ValueError(f"n must be >= 1; got {n}")
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    phi = np.pi * (3.0 - np.sqrt(5.0)) * i
    rho = np.sqrt(np.clip(1.0 - z * z, 0.0, None))
    return np.column_stack([rho * np.cos(phi), rho * np.sin(phi), z])


def _uniform_sphere(rng: np.random.Generator, n: int) -> np.ndarray:
    x = rng.standard_normal((n, 3))
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def _uniform_ball(rng: np.random.Generator, n: int, radius: float) -> np.ndarray:
    return _uniform_sphere(rng, n) * (radius * rng.random(n) ** (1.0 / 3.0))[:, None]


def _count(name: str, n: Any, minimum: int) -> int:
    """``n`` as an int >= ``minimum`` (an int, not a bool, float or string), else ValueError."""
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum} (a number of twists); got {n!r}")
    return int(n)


def _length(length_scale: Any) -> float:
    """``length_scale`` [m] (a number, or the ``length_scale`` of a profile or surface) as a
    positive float.  A number is judged by the rule of a contact's size
    (:func:`workbench.units.check_extent`, as a ``ContactProfile``'s ``l_s`` is: 20 given for a
    20 mm contact reads as 20 m and is refused); a profile's own ``l_s`` was judged when it was
    built (with its ``allow_scale``)."""
    from .units import check_extent

    given = not hasattr(length_scale, "length_scale")
    ls = length_scale if given else length_scale.length_scale
    if isinstance(ls, (bool, np.bool_)) or not isinstance(ls, numbers.Real):
        raise ValueError(
            f"length_scale must be a positive length [m] (a number) or a ContactProfile; got {length_scale!r}"
        )
    ls = float(ls)
    if not np.isfinite(ls) or ls <= 0:
        raise ValueError(f"length_scale must be a positive length [m] or a ContactProfile; got {ls}")
    if given:
        check_extent(
            ls,
            "length_scale (the contact's l_s, the longest side of its PCA box)",
            check_lower=False,
            fix=f"pass it in metres (length_scale={ls:g} x {{factor:g}}), or the profile itself",
            override=None,
        )
    return ls


def sample_twists_thesis(
    n: int,
    length_scale: Any,
    seed: SeedLike = None,
    *,
    translations: bool = True,
    radius_factor: float | None = None,
    pitch_range: tuple[float, float] | None = None,
) -> np.ndarray:
    """Motion sampling of thesis §3.3.2.

    ``e`` from a Fibonacci sphere of ``n`` points, ``q`` uniform in the ball of
    radius ``radius_factor * l_s`` around ``o``, ``m = q × e``, ``h`` uniform in
    ``pitch_range * l_s``; with ``translations=True`` the ``n`` pure
    translations along the same ``e`` are appended.

    length_scale : float [m] or ContactProfile (uses its ``length_scale`` ``l_s``).
    seed, radius_factor, pitch_range : default ``config.DEFAULTS.seed``,
    ``.twist_radius_factor``, ``.pitch_range`` (read now; for fresh randomness pass a
    ``np.random.Generator``).
    Returns (n or 2n, 6) unit twists about ``o``.
    """
    n = _count("n", n, 1)
    d = config.DEFAULTS
    seed = d.seed if seed is None else seed
    # the rules of the config fields they default to (a reversed range, a negative radius)
    radius_factor = (
        d.twist_radius_factor
        if radius_factor is None
        else config.check_value("twist_radius_factor", radius_factor, "radius_factor")
    )
    if pitch_range is None:
        pitch_range = d.pitch_range
    else:
        pitch_range = config.check_value("pitch_range", pitch_range, "pitch_range")
    rng = _rng(seed)
    ls = _length(length_scale)
    e = fibonacci_sphere(n)
    q = _uniform_ball(rng, n, radius_factor * ls)
    h = ls * rng.uniform(pitch_range[0], pitch_range[1], n)
    xi = twists_from_plucker(e, np.cross(q, e), h)
    return np.vstack([xi, translation_twists(e)]) if translations else xi


def sample_twists_6dfc(
    k1: int,
    k2: int,
    length_scale: Any,
    seed: SeedLike = None,
    *,
    radius_factor: float | None = None,
) -> np.ndarray:
    """Motion sampling of the 6DFC paper §IV-C.1.

    ``k1`` pure rotations (``h = 0``) about uniformly random axes ``ω`` through
    centers uniform in a ball of radius ``radius_factor * l_s`` around ``o``,
    then ``k2`` pure translations with uniformly random directions.  seed, radius_factor:
    default ``config.DEFAULTS.seed``, ``.twist_radius_factor`` (read now).
    Returns (k1 + k2, 6).
    """
    k1, k2 = _count("k1", k1, 0), _count("k2", k2, 0)
    seed = config.DEFAULTS.seed if seed is None else seed
    radius_factor = (
        config.DEFAULTS.twist_radius_factor
        if radius_factor is None
        else config.check_value("twist_radius_factor", radius_factor, "radius_factor")
    )
    rng = _rng(seed)
    w = _uniform_sphere(rng, k1)
    c = _uniform_ball(rng, k1, radius_factor * _length(length_scale))
    rot = twists_from_plucker(w, np.cross(c, w), np.zeros(k1)) if k1 else np.zeros((0, 6))
    trans = translation_twists(_uniform_sphere(rng, k2)) if k2 else np.zeros((0, 6))
    return np.vstack([rot, trans])


def canonical_twists() -> np.ndarray:
    """The six axis twists ``e_1..e_6`` (translations along / rotations about
    the axes through ``o``), shape (6, 6).

    Why they give ``w_max`` exactly: the set ``W`` of transmissible frictional
    wrenches is the Minkowski sum over elements of ``μ p_i a_i [t; r_i × t]``
    with ``t`` in the element's tangent unit disc, so ``W = -W``.  Maximum
    dissipation selects ``w(ξ) = argmin_{w∈W} ξ·w`` — exactly Eqs. 3.6–3.8,
    each element opposing its own slip.  Hence ``ξ·w(ξ) = -h_W(ξ)`` with
    ``h_W`` the support function, and for ``ξ = e_i``
    ``max_{w∈W} |w_i| = h_W(e_i) = -w(e_i)_i``.  Sampled maxima can only
    under-estimate this value.
    """
    return np.eye(6)

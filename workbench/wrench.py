"""Public wrappers of the 6D frictional-wrench (6DFW) and normal-wrench kernels.

All wrenches are ``[f_x, f_y, f_z, τ_x, τ_y, τ_z]`` acting **on the object**,
torques about the pressure center ``o`` of the profile (CONVENTIONS.md).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _kernels, config
from .kernel_launch import launch
from .profile import ContactProfile
from .twists import canonical_twists


def check_twists(twists: Any) -> tuple[np.ndarray, bool]:
    """Validate twists (finite, nonzero rows); returns a C-contiguous (K, 6) float64 array
    and whether the input was a single (6,) twist."""
    try:
        xi = np.asarray(twists, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f"twists must be a numeric (K, 6) array; got {type(twists).__name__} ({exc})"
        ) from None
    single = xi.ndim == 1
    if single:
        xi = xi[None, :]
    if xi.ndim != 2 or xi.shape[1] != 6:
        raise ValueError(
            f"twists must have shape (K, 6) ([v_x, v_y, v_z, ω_x, ω_y, ω_z] per row) or (6,); "
            f"got {np.shape(twists)} — transpose a (6, K) array"
        )
    bad = ~np.isfinite(xi)
    if bad.any():
        row = int(np.argwhere(bad)[0][0])
        raise ValueError(f"twists must be finite; row {row} has NaN/inf")
    zero = ~xi.any(axis=1)
    if zero.any():
        # a twist is a slip direction: all zeros is no motion, whose friction is undefined
        row = int(np.argmax(zero))
        raise ValueError(
            f"twists must be nonzero slip directions; row {row} is all zeros (no motion has no "
            "friction wrench) — drop it, or sample unit twists (workbench.twists.sample_twists_thesis)"
        )
    return np.ascontiguousarray(xi), single


def check_mu(mu: Any, *, what: str | None = None) -> float:
    """A friction coefficient as a float: its plausible range ``[0, 2]`` (one rule,
    :data:`workbench.plausible.RANGES` ``"mu"``: 30 is refused as a percentage, 1.8 warned).
    ``what``: name of a result that needs friction (e.g. "a limit surface"); then μ must be > 0."""
    from .plausible import check

    if isinstance(mu, np.ndarray) and mu.shape == ():
        mu = mu.item()
    if isinstance(mu, str):  # a numeric string ("0.5" from a file) is that number, here and everywhere
        try:
            mu = float(mu)
        except ValueError:
            raise ValueError(f"mu must be a friction coefficient (a number); got {mu!r}") from None
    mu_f = check("mu", mu, "mu")
    if what is not None and mu_f == 0:
        raise ValueError(
            f"mu = 0 has no friction wrench, so there is no {what} to compute; pass the contact's "
            "friction coefficient mu > 0 (normalised wrenches do not depend on its value, e.g. 1.0)"
        )
    return mu_f


def _check_profile(profile: Any) -> ContactProfile:
    if not isinstance(profile, ContactProfile):
        raise ValueError(
            f"profile must be a ContactProfile; got {type(profile).__name__} "
            "— build one with ContactProfile(centers, normals, areas, pressures)"
        )
    return profile


def frictional_wrenches(profile: ContactProfile, twists: Any, mu: float = 1.0) -> np.ndarray:
    """6D frictional wrenches for a batch of twists, Eqs. 3.6–3.8.

    profile : ContactProfile with N elements.
    twists : (K, 6) float, ``[v; ω]`` about ``profile.pressure_center``
        (unit twists per Eq. 2.30, though any magnitude gives the same wrench
        since Coulomb friction depends only on slip direction); (6,) accepted.
    mu : float, friction coefficient.
    Returns (K, 6) (or (6,) for a single twist): the wrench the static jaw
    exerts on the moving object.  Elements whose tangential velocity vanishes
    (``|v_t| <= config.TOL.tangential_velocity_rtol |v|``) contribute exactly zero.
    """
    prof = _check_profile(profile)
    xi, single = check_twists(twists)
    out = _frictional_wrenches(prof, xi, check_mu(mu))
    return out[0] if single else out


def _frictional_wrenches(prof: ContactProfile, xi: np.ndarray, mu_f: float) -> np.ndarray:
    """:func:`frictional_wrenches` (K, 6) of checked inputs: twists xi (K, 6) C-contiguous float64,
    finite and nonzero (e.g. a sampler's own), mu_f a checked float."""
    k = xi.shape[0]
    out = np.empty((k, 6))
    rtol2 = config.TOL.tangential_velocity_rtol**2
    # a batch is K segments (one per twist) spanning all N elements
    lo = np.zeros(k, dtype=np.int64)
    hi = np.full(k, len(prof), dtype=np.int64)
    launch(
        _kernels._fw_segments,
        k * len(prof),
        *(xi, np.arange(k, dtype=np.int64), lo, hi, *prof._soa, mu_f, rtol2, out),
    )
    return out


def normal_wrench(profile: ContactProfile) -> np.ndarray:
    """(6,) normal wrench ``w⊥ = -Σ p a [n; (c - o) × n]`` about ``o``, Eq. 3.2."""
    prof = _check_profile(profile)
    out = np.empty(6)
    _kernels._normal_wrench(*prof._soa, out)
    return out


def w_max(profile: ContactProfile, mu: float = 1.0) -> np.ndarray:
    """(6,) exact maximal wrench magnitudes per axis (support function).

    ``w_max,i = -w(e_i)_i`` for the canonical twists (see
    :func:`workbench.twists.canonical_twists` for why this is exact).
    """
    w = frictional_wrenches(profile, canonical_twists(), mu)
    return -np.diag(w) + 0.0  # + 0.0 turns -0.0 (mu = 0) into 0.0


def friction_directions(profile: ContactProfile, twist: Any) -> np.ndarray:
    """(n, 3) unit directions ``-v̂_r`` of the local friction force on the object
    for one twist (Eq. 3.6), zero at sticking elements.  For plotting (Fig 3.3);
    ``-μ Σ p a d`` equals the force part of :func:`frictional_wrenches`."""
    prof = _check_profile(profile)
    xi, single = check_twists(twist)
    if not single and xi.shape[0] != 1:
        raise ValueError(f"friction_directions takes one twist (6,); got {xi.shape}")
    v, w = xi[0, :3], xi[0, 3:]
    u = v + np.cross(w, prof.centers - prof.pressure_center)
    t = u - np.einsum("ij,ij->i", u, prof.normals)[:, None] * prof.normals
    tn = np.linalg.norm(t, axis=1)
    slip = tn > config.TOL.tangential_velocity_rtol * np.linalg.norm(u, axis=1)
    return -np.where(slip[:, None], t / np.where(slip, tn, 1.0)[:, None], 0.0)

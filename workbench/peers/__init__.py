"""Peer contact models as adapters, each giving for one contact case a
:class:`~workbench.profile.ContactProfile` (or, for a point-contact friction model, its 6D wrench-set
description) to compare with our FEM (issue 16):

- :mod:`.hertz` — analytic Hertz sphere on an elastic half-space;
- :mod:`.elastic_foundation` — the Winkler soft finger of GraspIt! (Ciocarlie et al. 2007);
- :mod:`.mujoco_cone` — MuJoCo's ``condim=6`` elliptic friction cone (the documented formula);
- :mod:`.drake_hydro` — Drake's hydroelastic contact (needs ``pydrake``: extra ``peers``).

Import the modules themselves (``from workbench.peers.hertz import hertz_profile``): this package
only holds the validators they share, each returning a plain float (or int) or raising
``ValueError`` naming what was expected, what came and the fix (STYLE.md).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..units import check_extent

__all__ = ["MODULUS_RANGE_PA", "count", "depth", "friction", "length", "modulus", "poisson", "real"]

#: plausible Young's / hydroelastic moduli [Pa]: soft gels (~1 kPa) to steel (2e11 Pa).  A
#: modulus outside was almost surely given in another unit (1 MPa passed as 1.0).
MODULUS_RANGE_PA = (1.0e2, 1.0e12)


def real(name: str, value: Any, unit: str) -> float:
    """``value`` as a finite float, or ValueError."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number [{unit}]; got {value!r}") from None
    if not np.isfinite(x):
        raise ValueError(f"{name} must be finite [{unit}]; got {x} — pass a finite value in {unit}")
    return x


def length(name: str, value: Any) -> float:
    """A positive length [m] of an object or pad (radius, thickness, side), with the unit check
    of :func:`workbench.units.check_extent` on it (a radius of 20 reads as 20 m, not 20 mm)."""
    x = real(name, value, "m")
    if x <= 0:
        raise ValueError(f"{name} must be a positive length [m]; got {x}")
    check_extent(
        x,
        name,
        check_lower=False,
        fix="give it in metres (20 mm = 0.02; scale by {factor:g})",
        override=None,
    )
    return x


def depth(name: str, value: Any, *, below: float, below_name: str) -> float:
    """A penetration / approach depth [m]: finite, > 0 and < ``below`` [m] (a length it must stay
    under, e.g. the sphere radius or the layer thickness, named ``below_name``)."""
    x = real(name, value, "m")
    if x <= 0:
        raise ValueError(
            f"{name} must be a positive depth [m]; got {x} — the bodies must overlap "
            "(a negative depth is a gap: no contact, nothing to model)"
        )
    if x >= below:
        raise ValueError(
            f"{name} = {x!r} m is not below {below_name} = {below!r} m: depths are in metres "
            f"(1 mm = 1e-3) and must stay small against {below_name}"
        )
    return x


def sphere(R: Any, delta: Any, delta_name: str) -> tuple[float, float]:
    """A rigid sphere's radius ``R`` [m] and its depth ``delta`` [m] into the layer (named
    ``delta_name`` in errors), checked by :func:`length` and :func:`depth` (below ``R``)."""
    r = length("R (sphere radius)", R)
    return r, depth(delta_name, delta, below=r, below_name="the sphere radius R")


def modulus(name: str, value: Any) -> float:
    """An elastic modulus [Pa] within :data:`MODULUS_RANGE_PA`."""
    x = real(name, value, "Pa")
    lo, hi = MODULUS_RANGE_PA
    if not lo <= x <= hi:
        raise ValueError(
            f"{name} must be a modulus in Pa within [{lo:g}, {hi:g}]; got {x!r} — moduli are in "
            "pascals (1 MPa = 1e6, silicone ~0.1-5e6)"
        )
    return x


def poisson(name: str, value: Any) -> float:
    """A Poisson ratio in (-1, 0.5)."""
    x = real(name, value, "-")
    if not -1.0 < x < 0.5:
        raise ValueError(f"{name} must be a Poisson ratio in (-1, 0.5); got {x} — for silicone use e.g. 0.45")
    return x


def count(name: str, value: Any, minimum: int) -> int:
    """An integer >= ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an int >= {minimum}; got {value!r} ({type(value).__name__})")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}; got {value}")
    return int(value)


def friction(name: str, value: Any) -> float:
    """A Coulomb friction coefficient, finite and > 0."""
    x = real(name, value, "-")
    if x <= 0:
        raise ValueError(f"{name} must be a friction coefficient > 0; got {x}")
    return x

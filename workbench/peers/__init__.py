"""Peer contact models as adapters, each giving for one contact case a
:class:`~workbench.profile.ContactProfile` (or, for a point-contact friction model, its 6D wrench-set
description) to compare with our FEM:

- :mod:`.hertz` — analytic Hertz sphere on an elastic half-space;
- :mod:`.elastic_foundation` — the Winkler soft finger of GraspIt! (Ciocarlie et al. 2007);
- :mod:`.mujoco_cone` — MuJoCo's ``condim=6`` elliptic friction cone (the documented formula);
- :mod:`.drake_hydro` — Drake's hydroelastic contact (needs ``pydrake``: extra ``peers``).

Import the modules themselves (``from workbench.peers.hertz import hertz_profile``): this package
only holds the validators they share, each returning a plain float (or int) or raising
``ValueError`` naming what was expected, what came and the fix (STYLE.md).  Each physical
quantity is judged by the library's one rule of it, so a peer and the core answer alike: μ by
:func:`workbench.wrench.check_mu`; a pad's modulus, Poisson ratio, thickness, side, element size
and compression by :func:`workbench.plausible.check`; an object's size by
:func:`workbench.units.check_extent` (the rule of a ``ContactProfile``'s size).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import config
from ..units import check_extent

__all__ = ["count", "depth", "friction", "length", "modulus", "poisson", "real"]


def real(name: str, value: Any, unit: str) -> float:
    """``value`` as a finite float (a numeric string too, not a bool), or ValueError."""
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(
            f"{name} must be a real number [{unit}]; got {value!r} (a bool is a slip, not a number)"
        )
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number [{unit}]; got {value!r}") from None
    if not np.isfinite(x):
        raise ValueError(f"{name} must be finite [{unit}]; got {x} — pass a finite value in {unit}")
    return x


def _plausible(key: str, name: str, x: float, note: str = "") -> float:
    """``x`` judged by :func:`workbench.plausible.check` as a ``key`` quantity named ``name``;
    ``note`` (a reminder of the unit) is added to its message."""
    from ..plausible import check

    try:
        return check(key, x, name)
    except ValueError as exc:
        if not note:
            raise
        raise ValueError(f"{exc} — {note}") from None


def _swap_hint(x: float, role: str) -> str:
    """A clause for the message of a refused length ``x`` [m] the size of a modulus (at or above
    the smallest plausible pad modulus, 1 kPa — as a length 1 km) or a refused modulus [Pa] the
    size of a length (at most ``TOL.max_object_extent_m``): the arguments may be swapped
    (``hertz_force(E, nu, R, delta)`` for ``hertz_force(R, delta, E, nu)``), which the unit
    reading alone would not say.  "" otherwise."""
    from ..plausible import RANGES

    lo, limit = RANGES["pad_modulus"].lower(), config.TOL.max_object_extent_m
    if (role == "length" and x >= lo) or (role == "modulus" and 0 < x <= limit):
        kind = "a modulus [Pa]" if role == "length" else "a length [m]"
        return (
            f" — or arguments swapped: {x:g} is the size of {kind}; the peers take lengths in metres "
            "and moduli in pascals in the order of their signature"
        )
    return ""


def _with_swap_hint(x: float, role: str, check, *args, **kwargs):
    """``check(*args, **kwargs)``, its ValueError extended by :func:`_swap_hint`."""
    try:
        return check(*args, **kwargs)
    except ValueError as exc:
        hint = _swap_hint(x, role)
        if not hint:
            raise
        raise ValueError(f"{exc}{hint}") from None


def length(name: str, value: Any, quantity: str | None = None) -> float:
    """A positive length [m].

    quantity : the :data:`workbench.plausible.RANGES` quantity it is (``"pad_thickness"`` for a
        layer's thickness, ``"pad_size"`` for a pad's side, ``"element_size"`` for a grid's
        spacing): judged by that rule.  None: the size of an object or of a contact patch (a
        sphere's radius, a cylinder's length), judged by :func:`workbench.units.check_extent`
        as a ``ContactProfile``'s size is (a radius of 20 reads as 20 m, not 20 mm).

    A refused length the size of a modulus also names a swap of arguments (:func:`_swap_hint`),
    a depth's too (:func:`depth`)."""
    x = real(name, value, "m")
    if x <= 0:
        raise ValueError(f"{name} must be a positive length [m]; got {x}")
    if quantity is not None:
        return _with_swap_hint(x, "length", _plausible, quantity, name, x)
    _with_swap_hint(
        x,
        "length",
        check_extent,
        x,
        name,
        check_lower=False,
        fix="give it in metres (20 mm = 0.02; scale by {factor:g})",
        override=None,
    )
    return x


def depth(name: str, value: Any, *, below: float, below_name: str) -> float:
    """A penetration / approach depth [m]: finite, > 0 and < ``below`` [m] (a length it must stay
    under, e.g. the sphere radius or the layer thickness, named ``below_name``), and a plausible
    pad compression (:func:`compression`)."""
    x = real(name, value, "m")
    if x <= 0:
        raise ValueError(
            f"{name} must be a positive depth [m]; got {x} — the bodies must overlap "
            "(a negative depth is a gap: no contact, nothing to model)"
        )
    if x >= below:
        raise ValueError(
            f"{name} = {x!r} m is not below {below_name} = {below!r} m: depths are in metres "
            f"(1 mm = 1e-3) and must stay small against {below_name}" + _swap_hint(x, "length")
        )
    return compression(name, x)


def compression(name: str, x: float) -> float:
    """A depth ``x`` [m] >= 0 a pad is pressed by, judged as the ``"compression"`` quantity of
    :data:`workbench.plausible.RANGES` (a pad pressed 20 mm deep was given in another unit)."""
    return _plausible("compression", name, x, "depths are in metres (1 mm = 1e-3)")


def sphere(R: Any, delta: Any, delta_name: str) -> tuple[float, float]:
    """A rigid sphere's radius ``R`` [m] and its depth ``delta`` [m] into the layer (named
    ``delta_name`` in errors), checked by :func:`length` and :func:`depth` (below ``R``)."""
    r = length("R (sphere radius)", R)
    return r, depth(delta_name, delta, below=r, below_name="the sphere radius R")


def modulus(name: str, value: Any) -> float:
    """An elastic modulus [Pa] of a pad (a Young's or a hydroelastic modulus), judged as the
    ``"pad_modulus"`` quantity of :data:`workbench.plausible.RANGES`; a length passed in its
    place is refused naming a swap of arguments as well as the unit (:func:`_swap_hint`)."""
    x = real(name, value, "Pa")
    return _with_swap_hint(
        x,
        "modulus",
        _plausible,
        "pad_modulus",
        name,
        x,
        "moduli are in pascals (1 MPa = 1e6, silicone ~0.1-5e6)",
    )


def poisson(name: str, value: Any) -> float:
    """A Poisson ratio in (-1, 0.5): the ``"poisson"`` quantity of :data:`workbench.plausible.RANGES`."""
    return _plausible("poisson", name, real(name, value, "-"))


def count(name: str, value: Any, minimum: int) -> int:
    """An integer >= ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an int >= {minimum}; got {value!r} ({type(value).__name__})")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}; got {value}")
    return int(value)


def friction(value: Any, result: str) -> float:
    """A Coulomb friction coefficient > 0 by the one rule of μ (:func:`workbench.wrench.check_mu`:
    its plausible range, 50 refused as a percentage); ``result``: what needs friction, named when
    μ = 0 ("a torsion capacity")."""
    from ..wrench import check_mu

    return check_mu(value, what=result)

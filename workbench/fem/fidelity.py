"""One interface to the three fidelity levels of the pad contact.

``fidelity="condensed"``: linear pad condensed to its face (milliseconds per
solve after a cached precompute); ``"linear"``: the same frictionless Signorini
problem on the full mesh (the exactness check of the condensed level);
``"nonlinear"``: neo-Hookean layer with augmented-Lagrangian contact and load
stepping (the accuracy reference at 20-60% layer compression).  All return
:class:`workbench.fem.contact.ContactSolution` per jaw displacement on the same face
nodes, collected in a :class:`Pressed` that also holds the pad and the obstacle,
so a profile is one call away::

    from workbench.fem import press
    res = press(PadGeometry(), Material(), obstacle, [1e-3, 2e-3])
    prof = res.profile(2e-3)   # == extract_profile(res.pad, res[2e-3], res.obstacle)
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .contact import ContactSolution, face_gaps, solve_contact, solve_contact_full
from .material import Material
from .pad import PadFace, PadGeometry, condense_pad

FIDELITIES = ("condensed", "linear", "nonlinear")


class Pressed(dict):
    """``{delta [m]: ContactSolution}`` (a plain dict, increasing ``delta``) plus what
    :func:`workbench.fem.extract.extract_profile` needs: ``pad`` (the
    :class:`~workbench.fem.pad.CondensedPad`, :class:`~workbench.fem.nonlinear.NonlinearPad` or, for
    ``fidelity="linear"``, the :class:`~workbench.fem.pad.PadFace`), ``obstacle`` and ``fidelity``.
    """

    def __init__(self, solutions: dict[float, ContactSolution], pad: Any, obstacle: Any, fidelity: str):
        super().__init__(solutions)
        self.pad = pad
        self.obstacle = obstacle
        self.fidelity = fidelity

    def profile(self, delta: float):
        """The contact profile at jaw displacement ``delta`` (a key of this dict), or
        ``None`` if nothing touches; ``profile.F == self[delta].force``."""
        from .extract import extract_profile

        key = float(delta)
        if key not in self:
            raise ValueError(
                f"no solution at delta = {delta!r} m; solved displacements are {sorted(self)} "
                "— pass one of them (or press again with this delta)"
            )
        return extract_profile(self.pad, self[key], self.obstacle)

    def profiles(self) -> dict:
        """``{delta: ContactProfile | None}`` for every solved displacement."""
        return {d: self.profile(d) for d in self}


def press(
    geometry: PadGeometry,
    material: Material,
    obstacle,
    deltas,
    *,
    fidelity: str = "condensed",
    cache_dir: str | Path | bool | None = None,
    **options,
) -> Pressed:
    """Press the pad into ``obstacle`` by each jaw displacement in ``deltas`` [m].

    Returns a :class:`Pressed`: the dict ``{delta: ContactSolution}`` with ``.pad``
    and ``.obstacle``; ``press(...).profile(delta)`` is the contact profile
    (:func:`workbench.fem.extract.extract_profile`), whose ``F`` equals the solved ``Σ λ``.

    cache_dir : the condensed level's compliance cache (:func:`workbench.fem.pad.condense_pad`:
        ``None`` the default user cache, a path, or ``False`` for none).
    options : passed to the level's solver (e.g. ``scheme`` for the linear levels,
        ``stabilization``/``step`` for the nonlinear one).

    Raises ``ValueError`` before any pad is built for displacements that are not plausible
    compressions below the layer thickness, for a :class:`~.obstacles.Plane` whose normal does
    not face the pad (:func:`~.contact.check_plane_faces_pad`) and for an obstacle reaching deeper
    than the layer at the largest displacement (:func:`~.contact.face_gaps`; the pad's face is at
    ``z = h``: a plane pressed from first touch is ``Plane(point=(0, 0, h))``).
    """
    if fidelity not in FIDELITIES:
        raise ValueError(f"fidelity must be one of {FIDELITIES}; got {fidelity!r}")
    from workbench.plausible import check_each

    given = np.atleast_1d(np.asarray(deltas, dtype=object)).tolist()  # one displacement or several
    deltas = sorted(float(d) for d in check_each("compression", given, "deltas (jaw displacements [m])"))
    if not deltas:
        raise ValueError("deltas is empty: give at least one jaw displacement [m]")
    if deltas[-1] >= geometry.thickness:
        # the jaw cannot advance by the layer's whole thickness past first touch: the rigid
        # back would hit the obstacle (a δ in millimetres, 1.0 for 1 mm, lands here and
        # otherwise moves the jaw through the obstacle: zero force, no error)
        raise ValueError(
            f"jaw displacement {deltas[-1]!r} m is not below the layer thickness h = "
            f"{geometry.thickness} m: displacements are in metres (1 mm = 1e-3)"
        )
    # before a pad is built: a flipped plane presses nothing, an obstacle placed inside the layer
    # (Plane()'s default point, the pad's back) would hit the rigid back
    x, y, _ = geometry.axes()
    _, gaps, _ = face_gaps(geometry, np.array(np.meshgrid(x, y)).reshape(2, -1).T, obstacle, deltas[-1])
    if gaps.min() > 0:
        # the face advanced by the largest delta still misses the obstacle: every force is 0 N
        raise ValueError(
            f"the obstacle is {gaps.min():.3g} m beyond the pad's face even at the largest jaw "
            f"displacement {deltas[-1]:.3g} m: nothing is pressed (0 N) — place it touching the face "
            f"(in the pad frame the face is at z = h = {geometry.thickness:g} m) or give larger deltas"
        )
    if fidelity == "nonlinear":
        from .nonlinear import NonlinearPad

        stab = options.pop("stabilization", 1.0)
        pad = NonlinearPad(geometry, material, stabilization=stab)
        return Pressed(pad.solve(obstacle, deltas, **options), pad, obstacle, fidelity)
    scheme = options.pop("scheme", "sri")
    if options:
        raise ValueError(f"unknown options for fidelity {fidelity!r}: {sorted(options)}")
    if fidelity == "linear":
        sols = {d: solve_contact_full(geometry, material, obstacle, d, scheme=scheme) for d in deltas}
        return Pressed(sols, PadFace.of(geometry, material), obstacle, fidelity)
    pad = condense_pad(geometry, material, scheme=scheme, cache_dir=cache_dir)
    out, prev = {}, None
    for d in deltas:
        out[d] = prev = solve_contact(pad, obstacle, d, warm=prev)
    return Pressed(out, pad, obstacle, fidelity)

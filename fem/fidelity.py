"""One interface to the three fidelity levels of the pad contact (issue scope 3).

``fidelity="condensed"``: linear pad condensed to its face (milliseconds per
solve after a cached precompute); ``"linear"``: the same frictionless Signorini
problem on the full mesh (the exactness check of the condensed level);
``"nonlinear"``: neo-Hookean layer with augmented-Lagrangian contact and load
stepping (the accuracy reference at 20-60% layer compression).  All return
:class:`fem.contact.ContactSolution` per jaw displacement on the same face
nodes, so :func:`fem.extract.extract_profile` turns any of them into a profile.
"""

from __future__ import annotations

from pathlib import Path

from .contact import ContactSolution, solve_contact, solve_contact_full
from .material import Material
from .pad import PadGeometry, condense_pad

FIDELITIES = ("condensed", "linear", "nonlinear")


def press(
    geometry: PadGeometry,
    material: Material,
    obstacle,
    deltas,
    *,
    fidelity: str = "condensed",
    cache_dir: str | Path | None = None,
    **options,
) -> dict[float, ContactSolution]:
    """Press the pad into ``obstacle`` by each jaw displacement in ``deltas`` [m].

    options : passed to the level's solver (e.g. ``scheme`` for the linear levels,
        ``stabilization``/``step`` for the nonlinear one).
    """
    if fidelity not in FIDELITIES:
        raise ValueError(f"fidelity must be one of {FIDELITIES}; got {fidelity!r}")
    deltas = sorted(float(d) for d in deltas)
    if not deltas:
        raise ValueError("deltas is empty: give at least one jaw displacement [m]")
    if fidelity == "nonlinear":
        from .nonlinear import NonlinearPad

        stab = options.pop("stabilization", 1.0)
        return NonlinearPad(geometry, material, stabilization=stab).solve(obstacle, deltas, **options)
    scheme = options.pop("scheme", "sri")
    if options:
        raise ValueError(f"unknown options for fidelity {fidelity!r}: {sorted(options)}")
    if fidelity == "linear":
        return {d: solve_contact_full(geometry, material, obstacle, d, scheme=scheme) for d in deltas}
    pad = condense_pad(geometry, material, scheme=scheme, cache_dir=cache_dir)
    out, prev = {}, None
    for d in deltas:
        out[d] = prev = solve_contact(pad, obstacle, d, warm=prev)
    return out

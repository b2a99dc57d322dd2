"""One peer's contact against the reference's at one depth: the errors of its jaw force, contact
area, pressure field, torsion length and 6DFW supports, and the resistance margins of the two-jaw
grasp each peer's contact makes, built from the measures of :mod:`workbench.peers.metrics`.

A peer's *row* is ``{"profile", "area" [m²], "field"}`` (a contact profile; ``field`` is
``("nodes", face_xy (n, 2), p_node (n,))`` for a FEM pad's nodal pressures or ``("elements",)``
for the profile's own) or ``{"profile": None, "coefficients" (5,)}`` for MuJoCo's point contact
(:func:`workbench.peers.mujoco_cone.patch_coefficients`): :func:`fem_row`, :func:`hertz_row`,
:func:`profile_row`.  The reference's measures are :func:`reference_measures`; the margins of
every peer at the reference's jaw force, :func:`equal_force_margins`.
"""

from __future__ import annotations

import numpy as np

from .. import peers as _checks
from ..profile import ContactProfile
from . import metrics

__all__ = [
    "DISTURBANCE_FORCE_N",
    "compare",
    "contact_area",
    "equal_force_jaws",
    "equal_force_margins",
    "fem_row",
    "grasp_margins",
    "hertz_row",
    "profile_row",
    "reference_measures",
]

#: :func:`equal_force_margins` scales the lever disturbances by jaw force / this [N]: at 25 N of
#: jaw force they are §4.1.3.1's weights as drawn
DISTURBANCE_FORCE_N = 25.0


def fem_row(pad, area0: np.ndarray, sol, prof: ContactProfile) -> dict:
    """A linear FEM peer's row: its profile, the tributary area ``area0`` (n_face,) [m²] of its
    loaded face nodes (``sol.lam > 0``) and its nodal pressure field."""
    from ..fem.extract import nodal_pressures

    return {
        "profile": prof,
        "area": float(area0[sol.lam > 0].sum()),
        "field": ("nodes", pad.face_xy, nodal_pressures(pad, sol.lam)),
    }


def contact_area(profile: ContactProfile) -> float:
    """The loaded area [m²] of a contact profile: the areas of its elements with pressure > 0 (a
    profile may carry unloaded elements, e.g. Drake's rim, whose round-off pressure is clipped to 0)."""
    return float(profile.areas[profile.pressures > 0].sum())


def profile_row(profile: ContactProfile) -> dict:
    """A peer's row from its contact profile alone (the Winkler foundation, Drake): the profile,
    its :func:`contact_area` [m²] and its own element pressures as the field."""
    return {"profile": profile, "area": contact_area(profile), "field": ("elements",)}


def hertz_row(profile: ContactProfile, R: float, delta: float) -> dict:
    """The Hertz peer's row (a rigid sphere of radius ``R`` [m] pressed ``delta`` [m] into the
    half-space): its profile, the contact area ``π a² = π R δ`` [m²] (``a = √(R δ)``,
    :func:`workbench.peers.hertz.hertz_contact_radius`) and the profile's element pressures."""
    r, d = _checks.sphere(R, delta, "delta (approach)")
    return {"profile": profile, "area": float(np.pi * r * d), "field": ("elements",)}


def reference_measures(row: dict, face_xy: np.ndarray, grid: np.ndarray, mu: float) -> dict:
    """The reference's measures at one δ from its solve ``row`` (``{"profile", "area", "p_node"}``
    of :func:`workbench.peers.pad_cases.reference_case`, nodal pressures on ``face_xy`` (n, 2)):
    ``{"force_N", "area" [m²], "field" (g,) [Pa] on ``grid`` (g, 2), "torsion_length" [m],
    "supports" (6,)}``."""
    return {
        "force_N": metrics.jaw_force(row["profile"]),
        "area": row["area"],
        "field": metrics.field_from_nodes(face_xy, row["p_node"], grid),
        "torsion_length": metrics.torsion_length(row["profile"], mu),
        "supports": metrics.supports(row["profile"], mu),
    }


def _contact_errors(row: dict, ref: dict, grid: np.ndarray) -> dict:
    """Force, area and pressure-field errors of a peer with a contact profile."""
    prof = row["profile"]
    out = {}
    out["force_N"] = metrics.jaw_force(prof)
    out["force_rel_err"] = out["force_N"] / ref["force_N"] - 1
    out["area_mm2"] = row["area"] * 1e6
    out["area_rel_err"] = row["area"] / ref["area"] - 1
    kind, *args = row["field"]
    p = (
        metrics.field_from_nodes(args[0], args[1], grid)
        if kind == "nodes"
        else metrics.field_from_elements(prof, grid)
    )
    out["pressure_rel_l2"] = metrics.rel_l2(p, ref["field"])
    return out


def compare(row: dict, ref: dict, grid: np.ndarray, mu: float) -> dict:
    """One peer's errors at one δ against the reference's measures ``ref``
    (:func:`reference_measures`), the pressure field compared on ``grid`` (g, 2) [m]:
    ``force_N``, ``force_rel_err``, ``area_mm2``, ``area_rel_err``, ``pressure_rel_l2`` (None for
    MuJoCo: a wrench set only), ``torsion_length_mm``, ``torsion_rel_err``, ``torque_rel_err``
    (μ × jaw force × torsion length), ``support_rel_err`` (6,) (None where the reference's support
    is below 1e-3 of its group's largest) and ``support_max_rel_err``."""
    prof = row.get("profile")
    if prof is not None:
        out = _contact_errors(row, ref, grid)
        sup = metrics.supports(prof, mu)
        tl = metrics.torsion_length(prof, mu)
    else:  # MuJoCo: a wrench set only
        out = {}
        sup = metrics.cone_supports(row["coefficients"])
        tl = float(row["coefficients"][2] / mu)
        for k in ("force_N", "force_rel_err", "area_mm2", "area_rel_err", "pressure_rel_l2"):
            out[k] = None
    out["torsion_length_mm"] = tl * 1e3
    out["torsion_rel_err"] = tl / ref["torsion_length"] - 1
    # the torque the contact resists at this δ: μ × jaw force × torsion length (no force: None)
    f = out["force_rel_err"]
    out["torque_rel_err"] = None if f is None else (1 + f) * (1 + out["torsion_rel_err"]) - 1
    # forces [N/N] and torques [m] each against their own group's largest
    ok = ref["supports"] > 1e-3 * metrics.group_max(ref["supports"])
    rel = np.where(ok, sup / np.where(ok, ref["supports"], 1.0) - 1, np.nan)
    out["support_rel_err"] = [None if not np.isfinite(v) else float(v) for v in rel]
    out["support_max_rel_err"] = float(np.nanmax(np.abs(rel)))
    return out


def _resists(spec: dict, center: np.ndarray, mu: float, seed: int):
    """``fn(w) -> bool``: whether the two-jaw grasp of one peer's jaw ``spec`` resists ``w``."""
    from ..grasp import resists
    from ..grasp.contacts import soft_point_contact
    from ..grasp.exact import ExactContacts, resists_exact

    if spec["kind"] == "profile":
        ec = ExactContacts(metrics.opposed_jaws(spec["profile"], center), seed=seed)
        return lambda v, ec=ec: resists_exact(ec, v, mu)[0]
    p = metrics.PAD_TO_GRASP @ (spec["point"] - center)
    q = np.array([-p[0], -p[1], p[2]])
    tl = spec["coefficients"][2] / mu
    sets = [
        soft_point_contact(p, [-1.0, 0.0, 0.0], spec["force"], tl, n_edges=32),
        soft_point_contact(q, [1.0, 0.0, 0.0], spec["force"], tl, n_edges=32),
    ]
    return lambda v, sets=sets: bool(resists(sets, v, mu))


def grasp_margins(
    jaws_by_peer: dict,
    center: np.ndarray,
    mu: float,
    *,
    seed: int,
    n_disturbances: int,
    steps: int,
    scale: float,
) -> dict:
    """Resistance margins (:func:`workbench.grasp.margin.resistance_margin`, ``steps`` bisection
    steps) of each peer's two-jaw grasp against the same ``n_disturbances`` lever disturbances
    (:func:`workbench.grasp.tasks.lever_disturbances`, thesis §4.1.3.1, drawn with ``seed`` and
    scaled by ``scale``): ``{peer: (n_disturbances,) margins}``.

    jaws_by_peer : ``{peer: {"kind": "profile", "profile"}}`` (the jaw's contact, opposed by its
        mirror image about the object's ``center`` (3,) [m], exact 6DFW sets) or ``{"kind": "cone",
        "coefficients" (5,), "force" [N], "point" (3,)}`` (MuJoCo: a soft point contact per jaw).
    """
    from ..grasp.margin import resistance_margin
    from ..grasp.tasks import lever_disturbances

    W = lever_disturbances(np.random.default_rng(seed), n_disturbances) * scale
    out = {}
    for peer, spec in jaws_by_peer.items():
        fn = _resists(spec, center, mu, seed)
        out[peer] = np.array([resistance_margin(fn, w, steps) for w in W])
    return out


def equal_force_jaws(rows: dict, ref_profile: ContactProfile, force: float) -> dict:
    """Each peer's jaw for :func:`grasp_margins` at the jaw force ``force`` [N] (the sensor reads
    it, so every peer is compared at one): a peer with a contact profile has its pressures scaled
    by ``force / jaw_force(profile)`` (:func:`workbench.peers.metrics.jaw_force`); MuJoCo's cone
    (a row of ``coefficients``) carries ``force`` at the reference profile's pressure centre.

    rows : ``{peer: row}`` as in the module docstring; returns ``{peer: jaw spec}`` in that order.
    """
    jaws = {}
    for peer, row in rows.items():
        if row.get("profile") is not None:
            p = row["profile"]
            jaws[peer] = {
                "kind": "profile",
                "profile": p.with_pressures(p.pressures * force / metrics.jaw_force(p)),
            }
        else:
            jaws[peer] = {
                "kind": "cone",
                "coefficients": row["coefficients"],
                "force": force,
                "point": ref_profile.pressure_center,
            }
    return jaws


def equal_force_margins(
    rows: dict,
    ref_profile: ContactProfile,
    center: np.ndarray,
    mu: float,
    *,
    seed: int,
    n_disturbances: int,
    steps: int,
) -> tuple[np.ndarray, dict]:
    """The resistance margins of the reference's grasp (the truth, exact 6DFW sets of
    ``ref_profile``) and of each peer's at the reference's jaw force ``f_ref``
    (:func:`equal_force_jaws`), against the same ``n_disturbances`` lever disturbances scaled by
    ``f_ref /`` :data:`DISTURBANCE_FORCE_N` (:func:`grasp_margins`, ``steps`` bisection steps,
    drawn with ``seed``; ``center`` (3,) [m] the object's centre).

    Returns ``(truth (n_disturbances,), {peer: (n_disturbances,) margins})``.
    """
    f_ref = metrics.jaw_force(ref_profile)
    # the truth first under a key no peer's name (a str) can take
    jaws = {None: {"kind": "profile", "profile": ref_profile}, **equal_force_jaws(rows, ref_profile, f_ref)}
    m = grasp_margins(
        jaws,
        center,
        mu,
        seed=seed,
        n_disturbances=n_disturbances,
        steps=steps,
        scale=f_ref / DISTURBANCE_FORCE_N,
    )
    truth = m.pop(None)
    return truth, m

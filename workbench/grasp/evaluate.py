"""One call from a mesh and an antipodal grasp to the verdict (thesis §4.1.4, §4.2).

:func:`evaluate_grasp` composes the pipeline a researcher would otherwise write out:

1. each jaw's contact profile from the mesh (:func:`~.reach.reach_profile`: the pad
   pressed ``closing`` past first touch, Winkler pressure), jaw 1 at ``p1``
   approaching along the grasp axis, jaw 2 at ``p2`` approaching against it;
2. both profiles scaled to the force-sensor reading along the grasp axis
   (:func:`~.reach.with_axis_force`, §4.1.3.2), after checking that each jaw
   *pushes* the object (a profile whose normals point into the object would pull);
3. the contact sets of the requested model only (:func:`~.models.contact_sets`:
   no quartic unless ``6dls_quartic``, no 6DFW sampling unless ``6dfw``/``3dls_nonplanar``,
   no GWS hull ever; limit surfaces through the given cache, so a repeated profile is
   not refitted);
4. :func:`~.resistance.resists`, and on request :func:`~.resistance.min_grasp_force`
   and :func:`~.robust.q_robust`, all with the same meaning of "resisted".
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from ..limit_surface import LimitSurfaceCache
from ..profile import ContactProfile
from .contacts import ContactSet
from .gws import check_mu, check_wrench
from .models import MODELS, contact_sets
from .reach import reach_profile, with_axis_force
from .resistance import CutStore, MinimalForce, Resistance, min_grasp_force, resists
from .robust import Perturbation, gravity_wrench, q_robust

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class GraspEvaluation:
    """What :func:`evaluate_grasp` found.

    resistance : the verdict for the task wrench (truthy iff resisted).
    min_force : the smallest grasp force (per-jaw reading × 2 for a two-jaw grasp is
        ``min_force.total``; the reading itself is ``force * min_force.scale``), or None.
    q_robust : fraction of perturbed samples resisted, or None.
    profiles : the two jaws' contact profiles at ``force``; contacts : the model's sets.
    timings_ms : wall time of each stage [ms].
    """

    model: str
    w_ext: np.ndarray
    resistance: Resistance
    min_force: MinimalForce | None
    q_robust: float | None
    profiles: list[ContactProfile] = field(repr=False)
    contacts: list[ContactSet] = field(repr=False)
    timings_ms: dict = field(default_factory=dict)

    @property
    def resisted(self) -> bool:
        return bool(self.resistance)


def jaw_profiles(
    mesh,
    grasp: dict,
    force: float,
    *,
    up=(0.0, 0.0, 1.0),
    pad: tuple[float, float] = (0.02, 0.04),
    closing: float = 1e-3,
    units: str | None = None,
    allow_scale: bool = False,
) -> list[ContactProfile]:
    """The two jaws' profiles of an antipodal ``grasp`` (a dict of
    :func:`~.sampling.antipodal_grasps`: ``p1``, ``p2``, ``axis`` from jaw 1 into the
    object), each scaled to ``force`` [N] along the grasp axis.  Raises ValueError when a
    jaw would pull the object (its net normal force points away from its approach)."""
    axis = np.asarray(grasp["axis"], float)
    axis = axis / np.linalg.norm(axis)
    out = []
    for point, approach in ((grasp["p1"], axis), (grasp["p2"], -axis)):
        prof = reach_profile(
            mesh, point, approach, up, pad=pad, closing=closing, units=units, allow_scale=allow_scale
        )
        # the jaw pushes the object along its approach: −Σ p a n · approach > 0
        push = float(prof.normal_wrench[:3] @ approach)
        if not push > 0:
            raise ValueError(
                f"the jaw at {np.round(point, 4).tolist()} would pull the object (net normal force "
                f"{push:.3g} N along its approach): the profile's normals point into the object, "
                "or the approach is reversed; normals must point out of the object (CONVENTIONS.md)"
            )
        out.append(with_axis_force(prof, axis, force))
    return out


def evaluate_grasp(
    mesh,
    grasp: dict,
    *,
    model: str = "6dls",
    force: float = 10.0,
    mu: float = 0.5,
    w_ext=None,
    mass: float | None = None,
    com=None,
    min_force: bool = True,
    robust: Perturbation | None = None,
    representation: str = "model",
    cache: LimitSurfaceCache | None = None,
    cuts: CutStore | None = None,
    profiles: list[ContactProfile] | None = None,
    up=(0.0, 0.0, 1.0),
    pad: tuple[float, float] = (0.02, 0.04),
    units: str | None = None,
    allow_scale: bool = False,
    seed: int = 0,
) -> GraspEvaluation:
    """Evaluate an antipodal grasp of ``mesh`` (metres) under contact model ``model``.

    grasp : one dict of :func:`~.sampling.antipodal_grasps` (``p1``, ``p2``, ``axis``).
    force : force-sensor reading of each jaw along the grasp axis [N] (§4.1.3.2).
    w_ext : the task wrench (6,) about the object origin; or ``mass`` [kg] and ``com``
        (3,) for holding against gravity (the thesis's lifting task).
    min_force : also solve the minimal grasp force (same model, ``objective="scale"``).
    robust : a :class:`Perturbation` to also compute ``q_robust`` (Eq. 2.101).
    profiles : the two jaws' profiles, if already computed (skips step 1–2).
    cache, cuts : reuse limit surfaces / cutting planes across calls (pass the same
        objects when evaluating many grasps).
    """
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}; got {model!r}")
    check_mu(mu)
    if not (np.isscalar(force) and np.isfinite(force) and force > 0):
        raise ValueError(f"force must be a positive grasp force [N]; got {force!r}")
    if w_ext is None:
        if mass is None or com is None:
            raise ValueError("give the task as w_ext (6,) or as mass [kg] and com (3,) [m]")
        w = gravity_wrench(mass, com)
    else:
        if mass is not None or com is not None:
            raise ValueError("give the task either as w_ext or as mass and com, not both")
        w = check_wrench(w_ext)
    cache = LimitSurfaceCache() if cache is None else cache
    cuts = CutStore() if cuts is None else cuts
    t = {}
    t0 = time.perf_counter()
    if profiles is None:
        profiles = jaw_profiles(mesh, grasp, force, up=up, pad=pad, units=units, allow_scale=allow_scale)
    t["profiles"] = (time.perf_counter() - t0) * 1e3
    t0 = time.perf_counter()
    contacts = [c for p in profiles for c in contact_sets(p, model, cache=cache, seed=seed)]
    t["contact_model"] = (time.perf_counter() - t0) * 1e3
    t0 = time.perf_counter()
    verdict = resists(contacts, w, mu, representation=representation, cuts=cuts)
    t["resists"] = (time.perf_counter() - t0) * 1e3
    mf = None
    if min_force:
        t0 = time.perf_counter()
        mf = min_grasp_force(contacts, w, mu, representation=representation, cuts=cuts)
        t["min_grasp_force"] = (time.perf_counter() - t0) * 1e3
    q = None
    if robust is not None:
        t0 = time.perf_counter()
        q = (
            q_robust(
                contacts,
                mu,
                1.0,
                np.zeros(3),
                robust,
                seed=seed,
                representation=representation,
                cuts=cuts,
                w_ext=w,
            )
            if w_ext is not None
            else q_robust(
                contacts, mu, mass, com, robust, seed=seed, representation=representation, cuts=cuts
            )
        )
        t["q_robust"] = (time.perf_counter() - t0) * 1e3
    return GraspEvaluation(model, w, verdict, mf, q, profiles, contacts, t)

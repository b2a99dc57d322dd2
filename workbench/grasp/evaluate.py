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
    min_force : the smallest grasp force, or None: the minimal per-jaw reading is
        ``force * min_force.scale``; ``min_force.total`` is the sum of the contacts'
        normal-force magnitudes there (Σ p a, larger than 2 × the reading on curved
        contacts; REACH contributes one entry per element cluster to ``forces``).
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


def _check_grasp(grasp) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(p1, p2, unit axis)`` of a grasp dict, or a ValueError naming what is missing."""
    if not isinstance(grasp, dict) or any(k not in grasp for k in ("p1", "p2", "axis")):
        got = sorted(grasp) if isinstance(grasp, dict) else type(grasp).__name__
        raise ValueError(
            "grasp must be a dict with 'p1', 'p2' (contact points [m]) and 'axis' (unit vector from "
            f"jaw 1 into the object), as antipodal_grasps returns; got {got}"
        )
    p1, p2, axis = (np.asarray(grasp[k], float) for k in ("p1", "p2", "axis"))
    if p1.shape != (3,) or p2.shape != (3,) or axis.shape != (3,) or not np.linalg.norm(axis) > 0:
        raise ValueError(f"grasp p1, p2, axis must be (3,) vectors, axis non-zero; got {p1}, {p2}, {axis}")
    return p1, p2, axis / np.linalg.norm(axis)


def _jaw(prof, point: np.ndarray, approach: np.ndarray, force: float, pad) -> ContactProfile:
    """One jaw's profile checked (it lies at the jaw and pushes) and scaled to ``force``."""
    if not isinstance(prof, ContactProfile):
        raise ValueError(f"profiles must be ContactProfile objects, one per jaw; got {type(prof).__name__}")
    off = float(np.linalg.norm(prof.pressure_center - point))
    if off > float(np.hypot(*pad)):
        raise ValueError(
            f"the profile's pressure centre is {off:.3g} m from its jaw's contact point "
            f"{np.round(point, 4).tolist()} (more than the pad's diagonal): a profile of another grasp, "
            "pose or unit?"
        )
    # the jaw pushes the object along its approach: −Σ p a n · approach > 0
    push = float(prof.normal_wrench[:3] @ approach)
    if not push > 0:
        raise ValueError(
            f"the jaw at {np.round(point, 4).tolist()} would pull the object (net normal force "
            f"{push:.3g} N along its approach): the profile's normals point into the object, "
            "or the approach is reversed; normals must point out of the object (CONVENTIONS.md)"
        )
    return with_axis_force(prof, approach, force)


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
    """The two jaws' REACH profiles (:func:`~.reach.reach_profile`) of an antipodal
    ``grasp`` (a dict of :func:`~.sampling.antipodal_grasps`: ``p1``, ``p2`` [m], ``axis``
    from jaw 1 into the object), each scaled to the reading ``force`` [N] along the grasp
    axis.  ``units`` is the unit of ``mesh.vertices`` only; the grasp is in metres.
    Raises ValueError when a jaw would pull the object."""
    p1, p2, axis = _check_grasp(grasp)
    out = []
    for point, approach in ((p1, axis), (p2, -axis)):
        prof = reach_profile(
            mesh, point, approach, up, pad=pad, closing=closing, units=units, allow_scale=allow_scale
        )
        out.append(_jaw(prof, point, approach, force, pad))
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

    grasp : one dict of :func:`~.sampling.antipodal_grasps` (``p1``, ``p2`` [m], ``axis``).
    force : force-sensor reading of *each* jaw along the grasp axis [N] (§4.1.3.2); a
        profile's ``F`` (Σ p a, the sum of element normal forces) exceeds it on curved
        contacts.  The minimal reading is ``force * result.min_force.scale``.
    mu : friction coefficient.
    w_ext : the task wrench (6,) about the object origin; or ``mass`` [kg] and ``com``
        (3,) [m] (inside the object's bounding box) for holding against gravity.
    min_force : also solve the minimal grasp force (same model, ``objective="scale"``).
    robust : a :class:`Perturbation` to also compute ``q_robust`` (Eq. 2.101).
    representation : "model" (default), "outer" or "inner" (see :func:`resists`).
    cache, cuts : reuse limit surfaces / cutting planes across calls (pass the same
        objects when evaluating many grasps).
    profiles : the two jaws' profiles, if already computed (skips the mesh step); they
        are checked (near their jaw, pushing) and scaled to ``force`` like new ones.
    up, pad : the jaws' length axis and face size ``(width, length)`` [m].
    units, allow_scale : the unit of ``mesh.vertices`` ("mm" converts a copy; the grasp
        stays in metres) and the escape from the size check (:mod:`workbench.units`).
    seed : sampler seed of the contact models.
    """
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}; got {model!r}")
    check_mu(mu)
    if not (np.isscalar(force) and np.isfinite(force) and force > 0):
        raise ValueError(f"force must be a positive grasp force [N]; got {force!r}")
    if w_ext is None:
        if mass is None or com is None:
            raise ValueError("give the task as w_ext (6,) or as mass [kg] and com (3,) [m]")
        if mesh is not None:  # before gravity_wrench's generic check: the object's box says more
            lo, hi = np.asarray(mesh.bounds, float)
            ext = float((hi - lo).max())
            c = np.asarray(com, float)
            if c.shape == (3,) and ((c < lo - ext) | (c > hi + ext)).any():
                raise ValueError(
                    f"com {c.tolist()} lies far outside the object's bounding box "
                    f"{lo.tolist()}–{hi.tolist()} [m]: is it in another unit than the mesh (metres)?"
                )
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
    else:
        p1, p2, axis = _check_grasp(grasp)
        if isinstance(profiles, ContactProfile) or len(profiles) != 2:
            raise ValueError(
                "profiles must be a list of the two jaws' ContactProfiles [jaw at p1, jaw at p2]"
            )
        profiles = [
            _jaw(p, q, a, force, pad) for p, q, a in zip(profiles, (p1, p2), (axis, -axis), strict=True)
        ]
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
        # a given w_ext is resisted as is (mass and com are then unused by q_robust)
        q = q_robust(
            contacts,
            mu,
            1.0 if mass is None else mass,
            np.zeros(3) if com is None else com,
            robust,
            seed=seed,
            representation=representation,
            cuts=cuts,
            w_ext=w if w_ext is not None else None,
        )
        t["q_robust"] = (time.perf_counter() - t0) * 1e3
    return GraspEvaluation(model, w, verdict, mf, q, profiles, contacts, t)

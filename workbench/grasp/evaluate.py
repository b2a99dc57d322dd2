"""One call from a grasp and its two jaws' contact profiles to the verdict (thesis §4.1.4, §4.2).

:func:`evaluate_grasp` composes the pipeline a researcher would otherwise write out:

1. each jaw's contact profile: given (``profiles=``, from any source in
   :mod:`workbench.sources` — the FEM pad's :func:`~workbench.sources.fem_jaw.fem_jaw_profiles`,
   a closed-form scene, a measured mesh with pressures), or by default made from the mesh
   by REACH (:func:`~workbench.sources.reach.jaw_profiles`: the pad pressed ``closing`` past
   first touch, Winkler pressure), jaw 1 at ``p1`` approaching along the grasp axis, jaw 2
   at ``p2`` approaching against it;
2. both profiles checked (each lies at its jaw and *pushes* the object; a profile whose
   normals point into the object would pull) and scaled to the force-sensor reading along
   the grasp axis within the readings their source holds for
   (:func:`~workbench.sources.jaws.checked_jaw_profile`, §4.1.3.2) — the same
   check and scaling whatever the source;
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
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..limit_surface import LimitSurfaceCache
from ..profile import ContactProfile
from ..sources.jaws import check_grasp, check_jaw_force, check_pad, checked_jaw_profile
from ..sources.reach import jaw_profiles
from .contacts import ContactSet
from .gws import check_mu
from .models import MODELS, contact_sets
from .resistance import CutStore, MinimalForce, Resistance, min_grasp_force, resists
from .robust import Perturbation, check_com, check_object_mass, check_task_wrench, gravity_wrench, q_robust

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
    down=(0.0, 0.0, -1.0),
) -> GraspEvaluation:
    """Evaluate an antipodal grasp of ``mesh`` (metres) under contact model ``model``, with
    the jaws' REACH profiles made from the mesh or the given ``profiles`` of any source.

    mesh : the object (a watertight trimesh); may be None when ``profiles`` are given
        (then a ``com`` is not checked against the object's box).
    grasp : one dict of :func:`~.sampling.antipodal_grasps` (``p1``, ``p2`` [m], ``axis``).
    force : force-sensor reading of *each* jaw along the grasp axis [N] (§4.1.3.2); a
        profile's ``F`` (Σ p a, the sum of element normal forces) exceeds it on curved
        contacts.  The minimal reading is ``force * result.min_force.scale``.
    mu : friction coefficient.
    w_ext : the task wrench (6,) about the object origin; or ``mass`` [kg] and ``com``
        (3,) [m] (inside the object's bounding box) for holding against gravity along
        ``down`` (3,; the object frame's −z unless given, e.g. a trial's gravity in the object's
        frame).  A gripper given as a 4×4 pose: :func:`~.gripper_eval.evaluate_gripper`.
    min_force : also solve the minimal grasp force (same model, ``objective="scale"``).
    robust : a :class:`Perturbation` to also compute ``q_robust`` (Eq. 2.101).
    representation : "model" (default), "outer" or "inner" (see :func:`resists`).
    cache, cuts : reuse limit surfaces / cutting planes across calls (pass the same
        objects when evaluating many grasps).
    profiles : the two jaws' profiles ``[jaw at p1, jaw at p2]`` from any source in
        :mod:`workbench.sources` (REACH computed before, the FEM pad's
        :func:`~workbench.sources.fem_jaw.fem_jaw_profiles`, a closed-form scene); the mesh
        step is skipped.  Each is checked as REACH's are
        (:func:`~workbench.sources.jaws.checked_jaw_profile`: a ContactProfile at its jaw —
        pressure centre in the pad's footprint around the jaw point and near it along the
        approach, ``config.TOL.jaw_profile_plane_rtol`` / ``jaw_profile_depth_rtol`` — that
        pushes the object along its approach) and scaled to ``force``; a ValueError says which
        check failed.  A profile that records its source (:class:`~workbench.profile.ProfileSource`,
        e.g. the FEM pad's) is not scaled to a reading the source cannot produce (refused) and,
        if its distribution changes with force, a ``UserWarning`` says when ``force`` is far
        from the reading it was made at (``config.TOL.profile_force_ratio_warn``).
    up, pad : the jaws' length axis and face size ``(width, length)`` [m] (REACH's
        footprint; for given profiles the bound of the check that each lies at its jaw:
        pass the FEM pad's ``(width, length)``).
    units, allow_scale : the unit of ``mesh.vertices`` ("mm" converts a copy; the grasp
        stays in metres) and the escape from the size check (:mod:`workbench.units`).
    seed : sampler seed of the contact models.
    """
    cache, mesh, units = _checked_setup(model, mu, force, pad, cache, mesh, units, allow_scale)
    w = _task_wrench(w_ext, mass, com, mesh, down)
    cuts = CutStore() if cuts is None else cuts
    t: dict = {}
    jaw_profs = _timed(
        t, "profiles", lambda: _stage_profiles(mesh, grasp, profiles, force, up, pad, units, allow_scale)
    )
    contacts = _timed(
        t,
        "contact_model",
        lambda: [c for p in jaw_profs for c in contact_sets(p, model, cache=cache, seed=seed)],
    )
    solve_kw = {"representation": representation, "cuts": cuts}
    verdict = _timed(t, "resists", lambda: resists(contacts, w, mu, **solve_kw))
    mf = None
    if min_force:
        mf = _timed(t, "min_grasp_force", lambda: min_grasp_force(contacts, w, mu, **solve_kw))
    q = None
    if robust is not None:
        # a given w_ext is resisted as is (mass and com are then unused by q_robust)
        q = _timed(
            t,
            "q_robust",
            lambda: q_robust(
                contacts,
                mu,
                1.0 if mass is None else mass,
                np.zeros(3) if com is None else com,
                robust,
                seed=seed,
                w_ext=w if w_ext is not None else None,
                down=down,
                **solve_kw,
            ),
        )
    return GraspEvaluation(model, w, verdict, mf, q, jaw_profs, contacts, t)


def _checked_setup(model: str, mu: float, force: float, pad, cache, mesh, units, allow_scale: bool) -> tuple:
    """The arguments of :func:`evaluate_grasp` checked before any work: (the limit-surface
    cache, the mesh in metres or None, the unit still to apply — None once the mesh is in metres)."""
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}; got {model!r}")
    check_mu(mu)
    check_jaw_force(force)
    check_pad(pad)  # before the mesh step: a bad pad is not "a footprint that covers nothing"
    cache = LimitSurfaceCache.check(cache)  # before the profiles are made: a path is not a cache
    if mesh is not None:
        # metres first: the mass and com checks below read the mesh's volume and box
        from ..units import closed_mesh

        mesh = closed_mesh(mesh, "mesh passed to evaluate_grasp", units=units, allow_scale=allow_scale)
        units = None
    return cache, mesh, units


def _timed(timings: dict, stage: str, run: Callable[[], Any]) -> Any:
    """``run()``, its wall time [ms] recorded as ``timings[stage]``."""
    t0 = time.perf_counter()
    out = run()
    timings[stage] = (time.perf_counter() - t0) * 1e3
    return out


def _stage_profiles(mesh, grasp: dict, profiles, force: float, up, pad, units, allow_scale: bool) -> list:
    """Step 1–2 of the module docstring: the jaws' REACH profiles made from ``mesh``, or the given
    ``profiles`` checked and scaled to ``force``."""
    if profiles is not None:
        return _given_profiles(profiles, grasp, force, pad)
    if mesh is None:
        raise ValueError(
            "give the object mesh (the jaws' REACH profiles are made from it) or the two jaws' "
            "profiles=[jaw at p1, jaw at p2] from any source (workbench.sources)"
        )
    return jaw_profiles(mesh, grasp, force, up=up, pad=pad, units=units, allow_scale=allow_scale)


def _task_wrench(w_ext, mass: float | None, com, mesh, down) -> np.ndarray:
    """The task wrench (6,) of :func:`evaluate_grasp`: ``w_ext`` checked, or gravity on ``mass``
    [kg] at ``com`` (3,) [m] along ``down`` (checked against ``mesh`` when given); a ValueError
    unless exactly one of the two is given."""
    if w_ext is None:
        if mass is None or com is None:
            raise ValueError("give the task as w_ext (6,) or as mass [kg] and com (3,) [m]")
        check_com(com, mesh)  # before gravity_wrench's generic check: the object's box says more
        check_object_mass(mass, mesh)
        return gravity_wrench(mass, com, down=down)
    if mass is not None or com is not None:
        raise ValueError("give the task either as w_ext or as mass and com, not both")
    return check_task_wrench(w_ext)


def _given_profiles(profiles, grasp: dict, force: float, pad: tuple[float, float]) -> list[ContactProfile]:
    """The two jaws' given ``profiles`` checked at their jaws of ``grasp`` and scaled to
    ``force`` (:func:`~workbench.sources.jaws.checked_jaw_profile`)."""
    p1, p2, axis = check_grasp(grasp)
    if not isinstance(profiles, (list, tuple)) or len(profiles) != 2:
        got = type(profiles).__name__ + (
            f" of {len(profiles)}" if isinstance(profiles, (list, tuple)) else ""
        )
        raise ValueError(
            f"profiles must be a list of the two jaws' ContactProfiles [jaw at p1, jaw at p2]; got a {got}"
        )
    return [
        checked_jaw_profile(p, q, a, force, pad)
        for p, q, a in zip(profiles, (p1, p2), (axis, -axis), strict=True)
    ]

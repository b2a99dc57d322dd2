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

Its inputs come in groups (:mod:`~.inputs`): the :class:`~.inputs.Task` (the load, shared with
the gripper evaluation), the :class:`~.inputs.Jaws` and the :class:`~.inputs.ModelOptions`.
"""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..groups import checked_group
from ..limit_surface import LimitSurfaceCache
from ..plausible import ImplausibleWarning
from ..profile import ContactProfile
from ..sources.jaws import check_grasp, checked_jaw_profile
from ..sources.reach import jaw_profiles
from .contacts import ContactSet
from .inputs import Jaws, ModelOptions, Task
from .models import contact_sets
from .resistance import CutStore, MinimalForce, Resistance, min_grasp_force, resists
from .robust import check_com, check_object_mass, gravity_wrench, q_robust

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class GraspEvaluation:
    """What :func:`evaluate_grasp` found.

    resistance : the verdict for the task wrench (truthy iff resisted); ``resisted`` is it as a bool.
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
    task: Task,
    *,
    jaws: Jaws | None = None,
    options: ModelOptions | None = None,
    profiles: list[ContactProfile] | None = None,
    cache: LimitSurfaceCache | None = None,
    cuts: CutStore | None = None,
) -> GraspEvaluation:
    """Evaluate an antipodal grasp of ``mesh`` (metres) under the contact model ``options.model``,
    with the jaws' REACH profiles made from the mesh or the given ``profiles`` of any source.

    mesh : the object (a watertight trimesh in metres); may be None when ``profiles`` are given
        (then a ``com`` is not checked against the object's box, nor the mass against its volume).
        A mesh in another unit is converted first by the one gate of every mesh input,
        ``workbench.units.mesh_in_metres(mesh, "object", units="mm")``: this call takes no
        ``units`` / ``allow_scale`` of its own (the unit belongs to the mesh; with the task, the
        jaws and the model options in three groups and the reuse objects apart, the call keeps
        to eight arguments).  A mesh of an unusual size on purpose is refused here: make its
        jaws' profiles with ``workbench.sources.reach.jaw_profiles(..., allow_scale=True)`` and
        pass them with ``mesh=None``.
    grasp : one dict of :func:`~.sampling.antipodal_grasps` (``p1``, ``p2`` [m], ``axis``).
    task : a :class:`~.inputs.Task`: the task wrench ``w_ext`` (6,) about the object origin, or
        ``mass`` [kg] and ``com`` (3,) [m] (inside the object's convex hull, up to
        ``config.TOL.com_hull_rtol`` of its size; required here) for holding against gravity
        along ``down`` (3,).  A gripper given as a 4×4 pose:
        :func:`~.gripper_eval.evaluate_gripper`, with the same Task.
    jaws : a :class:`~.inputs.Jaws` (default ``Jaws()``): ``force``, the force-sensor reading of
        *each* jaw along the grasp axis [N] (§4.1.3.2) — a profile's ``F`` (Σ p a, the sum of
        element normal forces) exceeds it on curved contacts; the minimal reading is
        ``jaws.force * result.min_force.scale`` — and ``pad``, ``up``: the jaws' face size
        ``(width, length)`` [m] and length axis (REACH's footprint; for given profiles the bound
        of the check that each lies at its jaw: pass the FEM pad's ``(width, length)``).
    options : a :class:`~.inputs.ModelOptions` (default ``ModelOptions()``): ``model``, ``mu``,
        ``representation`` ("model", "outer" or "inner", see :func:`resists`), ``min_force``
        (also solve the minimal grasp force, same model, ``objective="scale"``), ``robust`` (a
        :class:`Perturbation` to also compute ``q_robust``, Eq. 2.101) and ``seed`` (the contact
        models' sampler seed).
    profiles : the two jaws' profiles ``[jaw at p1, jaw at p2]`` from any source in
        :mod:`workbench.sources` (REACH computed before, the FEM pad's
        :func:`~workbench.sources.fem_jaw.fem_jaw_profiles`, a closed-form scene); the mesh
        step is skipped.  Each is checked as REACH's are
        (:func:`~workbench.sources.jaws.checked_jaw_profile`: a ContactProfile at its jaw —
        pressure centre in the pad's footprint around the jaw point and near it along the
        approach, ``config.TOL.jaw_profile_plane_rtol`` / ``jaw_profile_depth_rtol`` — that
        pushes the object along its approach) and scaled to ``jaws.force``; a ValueError says which
        check failed.  A profile that records its source (:class:`~workbench.profile.ProfileSource`,
        e.g. the FEM pad's) is not scaled to a reading the source cannot produce (refused) and,
        if its distribution changes with force, a ``UserWarning`` says when ``jaws.force`` is far
        from the reading it was made at (``config.TOL.profile_force_ratio_warn``).
    cache, cuts : reuse limit surfaces / cutting planes across calls (pass the same
        objects when evaluating many grasps).
    """
    # no defaults to stand in for None: the load is the caller's
    task = checked_group(
        task, Task, "task", hint="pass Task(w_ext=...) or Task(mass=..., com=...)", required=True
    )
    jaws = checked_group(jaws, Jaws, "jaws")
    opts = checked_group(options, ModelOptions, "options")
    cache, mesh = _checked_setup(cache, mesh)
    w = _task_wrench(task, mesh)
    cuts = CutStore() if cuts is None else cuts
    t: dict = {}
    solve_kw = {"representation": opts.representation, "cuts": cuts}
    mf = q = None
    with warnings.catch_warnings():  # the jaws' force and μ warned when their groups were made
        warnings.simplefilter("ignore", ImplausibleWarning)
        jaw_profs = _timed(t, "profiles", lambda: _stage_profiles(mesh, grasp, profiles, jaws))
        contacts = _timed(
            t,
            "contact_model",
            lambda: [c for p in jaw_profs for c in contact_sets(p, opts.model, cache=cache, seed=opts.seed)],
        )
        verdict = _timed(t, "resists", lambda: resists(contacts, w, opts.mu, **solve_kw))
        if opts.min_force:
            mf = _timed(t, "min_grasp_force", lambda: min_grasp_force(contacts, w, opts.mu, **solve_kw))
        if opts.robust is not None:
            q = _timed(t, "q_robust", lambda: _q_robust(contacts, task, w, opts, solve_kw))
    return GraspEvaluation(opts.model, w, verdict, mf, q, jaw_profs, contacts, t)


def _q_robust(
    contacts: list[ContactSet], task: Task, w: np.ndarray, opts: ModelOptions, solve_kw: dict
) -> float:
    """:func:`~.robust.q_robust` of :func:`evaluate_grasp`: a given w_ext is resisted as is (``w``),
    else gravity on the perturbed mass at the perturbed com."""
    load = w if task.w_ext is not None else task
    return q_robust(contacts, opts.mu, load, opts.robust, seed=opts.seed, **solve_kw)


def _checked_setup(cache, mesh) -> tuple:
    """The reuse cache and the mesh of :func:`evaluate_grasp` checked before any work: (the
    limit-surface cache, the mesh — closed, outward, of a graspable size in metres — or None)."""
    cache = LimitSurfaceCache.check(cache)  # before the profiles are made: a path is not a cache
    if mesh is not None:
        # the mass and com checks below read the mesh's volume and box
        from ..units import MESH_UNIT_FIX, closed_mesh

        mesh = closed_mesh(mesh, "mesh passed to evaluate_grasp", fix=MESH_UNIT_FIX, override=None)
    return cache, mesh


def _timed(timings: dict, stage: str, run: Callable[[], Any]) -> Any:
    """``run()``, its wall time [ms] recorded as ``timings[stage]``."""
    t0 = time.perf_counter()
    out = run()
    timings[stage] = (time.perf_counter() - t0) * 1e3
    return out


def _stage_profiles(mesh, grasp: dict, profiles, jaws: Jaws) -> list:
    """Step 1–2 of the module docstring: the jaws' REACH profiles made from ``mesh``, or the given
    ``profiles`` checked and scaled to ``jaws.force``."""
    if profiles is not None:
        return _given_profiles(profiles, grasp, jaws.force, jaws.pad)
    if mesh is None:
        raise ValueError(
            "give the object mesh (the jaws' REACH profiles are made from it) or the two jaws' "
            "profiles=[jaw at p1, jaw at p2] from any source (workbench.sources)"
        )
    return jaw_profiles(mesh, grasp, jaws.force, up=jaws.up, pad=jaws.pad)


def _task_wrench(task: Task, mesh) -> np.ndarray:
    """The task wrench (6,) of :func:`evaluate_grasp`: the Task's ``w_ext``, or gravity on its
    ``mass`` [kg] at ``com`` (3,) [m] along ``down`` (checked against ``mesh`` when given); a
    ValueError for a gravity task without its ``com``."""
    if task.w_ext is not None:
        return np.array(task.w_ext)
    if task.com is None:
        raise ValueError(
            "give the task as w_ext (6,) or as mass [kg] and com (3,) [m]: evaluate_grasp takes no default "
            "centre of mass (Task(mass=..., com=mesh.center_mass) for a uniform density)"
        )
    check_com(task.com, mesh)  # before gravity_wrench's generic check: the object's box says more
    check_object_mass(task.mass, mesh, checked=True)  # the Task checked the mass itself
    with warnings.catch_warnings():  # gravity_wrench's own mass check: the Task warned already
        warnings.simplefilter("ignore", ImplausibleWarning)
        return gravity_wrench(task.mass, task.com, down=task.down)


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

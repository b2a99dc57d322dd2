"""A grasp given as users have it: a gripper (:class:`~workbench.sources.gripper.Gripper`) at a
4×4 pose in the object's frame, gravity in a direction, the contact recomputed from the pose.

:func:`gripper_contact` is the contact (model-independent): both pads pressed on the mesh
(:func:`~workbench.sources.reach.pad_profile`, the gripper's polygon pad) with the object free
to settle between them (:func:`~.settle.settle_contact`), or a miss.  :func:`judge_contact`
asks one contact model whether that contact holds the object (thesis Eq. 2.100) and how much
force it needs (Eq. 4.4): its ``margin`` ``1 − f_min / f`` is the thesis's force quality
(§4.3.3.2) with the gripper's own force as ``f⊥max``, 0 when the pads miss or the model
cannot hold it.  :func:`evaluate_gripper` composes them, and with a
:class:`~.pose_robust.PoseNoise` recomputes the contact at N_r perturbed poses and reports
the mean margin and the fraction held (6DFC §V-B.1); :func:`evaluate_models` does it for
several models on the same contacts.  The object's load is a :class:`~.inputs.Task` (the same as
:func:`~.evaluate.evaluate_grasp`'s, gravity only here), the rest a :class:`~.inputs.GripperOptions`.
"""

from __future__ import annotations

import logging
import time
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..groups import checked_group
from ..limit_surface import LimitSurfaceCache
from ..plausible import ImplausibleWarning
from .inputs import GripperOptions, Task, check_down_direction
from .models import MODELS, check_model, contact_sets
from .pose_robust import check_pose, pose_samples
from .resistance import CutStore, min_grasp_force, resists
from .robust import check_com, check_object_mass, gravity_wrench
from .settle import SettledContact, settle_contact

log = logging.getLogger(__name__)

__all__ = [
    "GripperEvaluation",
    "Verdict",
    "check_down",
    "check_task",
    "evaluate_gripper",
    "evaluate_models",
    "gripper_contact",
    "judge_contact",
]


@dataclass(frozen=True)
class Verdict:
    """One contact model's answer for one contact.

    resisted : the model holds the task wrench at the gripper's force; margin : ``1 −
    f_min / f`` in [0, 1] (0: a miss or not held at any force up to f); scale : ``f_min /
    f`` (inf when no force holds); reason : why not, in words ("" when held).
    """

    model: str
    resisted: bool
    margin: float
    scale: float
    reason: str = ""


@dataclass(frozen=True)
class GripperEvaluation:
    """What :func:`evaluate_gripper` found: the nominal ``contact`` and ``verdict``; with pose
    robustness the per-sample verdicts, ``q_pose`` (mean margin) and ``p_held`` (fraction of
    samples held, a miss counting as not held); ``timings_ms`` per stage."""

    verdict: Verdict
    contact: SettledContact = field(repr=False)
    q_pose: float | None = None
    p_held: float | None = None
    samples: tuple[Verdict, ...] = field(default=(), repr=False)
    timings_ms: dict = field(default_factory=dict)


def check_task(mesh, mass: float, mu: float, down, *, checked: bool = False) -> np.ndarray:
    """Gripper-level careless-input checks; returns the unit ``down`` (3,).

    mass [kg] against the object's volume (a mean density above the plausible range of
    :data:`workbench.plausible.RANGES` ``"density"`` is refused as a mass in grams, one below it
    warned as a mesh in another unit); mu a friction coefficient in (0, 2] (30 is a percentage
    or a slip); down a non-zero (3,) direction (:func:`~.inputs.check_down_direction`).
    ``checked``: the mass passed its own check already (a :class:`~.inputs.Task`'s).
    """
    from ..sources.gripper import check_pad_mu

    check_pad_mu(mu)
    check_object_mass(mass, mesh, checked=checked)
    return check_down_direction(down)


def gripper_contact(mesh, gripper, pose, *, settle: bool = True, max_edge: float = 1e-3) -> SettledContact:
    """Both pads of ``gripper`` at ``pose`` (4, 4; the gripper in the object frame [m]) pressed
    on ``mesh``, each until its normal force along its closing axis is the gripper's force, the
    object settled between them (``settle=False``: each pad pressed alone at the pose as given).
    A pad that touches nothing within its stroke is a miss (``contact.touches`` False,
    ``contact.reason`` says which), not an error.
    """
    from ..sources.gripper import check_gripper
    from ..sources.reach import pad_patch

    gripper = check_gripper(gripper)
    T = check_pose(pose, "gripper pose")
    jaws = gripper.jaws(T)
    k = gripper.pad.stiffness  # Winkler modulus [Pa/m]

    def press(jaw):
        return pad_patch(mesh, jaw, stiffness=k, max_edge=max_edge)

    contact = settle_contact(jaws, press, gripper.force, settle=settle)
    if not contact.touches and "touches nothing" in contact.reason:
        lo, hi = np.asarray(mesh.bounds, float)
        mid = 0.5 * (jaws[0].origin + jaws[1].origin)
        gap = float(np.linalg.norm(np.clip(mid, lo, hi) - mid))
        if gap > 0:  # say how far: a pose metres away is likely in another unit
            where = f"the gripper's centre is {gap:.3g} m outside the object's box"
            contact = replace(contact, reason=f"{contact.reason} ({where})")
    return contact


def judge_contact(
    contact: SettledContact,
    model: str,
    task: Task,
    *,
    mu: float,
    cache: LimitSurfaceCache | None = None,
    cuts: CutStore | None = None,
    seed: int = 0,
) -> Verdict:
    """Whether ``model`` (one of :data:`~.models.MODELS`) says ``contact`` holds the object of the
    gravity ``task`` (a :class:`~.inputs.Task`: ``mass`` [kg] at ``com`` (3,) [m], both given,
    against gravity along ``down`` (3,; object frame, before the settle's turn, which is applied
    here)) at the contact's force with friction ``mu``, and its margin."""
    check_model(model)
    task = _gravity_task(task, need_com=True)
    if not contact.touches:
        return Verdict(model, False, 0.0, np.inf, f"no contact: {contact.reason}")
    d = contact.rotation @ np.asarray(task.down, float)  # the object turned as it settled
    w = gravity_wrench(task.mass, task.com, down=d)
    cache = LimitSurfaceCache.check(cache)
    sets = [c for p in contact.profiles for c in contact_sets(p, model, cache=cache, seed=seed)]
    return _judge_sets(sets, model, w, mu=mu, cuts=cuts)


def _judge_sets(sets, model: str, w: np.ndarray, *, mu: float, cuts: CutStore | None = None) -> Verdict:
    """The :class:`Verdict` of ``model``'s contact ``sets`` (both jaws', at the gripper's force)
    against the gravity wrench ``w`` (6,) [N, N·m]: resisted (Eq. 2.100) and the margin ``1 −
    f_min / f`` (Eq. 4.4): :func:`judge_contact` once the sets are built (unchecked: its
    callers built them)."""
    cuts = CutStore() if cuts is None else cuts
    held = resists(sets, w, mu, cuts=cuts)
    mf = min_grasp_force(sets, w, mu, cuts=cuts)
    scale = float(mf.scale) if mf.feasible and np.isfinite(mf.scale) else np.inf
    margin = float(np.clip(1.0 - scale, 0.0, 1.0)) if np.isfinite(scale) else 0.0
    reason = ""
    if not held:
        reason = (
            f"the {model} contacts cannot balance gravity at this force (relative residual "
            f"{held.residual:.2g}; minimal force "
            f"{'none' if not np.isfinite(scale) else f'{scale:.3g} × the force'})"
        )
        if model == "point":
            reason += ": two point contacts on one line resist no torque about that line"
    return Verdict(model, bool(held), margin if held else 0.0, scale, reason)


def _gravity_task(task: Task, *, need_com: bool = False) -> Task:
    """``task`` if it is a gravity :class:`~.inputs.Task` (``mass``, ``com``, ``down``) — the
    gripper holds the object against gravity, so a ``w_ext`` task is refused, and without a mesh
    to take its centre of mass from (``need_com``) so is one without ``com``."""
    task = checked_group(task, Task, "task")
    if task.w_ext is not None:
        raise ValueError(
            "the gripper evaluation holds the object against gravity: give the task as "
            "Task(mass=..., com=..., down=...), not w_ext (a wrench task: evaluate_grasp)"
        )
    if need_com and task.com is None:
        raise ValueError(
            "give the task's com (3,) [m]: judge_contact has no mesh to take its centre of mass from "
            "(Task(mass=..., com=mesh.center_mass, down=...))"
        )
    return task


def check_down(pose, down) -> None:
    """Warn (:class:`~workbench.plausible.ImplausibleWarning`) when gravity points against the
    gripper's approach (its z axis): a grasp from below the object is possible but unusual —
    ``down`` given as an up vector?  (A table-top grasp approaches along gravity or across it.)"""
    import warnings

    from ..plausible import ImplausibleWarning

    approach = np.asarray(pose, float)[:3, 2]
    d = np.asarray(down, float) / np.linalg.norm(down)
    if approach @ d < -0.5:
        warnings.warn(
            f"the gripper approaches against gravity (approach · down = {approach @ d:.2f}): a grasp "
            "from below the object — is down an up vector? (down is gravity's direction in the object "
            "frame)",
            ImplausibleWarning,
            stacklevel=3,
        )


def evaluate_gripper(
    mesh,
    gripper,
    pose,
    task: Task,
    *,
    model: str = "6dls",
    options: GripperOptions | None = None,
    cache: LimitSurfaceCache | None = None,
    cuts: CutStore | None = None,
) -> GripperEvaluation:
    """Evaluate ``gripper`` at ``pose`` under one contact model ``model``: :func:`evaluate_models`
    with ``models=(model,)`` (its arguments and defaults; settling on, no pose robustness unless
    ``options.robust`` is given)."""
    out = evaluate_models(mesh, gripper, pose, task, models=(model,), options=options, cache=cache, cuts=cuts)
    return out[model]


def evaluate_models(
    mesh,
    gripper,
    pose,
    task: Task,
    *,
    models=MODELS,
    options: GripperOptions | None = None,
    cache: LimitSurfaceCache | None = None,
    cuts: CutStore | None = None,
) -> dict[str, GripperEvaluation]:
    """Evaluate ``gripper`` at ``pose`` (4, 4: the gripper frame in the object frame [m]) on
    ``mesh`` (metres) under each contact model of ``models``, holding the object of the gravity
    ``task`` (a :class:`~.inputs.Task`: ``mass`` [kg] at ``com`` (3,) [m; None: the mesh's centre
    of mass] against gravity along ``down`` (3,; gravity's direction in the object frame, e.g.
    :attr:`~workbench.sources.trials.TrialGrasp.down`)).
    The contacts — nominal and at each pose sample — are computed once and shared by the models.

    options : a :class:`~.inputs.GripperOptions` (default ``GripperOptions()``): ``mu``, the pad's
        friction coefficient (None: ``gripper.mu``); ``robust``, a :class:`~.pose_robust.PoseNoise`
        — also recompute the contact at N_r perturbed poses; then ``q_pose`` is the mean ``margin``
        over the samples (a miss counts 0) and ``p_held`` the fraction of samples held (both None
        without it); ``settle`` — True (default): the object free to settle between the pads
        (:mod:`~.settle`), False: each pad pressed alone at the pose as given; ``seed`` — pose
        samples and the models' samplers.
    cache, cuts : reuse limit surfaces / cutting planes across calls.

    ``verdict.margin`` is ``1 − f_min / f``: the share of the gripper's force ``f`` not needed
    to hold the object (the thesis's force quality, §4.3.3.2).  For a light object it sits near
    1 on every grasp that touches and its differences come from the torque the weight puts on
    the contact; ``verdict.scale`` (``f_min / f``) says the same unclipped.
    """
    models = _checked_models(models)
    from ..sources.gripper import check_gripper
    from ..units import MESH_UNIT_FIX, closed_mesh

    gripper = check_gripper(gripper)  # a preset's name is refused with the call to make
    # the mesh's unit before the mass check, which reads its volume: a mesh in millimetres
    # would otherwise be reported as a mass in the wrong unit
    mesh = closed_mesh(mesh, "mesh passed to evaluate_models", fix=MESH_UNIT_FIX, override=None)
    opts = checked_group(options, GripperOptions, "options")
    mu, task = _checked_task(mesh, gripper, pose, task, opts)
    judge = {
        "mu": mu,
        "cache": LimitSurfaceCache.check(cache),
        "cuts": CutStore() if cuts is None else cuts,
        "seed": opts.seed,
    }
    t0 = time.perf_counter()
    contact = gripper_contact(mesh, gripper, pose, settle=opts.settle)
    t_contact = (time.perf_counter() - t0) * 1e3
    samples, t_samples = [], 0.0
    if opts.robust is not None:
        t0 = time.perf_counter()
        poses = pose_samples(pose, opts.robust, opts.seed)
        samples = [gripper_contact(mesh, gripper, T, settle=opts.settle) for T in poses]
        t_samples = (time.perf_counter() - t0) * 1e3
    with warnings.catch_warnings():  # μ and the task warned once above; not once per judgement
        warnings.simplefilter("ignore", ImplausibleWarning)
        return _judge_models(
            models, contact, samples if opts.robust is not None else None, task, judge, t_contact, t_samples
        )


def _judge_models(models, contact, samples, task, judge: dict, t_contact: float, t_samples: float) -> dict:
    """:func:`evaluate_models`' verdicts: each model on the contact and on the pose ``samples``
    (None: no gripper-pose robustness)."""
    out = {}
    for m in models:
        t = {"contact": t_contact}
        t0 = time.perf_counter()
        v = judge_contact(contact, m, task, **judge)
        t["judge"] = (time.perf_counter() - t0) * 1e3
        if samples is None:
            out[m] = GripperEvaluation(v, contact, timings_ms=t)
            continue
        t0 = time.perf_counter()
        judged = tuple(judge_contact(sc, m, task, **judge) for sc in samples)
        t["pose_robust"] = t_samples + (time.perf_counter() - t0) * 1e3  # contacts shared by the models
        q = float(np.mean([s.margin for s in judged]))
        p = float(np.mean([s.resisted for s in judged]))
        out[m] = GripperEvaluation(v, contact, q, p, judged, t)
    return out


def _checked_models(models) -> tuple[str, ...]:
    """``models`` of :func:`evaluate_models` as a tuple of checked names."""
    if isinstance(models, str):  # one model by name: ("6dls",), not the characters of "6dls"
        models = (models,)
    models = tuple(models)
    if not models:
        raise ValueError(f"models must name at least one contact model of {MODELS}; got none")
    for m in models:
        check_model(m)
    twice = sorted({m for m in models if models.count(m) > 1})
    if twice:  # the answers are keyed by model: a second judgement of one model would overwrite the first
        raise ValueError(
            f"models must name each contact model once; {twice} named more than once in {models}"
        )
    return models


def _checked_task(mesh, gripper, pose, task: Task, opts: GripperOptions) -> tuple[float, Task]:
    """(μ, the task with its unit ``down`` and its ``com`` checked inside ``mesh`` — the mesh's
    centre of mass when not given) of :func:`evaluate_models`, after the gripper-level checks
    (:func:`check_task`, :func:`check_down`)."""
    task = _gravity_task(task)
    mu = gripper.mu if opts.mu is None else opts.mu
    if mu is None:
        raise ValueError(
            "give mu (GripperOptions(mu=...)): the gripper has no friction coefficient of its own "
            "(Gripper.mu is None)"
        )
    d = check_task(mesh, task.mass, mu, task.down, checked=True)
    check_down(check_pose(pose, "gripper pose"), d)
    c = check_com(mesh.center_mass if task.com is None else task.com, mesh)
    with warnings.catch_warnings():  # the Task's values warned once when it was made
        warnings.simplefilter("ignore", ImplausibleWarning)
        return mu, replace(task, com=c, down=d)

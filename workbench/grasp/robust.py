"""Robust wrench resistance ``q_robust`` (thesis Eq. 2.101, §2.5.3.2; Mahler et al.).

``q_robust = (1/K) Σ R_i``: the fraction of K Monte-Carlo samples in which the
grasp still resists the (perturbed) gravity wrench.  Perturbed per sample:
the grasp pose (a rigid motion of all contact frames about the object origin:
rotation by a random axis–angle with σ_rot, translation with σ_trans — the
profiles ride along with the jaws; re-simulating the contact at the new pose is
the expensive exact alternative), the friction coefficient (relative σ_mu), the
mass (relative σ_mass) and the centre of mass (σ_com).  All samples are drawn
at once from one seeded generator (same seed ⇒ same q_robust).
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from ..groups import checked_group
from ..plausible import ImplausibleWarning
from ..quiet_log import quieted
from ..seeds import check_seed
from .contacts import check_object_point
from .gws import check_contacts, check_mu, check_resist_tol, check_wrench, squeeze_check
from .resistance import REPRESENTATIONS, CutStore
from .resistance import api as resistance_api
from .resistance.api import _resists

log = logging.getLogger(__name__)

G_ACC = 9.81  # m/s²


@dataclass(frozen=True)
class Perturbation:
    """Standard deviations of the Monte-Carlo perturbations (0 switches one off):
    grasp-pose translation [m] and rotation [rad], relative friction coefficient and mass
    (σ of a factor 1 + N(0, σ)), centre of mass [m]; ``n_samples`` is N_r of Eq. 2.101."""

    n_samples: int = 100  # N_r
    sigma_trans: float = 0.002  # m, grasp-pose translation (σ_r of the 6DFC paper, position part)
    sigma_rot: float = 0.05  # rad, grasp-pose rotation
    sigma_mu: float = 0.1  # relative
    sigma_mass: float = 0.1  # relative
    sigma_com: float = 0.002  # m

    def __post_init__(self) -> None:
        if isinstance(self.n_samples, bool) or int(self.n_samples) != self.n_samples or self.n_samples < 1:
            raise ValueError(f"n_samples must be an integer >= 1; got {self.n_samples!r}")
        from workbench.plausible import check

        quantity = {
            "sigma_trans": "pose_noise_trans",
            "sigma_rot": "pose_noise_rot",
            "sigma_mu": "relative_noise",
            "sigma_mass": "relative_noise",
            "sigma_com": "pose_noise_trans",
        }
        for name, q in quantity.items():
            v = getattr(self, name)
            if isinstance(v, (np.integer, np.floating)):
                v = v.item()
            check(q, v, f"Perturbation.{name}")


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a × b`` of (..., 3) arrays by components: ``np.cross``'s axis handling costs a
    sizeable part of the minimal-work metric's 5 ms budget per grasp (docs/decisions.md)."""
    return np.stack(
        [
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ],
        axis=-1,
    )


def check_mass(mass) -> float:
    """``mass`` [kg] as a float: a finite number > 0 and at most
    ``config.TOL.max_plausible_mass_kg`` (a larger value is taken for grams); else ValueError."""
    from workbench.plausible import check

    if isinstance(mass, (np.integer, np.floating)):
        mass = mass.item()
    return check("mass", mass, "mass")


def check_object_mass(mass, mesh=None, *, checked: bool = False) -> float:
    """``mass`` [kg] by :func:`check_mass`, and against the volume ``mesh`` encloses (its convex
    hull's: a hollow object's mesh may hold only its wall, while its mass counts the content): a
    mean density above the plausible range (:data:`workbench.plausible.RANGES` ``"density"``) is
    refused as a mass in grams (8 kg in a 240 mL box), one below it warned (a mesh in another
    unit, or a mass in tonnes).  The one rule of an object's mass: :func:`~.evaluate.evaluate_grasp`
    and the gripper tasks (:func:`~.gripper_eval.check_task`) call it.  ``checked``: ``mass``
    passed :func:`check_mass` already (a :class:`~.inputs.Task`'s), so its warnings are not
    given twice."""
    from workbench.plausible import RANGES, check

    m = float(mass) if checked else check_mass(mass)
    if mesh is None or not getattr(mesh, "is_volume", False):
        return m
    volume = float(mesh.convex_hull.volume)
    if not volume > 0:
        return m
    rho = m / volume
    cm3 = volume * 1e6
    what = f"mass {mass!r} kg in a {cm3:.3g} cm³ object: its mean density [kg/m³]"
    try:
        check("density", rho, what)  # warns (ImplausibleWarning) in the unusual bands
    except ValueError as exc:
        ext = np.ptp(np.asarray(mesh.vertices, float), axis=0)
        thin = ext.min() / ext.max()
        fix = (
            f"denser than any solid (osmium: 22,600): a mass in grams? pass {m / 1e3:g}"
            if rho > RANGES["density"].hi
            else "lighter than any object a gripper lifts: a mass in tonnes, or a mesh in millimetres?"
        )
        if rho > RANGES["density"].hi and thin < 0.01:
            # the volume, not the mass, is what is off: a sheet with next to no volume
            fix = (
                f"the mesh is nearly flat (its thinnest side {thin:.2g} of its longest: "
                f"{ext.min() * 1e3:.3g} mm of {ext.max() * 1e3:.3g} mm), so it holds next to no volume — "
                "check its export or the scale of one axis; if the mesh is right, a mass in grams? "
                f"pass {m / 1e3:g}"
            )
        if rho < RANGES["density"].lo:
            # the density's own unit hint ("probably in g/cm³ — pass 902 [kg/m³]") is a fix for an
            # argument nobody passed: the input is the mass, so the message speaks of the mass
            raise ValueError(
                f"mass {mass!r} kg is lighter than any object a gripper lifts for its {cm3:.3g} cm³: a mean "
                f"density of {rho:.3g} kg/m³, below the {RANGES['density'].lo:g} kg/m³ of the lightest "
                f"(real values: {RANGES['density'].examples}) — pass the mass in kg (grams divided by 1000 "
                f"twice? then {m * 1e3:g}); or is the mesh in millimetres?"
            ) from None
        raise ValueError(f"{exc} — {fix}") from None
    return m


def check_com(com, mesh=None) -> np.ndarray:
    """``com`` (3,) [m] as a float array, refused when it is not three finite numbers or lies
    outside ``mesh``'s convex hull by more than ``config.TOL.com_hull_rtol`` of the object's
    largest bounding-box side: a centre of mass is a weighted mean of the object's points, so it
    lies in their convex hull (a com in millimetres, or 30 mm off an 80 mm box, cannot be) — the
    one rule of a centre of mass for :func:`~.evaluate.evaluate_grasp`,
    :func:`~.gripper_eval.evaluate_models` and the engine trials.  The distance outside is
    measured to the hull's facet planes (the largest signed offset: exact off a facet, a lower
    bound off an edge or corner, so the rule errs towards accepting)."""
    from workbench import config
    from workbench.plausible import check

    try:
        c = np.asarray(com, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"com must be the centre of mass, (3,) numbers [m]; got {com!r}") from None
    if c.shape != (3,) or not np.isfinite(c).all():
        raise ValueError(f"com must be the centre of mass, (3,) finite numbers [m]; got {com!r}")
    if mesh is None:  # no object to judge it by: its lever about the origin, as a task wrench's
        c = check_object_point(c, "com", "the centre of mass [m]")
        if np.linalg.norm(c) > 0:
            check(
                "lever",
                float(np.linalg.norm(c)),
                "com's distance from the object origin [m]",
                named="lever of the weight about the object origin",
            )
        return c
    lo, hi = np.asarray(mesh.bounds, float)
    ext = float((hi - lo).max())
    if ((c < lo - ext) | (c > hi + ext)).any():  # farther than the object's own size: a unit
        raise ValueError(
            f"com {c.tolist()} lies far outside the object's bounding box "
            f"{lo.tolist()}–{hi.tolist()} [m]: is it in another unit than the mesh (metres)? "
            f"A centre of mass lies inside the object (pass e.g. mesh.center_mass = "
            f"{np.round(np.asarray(mesh.center_mass, float), 6).tolist()} for a uniform density)"
        )
    hull = mesh.convex_hull
    outside = float(np.max(np.einsum("ij,ij->i", hull.face_normals, c - hull.triangles[:, 0])))
    slack = config.TOL.com_hull_rtol * ext
    if outside > slack:
        raise ValueError(
            f"com {c.tolist()} lies {outside * 1e3:.3g} mm outside the object's convex hull (its "
            f"bounding box {np.round(lo, 6).tolist()}–{np.round(hi, 6).tolist()} m), more than "
            f"config.TOL.com_hull_rtol = {config.TOL.com_hull_rtol:g} x its size {ext * 1e3:.3g} mm: a "
            f"centre of mass is a weighted mean of the object's points and lies inside their hull — "
            f"check the com's frame (the mesh's) and its coordinates, or pass mesh.center_mass = "
            f"{np.round(np.asarray(mesh.center_mass, float), 6).tolist()} for a uniform density"
        )
    return c


def check_task_wrench(w_ext, name: str = "w_ext") -> np.ndarray:
    """``w_ext`` (6,) = ``[f; τ]`` [N, N·m] about the object origin as a float array, judged
    as a load a gripper could hold — the one rule of a given task wrench for
    :func:`~.evaluate.evaluate_grasp`: ``|f|`` by the plausible "weight" range, ``|τ|`` by the
    "torque" range and, with a force, the lever ``|τ|/|f|`` it implies (the load's line of action
    at least that far from the origin) by the "lever" range — a torque in N·mm beside a force
    in N puts a 2.9 N load 10 m away (refused above the range, warned with an
    :class:`~workbench.plausible.ImplausibleWarning` above its usual 0.3 m: a load half a metre
    off a hand-held object).  A lower-level call (``resists``, ``min_grasp_force``)
    takes any finite wrench (a normalised direction, a unit test's)."""
    from workbench.plausible import RANGES, check

    from .gws import check_wrench

    w = check_wrench(w_ext, name)
    f, tau = float(np.linalg.norm(w[:3])), float(np.linalg.norm(w[3:]))
    if f > 0:  # a task's force is a load a gripper could hold (1 MN is a slip)
        check("weight", f, f"{name}'s force |f| [N]")
    if f > 0 and tau / f > RANGES["lever"].hi:
        raise ValueError(
            f"{name}'s torque |τ| = {tau:g} N·m with a force |f| = {f:g} N puts the load at least "
            f"{tau / f:.3g} m from the object origin (a lever above {RANGES['lever'].hi:g} m): the "
            f"torque is probably in N·mm — pass {w[3:] * 1e-3} N·m — or the origin is not on the object"
        )
    if f > 0 and tau / f > RANGES["lever"].usual[1]:  # within the range, above its usual part: warns
        check(
            "lever",
            tau / f,
            f"{name}'s lever |τ|/|f| (|τ| = {tau:g} N·m over |f| = {f:g} N: a torque in N·mm, or an "
            "origin off the object?)",
        )
    check("torque", tau, f"{name}'s torque |τ| [N·m]")
    return w


def gravity_wrench(mass: float, com, down=(0.0, 0.0, -1.0)) -> np.ndarray:
    """(6,) gravity wrench about the object origin: ``[m g d; com × m g d]``, g = 9.81 m/s²
    (:data:`G_ACC`).

    mass : kg, > 0 and at most ``config.TOL.max_plausible_mass_kg`` (a larger value is
    taken for grams); com : (3,) centre of mass [m], within ``TOL.max_object_extent_m`` of
    the origin (farther is taken for millimetres); down : (3,) gravity direction.
    """
    check_mass(mass)
    c = check_object_point(com, "com", "the centre of mass [m]")
    d = np.asarray(down, float)
    if d.shape != (3,) or not np.isfinite(d).all() or np.linalg.norm(d) == 0:
        raise ValueError(f"down must be a non-zero (3,) direction; got {d.tolist()}")
    return _gravity(float(mass), c, d)


def _gravity(mass: float, com: np.ndarray, down: np.ndarray) -> np.ndarray:
    """:func:`gravity_wrench` of inputs already checked (a perturbed sample of a judged task is
    not judged again: a mass drawn past a limit is the noise's, not the user's)."""
    f = mass * G_ACC * down / np.linalg.norm(down)
    return np.concatenate([f, cross3(com, f)])


def q_robust(
    contacts,
    mu: float,
    task,
    perturbation: Perturbation | None = None,
    *,
    seed: int | np.random.Generator = 0,
    representation: str = "model",
    cuts: CutStore | None = None,
) -> float:
    """Eq. 2.101 for the task "hold against gravity" (vertical lifting): the fraction
    of perturbed samples that :func:`~workbench.grasp.resistance.resists` says hold —
    the same meaning of "resisted", the same ``representation`` (default: the contact
    models themselves).

    task : a :class:`~.inputs.Task` — gravity on its ``mass`` [kg] at ``com`` (3,) [m] along its
        ``down`` (3,; gravity's direction in the object frame), each perturbed per sample; or its
        fixed ``w_ext`` — or a fixed disturbance (6,) [N, N·m] given as an array, any finite
        wrench (as :func:`~.resistance.resists` takes), resisted as is (σ_mass and σ_com do not
        apply to a fixed wrench).
    cuts : a cut store shared by the samples (a fresh one if None).

    The pose noise turns the gripper about the grasp's centre — the contacts' origins weighted
    by their normal forces (for two jaws at one force, the midpoint of their pressure centres) —
    and then shifts it, so q does not depend on where the object sits in its mesh file's frame.
    The contacts ride along rigidly: no contact is recomputed at the perturbed pose (a pad
    that would slide off the object still holds).  Robustness that moves the gripper and
    recomputes the contact: :func:`~.gripper_eval.evaluate_gripper` with a
    :class:`~.pose_robust.PoseNoise` (6DFC §V-B.1).
    """
    contacts = check_contacts(contacts)
    squeeze_check(contacts)
    check_mu(mu)
    if representation not in REPRESENTATIONS:
        raise ValueError(f"representation must be one of {REPRESENTATIONS}; got {representation!r}")
    w_ext, mass, com, down = _robust_load(task)
    p = checked_group(perturbation, Perturbation, "perturbation")
    cuts = CutStore() if cuts is None else cuts
    rng = np.random.default_rng(check_seed(seed))
    K = p.n_samples
    Rs = Rotation.from_rotvec(rng.normal(0.0, p.sigma_rot, (K, 3))).as_matrix()
    ts = rng.normal(0.0, p.sigma_trans, (K, 3))
    mus = mu * np.clip(1 + rng.normal(0.0, p.sigma_mu, K), 0.0, None)
    ok = 0
    pivot = grasp_centre(contacts)
    if w_ext is None:
        # a perturbed mass stays positive (a draw below -100 % is clipped, not a negative mass)
        masses = mass * np.clip(1 + rng.normal(0.0, p.sigma_mass, K), 1e-6, None)
        coms = np.asarray(com, float) + rng.normal(0.0, p.sigma_com, (K, 3))
    tol = check_resist_tol(None)
    # the samples are perturbations of the inputs checked above, not a user's inputs: none is
    # judged again (a friction drawn past 2 or a mass past the limit is the noise's); their
    # solver fallbacks are logged once for the call, with a count, not once per sample
    fallbacks: list[str] = []
    with quieted(resistance_api.log):  # where resists logs a fallback as it happens
        for i in range(K):
            moved = [c.moved(Rs[i], pivot - Rs[i] @ pivot + ts[i]) for c in contacts]
            w = _gravity(masses[i], coms[i], down) if w_ext is None else w_ext
            answer = _resists(moved, w, float(mus[i]), representation, cuts, None, tol)
            ok += bool(answer)
            fallbacks += answer.fallbacks
    if fallbacks:
        log.warning("q_robust: %d solver fallbacks in %d samples, e.g. %s", len(fallbacks), K, fallbacks[0])
    return ok / K


def grasp_centre(contacts) -> np.ndarray:
    """(3,) [m] the centre a gripper-pose perturbation turns the ``contacts`` about: their frames'
    origins weighted by their normal forces (bounds, for cone contacts), or their plain mean when
    every force is 0."""
    t = np.array([c.t for c in contacts], dtype=float)
    f = np.array([c.force for c in contacts], dtype=float)
    return f @ t / f.sum() if f.sum() > 0 else t.mean(axis=0)


def _robust_load(task) -> tuple:
    """``(w_ext, mass, com, down)`` of :func:`q_robust`'s ``task``: a fixed wrench (6,) and
    None, None, None, or None and gravity's mass [kg], com (3,) [m] and down (3,), checked.
    A Task is recognised by its fields (this module is below :mod:`~.inputs`, which imports it)."""
    if not all(hasattr(task, k) for k in ("w_ext", "mass", "com", "down")):
        return check_wrench(task, "task (a Task, or a fixed disturbance (6,))"), None, None, None
    if task.w_ext is not None:
        return check_wrench(task.w_ext, "task.w_ext"), None, None, None
    with warnings.catch_warnings():  # an unusual mass: the Task warned when it was made
        warnings.simplefilter("ignore", ImplausibleWarning)
        gravity_wrench(task.mass, task.com, down=task.down)  # validates mass, com and down
    return None, task.mass, np.asarray(task.com, float), np.asarray(task.down, float)

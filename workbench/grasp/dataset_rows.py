"""One top-grasp candidate scored by several contact models: a row of the grasp dataset of
thesis §4.2.2 (Figs 4.8–4.9).

The contact is computed once from the gripper's pose (:func:`~.gripper_eval.gripper_contact`:
both pads pressed on the mesh, the object settled between them) and shared by the models; 6DLS
and 6DFC share one fitted limit surface (a :class:`~workbench.limit_surface.LimitSurfaceCache`
per candidate).  Each model's quality is the robust wrench resistance of Eq. 2.101: the fraction
of ``N_r`` perturbed samples (pose, μ, mass, centre of mass) whose gravity wrench the model's
contacts resist (Eq. 2.100, :func:`~.robust.q_robust`), beside the nominal verdict and its force
margin ``1 − f_min / f`` (Eq. 4.4).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..groups import checked_group
from ..limit_surface import LimitSurfaceCache
from ..seeds import check_seed
from .gripper_eval import _checked_models, _judge_sets, gripper_contact
from .inputs import Task
from .models import contact_sets
from .resistance import CutStore
from .robust import Perturbation, gravity_wrench, q_robust
from .settle import SettledContact

__all__ = [
    "DatasetOptions",
    "contact_summary",
    "dataset_cost",
    "model_columns",
    "quality_agreement",
    "quality_summary",
    "nonplanarity",
    "score_candidate",
]


@dataclass(frozen=True)
class DatasetOptions:
    """How each candidate is scored.

    mu : the pads' friction coefficient, in (0, 2].
    robust : the perturbations of Eq. 2.101 (``n_samples`` is N_r; the thesis's example has 10).
    settle : True (default): the object free to turn between the pads until their normal forces
        balance, each pad then carrying its force (:mod:`~.settle`; ten or more presses a grasp);
        False: each pad pressed once at the planned pose to the compression the force gives over
        the whole pad — a grasp a few degrees off square then touches with an edge only.
    seed : the perturbations' and the models' samplers' seed.
    """

    mu: float = 0.3
    robust: Perturbation = field(default_factory=lambda: Perturbation(n_samples=10))
    settle: bool = True
    seed: int = 0

    def __post_init__(self) -> None:
        from ..sources.gripper import check_pad_mu

        check_pad_mu(self.mu)
        object.__setattr__(self, "mu", float(self.mu))
        object.__setattr__(self, "robust", checked_group(self.robust, Perturbation, "robust"))
        if not isinstance(self.settle, bool):
            raise ValueError(f"settle must be True or False; got {self.settle!r}")
        object.__setattr__(self, "seed", check_seed(self.seed, generator=False))


def model_columns(model: str) -> tuple[str, ...]:
    """The columns :func:`score_candidate` writes for ``model``: ``q_<m>`` (Eq. 2.101),
    ``held_<m>`` and ``margin_<m>`` (the nominal verdict), ``t_<m>_build_ms`` (its contact
    sets) and ``t_<m>_q_ms`` (verdict and Eq. 2.101's samples)."""
    return (f"q_{model}", f"held_{model}", f"margin_{model}", f"t_{model}_build_ms", f"t_{model}_q_ms")


def nonplanarity(centers, areas) -> float:
    """Area-weighted RMS distance [m] of a contact's element ``centers`` (n, 3) [m] to their best
    plane (weights ``areas`` (n,) > 0): 0 on a flat face; how far a contact is from the planar
    contacts of §2.4 (the smallest eigenvalue of the centres' weighted covariance, square-rooted)."""
    centers = np.asarray(centers, float)
    areas = np.asarray(areas, float)
    if centers.ndim != 2 or centers.shape[1] != 3 or areas.shape != (len(centers),) or len(centers) == 0:
        raise ValueError(
            f"centers must be (n, 3) and areas (n,), n >= 1; got {centers.shape} and {areas.shape}"
        )
    if not (np.isfinite(centers).all() and np.isfinite(areas).all() and (areas > 0).all()):
        raise ValueError("centers must be finite and areas finite and > 0")
    w = areas / areas.sum()
    c = centers - w @ centers
    cov = (c * w[:, None]).T @ c
    return float(np.sqrt(max(np.linalg.eigvalsh(cov)[0], 0.0)))


def contact_summary(contact: SettledContact) -> dict:
    """Per jaw ``jaw{1,2}_F_N`` (normal force [N]), ``_area_mm2``, ``_n_elements``,
    ``_nonplanarity_mm`` (area-weighted RMS distance of the element centres to their best plane:
    0 on a flat face) and ``_compression_mm`` (how deep the pad is pressed to carry its force:
    near the layer's thickness it has bottomed out), and the settle's ``settle_tilt_deg`` and
    ``settle_converged`` (False: the normal forces still turn the object where the settle
    stopped, ``reason`` says how much; None when the settle was off, as it then searched
    nothing); NaN / 0 / False for a miss."""
    out: dict = {
        "settle_tilt_deg": math.degrees(contact.tilt) if contact.touches else math.nan,
        "settle_converged": bool(contact.touches and contact.converged) if contact.searched else None,
    }
    for j in (1, 2):
        p = contact.profiles[j - 1] if contact.touches else None
        if p is None:
            out |= {f"jaw{j}_F_N": math.nan, f"jaw{j}_area_mm2": math.nan}
            out |= {f"jaw{j}_n_elements": 0, f"jaw{j}_nonplanarity_mm": math.nan}
            out[f"jaw{j}_compression_mm"] = math.nan
            continue
        a = np.asarray(p.areas, float)
        out[f"jaw{j}_F_N"] = float(np.sum(np.asarray(p.pressures, float) * a))
        out[f"jaw{j}_area_mm2"] = float(a.sum() * 1e6)
        out[f"jaw{j}_n_elements"] = int(a.size)
        out[f"jaw{j}_nonplanarity_mm"] = nonplanarity(p.centers, a) * 1e3
        out[f"jaw{j}_compression_mm"] = float(contact.depths[j - 1]) * 1e3
    return out


def _bottomed_out(contact: SettledContact, thickness: float) -> bool:
    """Whether either pad of ``contact`` is pressed deeper than ``thickness`` [m], its layer."""
    return bool(contact.touches and max(contact.depths) > thickness)


def score_candidate(mesh, gripper, pose, task: Task, models, options: DatasetOptions | None = None) -> dict:
    """One dataset row: ``gripper`` at ``pose`` (4, 4; the gripper in the mesh's frame [m]) on
    ``mesh`` (metres), holding the gravity ``task`` (a :class:`~.inputs.Task` with ``mass`` [kg]
    and ``com`` (3,) [m]), scored by each of ``models`` (names of :data:`~.models.MODELS`).

    Returns ``status`` ("scored", or "miss" when a pad touches nothing: every model's q 0, not
    held), ``reason``, ``t_contact_ms``, :func:`contact_summary`'s columns, ``bottomed_out``
    (a pad pressed deeper than the gripper's pad layer is thick, said in ``reason`` too; the row
    is scored all the same) and :func:`model_columns` per model.  ``q_<m>`` is on the grid
    ``k / N_r``.
    """
    opts = checked_group(options, DatasetOptions, "options")
    task = checked_group(task, Task, "task")
    if task.mass is None or task.com is None:
        raise ValueError("task must be gravity on a mass at a com: Task(mass=..., com=..., down=...)")
    models = _checked_models(models)
    t0 = time.perf_counter()
    contact = gripper_contact(mesh, gripper, pose, settle=opts.settle)
    row: dict = {
        "status": "scored" if contact.touches else "miss",
        "reason": contact.reason,
        "t_contact_ms": (time.perf_counter() - t0) * 1e3,
        **contact_summary(contact),
        "bottomed_out": _bottomed_out(contact, gripper.pad.thickness),
    }
    if row["bottomed_out"]:
        deepest = max(contact.depths) * 1e3
        note = (
            f"a pad is pressed {deepest:.2f} mm, deeper than its {gripper.pad.thickness * 1e3:g} mm layer: "
            "the finger behind it would touch, which a Winkler pad does not describe"
        )
        row["reason"] = f"{row['reason']}; {note}" if row["reason"] else note
    if not contact.touches:
        for m in models:
            row |= dict(zip(model_columns(m), (0.0, False, 0.0, 0.0, 0.0), strict=True))
        return row
    down = contact.rotation @ np.asarray(task.down, float)  # the object turned as it settled
    turned = Task(mass=task.mass, com=task.com, down=tuple(down))
    w = gravity_wrench(task.mass, task.com, down=down)
    cache, cuts = LimitSurfaceCache(), CutStore()
    for m in models:
        t0 = time.perf_counter()
        sets = [c for p in contact.profiles for c in contact_sets(p, m, cache=cache, seed=opts.seed)]
        t1 = time.perf_counter()
        verdict = _judge_sets(sets, m, w, mu=opts.mu, cuts=cuts)
        q = q_robust(sets, opts.mu, turned, opts.robust, seed=opts.seed, cuts=cuts)
        t2 = time.perf_counter()
        values = (float(q), verdict.resisted, verdict.margin, (t1 - t0) * 1e3, (t2 - t1) * 1e3)
        row |= dict(zip(model_columns(m), values, strict=True))
    return row


def dataset_cost(
    ms_per_grasp: float, n_grasps: int, workers=(1, 2, 8, 32, 128), utilisation: float = 1.0
) -> dict:
    """What ``n_grasps`` candidates cost at ``ms_per_grasp`` [ms, one core, every model]:
    ``core_hours`` and ``hours_on`` each worker count, each worker one core busy the fraction
    ``utilisation`` of the time (1: no scheduling overhead, the fastest the cluster could be)."""
    if not (isinstance(ms_per_grasp, int | float) and math.isfinite(ms_per_grasp) and ms_per_grasp > 0):
        raise ValueError(f"ms_per_grasp must be a positive time [ms]; got {ms_per_grasp!r}")
    if isinstance(n_grasps, bool) or not isinstance(n_grasps, int | np.integer) or n_grasps < 1:
        raise ValueError(f"n_grasps must be an integer >= 1; got {n_grasps!r}")
    if not (isinstance(utilisation, int | float) and 0 < utilisation <= 1):
        raise ValueError(f"utilisation must be a fraction in (0, 1]; got {utilisation!r}")
    core_h = ms_per_grasp * n_grasps / 3.6e6
    return {
        "core_hours": core_h,
        "hours_on": {int(n): core_h / (int(n) * utilisation) for n in workers},
    }


def quality_summary(q, candidates) -> dict:
    """One model's qualities ``q`` (n,) in [0, 1] over the candidates numbered ``candidates`` (n,):
    ``max_q``, ``median_q``, ``frac_q_ge_half`` (the share a 0.5 threshold calls held) and
    ``best_candidate`` (the first with the largest q)."""
    q = np.asarray(q, float)
    if q.ndim != 1 or q.size == 0 or len(candidates) != q.size:
        raise ValueError(
            f"q must be (n,) with n >= 1 and one candidate each; got {q.shape}, {len(candidates)}"
        )
    if not (np.isfinite(q).all() and (q >= 0).all() and (q <= 1).all()):
        raise ValueError("q must be qualities in [0, 1]")
    return {
        "max_q": float(q.max()),
        "median_q": float(np.median(q)),
        "frac_q_ge_half": float(np.mean(q >= 0.5)),
        "best_candidate": int(candidates[int(np.argmax(q))]),
    }


def quality_agreement(a, b) -> tuple[float | None, float]:
    """How alike two models' qualities (n,) of the same candidates are: Spearman's rank
    correlation (None when either is constant: no ranking to compare) and the median |a − b|."""
    from scipy.stats import spearmanr

    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape or a.ndim != 1 or a.size < 2:
        raise ValueError(
            f"a and b must be (n,) qualities of the same n >= 2 candidates; got {a.shape}, {b.shape}"
        )
    rho = float(spearmanr(a, b).statistic) if np.ptp(a) > 0 and np.ptp(b) > 0 else None
    return rho, float(np.median(np.abs(a - b)))

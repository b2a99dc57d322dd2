"""Simulated grasp outcomes from the *exact* 6DFW sets of the profiles (no robot data here).

The sensitivity studies' ground truth (thesis Fig 4.4, Table 4.1's scenes): a grasp resists its
disturbance iff the exact sets (:mod:`.exact`, no limit-surface model) resist it at the grasp's
own true μ and force (:func:`truth_deciders`).

The minimal-work study (thesis §4.3): the gripper closes to ``safety ×`` the jaw force the
exact sets need (:func:`required_force_scale`, capped at the gripper's force), with friction
and force noise; the grasp succeeds iff the exact sets resist every pose's wrench in most noise samples
and the jaw closing at that force, from a wall stiffness, stays within a limit
(:func:`simulated_success`).  Shares no limit surface, map interpolation or linearisation with
the quality metrics it judges.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial

import numpy as np

from ..profile import ContactProfile
from .exact import ExactContacts, resists_exact

__all__ = ["TRUTH_COLUMNS_SEED", "TruthModel", "required_force_scale", "simulated_success", "truth_deciders"]

#: seed of the exact sets' starting columns in the sensitivity studies' truth: one fixed draw,
#: so the truth of a grasp does not depend on the study's seed (which draws the grasps)
TRUTH_COLUMNS_SEED = 1

#: noisy friction and force factors ``1 + N(0, σ)`` are floored here: a draw of ~10 σ below
#: the mean would otherwise give zero or negative friction / force (non-physical, and refused
#: by the resistance test); 0.05 keeps such a draw a near-certain failure.
NOISE_FACTOR_FLOOR = 0.05


def _resists(exact: ExactContacts, w: np.ndarray, mu: float, scale: float) -> bool:
    return bool(resists_exact(exact, w, mu, forces=exact.F * scale)[0])


def truth_deciders(
    profiles: Sequence[ContactProfile], mu: Sequence[float], force_scale: Sequence[float], n_start: int
) -> list[Callable[[np.ndarray], bool]]:
    """The sensitivity studies' simulated ground truth, one decider per grasp: decider ``i``
    says whether the exact 6DFW sets of ``profiles`` (:class:`~.exact.ExactContacts`, starting
    columns ``n_start`` sampled with :data:`TRUTH_COLUMNS_SEED`, built once for every grasp)
    pressed with forces ``F × force_scale[i]`` resist a disturbance ``w`` (6,) [N, N m] in the
    profiles' frame at friction ``mu[i]`` (:func:`~.exact.resists_exact`, Eq. 2.100's meaning
    of "resisted").

    profiles : the jaws' contact profiles of the grasps (one set, shared by all of them), each
        with its own force F [N].
    mu : (n,) each grasp's true friction coefficient (the noisy μ of the truth, or the nominal).
    force_scale : (n,) each grasp's true force over the profiles' F: the true force itself for
        unit-force profiles, true / read force for profiles at the sensor's reading.
    n_start : starting columns of the column generation (``n_start // 2`` sampled twists).

    A margin bisection calls a decider at many scales of its disturbance; the exact sets are
    stateless between calls, so the answers do not depend on the order of the calls.
    """
    if len(mu) != len(force_scale):
        raise ValueError(
            f"mu and force_scale must give one value per grasp, the same count; got {len(mu)} and "
            f"{len(force_scale)} — pass the true mu and force scale of every grasp"
        )
    exact = ExactContacts(list(profiles), n_start=n_start, seed=TRUTH_COLUMNS_SEED)
    return [partial(_resists, exact, mu=m, scale=s) for m, s in zip(mu, force_scale, strict=True)]


def required_force_scale(
    exact: ExactContacts, w: np.ndarray, mu: float, hi: float, iters: int = 12, span: float = 1000.0
) -> float:
    """Smallest scale of the profiles' forces ``exact.F`` (2,) at which the exact sets resist
    the wrench ``w`` (6,) with friction ``mu``: bisection on the log scale in ``[hi / span, hi]``,
    ``iters`` steps (the result is at most a factor ``span^(2^-iters)`` above the true scale,
    0.17 % for the defaults); ``hi / span`` if resisted there, ``inf`` if not resisted at ``hi``.
    """
    if not (np.isfinite(hi) and hi > 0 and np.isfinite(span) and span > 1):
        raise ValueError(f"hi must be a finite scale > 0 and span > 1; got hi={hi!r}, span={span!r}")
    if not _resists(exact, w, mu, hi):
        return np.inf
    lo = hi / span
    if _resists(exact, w, mu, lo):
        return lo
    for _ in range(iters):
        mid = np.sqrt(lo * hi)
        lo, hi = (lo, mid) if _resists(exact, w, mu, mid) else (mid, hi)
    return hi


@dataclass(frozen=True)
class TruthModel:
    """The simulated gripper and its noise, the same for every grasp of a study: it closes to
    ``safety ×`` the required force, at most ``force_cap`` [N per jaw]; a jaw closing beyond
    ``closing_limit`` [m] fails the grasp; ``noise_samples`` draws of friction and force, with
    relative standard deviations ``sigma_mu`` and ``sigma_force``.  Values only: an experiment's
    config keys check them (e.g. ``minimal_work``'s ``force_cap``, ``sigma_mu``)."""

    safety: float
    force_cap: float  # [N per jaw]
    closing_limit: float  # [m]
    noise_samples: int
    sigma_mu: float  # relative
    sigma_force: float  # relative


def simulated_success(
    exact: ExactContacts,
    poses: np.ndarray,
    mu: float,
    reading: float,
    *,
    stiffness: float,
    model: TruthModel,
    rng: np.random.Generator,
) -> tuple[bool, float]:
    """(success, required jaw force [N]) of a grasp holding the wrenches ``poses`` (P, 6).

    ``reading`` [N] is the jaw force the profiles were made at (their sensor reading): the
    required force ``f_req`` is the largest over poses of :func:`required_force_scale` times
    it (``inf`` when some pose is not resisted at ``model.force_cap`` [N]).  The gripper
    (:class:`TruthModel`) applies ``f_app = min(safety f_req, force_cap)``; each of
    ``noise_samples`` draws scales friction by ``1 + N(0, sigma_mu)`` and force by
    ``1 + N(0, sigma_force)`` (floored at :data:`NOISE_FACTOR_FLOOR`).  Success iff more than
    half of the draws resist every pose and the closing ``f_app / stiffness`` [m] (stiffness
    [N/m], ``inf``: rigid) is at most ``closing_limit`` [m].  ``rng`` is drawn from only when
    ``f_req`` is finite.
    """
    if not (np.isfinite(reading) and reading > 0):
        raise ValueError(f"reading must be the profiles' jaw force > 0 [N]; got {reading!r}")
    F0 = reading
    f_req = max(required_force_scale(exact, w, mu, model.force_cap / F0) for w in poses) * F0
    if not np.isfinite(f_req):
        return False, f_req
    f_app = min(model.safety * f_req, model.force_cap)
    ok = 0
    for _ in range(model.noise_samples):
        mu_k = mu * max(1 + rng.normal(0, model.sigma_mu), NOISE_FACTOR_FLOOR)
        f_k = f_app * max(1 + rng.normal(0, model.sigma_force), NOISE_FACTOR_FLOOR)
        ok += all(_resists(exact, w, mu_k, f_k / F0) for w in poses)
    return bool(ok > model.noise_samples / 2 and f_app / stiffness <= model.closing_limit), f_req

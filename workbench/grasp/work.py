"""Minimal work of the jaws (thesis §4.3.2.3, Eqs. 4.4–4.6) and the minimal-force quality.

The grasp's minimal normal forces ``f_i`` (Eq. 4.4, :func:`~.resistance.min_grasp_force`
with ``objective="sum"``) press the object by ``d_i = f_i / s_i + ε`` at each contact
(Hooke's law with the object's stiffness ``s_i`` there; ε lets rigid regions,
``s_i = inf``, count), and the jaws do the work ``W = Σ_i f_i d_i`` (Eq. 4.5).  The
qualities normalise by a maximum chosen from physical data:
``q_work = 1 − W / W_max`` (Eq. 4.6), ``q_force = 1 − Σ f / f⊥max`` (§4.3.3.2).

``s_i`` is the object's stiffness as the thesis measured it (§4.3.3.1): the squeezing force
over the closing of *both* jaws, ``s = f / Δ``, so ``d_i = f_i / s_i`` charges each contact
the grasp's whole closing (``W ≈ 2 f² / s`` for a grasp of two equal forces) — the thesis's
convention, kept.  Where ε ≪ f / s it scales every grasp's W alike (charging half the
closing would halve them all), so the ranking, and ``q_work`` with ``W_max`` fitted on the
same grasps, hardly depend on it.

W is evaluated at the forces that minimise ``Σ f`` — the thesis's algorithm — not
minimised itself: with unequal stiffness a different split of the forces could need
less work.  With every contact rigid, ``W = ε Σ f`` and ``q_work`` ranks grasps as
``q_force`` does.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from .. import config
from .gws import check_contacts, check_wrench
from .resistance import CutStore, min_grasp_force
from .resistance.api import _check as _check_question
from .resistance.program import assemble
from .resistance.solvers import MinLP
from .stiffness_map import StiffnessMap, check_stiffness

log = logging.getLogger(__name__)

__all__ = ["MinimalWork", "minimal_work", "minimal_work_poses", "q_force", "q_work", "work"]


def _eps(eps) -> float:
    e = config.DEFAULTS.work_eps if eps is None else eps
    if isinstance(e, (bool, np.bool_)) or not np.isscalar(e) or not (np.isfinite(e) and e >= 0):
        raise ValueError(
            f"eps must be a finite displacement >= 0 [m] (Eq. 4.5); got {e!r} — "
            f"None uses config.DEFAULTS.work_eps = {config.DEFAULTS.work_eps:g} m"
        )
    from ..plausible import check

    # ε is a jaw displacement (a rigid region's pad compression): the closing range's hard limits
    return check("closing", float(e), "eps (a displacement [m], Eq. 4.5)", warn=False)


def _check_stiffness(stiffness, n: int) -> np.ndarray:
    return check_stiffness(
        stiffness,
        n,
        "contact",
        fix="evaluate a StiffnessMap at the contact points: smap(np.array([c.t for c in contacts]))",
    )


def _check_forces(forces) -> np.ndarray:
    """(N,) normal forces [N]: finite, >= 0 (a contact may carry none)."""
    try:
        f = np.asarray(forces, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"forces must be (N,) normal forces [N], numbers; got {forces!r}") from None
    if f.ndim != 1:
        raise ValueError(f"forces must be (N,) normal forces [N]; got shape {f.shape}")
    bad = ~np.isfinite(f) | (f < 0)
    if bad.any():
        k = int(np.argmax(bad))
        raise ValueError(
            f"forces must be finite and >= 0 [N]; got {f[k]} at contact {k} "
            "(an unresisted grasp has no forces: its work is inf, see minimal_work)"
        )
    return f


def displacements(forces, stiffness, eps: float | None = None) -> np.ndarray:
    """(N,) jaw displacements ``d_i = f_i / s_i + ε`` [m] (Eq. 4.5); ``s_i = inf`` gives ε.

    forces : (N,) float — normal forces [N], finite, >= 0.
    stiffness : (N,) float — object stiffness at each contact [N/m], > 0 or ``np.inf``.
    eps : ε [m], >= 0; None reads ``config.DEFAULTS.work_eps``.
    """
    f = _check_forces(forces)
    s = _check_stiffness(stiffness, len(f))
    d = f / s
    return d + _eps(eps)


def work(forces, stiffness, eps: float | None = None) -> float:
    """``W = Σ_i f_i (f_i / s_i + ε)`` [J] (thesis Eq. 4.5).

    forces : (N,) float — normal forces [N], finite, >= 0; the largest judged by the jaw-force
        range (:data:`workbench.plausible.RANGES` ``"jaw_force"``, hard limits only: a contact may
        carry a few mN), so 5000 given for 5 N is refused as millinewtons.
        (:func:`displacements` takes any such forces: the building block of a computed answer.)
    stiffness : (N,) float — object stiffness at each contact [N/m], > 0; ``np.inf``
        for a rigid contact (its displacement is ε).
    eps : ε [m], >= 0; None reads ``config.DEFAULTS.work_eps``.
    """
    f = _check_forces(forces)
    if f.size and f.max() > 0:
        from ..plausible import check

        k = int(np.argmax(f))
        check("jaw_force", float(f[k]), f"forces[{k}] (a contact's normal force [N])", warn=False)
    return float(f @ displacements(f, stiffness, eps))


def _quality(x, x_max, name: str, max_name: str):
    xm = x_max
    if isinstance(xm, (bool, np.bool_)) or not np.isscalar(xm) or not (np.isfinite(xm) and xm > 0):
        raise ValueError(
            f"{max_name} must be a finite number > 0 (the normaliser); got {xm!r} — "
            "fit it on training grasps with workbench.grasp.fit_normaliser"
        )
    a = np.asarray(x, dtype=float)
    bad = np.isnan(a) | (a < 0)
    if bad.any():
        raise ValueError(
            f"{name} must be >= 0 (np.inf for an unresisted grasp); got {a[bad].ravel()[:3].tolist()}"
        )
    q = 1.0 - a / float(xm)
    return float(q) if q.ndim == 0 else q


def q_work(W, W_max: float):
    """Minimal-work quality ``q_work = 1 − W / W_max`` (thesis Eq. 4.6).

    W : float or (n,) float — work [J], >= 0; ``np.inf`` (unresisted) gives ``-inf``.
    W_max : normaliser [J], > 0 (the thesis chose it from physical data, §4.3.3.2).

    Not clipped: ``W > W_max`` gives ``q < 0``, so the ranking of grasps is kept.
    Returns a float for a scalar ``W``, else an array of its shape.
    """
    return _quality(W, W_max, "W", "W_max")


def q_force(f_sum, f_max: float):
    """Minimal-force quality ``q_force = 1 − f⊥ / f⊥max`` (thesis §4.3.3.2).

    f_sum : float or (n,) float — minimal total normal force [N] (Eq. 4.4), >= 0;
        ``np.inf`` (unresisted) gives ``-inf``.
    f_max : normaliser [N], > 0 ("determined experimentally").

    Not clipped (as :func:`q_work`).  Returns a float for a scalar, else an array.
    """
    return _quality(f_sum, f_max, "f_sum", "f_max")


@dataclass(frozen=True)
class MinimalWork:
    """Work of the minimal grasp forces (thesis Eqs. 4.4–4.5).

    f_sum : ``Σ f_i`` [N], the minimal total normal force; ``inf`` when unresisted.
    forces : (N,) per-contact normal forces [N] (NaN when unresisted).
    stiffness : (N,) stiffness used [N/m] (``inf``: rigid).
    displacements : (N,) ``d_i = f_i / s_i + ε`` [m] (NaN when unresisted).
    W : work [J]; ``inf`` when unresisted.
    eps : ε used [m].
    feasible : whether some forces resist ``w_ext`` — any forces: Eq. 4.4 leaves them free,
        so a contact's own ``force`` / ``f_max`` does not bound them (as
        :attr:`~.resistance.MinimalForce.feasible`; :func:`~.resistance.resists` asks about
        the contacts' given forces instead — read ``forces`` against your gripper's limit).
    solver, representation, fallbacks, converged : of the
        :class:`~.resistance.MinimalForce` answer (``converged`` False: cutting planes
        ran out and ``f_sum`` is a lower bound).
    """

    f_sum: float
    forces: np.ndarray
    stiffness: np.ndarray
    displacements: np.ndarray
    W: float
    eps: float
    feasible: bool
    solver: str
    representation: str
    fallbacks: tuple[str, ...] = ()
    converged: bool = True


def minimal_work(
    contacts,
    w_ext,
    mu: float,
    stiffness,
    *,
    eps: float | None = None,
    representation: str = "model",
    cuts: CutStore | None = None,
) -> MinimalWork:
    """Minimal grasp forces against ``w_ext`` and the work they do (Eqs. 4.4–4.5).

    contacts : list of N :class:`~.contacts.ContactSet` (one per jaw in the thesis:
        a 6DLS of each jaw's REACH profile).
    w_ext : (6,) disturbance wrench [N, N·m], object frame.
    mu : friction coefficient.
    stiffness : (N,) float — object stiffness at each contact [N/m], ``np.inf`` rigid; or a
        :class:`~.stiffness_map.StiffnessMap`, evaluated at the contacts' points ``c.t`` (each
        contact's origin: the pressure centre of a 6DLS).
    eps : ε of Eq. 4.5 [m]; None reads ``config.DEFAULTS.work_eps``.
    representation : "model" (default: the limit surfaces themselves, an ellipsoid as its
        second-order cone) or "outer" (the thesis's ``C_outer``, Eq. 3.28, an LP: a lower bound);
        passed to :func:`~.resistance.min_grasp_force` with ``objective="sum"`` (each
        contact's force free, ``Σ f`` minimised: Eq. 4.4 as published).
    cuts : cut store for quartic models under "model" (shared across calls).

    An unresisted ``w_ext`` gives ``f_sum = W = inf`` and ``feasible=False``.

    Notes
    -----
    * The balance is accepted to ``config.TOL.resist_rtol`` of the capacity at the
      contacts' *given* forces (``ContactSet.force``), so give them forces of the
      order of the answer: at 1e4 times the minimal force the band is ~10 % of it.
    * "outer" lies outside a 6DLS ellipsoid, so its forces are lower bounds that converge
      slowly with M in six dimensions (a point or soft-point contact is polyhedral already:
      its ``kind``, inner or outer polygon, decides).  On a curved jaw's ill-conditioned
      ellipsoid they can be several times too low, and finite where the ellipsoid resists at
      no force (``tests/test_work.py`` has such a case): use "outer" only to reproduce the
      thesis's program.
    * Stiffness is per contact: a jaw made of many contacts (REACH elements) would
      count each element's force in its own ``f (f / s + ε)``; pass one contact per
      jaw (the thesis: the 6DLS of the jaw's REACH profile).
    * Several poses of one grasp (a task's, or both tasks'): :func:`minimal_work_poses`
      gives the same numbers at about half the cost of a call per pose.
    """
    (res,) = _minimal_work_many(contacts, [w_ext], mu, stiffness, eps, representation, cuts)
    return res


def minimal_work_poses(
    contacts,
    wrenches,
    mu: float,
    stiffness,
    *,
    eps: float | None = None,
    representation: str = "model",
    cuts: CutStore | None = None,
) -> list[MinimalWork]:
    """:func:`minimal_work` at each of k disturbances — a task's poses
    (:func:`~.tasks.task_wrenches`), or several tasks' stacked — on one grasp.

    wrenches : (k, 6) float — disturbance wrenches [N, N·m], object frame.
    Other arguments as :func:`minimal_work`.

    Returns ``[minimal_work(contacts, w, mu, stiffness, ...) for w in wrenches]`` — the
    first bit for bit, the others to round-off (~1e-13 N) — but cheaper: under
    "outer" / "inner" the program is assembled once for all wrenches (it depends on the
    disturbance only through its right-hand side), each wrench after the first starts
    the dual simplex from the previous one's optimal basis (kept only when that optimum
    is unique, else solved cold: :class:`~.resistance.solvers.MinLP`), and a wrench
    that repeats — the 0° pose that lifting and lift-and-rotate share — is solved once
    (its result is a copy).  Under "model" each wrench is :func:`minimal_work` itself.
    """
    W = np.asarray(wrenches, dtype=float)
    if W.ndim != 2 or W.shape[1] != 6:
        raise ValueError(
            f"wrenches must be (k, 6) disturbance wrenches, one per pose (task_wrenches gives them); "
            f"got shape {W.shape}"
        )
    return _minimal_work_many(contacts, list(W), mu, stiffness, eps, representation, cuts)


def _minimal_work_many(contacts, wrenches, mu, stiffness, eps, representation, cuts) -> list[MinimalWork]:
    """:func:`minimal_work` for each of ``wrenches`` (a list of (6,)): the checks in
    :func:`minimal_work`'s order, then the minimal forces of Eq. 4.4 — one LP, which
    :class:`_MinForceLP` solves for every wrench from one assembly, under a polyhedral
    representation; :func:`~.resistance.min_grasp_force` (``objective="sum"``) per
    wrench under "model" (cutting planes may refine a shared cut store between calls,
    so nothing is reused there)."""
    e = _eps(eps)
    contacts = check_contacts(contacts)
    s = _check_stiffness(_at_contacts(stiffness, contacts), len(contacts)).copy()
    out: list[MinimalWork] = []
    seen: dict[bytes, MinimalWork] = {}
    lp: _MinForceLP | None = None
    for w_in in wrenches:
        if representation != "model":
            if lp is None:  # min_grasp_force's checks and warnings, before anything is solved
                contacts, w, mu = _check_question(contacts, w_in, mu, representation)
                lp = _MinForceLP.build(contacts, mu, representation, cuts)
            else:  # the same contacts, μ and representation: only the wrench is new
                w = check_wrench(w_in)
        if lp is None:
            mf = min_grasp_force(
                contacts, w_in, mu, objective="sum", representation=representation, cuts=cuts
            )
            f = mf.forces if mf.feasible else None
            out.append(_result(f, s.copy(), e, mf.solver, representation, mf.fallbacks, mf.converged))
            continue
        key = w.tobytes()
        if key in seen:  # the same disturbance: the same answer (arrays copied)
            m = seen[key]
            out.append(
                replace(m, forces=m.forces.copy(), stiffness=s.copy(), displacements=m.displacements.copy())
            )
            continue
        out.append(_result(lp.forces(w), s.copy(), e, "highs", representation, (), True))
        seen[key] = out[-1]
    return out


def _at_contacts(stiffness, contacts) -> np.ndarray:
    """``stiffness`` as given, or a :class:`~.stiffness_map.StiffnessMap` evaluated at the
    contacts' origins ``c.t`` (N,)."""
    if not isinstance(stiffness, StiffnessMap):
        return stiffness
    points = np.array([c.t for c in contacts])
    s = stiffness(points)
    log.debug("minimal work: the stiffness map at the %d contact points: %s N/m", len(points), s)
    return s


def _result(forces, s, e, solver, representation, fallbacks, converged) -> MinimalWork:
    """The :class:`MinimalWork` of the minimal forces (None: not resisted)."""
    if forces is None:
        log.debug("minimal work: w_ext is not resisted; W = inf")
        nan = np.full(len(s), np.nan)
        return MinimalWork(
            float("inf"),
            nan,
            s,
            nan.copy(),
            float("inf"),
            e,
            False,
            solver,
            representation,
            fallbacks,
            converged,
        )
    # the solver may return forces a rounding below 0
    f = np.maximum(np.asarray(forces, dtype=float), 0.0)
    d = f / s + e  # displacements(f, s, e): s and e checked by the caller, f >= 0 here
    return MinimalWork(
        float(f.sum()), f, s, d, float(f @ d), e, True, solver, representation, fallbacks, converged
    )


@dataclass
class _MinForceLP:
    """The minimal-force LP of :func:`~.resistance.min_grasp_force` (``objective="sum"``,
    a polyhedral representation) for one grasp and μ, solved for any disturbance.

    The program is assembled once per grasp — it depends on the disturbance only through
    ``prog.w = w D`` (``D`` the capacity scaling, read off a program assembled for
    ``w = 1``) — and held as one :class:`~.resistance.solvers.MinLP`, the HiGHS model
    ``min_grasp_force`` builds per call.  The first solve starts cold, so its forces are
    ``min_grasp_force``'s bit for bit; later ones start warm from the previous optimal
    basis and keep their forces only when the optimum is unique (else they re-solve
    cold): the same forces to round-off, whatever the order of the poses
    (tests/test_work_poses.py)."""

    prog: object
    lp: MinLP

    @classmethod
    def build(cls, contacts, mu, representation, cuts) -> _MinForceLP:
        prog = assemble(contacts, np.ones(6), mu, representation, cuts, minforce="sum")
        if prog.soc or "cuts" in prog.kinds:  # pragma: no cover - not one LP ("model" only)
            raise ValueError(f"the {representation!r} program of these contacts is not one LP")
        return cls(prog, MinLP(prog, prog.Phi.sum(axis=0) * prog.S, config.TOL.resist_rtol))

    def solve(self, w: np.ndarray) -> tuple[np.ndarray | None, str]:
        """``solve_min_lp`` of the program at the disturbance ``w`` (6,)."""
        # prog.w = assemble(..., w, ...).w / w (assembled at w = 1); warm: MinLP's notes
        return self.lp.solve(w * self.prog.w, warm=True)

    def forces(self, w: np.ndarray) -> np.ndarray | None:
        """(N,) minimal normal forces against ``w`` (min_grasp_force's), None if unresisted."""
        y, status = self.solve(w)
        if y is None and status != "infeasible":
            raise RuntimeError(f"HiGHS failed on the minimal-force LP: {status}")
        return None if y is None else self.prog.forces(y)  # = contact_solution(contacts, y)[1]

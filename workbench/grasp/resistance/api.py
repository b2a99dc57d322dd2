"""Public grasp-resistance questions: one meaning of "resisted" for all of them.

A grasp resists ``w_ext`` iff some contact wrenches ``c_i ∈ C_i`` balance it,
``Σ_i G_i c_i + w_ext = 0`` (thesis Eq. 2.100), where ``C_i`` is contact i's model
*itself* unless the caller names a linearisation (``representation=``), and
"balance" means a relative residual ``<= config.TOL.resist_rtol``.  Every answer
says which solver decided, the residual and any fallback (fallbacks are logged
and recorded, never silent).  Nothing here recurses: :func:`resists` tries the
cone program, then the cutting-plane loop, then the conservative inner LP, in
that order.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ... import config
from ..gws import check_contacts, check_mu, check_resist_tol, check_wrench, squeeze_check
from .cuts import CutStore
from .program import REPRESENTATIONS, Program, add_cuts, assemble, contact_violations
from .result import MinimalForce, Resistance
from .solvers import choose_qp_solver, solve_conic, solve_l1_lp, solve_l2_qp, solve_min_lp

log = logging.getLogger(__name__)

OBJECTIVES = ("scale", "sum")


def _check(contacts, w_ext, mu, representation):
    w = check_wrench(w_ext)
    contacts = check_contacts(contacts)
    check_mu(mu)
    squeeze_check(contacts)
    if representation not in REPRESENTATIONS:
        raise ValueError(
            f"representation must be one of {REPRESENTATIONS} ('model': the contact models "
            f"themselves; 'outer'/'inner': their linearisations); got {representation!r}"
        )
    return contacts, w, float(mu)


def _fallback(fallbacks: list[str], text: str) -> None:
    log.warning("grasp resistance: %s", text)
    fallbacks.append(text)


def resists(
    contacts,
    w_ext,
    mu: float,
    *,
    representation: str = "model",
    cuts: CutStore | None = None,
    solver: str | None = None,
    tol: float | None = None,
) -> Resistance:
    """Whether the contacts resist the disturbance ``w_ext`` (6,) at friction ``mu``
    (thesis Eq. 2.100; 6DFC Eq. IV.3), as a :class:`Resistance` (truthy iff resisted).

    representation : "model" (default) — each contact as its model: an ellipsoidal
        limit surface (6DLS, 6DFC, 3DLS) as its second-order cone (exact, Clarabel),
        another model (quartic) by cutting planes until the contact wrenches lie on it,
        polygonal contacts (point, soft point, REACH) by their half-spaces, the raw
        6DFW by its wrenches; "outer" — the fixed outer linearisations (Eqs. 3.28, 3.30,
        the thesis's QP); "inner" — the vertices (Eq. 3.27, the GWS of Eq. 4.2).
    cuts : a :class:`CutStore` shared between calls (cuts of a model are valid for
        every pose, μ and force); a fresh one per call if None.
    solver : dense QP solver for polyhedral programs (``config.DEFAULTS.qp_solver``): "auto" or
        one of ``qpsolvers.available_solvers`` (another name is refused before solving).
    tol : residual threshold, relative to the contacts' capacity, in (0, 0.1]
        (``config.TOL.resist_rtol``; the same rule as that field).

    Known-force contacts take their force from the interval of
    :meth:`ContactSet.force_bounds` (a sensor reading's accuracy), cones from ``[0, f_max]``.
    """
    contacts, w, mu = _check(contacts, w_ext, mu, representation)
    tol = check_resist_tol(tol)
    if solver is not None:  # a misspelt name would fail as a solver and fall back: refuse it by name
        config.check_value("qp_solver", solver, "solver (the dense QP solver of polyhedral programs)")
    return _resists(contacts, w, mu, representation, CutStore() if cuts is None else cuts, solver, tol)


def _resists(contacts, w, mu: float, representation: str, cuts: CutStore, solver, tol) -> Resistance:
    """:func:`resists` of inputs it checked: a caller that perturbs checked inputs (the samples of
    :func:`~workbench.grasp.robust.q_robust`, a friction drawn past the plausible range) asks the
    same question without judging each draw as a user's input."""
    q = _Question(contacts, w, mu, representation, cuts, solver, tol, [])
    prog = assemble(contacts, w, mu, representation, cuts)
    if prog.soc:
        y, status = solve_conic(prog)
        if y is not None:
            if status != "optimal":
                _fallback(q.fallbacks, f"Clarabel {status}")
            return _result(q, prog, y, "clarabel", "l2", 0)
        _fallback(q.fallbacks, f"Clarabel {status} on the cone program; cutting planes on the ellipsoids")
        prog = None
    return _cut_loop(q, prog)


#: Eq. 2.100 by its thesis name; the same function as :func:`resists`.
wrench_resistance = resists


def _solve_polyhedral(
    prog: Program, solver, fallbacks, tol: float | None = None
) -> tuple[np.ndarray, str, str, float | None]:
    """(y, solver, norm, residual or None): the L1 LP for vertex sets (6DFW, inner
    linearisations: large and sparse), the dense L2 QP otherwise.  A QP answer just outside the
    residual band ``tol`` (within ``config.TOL.qp_recheck_factor`` of it) is checked by the exact
    residual LP (HiGHS), which decides (a recorded fallback) when it resists: an active-set QP
    stopping at its own tolerance can leave a residual a few times ``tol`` on a wrench the
    contacts do resist.  Confirmed answers stay the QP's."""
    if "vertex" in prog.kinds:
        y, resid = solve_l1_lp(prog)
        if y is None:
            raise RuntimeError("HiGHS failed on the residual LP of a polyhedral grasp")
        return y, "highs", "l1", resid
    name = choose_qp_solver(solver, prog.n)
    y = solve_l2_qp(prog, name)
    if y is None:
        backup = config.DEFAULTS.qp_fallback_solver
        _fallback(fallbacks, f"QP solver {name!r} returned no solution; retrying with {backup!r}")
        name = backup
        y = solve_l2_qp(prog, name)
    if y is None:
        _fallback(fallbacks, "every QP solver failed; the residual LP (HiGHS) decides")
        y, resid = solve_l1_lp(prog)
        if y is None:
            raise RuntimeError("every solver failed on the grasp-resistance program")
        return y, "highs", "l1", resid
    if tol is not None:
        resid = float(np.linalg.norm(prog.A6 @ y + prog.w))
        if tol < resid <= config.TOL.qp_recheck_factor * tol:
            y_lp, resid_lp = solve_l1_lp(prog)
            if y_lp is not None and resid_lp <= tol:  # the QP stopped short: the LP resists it
                _fallback(
                    fallbacks,
                    f"QP solver {name!r} left a residual {resid:.3g}, within "
                    f"{config.TOL.qp_recheck_factor:g}x the band {tol:.3g}, where the residual LP (HiGHS) "
                    f"resists it ({resid_lp:.3g}): the LP decides",
                )
                return y_lp, "highs", "l1", resid_lp
            log.debug("QP residual %.3g confirmed by the residual LP (%s)", resid, resid_lp)
    return y, name, "l2", None


@dataclass(frozen=True)
class _Question:
    """One :func:`resists` call: its validated inputs and the record of its fallbacks."""

    contacts: list
    w: np.ndarray  # (6,) the disturbance
    mu: float
    representation: str
    cuts: CutStore
    solver: str | None  # the dense QP solver
    tol: float  # the residual band
    fallbacks: list[str]


def _cut_loop(q: _Question, prog: Program | None) -> Resistance:
    """Polyhedral program; contacts refined by cuts are re-solved with the tangent planes
    at their violations until none is left (Kelley).  ``prog`` None: ellipsoids by cuts
    as well (the cone solver failed)."""
    contacts, w, mu, representation, cuts = q.contacts, q.w, q.mu, q.representation, q.cuts
    cone_as_cuts = prog is None
    rounds = 0
    while True:
        if prog is None:
            prog = assemble(contacts, w, mu, representation, cuts, cone_as_cuts=cone_as_cuts)
        y, name, norm, resid = _solve_polyhedral(prog, q.solver, q.fallbacks, q.tol)
        res = _result(q, prog, y, name, norm, rounds, resid)
        if "cuts" not in prog.kinds or not res.resisted:
            return res  # the outer set fails to resist: the model inside it fails too
        viol = contact_violations(prog, contacts, y, mu)
        if not viol:
            return res
        if rounds >= config.TOL.max_cut_rounds:
            break
        add_cuts(cuts, contacts, viol)
        rounds += 1
        prog = None
    # unconverged: "resisted" by the outer set may be optimistic; the inner vertices
    # (on the model) decide, conservatively
    _fallback(q.fallbacks, f"cutting planes did not converge in {rounds} rounds; the inner vertices decide")
    inner = assemble(contacts, w, mu, "inner", cuts)
    y, resid = solve_l1_lp(inner)
    if y is None:
        raise RuntimeError("HiGHS failed on the inner-vertex LP")
    return _result(q, inner, y, "highs", "l1", rounds, resid)


def _result(q: _Question, prog: Program, y, solver: str, norm: str, rounds: int, resid=None) -> Resistance:
    """The :class:`Resistance` of the solution ``y`` of ``prog`` (its residual computed when
    ``resid`` is None)."""
    if resid is None:
        resid = float(np.linalg.norm(prog.A6 @ y + prog.w))
    cw, f = prog.contact_solution(q.contacts, y)
    tol = q.tol
    return Resistance(
        bool(resid <= tol),
        float(resid),
        tol,
        solver,
        q.representation,
        norm,
        cw,
        f,
        rounds,
        tuple(q.fallbacks),
    )


def min_grasp_force(
    contacts,
    w_ext,
    mu: float,
    *,
    objective: str = "scale",
    representation: str = "model",
    cuts: CutStore | None = None,
    f_max: float | None = None,
) -> MinimalForce:
    """Smallest grasp force that resists ``w_ext`` (thesis Eq. 4.4), on the same contact
    models and force semantics as :func:`resists`.

    objective : "scale" (default) — the smallest factor ``s`` on every contact's current
        force such that ``resists([c.with_force(s * c.force) ...])`` holds: the jaws keep
        their force ratio, as one gripper force does; "sum" — Eq. 4.4 as published:
        every contact's force an independent variable in ``[0, f_max]`` (known-force
        contacts become cones), ``Σ f_i`` minimised.  With ``representation="outer"``
        and "sum" this is the thesis's program over ``C_outer``.
    representation : as in :func:`resists` ("model": second-order cones for
        ellipsoids, cutting planes for quartics).
    f_max : per-contact force cap for "sum" [N]; refused with "scale", whose answer is a factor
        on the contacts' given forces (compare ``result.forces`` with a cap there).

    The balance is accepted to the residual band of :func:`resists`
    (``config.TOL.resist_rtol`` of the capacity at the contacts' given forces), so
    ``resists`` agrees just above and below the answer; a wrench out of the contacts'
    reach (a torque about the axis of two hard points) stays out of reach at any force.
    """
    contacts, w, mu = _check(contacts, w_ext, mu, representation)
    # the residual band of resists, relative to the capacity at the contacts' *given*
    # forces and fixed: relative to the scaled forces any shortfall would vanish at
    # absurd forces (point contacts "resisting" torsion at 10⁶ × F)
    tol = config.TOL.resist_rtol
    _check_objective(objective, f_max)
    cuts = CutStore() if cuts is None else cuts
    fallbacks: list[str] = []
    rounds = 0
    cone_as_cuts = False
    while True:
        prog = assemble(
            contacts, w, mu, representation, cuts, minforce=objective, f_max=f_max, cone_as_cuts=cone_as_cuts
        )
        y, solver, retry = _solve_min_force(prog, _min_force_cost(prog, objective), tol, fallbacks)
        if retry:
            cone_as_cuts = True
            continue
        if y is None:
            nan = np.full(len(contacts), np.nan)
            # no scale of the jaws' force resists it: inf, as the total (NaN: "sum" has no scale)
            s = float("inf") if objective == "scale" else float("nan")
            return MinimalForce(
                float("inf"), nan, s, objective, solver, representation, rounds, tuple(fallbacks)
            )
        viol = contact_violations(prog, contacts, y, mu)
        if viol and rounds < config.TOL.max_cut_rounds:
            add_cuts(cuts, contacts, viol)
            rounds += 1
            continue
        if viol:
            _fallback(
                fallbacks, f"cutting planes did not converge in {rounds} rounds; the value is a lower bound"
            )
        s, forces = _min_forces(prog, contacts, y, objective)
        return MinimalForce(
            float(forces.sum()),
            forces,
            s,
            objective,
            solver,
            representation,
            rounds,
            tuple(fallbacks),
            not viol,
        )


def _check_objective(objective: str, f_max: float | None) -> None:
    """ValueError unless ``objective`` is one of :data:`OBJECTIVES` and ``f_max`` a positive
    force [N] or None, given with "sum" only."""
    if objective not in OBJECTIVES:
        raise ValueError(f"objective must be one of {OBJECTIVES}; got {objective!r}")
    if f_max is not None and not (np.isfinite(f_max) and f_max > 0):
        raise ValueError(f"f_max must be a positive force [N] or None; got {f_max}")
    if f_max is not None:  # a contact's cap is a jaw's force: 1e4 is millinewtons (None: no cap)
        from ...plausible import check

        check("jaw_force", f_max, "f_max (each contact's force cap [N]; None: no cap)", warn=False)
    if f_max is not None and objective == "scale":
        raise ValueError(
            f"f_max caps each contact's force under objective='sum' only (every force a free variable "
            f"in [0, f_max]); got f_max={f_max!r} with objective='scale', whose answer is a factor on "
            "the contacts' given forces and takes no cap — pass objective='sum' to cap them, or drop "
            "f_max and compare result.forces with your cap"
        )


def _min_force_cost(prog: Program, objective: str) -> np.ndarray:
    """(n,) cost of the minimal-force program in ``y``: the force scale s, or Σ f_i."""
    cost = np.zeros(prog.n)
    if objective == "scale":
        cost[-1] = 1.0
    else:
        cost = prog.Phi.sum(axis=0) * prog.S  # Σ f_i in y
    return cost


def _solve_min_force(
    prog: Program, cost: np.ndarray, tol: float, fallbacks: list[str]
) -> tuple[np.ndarray | None, str, bool]:
    """(y, the solver that decided, False) — y None when no force resists — or (None,
    "clarabel", True) when Clarabel failed on the cone program: the caller retries with the
    ellipsoids as cutting planes.  A stalled iterate is feasible but not minimal: no answer."""
    if prog.soc:
        y, status = solve_conic(prog, cost, tol)
        if y is not None and status != "optimal":
            y = None  # a stalled iterate is feasible but not minimal
        if y is None and status != "infeasible":
            _fallback(fallbacks, f"Clarabel {status} on the minimal-force cone program; cutting planes")
            return None, "clarabel", True
        return y, "clarabel", False
    y, status = solve_min_lp(prog, cost, tol)
    if y is None and status != "infeasible":
        # HiGHS undecided (seen: "Unknown" on two hard points' infeasible LP): the same
        # polyhedral program to Clarabel's interior point, which certifies infeasibility
        _fallback(fallbacks, f"HiGHS {status} on the minimal-force LP; Clarabel")
        y, status = solve_conic(prog, cost, tol)
        if y is not None and status != "optimal":
            y = None
        if y is None and status != "infeasible":
            raise RuntimeError(f"HiGHS and Clarabel failed on the minimal-force LP: {status}")
        return y, "clarabel", False
    return y, "highs", False


def _min_forces(prog: Program, contacts, y: np.ndarray, objective: str) -> tuple[float, np.ndarray]:
    """(scale s, (N,) contact forces [N]) at the minimal-force solution ``y`` (s NaN for "sum")."""
    _, f = prog.contact_solution(contacts, y)
    if objective == "scale":
        s = float(y[-1] * prog.S[-1])
        return s, s * np.array([c.force for c in contacts])
    return float("nan"), f

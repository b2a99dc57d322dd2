"""Solver adapters for :class:`~.program.Program`: dense QP (qpsolvers: quadprog,
DAQP, …), LP (HiGHS) and second-order-cone programs (Clarabel).  Each returns the
solution ``y`` (or None) and never decides anything; the caller records fallbacks."""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from ... import config
from .program import Program

log = logging.getLogger(__name__)


def _qp_opts(solver: str) -> dict:
    # tight tolerances for the first-order / interior-point solvers (defaults ~1e-3..1e-6
    # would blur the resisted / not-resisted boundary)
    return {
        "osqp": {"eps_abs": 1e-9, "eps_rel": 1e-9, "max_iter": 20_000, "polish": True, "verbose": False},
        "scs": {"eps_abs": 1e-9, "eps_rel": 1e-9, "verbose": False},
        "proxqp": {"eps_abs": 1e-10},
        # DAQP's plain active set cycles on the near-singular Hessian when the residual
        # is non-zero; its proximal-point mode is robust but less accurate (~1e-6)
        "daqp": {"eps_prox": 1e-8},
        # HiGHS's QP solver was seen to cycle for > 30 min on one 12-variable program
        # (benchmarks/bench_grasp.py): a time limit turns that into a recorded failure
        "highs": {"time_limit": 2.0},
    }.get(solver, {})


def _ineq_with_bounds(prog: Program) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The inequality rows with the finite bounds appended as rows (for solvers without
    native bounds: quadprog, Clarabel)."""
    G, h = prog.rows("ineq")
    lo, hi = np.flatnonzero(np.isfinite(prog.lb)), np.flatnonzero(np.isfinite(prog.ub))
    rows = [G] if G is not None else []
    rhs = [h] if h is not None else []
    if lo.size:
        Gb = np.zeros((lo.size, prog.n))
        Gb[np.arange(lo.size), lo] = -1.0
        rows.append(Gb)
        rhs.append(-prog.lb[lo])
    if hi.size:
        Gb = np.zeros((hi.size, prog.n))
        Gb[np.arange(hi.size), hi] = 1.0
        rows.append(Gb)
        rhs.append(prog.ub[hi])
    if not rows:
        return None, None
    return np.vstack(rows), np.concatenate(rhs)


def _bounds(prog: Program) -> list[tuple[float | None, float | None]]:
    """HiGHS bounds (None: unbounded)."""
    return [
        (lo if np.isfinite(lo) else None, hi if np.isfinite(hi) else None)
        for lo, hi in zip(prog.lb, prog.ub, strict=True)
    ]


def choose_qp_solver(solver: str | None, n: int) -> str:
    solver = config.DEFAULTS.qp_solver if solver is None else solver
    if solver == "auto":
        return "quadprog" if n <= config.DEFAULTS.qp_auto_large else "daqp"
    return solver


def solve_l2_qp(prog: Program, solver: str) -> np.ndarray | None:
    """``min ½‖A6 y + w‖² + ridge`` over the polyhedral rows (no cones)."""
    from qpsolvers import solve_qp

    P = prog.A6.T @ prog.A6
    P[np.diag_indices(prog.n)] += config.TOL.qp_ridge * max(float(np.trace(P)) / prog.n, 1e-300)
    A, b = prog.rows("eq")
    bounds = {}
    if solver == "daqp":  # native simple bounds (1e30: none)
        G, h = prog.rows("ineq")
        bounds = {"lb": np.maximum(prog.lb, -1e30), "ub": np.minimum(prog.ub, 1e30)}
    else:
        G, h = _ineq_with_bounds(prog)
    try:
        y = solve_qp(P, prog.A6.T @ prog.w, G, h, A, b, solver=solver, **bounds, **_qp_opts(solver))
    except Exception as exc:  # noqa: BLE001 - solver-specific errors (e.g. quadprog's ValueError)
        log.debug("QP solver %s raised %s", solver, exc)
        return None
    if y is not None and not np.isfinite(y).all():
        return None
    return y


def _slack_form(prog: Program):
    """The polyhedral rows with the residual written as slacks, ``A6 y + w = t⁺ − t⁻``
    (12 slack columns appended, t >= 0): ``(A_eq, b_eq, G, h, bounds)`` for HiGHS."""
    G, h = prog.rows("ineq")
    A, b = prog.rows("eq")
    A_eq = [np.hstack([prog.A6, -np.eye(6), np.eye(6)])]
    b_eq = [-prog.w]
    if A is not None:
        A_eq.append(np.hstack([A, np.zeros((len(A), 12))]))
        b_eq.append(b)
    G12 = None if G is None else np.hstack([G, np.zeros((len(G), 12))])
    return np.vstack(A_eq), np.concatenate(b_eq), G12, h, _bounds(prog) + [(0, None)] * 12


def solve_l1_lp(prog: Program) -> tuple[np.ndarray | None, float]:
    """``min ‖A6 y + w‖₁`` (slacks ``t⁺, t⁻``) over the polyhedral rows (HiGHS): always
    feasible when the rows are; returns (y, residual)."""
    A_eq, b_eq, G, h, bounds = _slack_form(prog)
    res = linprog(
        np.r_[np.zeros(prog.n), np.ones(12)],
        A_ub=None if G is None else sp.csr_matrix(G),
        b_ub=h,
        A_eq=sp.csr_matrix(A_eq),
        b_eq=b_eq,
        bounds=bounds,
        method="highs",
    )
    if res.status != 0:
        log.debug("HiGHS on the residual LP: %s", res.message)
        return None, float("nan")
    return res.x[: prog.n], float(res.fun)


class MinLP:
    """``min costᵀ y`` s.t. ``‖A6 y + w‖₁ <= tol`` (slacks ``t⁺, t⁻``; the same band
    :func:`resists` accepts) and the polyhedral rows of ``prog``, as one HiGHS model
    (``highspy``) that is solved for any disturbance ``w``.

    The disturbance enters only the bounds of the 6 balance rows, so a grasp's poses
    change those bounds and nothing else.  Every :meth:`solve` starts cold (the basis of
    the previous solve is dropped), so its answer depends on ``(prog, cost, tol, w)``
    alone — not on which poses were solved before: :func:`solve_min_lp` (one solve) and
    many solves of one model give the same ``y`` bit for bit.  Presolve follows
    ``config.DEFAULTS.lp_presolve``, read when the model is built.
    """

    def __init__(self, prog: Program, cost: np.ndarray, tol: float = 0.0) -> None:
        import highspy

        A_eq, b_eq, G, h, _ = _slack_form(prog)
        band = np.zeros((1, prog.n + 12))
        band[0, prog.n :] = 1.0  # Σ t <= tol
        A_ub = band if G is None else np.vstack([G, band])
        b_ub = np.array([tol]) if h is None else np.append(h, tol)
        inf = highspy.kHighsInf
        At = np.vstack([A_eq, A_ub]).T  # column-wise storage of the rows = row-wise of At
        n_col, n_row = At.shape
        col, row = np.nonzero(At)
        start = np.zeros(n_col + 1, dtype=np.int32)
        np.cumsum(np.bincount(col, minlength=n_col), out=start[1:])
        zeros12 = np.zeros(12)
        model = (
            n_col,
            n_row,
            len(row),
            int(highspy.MatrixFormat.kColwise),
            int(highspy.ObjSense.kMinimize),
            0.0,  # objective offset
            np.concatenate([cost, zeros12]),
            np.concatenate([np.where(np.isfinite(prog.lb), prog.lb, -inf), zeros12]),
            np.concatenate([np.where(np.isfinite(prog.ub), prog.ub, inf), np.full(12, inf)]),
            np.concatenate([b_eq, np.full(len(b_ub), -inf)]),
            np.concatenate([b_eq, b_ub]),
            start,
            row.astype(np.int32),
            At[col, row],
            np.zeros(n_col, dtype=np.int32),  # integrality: every column continuous (0)
        )
        # highspy._Highs (in highspy.__all__) is the HiGHS object without the Python
        # callback layer of highspy.Highs, whose constructor prints HiGHS's banner to
        # stdout before output can be switched off (HiGHS issues 1702, 2749)
        self._h = highspy._Highs()
        self._h.setOptionValue("output_flag", False)
        self._h.setOptionValue("presolve", "on" if config.DEFAULTS.lp_presolve else "off")
        # kWarning: HiGHS dropped matrix entries below its small_matrix_value (1e-9),
        # round-off zeros of the assembled rows, as linprog's HiGHS does
        status = self._h.passModel(*model)
        if status == highspy.HighsStatus.kError:  # pragma: no cover - a malformed program is a bug
            raise RuntimeError(f"HiGHS refused the minimal-force LP: {status}")
        self._n = prog.n
        self._statuses = highspy.HighsModelStatus

    def solve(self, w: np.ndarray) -> tuple[np.ndarray | None, str]:
        """(y, status) against the (scaled) disturbance ``w`` (6,): status "optimal",
        "infeasible" or HiGHS's model status."""
        h = self._h
        h.clearSolver()  # cold: no basis carried over from another disturbance
        for i, b in enumerate((-np.asarray(w, dtype=float)).tolist()):  # the balance rows
            h.changeRowBounds(i, b, b)  # (one row per call: in every highspy >= 1.7)
        h.run()
        status = h.getModelStatus()
        if status == self._statuses.kOptimal:
            return np.array(h.getSolution().col_value[: self._n]), "optimal"
        if status == self._statuses.kInfeasible:
            return None, "infeasible"
        return None, h.modelStatusToString(status)


def solve_min_lp(prog: Program, cost: np.ndarray, tol: float = 0.0) -> tuple[np.ndarray | None, str]:
    """``min costᵀ y`` s.t. ``‖A6 y + w‖₁ <= tol`` and the polyhedral rows (HiGHS):
    (y, status) with status "optimal", "infeasible" or HiGHS's message — one
    :meth:`MinLP.solve` at ``prog.w``."""
    return MinLP(prog, cost, tol).solve(prog.w)


def _conic_data(prog: Program, band: float | None):
    """Clarabel's ``(A, b, cones)``; ``band`` adds the residual bound
    ``‖A6 y + w‖₂ <= band`` as one more second-order cone."""
    import clarabel

    parts = []
    A, b = prog.rows("eq")
    if A is not None:
        parts.append((A, b, clarabel.ZeroConeT))
    G, h = _ineq_with_bounds(prog)
    if G is not None:
        parts.append((G, h, clarabel.NonnegativeConeT))
    for rows, rhs in prog.soc:
        parts.append((rows, rhs, clarabel.SecondOrderConeT))
    if band is not None:  # s = [band; A6 y + w] = rhs − rows y
        rows = np.vstack([np.zeros(prog.n), -prog.A6])
        parts.append((rows, np.r_[band, prog.w], clarabel.SecondOrderConeT))
    A_all = np.vstack([a for a, _, _ in parts])
    b_all = np.concatenate([r for _, r, _ in parts])
    cones = [cone(len(a)) for a, _, cone in parts]
    return A_all, b_all, cones, [len(a) for a, _, _ in parts]


def _in_cones(slack: np.ndarray, cones: list, sizes: list[int], atol: float = 1e-7) -> bool:
    """Whether a Clarabel slack vector lies in its cones (zero, nonnegative, SOC) to ``atol``."""
    import clarabel

    k = 0
    for cone, n in zip(cones, sizes, strict=True):
        part = slack[k : k + n]
        k += n
        if isinstance(cone, clarabel.ZeroConeT) and np.abs(part).max(initial=0.0) > atol:
            return False
        if isinstance(cone, clarabel.NonnegativeConeT) and part.min(initial=0.0) < -atol:
            return False
        if isinstance(cone, clarabel.SecondOrderConeT) and np.linalg.norm(part[1:]) > part[0] + atol:
            return False
    return True


def solve_conic(
    prog: Program, cost: np.ndarray | None = None, tol: float = 0.0
) -> tuple[np.ndarray | None, str]:
    """Clarabel: ``min ½‖A6 y + w‖²`` (``cost`` None) or ``min costᵀ y`` s.t.
    ``‖A6 y + w‖₂ <= tol`` (the band :func:`resists` accepts), over rows and cones.
    Returns (y, status); y is None unless solved, or stalled at
    an iterate that satisfies every cone (Clarabel stalls now and then on low-rank,
    planar models; such an iterate is still a valid point of the program)."""
    import clarabel

    A_all, b_all, cones, sizes = _conic_data(prog, None if cost is None else tol)
    if cost is None:
        P = sp.triu(sp.csc_matrix(prog.A6.T @ prog.A6)).tocsc()
        q = prog.A6.T @ prog.w
    else:
        P = sp.csc_matrix((prog.n, prog.n))
        q = cost
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-10
    settings.tol_feas = 1e-10
    sol = clarabel.DefaultSolver(P, q, sp.csc_matrix(A_all), b_all, cones, settings).solve()
    status = str(sol.status)
    y = np.array(sol.x)
    if status in ("Solved", "AlmostSolved"):
        return y, "optimal"
    if "Infeasible" in status:
        return None, "infeasible"
    if np.isfinite(y).all() and _in_cones(b_all - A_all @ y, cones, sizes):
        return y, f"stalled ({status}), iterate feasible"
    return None, status

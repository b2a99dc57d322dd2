"""Solver adapters for :class:`~.program.Program`: dense QP (qpsolvers: quadprog,
DAQP, …), LP (HiGHS) and second-order-cone programs (Clarabel).  Each returns the
solution ``y`` (or None) and never decides anything; the caller records fallbacks."""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

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
        # HiGHS's QP solver can cycle for very long on a small program (benchmarks/bench_grasp.py,
        # docs/decisions.md): a time limit turns that into a recorded failure
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
    (12 slack columns appended, t >= 0): ``(A_eq, b_eq, G, h, lb, ub)`` for HiGHS, bounds
    (n + 12,) with ±inf where there is none."""
    G, h = prog.rows("ineq")
    A, b = prog.rows("eq")
    A_eq = [np.hstack([prog.A6, -np.eye(6), np.eye(6)])]
    b_eq = [-prog.w]
    if A is not None:
        A_eq.append(np.hstack([A, np.zeros((len(A), 12))]))
        b_eq.append(b)
    G12 = None if G is None else np.hstack([G, np.zeros((len(G), 12))])
    lb = np.concatenate([prog.lb, np.zeros(12)])
    ub = np.concatenate([prog.ub, np.full(12, np.inf)])
    return np.vstack(A_eq), np.concatenate(b_eq), G12, h, lb, ub


def _csc_arrays(M: np.ndarray | sp.spmatrix) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(indptr, indices, data) of ``M`` (m, n) in compressed columns, row indices sorted, the
    zeros left out: what ``scipy.sparse.csc_matrix(M)`` holds, built from a dense ``M`` in NumPy
    (scipy's constructor's Python overhead is a sizeable part of a small LP's solve)."""
    if sp.issparse(M):
        M = sp.csc_matrix(M)
        M.sort_indices()
        return M.indptr.astype(np.int32), M.indices.astype(np.int32), M.data.astype(float)
    M = np.asarray(M, dtype=float)
    col, row = np.nonzero(M.T)  # column by column, rows ascending
    indptr = np.zeros(M.shape[1] + 1, dtype=np.int32)
    np.cumsum(np.bincount(col, minlength=M.shape[1]), out=indptr[1:])
    return indptr, row.astype(np.int32), M.T[col, row]


def _csc(M: np.ndarray) -> sp.csc_matrix:
    """``scipy.sparse.csc_matrix(M)`` of a dense ``M``, the same arrays (:func:`_csc_arrays`)."""
    indptr, indices, data = _csc_arrays(M)
    return sp.csc_matrix((data, indices, indptr), shape=M.shape)


def highs_lp(
    cost: np.ndarray,
    M: np.ndarray | sp.spmatrix,
    row_lo: np.ndarray,
    row_hi: np.ndarray,
    col_lo: np.ndarray,
    col_hi: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, float] | None:
    """``min costᵀx`` s.t. ``row_lo <= M x <= row_hi``, ``col_lo <= x <= col_hi`` (±inf: no
    bound) by HiGHS with its defaults (those of ``linprog(method="highs")``) but presolve
    (``config.DEFAULTS.lp_presolve``, read now), one model passed straight to ``highspy``:
    ``(x (n,), row duals (m,), objective)``, None unless optimal.

    cost : (n,); M : (m, n) dense or sparse; row duals as ``linprog``'s ``marginals`` (∂ objective / ∂ row
    bound).  scipy's ``linprog`` spends longer per call cleaning and converting its inputs
    in Python than HiGHS takes on the workbench's small LPs (docs/decisions.md)."""
    import highspy

    inf = highspy.kHighsInf
    indptr, indices, data = _csc_arrays(M)
    n = M.shape[1]
    h = highspy._Highs()  # without highspy.Highs's banner on stdout (see MinLP)
    h.setOptionValue("output_flag", False)
    h.setOptionValue("presolve", "on" if config.DEFAULTS.lp_presolve else "off")
    status = h.passModel(
        n,
        M.shape[0],
        len(data),
        int(highspy.MatrixFormat.kColwise),
        int(highspy.ObjSense.kMinimize),
        0.0,
        np.asarray(cost, dtype=float),
        np.where(np.isfinite(col_lo), col_lo, -inf),
        np.where(np.isfinite(col_hi), col_hi, inf),
        np.where(np.isfinite(row_lo), row_lo, -inf),
        np.where(np.isfinite(row_hi), row_hi, inf),
        indptr,
        indices,
        data,
        np.zeros(n, dtype=np.int32),
    )
    if status == highspy.HighsStatus.kError:  # pragma: no cover - a malformed program is a bug
        raise RuntimeError(f"HiGHS refused the LP: {status}")
    h.run()
    model_status = h.getModelStatus()
    if model_status != highspy.HighsModelStatus.kOptimal:
        log.debug("HiGHS: %s", h.modelStatusToString(model_status))
        return None
    sol = h.getSolution()
    return np.array(sol.col_value), np.array(sol.row_dual), float(h.getInfo().objective_function_value)


def solve_l1_lp(prog: Program) -> tuple[np.ndarray | None, float]:
    """``min ‖A6 y + w‖₁`` (slacks ``t⁺, t⁻``) over the polyhedral rows (HiGHS, :func:`highs_lp`):
    always feasible when the rows are; returns (y, residual)."""
    A_eq, b_eq, G, h, lb, ub = _slack_form(prog)
    rows = [A_eq] if G is None else [A_eq, G]
    row_lo = np.concatenate([b_eq] + ([] if G is None else [np.full(len(G), -np.inf)]))
    row_hi = np.concatenate([b_eq] + ([] if G is None else [h]))
    out = highs_lp(np.r_[np.zeros(prog.n), np.ones(12)], np.vstack(rows), row_lo, row_hi, lb, ub)
    if out is None:
        return None, float("nan")
    x, _, objective = out
    return x[: prog.n], objective


def _dual_model(prog: Program, cost: np.ndarray, tol: float) -> tuple:
    """The dual of :class:`MinLP`'s LP (its class notes) as HiGHS's ``passModel`` arguments
    (column-wise storage), with its columns' lower bounds (n_col,), its rows' lower bounds
    (n_y,) and the LP's cost ``c`` (n_y,), which is the rows' upper bounds."""
    import highspy

    inf = highspy.kHighsInf
    n, n_y = prog.n, prog.n + 12
    G, h = prog.rows("ineq")
    A, b = prog.rows("eq")
    c = np.concatenate([cost, np.zeros(12)])
    lb = np.concatenate([prog.lb, np.zeros(12)])
    ub = np.concatenate([prog.ub, np.full(12, np.inf)])
    # the dual below takes a column as y >= 0 or free; any other bound becomes a row
    nonneg = (lb == 0) & ~np.isfinite(ub)
    lo, hi = np.flatnonzero(np.isfinite(lb) & ~nonneg), np.flatnonzero(np.isfinite(ub))
    # the LP's rows, one dual column each: μ for the equalities — the balance
    # A6 y − t⁺ + t⁻ = −w (_slack_form's), then prog's own — and λ >= 0 for the
    # inequalities: prog's G y <= h, the band Σ t <= tol, the bound rows
    n_eq = 6 + (0 if A is None else len(A))
    m = 0 if G is None else len(G)
    n_mu, n_lam = n_eq, m + 1 + len(lo) + len(hi)
    # dual: min −b_eqᵀμ + h_allᵀλ  s.t.  A_eqᵀμ − G_allᵀλ (<= c on y >= 0 columns,
    # = c on free ones), λ >= 0; Dt holds its columns, i.e. [A_eq; −G_all]
    Dt = np.zeros((n_mu + n_lam, n_y))
    Dt[:6, :n] = prog.A6
    Dt[:6, n : n + 6] = -np.eye(6)
    Dt[:6, n + 6 :] = np.eye(6)
    if A is not None:
        Dt[6:n_eq, :n] = A
    if G is not None:
        Dt[n_eq : n_eq + m, :n] = -G
    Dt[n_eq + m, n:] = -1.0  # −(band row)
    k = n_eq + m + 1
    Dt[k + np.arange(len(lo)), lo] = 1.0  # −(−y_j <= −lb_j)
    Dt[k + len(lo) + np.arange(len(hi)), hi] = -1.0  # −(y_j <= ub_j)
    h_all = np.concatenate([np.zeros(0) if h is None else h, [tol], -lb[lo], ub[hi]])
    b_eq = np.concatenate([-prog.w, np.zeros(0) if b is None else b])
    col, row = np.nonzero(Dt)  # column-wise storage of the dual: Dt row by row
    start = np.zeros(n_mu + n_lam + 1, dtype=np.int32)
    np.cumsum(np.bincount(col, minlength=n_mu + n_lam), out=start[1:])
    row_lo = np.where(nonneg, -inf, c)
    col_lo = np.concatenate([np.full(n_mu, -inf), np.zeros(n_lam)])
    model = (
        n_mu + n_lam,
        n_y,
        len(row),
        int(highspy.MatrixFormat.kColwise),
        int(highspy.ObjSense.kMinimize),
        0.0,  # objective offset
        np.concatenate([-b_eq, h_all]),
        col_lo,
        np.full(n_mu + n_lam, inf),
        row_lo,
        c,
        start,
        row.astype(np.int32),
        Dt[col, row],
        np.zeros(n_mu + n_lam, dtype=np.int32),  # integrality: every column continuous (0)
    )
    return model, col_lo, row_lo, c


class MinLP:
    """``min costᵀ y`` s.t. ``‖A6 y + w‖₁ <= tol`` (slacks ``t⁺, t⁻``; the same band
    :func:`resists` accepts) and the polyhedral rows of ``prog``, held as one HiGHS model
    (``highspy``) that is solved for any disturbance ``w``.

    HiGHS gets the LP's dual, ``max −wᵀμ − hᵀλ`` over ``λ >= 0`` with one row per
    column of the LP above, and solves it by the primal simplex; ``y`` is read off the
    dual values of those rows.  The dual is the smaller basis (26 rows against 407 on a
    two-jaw 6DLS grasp at M = 200) and the faster cold solve (docs/decisions.md), and the
    disturbance enters only its objective, so a previous optimal basis stays feasible
    for the next disturbance.  The dual is always feasible (``μ = λ = 0``), so an
    unbounded dual is an infeasible LP ("infeasible").

    A cold :meth:`solve` (the default) drops the basis of the previous solve, so its
    answer depends on ``(prog, cost, tol, w)`` alone: :func:`solve_min_lp` (one solve)
    and many cold solves of one model give the same ``y`` bit for bit.  A warm solve
    starts from the last optimal basis — about a third of the iterations — and returns
    the cold answer whenever that answer is unique: it keeps its ``y`` only when the
    dual's optimal basis is nondegenerate (every basic variable and row strictly
    inside its bounds, by more than HiGHS's primal feasibility tolerance, which pins
    ``y`` by complementary slackness: no other optimal ``y`` exists; the two then
    differ by round-off, ~1e-13), and re-solves cold otherwise (logged; counted in
    :attr:`cold_resolves`).  Presolve, scaling and the dual feasibility tolerance follow
    ``config.DEFAULTS.lp_presolve``, ``lp_scale_strategy`` and
    ``lp_dual_feasibility_tolerance``, read when the model is built.
    """

    def __init__(self, prog: Program, cost: np.ndarray, tol: float = 0.0) -> None:
        import highspy

        inf = highspy.kHighsInf
        model, col_lo, row_lo, c = _dual_model(prog, cost, tol)
        n_col = model[0]
        # highspy._Highs (in highspy.__all__) is the HiGHS object without the Python
        # callback layer of highspy.Highs, whose constructor prints HiGHS's banner to
        # stdout before output can be switched off (HiGHS issues 1702, 2749)
        self._h = highspy._Highs()
        self._h.setOptionValue("output_flag", False)
        self._h.setOptionValue("presolve", "on" if config.DEFAULTS.lp_presolve else "off")
        self._h.setOptionValue("simplex_strategy", 4)  # primal: a cost change keeps the basis feasible
        self._h.setOptionValue("simplex_scale_strategy", int(config.DEFAULTS.lp_scale_strategy))
        # the LP's rows G y <= h are this dual's dual-feasibility conditions (config's notes)
        self._h.setOptionValue(
            "dual_feasibility_tolerance", float(config.DEFAULTS.lp_dual_feasibility_tolerance)
        )
        # kWarning: HiGHS dropped matrix entries below its small_matrix_value (1e-9),
        # round-off zeros of the assembled rows, as linprog's HiGHS does
        status = self._h.passModel(*model)
        if status == highspy.HighsStatus.kError:  # pragma: no cover - a malformed program is a bug
            raise RuntimeError(f"HiGHS refused the minimal-force LP: {status}")
        self._n = prog.n
        self._statuses = highspy.HighsModelStatus
        self._n_col = n_col
        self._balance = np.arange(6, dtype=np.int32)  # μ of the balance rows: columns 0-5
        # bounds of the dual's columns then rows, in HiGHS's order of variables
        self._lo = np.concatenate([col_lo, row_lo])
        self._hi = np.concatenate([np.full(n_col, inf), c])
        self._primal_tol = float(self._h.getOptionValue("primal_feasibility_tolerance")[1])
        self._optimal = False  # whether the model holds an optimal basis to start from
        #: warm solves whose optimum was not provably unique, re-solved cold
        self.cold_resolves = 0
        #: solves that ended neither optimal nor infeasible without presolve, re-solved with it
        self.presolve_resolves = 0

    def solve(self, w: np.ndarray, warm: bool = False) -> tuple[np.ndarray | None, str]:
        """(y, status) against the (scaled) disturbance ``w`` (6,): status "optimal",
        "infeasible" or HiGHS's model status.  ``warm``: start from the last optimal
        basis (the class notes say when that answer is kept)."""
        warm = warm and self._optimal
        y, status = self._run(w, warm)
        if warm and not (status == "infeasible" or (y is not None and self._unique())):
            self.cold_resolves += 1
            log.debug(
                "warm minimal-force LP: %s; re-solved cold", "optimum not unique" if y is not None else status
            )
            y, status = self._run(w, False)
        if y is None and status != "infeasible" and not config.DEFAULTS.lp_presolve:
            # without presolve the primal simplex can stop at "Unknown" on an infeasible
            # program of two hard point contacts (their dual unbounded only along a ray it
            # does not follow): one cold re-solve with presolve decides it
            log.warning("minimal-force LP: HiGHS %s without presolve; re-solved with presolve", status)
            self.presolve_resolves += 1
            self._h.setOptionValue("presolve", "on")
            try:
                y, status = self._run(w, False)
            finally:
                self._h.setOptionValue("presolve", "off")
        self._optimal = y is not None
        return y, status

    def _run(self, w: np.ndarray, warm: bool) -> tuple[np.ndarray | None, str]:
        h = self._h
        if not warm:
            h.clearSolver()  # cold: no basis carried over from another disturbance
        h.changeColsCost(6, self._balance, np.asarray(w, dtype=float))  # μ's costs: −b_eq = w
        h.run()
        status = h.getModelStatus()
        if status == self._statuses.kOptimal:
            self._sol = h.getSolution()
            # the LP's y is minus the dual of its row in the dual (HiGHS's sign convention)
            return -np.array(self._sol.row_dual[: self._n]), "optimal"
        if status == self._statuses.kUnbounded:
            return None, "infeasible"
        return None, h.modelStatusToString(status)

    def _unique(self) -> bool:
        """Whether the dual's optimal basis is nondegenerate: every basic column and row
        strictly inside its bounds, so complementary slackness pins every component of
        ``y`` — the LP's optimum is unique (a sufficient condition)."""
        h = self._h
        basic = h.getBasicVariables()[1]  # HiGHS: column j as j, row i as -(1 + i)
        k = np.where(basic >= 0, basic, self._n_col - 1 - basic)
        v = np.concatenate([self._sol.col_value, self._sol.row_value])[k]  # (the last optimal solve's)
        return bool(((v - self._lo[k] > self._primal_tol) & (self._hi[k] - v > self._primal_tol)).all())


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


# atol: absolute on slacks of O(1) rows (the program is scaled, program.py); a stalled iterate
# within 1e-7 of its cones is accepted as feasible, well above the 1e-10 stopping tolerances below
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
        P = _csc(np.triu(prog.A6.T @ prog.A6))
        q = prog.A6.T @ prog.w
    else:
        P = sp.csc_matrix((prog.n, prog.n))
        q = cost
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    # tighter than resist_rtol (1e-6) by four orders: the decision reads the optimum, not the solver's noise
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-10
    settings.tol_feas = 1e-10
    sol = clarabel.DefaultSolver(P, q, _csc(A_all), b_all, cones, settings).solve()
    status = str(sol.status)
    y = np.array(sol.x)
    if status in ("Solved", "AlmostSolved"):
        return y, "optimal"
    if "Infeasible" in status:
        return None, "infeasible"
    if np.isfinite(y).all() and _in_cones(b_all - A_all @ y, cones, sizes):
        return y, f"stalled ({status}), iterate feasible"
    return None, status

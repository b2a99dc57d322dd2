"""Wrench resistance as a quadratic program (thesis Eq. 2.100, 6DFC Eq. IV.3) and the
minimal grasp force LP (Eq. 4.4).

QP over the V-representation: contact wrench ``c_i = Σ_k α_ik v_ik`` with
``α_i`` in a simplex (``Σ = 1`` for a known force, ``<= 1`` for a cone whose
zero-force origin is implicit), so

    min ½ ‖A α + w_ext‖²,   A = [v_11 … v_NM] (6 × n),  α >= 0,  block sums,

a dense QP with n = Σ M_i variables whose Hessian ``AᵀA`` has rank <= 6; a
ridge ``ρ I`` (ρ = ``RIDGE`` × mean diagonal) makes it strictly convex for the
active-set solvers that need it (quadprog, DAQP) and biases the residual by
O(ρ) only.  Forces and torques are scaled by the largest vertex force and
torque first (so the residual is relative in each).  The grasp
resists ``w_ext`` iff ``√ε <= tol`` (relative).  Solvers are called through
qpsolvers; which one is the default was decided by
``benchmarks/bench_grasp.py`` (results/benchmarks/grasp.json).
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from .gws import capacity_scaling, check_contacts, check_wrench, resists_lp, simplex_rows, stacked_vertices

log = logging.getLogger(__name__)

#: relative Tikhonov term on the rank-6 Hessian (see module docstring)
RIDGE = 1e-9
#: default QP solver: "auto" = quadprog up to AUTO_LARGE_QP variables, DAQP above
#: (benchmarks/bench_grasp.py: both agree with the exact LP on every case; at 12
#: variables (two 6DLS contacts) quadprog 0.24 ms vs DAQP 0.26 ms, at 224 (REACH, 32
#: soft contacts) quadprog 25 ms vs DAQP 5.4 ms — the dense active set scales as n³)
DEFAULT_SOLVER = "auto"
AUTO_LARGE_QP = 48
#: tried when the chosen solver returns nothing (interior point: slower, never cycles)
FALLBACK_SOLVER = "clarabel"
#: relative residual below which the wrench counts as resisted
RESIST_TOL = 1e-5


def qp_matrices(contacts, w_ext, mu: float) -> dict:
    """The dense QP of the module docstring (scaled); keys P, q, G, h, A, b, lb, A6, w and
    the vertex blocks (``V``, ``sizes``, ``starts``) for recovering the contact wrenches."""
    w = check_wrench(w_ext)
    contacts = check_contacts(contacts)
    V, sizes, starts, Vs = stacked_vertices(contacts, mu)
    D = capacity_scaling(V)
    A6 = V.T * D[:, None]
    n = V.shape[0]
    P = A6.T @ A6
    P[np.diag_indices(n)] += RIDGE * max(float(np.trace(P)) / n, 1e-300)
    rows_eq, rows_ub = simplex_rows(contacts, sizes, starts)
    return {
        "P": P,
        "q": A6.T @ (w * D),
        "G": np.array(rows_ub) if rows_ub else None,
        "h": np.ones(len(rows_ub)) if rows_ub else None,
        "A": np.array(rows_eq) if rows_eq else None,
        "b": np.ones(len(rows_eq)) if rows_eq else None,
        "lb": np.zeros(n),
        "ub": None,
        "A6": A6,
        "w": w * D,
        "blocks": (sizes, starts, Vs),
    }


def qp_matrices_outer(contacts, w_ext, mu: float, conic: frozenset[int] = frozenset()) -> dict:
    """QP over the outer H-representation (thesis §4.1.2.2: Eq. 3.28 for a known force,
    Eq. 3.30 for the 6DFC): variables ``c_i`` (6, frame C) and, for a cone, ``f_i``;

        min ½ ‖D (Σ G_i c_i + w_ext)‖²   s.t.   A_i c_i <= F_i (μ b_i + A_i ŵ⊥_i)   (known F_i)
                                                A_i c_i − f_i (μ b_i + A_i ŵ⊥_i) <= 0,  0 <= f_i <= f_max.

    Small (6–7 variables per contact) whatever M is: the fast path for grasp analysis.
    conic : indices of contacts whose inequalities :func:`socp_resistance` replaces by
        their model's second-order cone (their equalities and force bounds stay).
    """
    w = check_wrench(w_ext)
    contacts = check_contacts(contacts)
    if any(c.A is None for c in contacts):
        raise ValueError(
            "every contact needs half-spaces (A, b) for the outer QP; use representation='inner'"
        )
    D = capacity_scaling(np.vstack([c.vertices(mu) for c in contacts]))
    sf, st = 1 / D[0], 1 / D[3]
    nvar = sum(6 + c.cone for c in contacts)
    L = np.zeros((6, nvar))
    rows, rhs, eq_rows = [], [], []
    k = 0
    for i, c in enumerate(contacts):
        L[:, k : k + 6] = c.G
        # s_j = 0 rows (± pairs in A s <= b; flat or point-like sets): equalities
        # A_eq (c − F ŵ⊥) = 0, or A_eq c − f A_eq ŵ⊥ = 0 for a cone — as equalities, since
        # active-set solvers (quadprog) reject the degenerate ± pair
        A_in, b_in, An_in, A_eq, An_eq = halfspace_parts(c)
        if i in conic:
            A_in, b_in, An_in = A_in[:0], b_in[:0], An_in[:0]
        bb = mu * b_in + An_in
        row = np.zeros((len(A_in), nvar))
        row[:, k : k + 6] = A_in
        erow = np.zeros((len(A_eq), nvar))
        erow[:, k : k + 6] = A_eq
        if c.cone:
            row[:, k + 6] = -bb
            erow[:, k + 6] = -An_eq
            rhs.append(np.zeros(len(A_in)))
            bounds = np.zeros((2, nvar))
            bounds[0, k + 6], bounds[1, k + 6] = -1.0, 1.0  # -f <= 0, f <= f_max
            rows += [row, bounds]
            rhs.append([0.0, c.force])
            eq_rows.append((erow, np.zeros(len(A_eq))))
        else:
            rows.append(row)
            rhs.append(c.force * bb)
            eq_rows.append((erow, c.force * An_eq))
        k += 6 + c.cone
    # variables in units of the grasp's capacities (x = S y): O(1) entries, so the
    # ridge and the solvers' tolerances mean the same for forces, torques and f_i
    S = np.concatenate([np.r_[np.full(3, sf), np.full(3, st), [sf] * c.cone] for c in contacts])
    L6 = L * D[:, None] * S
    P = L6.T @ L6
    P[np.diag_indices(nvar)] += RIDGE * max(float(np.trace(P)) / nvar, 1e-300)
    G = np.vstack(rows) * S
    h = np.concatenate(rhs)
    gn = np.linalg.norm(G, axis=1)
    gn[gn == 0] = 1.0
    has_eq = any(len(e) for e, _ in eq_rows)
    return {
        "P": P,
        "q": L6.T @ (w * D),
        "G": G / gn[:, None],
        "h": h / gn,
        "A": np.vstack([e for e, _ in eq_rows]) * S if has_eq else None,
        "b": np.concatenate([r for _, r in eq_rows]) if has_eq else None,
        "lb": None,
        "ub": None,
        "A6": L6,
        "w": w * D,
        "S": S,
    }


def _split_pairs(A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Masks (inequality rows, one row of each ``a s <= 0, −a s <= 0`` pair)."""
    eq = np.zeros(len(A), dtype=bool)
    ineq = np.ones(len(A), dtype=bool)
    Z = np.flatnonzero(b == 0)
    if Z.size >= 2:
        dots = A[Z] @ A[Z].T
        sq = np.diag(dots)
        pair = np.isclose(dots, -np.sqrt(np.outer(sq, sq)), rtol=1e-12, atol=0) & (sq[:, None] > 0)
        for r, c in zip(*np.nonzero(np.triu(pair, 1)), strict=True):
            if ineq[Z[r]] and ineq[Z[c]]:
                eq[Z[r]] = True
                ineq[Z[r]] = ineq[Z[c]] = False
    return ineq, eq


def wrench_resistance(
    contacts,
    w_ext,
    mu: float,
    *,
    solver: str = DEFAULT_SOLVER,
    tol: float = RESIST_TOL,
    representation: str = "outer",
    fallback: bool = True,
    refine: bool = True,
    exact: bool = True,
    max_cuts: int = 40,
) -> tuple[bool, float, np.ndarray]:
    """Eq. (2.100): (resisted, relative residual ``‖D (G c + w)‖``, object-frame contact
    wrenches (N, 6)).

    representation : "outer" — half-spaces (Eq. 3.28/3.30, the thesis's QP; 6–7
        variables per contact); "inner" — convex combinations of the vertices
        (conservative, like the GWS).
    refine : for contacts carrying their limit-surface model (6DLS, 6DFC, 3DLS), cut
        the outer polytope down to the model where the solution lands outside it: add
        the tangent plane at the ray point ``s f(s)^(-1/d)`` (Eq. 3.22–3.24) and re-solve
        (Kelley's cutting planes), until every contact wrench satisfies ``f <= 1 + CUT_TOL``.
        In 6D a fixed outer linearisation is loose (support ratio 2.3 at M = 200,
        results/benchmarks/limit_surface.json); the cuts make the answer the model's own.
    exact : with ``refine``, ellipsoidal models go straight to :func:`socp_resistance`
        (their second-order cones, ~1 ms); other models (quartic) use the cuts.
    fallback : retry with ``FALLBACK_SOLVER`` (logged) if the solver returns nothing.
    """
    contacts = check_contacts(contacts)
    if representation == "inner":
        return _solve(contacts, w_ext, mu, solver, tol, "inner", fallback)
    if representation != "outer":
        raise ValueError(f"representation must be 'outer' or 'inner'; got {representation!r}")
    if refine and exact and mu > 0:
        Qs = [_ellipsoid_factor(c) for c in contacts]
        # every model an ellipsoid (polyhedral contacts may join): the cone QP is exact
        if any(Q is not None for Q in Qs) and all(
            Q is not None or "model" not in c.meta for c, Q in zip(contacts, Qs, strict=True)
        ):
            return socp_resistance(contacts, w_ext, mu, tol=tol)
    work = list(contacts)
    for _ in range(max_cuts + 1):
        ok, resid, c, x = _solve(work, w_ext, mu, solver, tol, "outer", fallback, return_x=True)
        if not refine:
            break
        if not ok:  # the outer set cannot resist it: neither can the model inside it
            break
        cut = False
        k = 0
        for ci in work:
            model = ci.meta.get("model")
            n_i = 6 + ci.cone
            if model is not None and mu > 0:
                f = x[k + 6] if ci.cone else ci.force
                if f > 1e-12 * max(ci.force, 1e-300):
                    s = (x[k : k + 6] / f - ci.normal) / mu  # friction wrench, unit force, μ = 1
                    val = float(model.value(s))
                    if val > 1.0 + CUT_TOL:
                        s_star = s * val ** (-1.0 / model.degree)
                        g = model.gradient(s_star)
                        g = g / np.linalg.norm(g)
                        add_cut(ci, g, float(g @ s_star))
                        cut = True
            k += n_i
        if not cut:
            break
    else:
        # the cuts did not converge: the outer answer "resisted" may be optimistic, so
        # the inner vertices (on the model) decide, conservatively
        ok = resists_lp(contacts, w_ext, mu)
        log.warning("cutting planes did not converge in %d cuts; inner-vertex LP decides: %s", max_cuts, ok)
    return ok, resid, c


#: a contact wrench may exceed its limit-surface model by this (relative f) before a cut
CUT_TOL = 1e-4
#: cuts kept per contact model; beyond it the oldest is dropped (every cut is a valid
#: tangent plane, so any subset keeps an outer approximation; the newest must stay, or
#: the refinement would re-solve the same QP)
MAX_STORED_CUTS = 2000


def halfspace_parts(c) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(A_in, b_in, A_in ŵ⊥, A_eq, A_eq ŵ⊥)`` of a contact: its half-spaces split into
    inequalities and ``a s = 0`` rows (given as ± pairs), plus the tangent-plane cuts
    found by earlier refinements.  Cuts live in ``c.meta``, which every ``with_force`` /
    ``moved`` copy shares, so a cached contact model is refined once for all grasps
    (cuts are in the contact frame at μ = 1 and unit force: valid for any pose, μ, F)."""
    base = c.meta.get("_split")
    if base is None or base[0] is not c.A:
        ineq, eq = _split_pairs(c.A, c.b)
        A_in, A_eq = c.A[ineq], c.A[eq]
        base = (c.A, A_in, c.b[ineq], A_in @ c.normal, A_eq, A_eq @ c.normal)
        c.meta["_split"] = base
    _, A_in, b_in, An_in, A_eq, An_eq = base
    cuts = c.meta.get("_cuts")
    if cuts and cuts[0]:
        A_c = np.array(cuts[0])
        A_in = np.vstack([A_in, A_c])
        b_in = np.concatenate([b_in, cuts[1]])
        An_in = np.concatenate([An_in, A_c @ c.normal])
    return A_in, b_in, An_in, A_eq, An_eq


def add_cut(c, a: np.ndarray, b: float) -> None:
    """Store the tangent plane ``a s <= b`` of contact ``c``'s model (shared by its copies)."""
    cuts = c.meta.setdefault("_cuts", ([], []))
    while cuts[0] and len(cuts[0]) >= MAX_STORED_CUTS:
        del cuts[0][0], cuts[1][0]
    cuts[0].append(np.asarray(a, float))
    cuts[1].append(float(b))


def _solve(contacts, w_ext, mu, solver, tol, representation, fallback, return_x=False):
    from qpsolvers import solve_qp

    m = (qp_matrices_outer if representation == "outer" else qp_matrices)(contacts, w_ext, mu)
    if solver == "auto":
        solver = "quadprog" if m["P"].shape[0] <= AUTO_LARGE_QP else "daqp"
    x = solve_qp(
        m["P"], m["q"], m["G"], m["h"], m["A"], m["b"], lb=m["lb"], ub=m["ub"], solver=solver, **_opts(solver)
    )
    if x is not None and not np.isfinite(x).all():
        x = None
    if x is None and fallback and solver != FALLBACK_SOLVER:
        log.warning("QP solver %r returned no solution; retrying with %r", solver, FALLBACK_SOLVER)
        x = solve_qp(
            m["P"], m["q"], m["G"], m["h"], m["A"], m["b"], lb=m["lb"], ub=m["ub"], solver=FALLBACK_SOLVER
        )
    if x is None:
        raise RuntimeError(f"QP solver {solver!r} (and the fallback) returned no solution")
    resid = float(np.linalg.norm(m["A6"] @ x + m["w"]))
    if representation == "outer":
        x = x * m["S"]
        out = (resid <= tol, resid, _contact_wrenches(contacts, x))
        return (*out, x) if return_x else out
    sizes, starts, Vs = m["blocks"]
    c = np.array([x[s : s + k] @ v for s, k, v in zip(starts, sizes, Vs, strict=True)])
    return resid <= tol, resid, c


def _contact_wrenches(contacts, x: np.ndarray) -> np.ndarray:
    """(N, 6) object-frame contact wrenches from the outer/conic variables x (unscaled)."""
    c, k = [], 0
    for ci in contacts:
        c.append(ci.G @ x[k : k + 6])
        k += 6 + ci.cone
    return np.array(c)


def _opts(solver: str) -> dict:
    # tight tolerances for the first-order / interior-point solvers (defaults ~1e-3..1e-6
    # would blur the resisted / not-resisted boundary)
    return {
        "osqp": {"eps_abs": 1e-9, "eps_rel": 1e-9, "max_iter": 20_000, "polish": True, "verbose": False},
        "scs": {"eps_abs": 1e-9, "eps_rel": 1e-9, "verbose": False},
        "proxqp": {"eps_abs": 1e-10},
        # DAQP's plain active set cycles on the near-singular Hessian when the residual
        # is non-zero; its proximal-point mode is robust but less accurate (~1e-5)
        "daqp": {"eps_prox": 1e-8},
    }.get(solver, {})


def min_grasp_force(contacts, w_ext, mu: float, f_max: float | None = None) -> tuple[float, np.ndarray]:
    """Eq. (4.4): ``min Σ f⊥_i`` s.t. ``G c + w_ext = 0``, ``c_i`` in contact i's cone.

    Every contact is used with its force as a variable (the cone over its
    unit-force vertices ``μ s + ŵ⊥``), optionally ``f⊥_i <= f_max``.
    Returns (total normal force [N], per-contact forces (N,)); ``inf`` and NaNs
    if no finite force resists ``w_ext``.
    """
    w = check_wrench(w_ext)
    contacts = check_contacts(contacts)
    gens = [(mu * c.friction + c.normal) @ c.G.T for c in contacts]  # unit normal force
    V = np.vstack(gens)
    n = len(V)
    sizes = [len(g) for g in gens]
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    D = capacity_scaling(V)
    A_ub = b_ub = None
    if f_max is not None:
        A_ub = np.zeros((len(contacts), n))
        for i, (s, k) in enumerate(zip(starts, sizes, strict=True)):
            A_ub[i, s : s + k] = 1.0
        b_ub = np.full(len(contacts), float(f_max))
    res = linprog(
        np.ones(n),
        A_ub=A_ub,
        b_ub=b_ub,
        A_eq=sp.csr_matrix(V.T * D[:, None]),
        b_eq=-w * D,
        bounds=(0, None),
        method="highs",
    )
    if res.status == 2:
        return float("inf"), np.full(len(contacts), np.nan)
    if res.status != 0:
        raise RuntimeError(f"HiGHS failed on the minimal-force LP: {res.message}")
    f = np.array([res.x[s : s + k].sum() for s, k in zip(starts, sizes, strict=True)])
    return float(f.sum()), f


def resists(contacts, w_ext, mu: float, **kw) -> bool:
    """Prediction used by the experiments: the outer QP (Eq. 2.100 with Eq. 3.28/3.30)
    when every contact has half-spaces, else the exact LP over its vertices (6DFW)."""

    contacts = check_contacts(contacts)
    if all(c.A is not None for c in contacts):
        try:
            return wrench_resistance(contacts, w_ext, mu, **kw)[0]
        except RuntimeError as exc:  # every QP route failed: the conservative inner LP decides
            log.warning("%s; deciding by the inner-vertex LP (conservative)", exc)
    return resists_lp(contacts, w_ext, mu)


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


def _ellipsoid_factor(c) -> np.ndarray | None:
    """(r, 6) ``Q`` with ``f(s) = ‖Q s‖²`` if the contact's model is an ellipsoid (cached)."""
    from ..limit_surface.ellipsoid import EllipsoidLS

    model = c.meta.get("model")
    if not isinstance(model, EllipsoidLS):
        return None
    Q = c.meta.get("_Q")
    if Q is None:
        # the model restricted to its PCA subspace B (the complement is pinned by the
        # equality rows; A_e carries a large penalty there, which must not enter Q):
        # f(w) = yᵀ (Bᵀ A_e B) y with y = Bᵀ (w / scale)
        B = model.subspace.basis
        lam, U = np.linalg.eigh(B.T @ model.A_e @ B)
        Q = (np.sqrt(np.clip(lam, 0.0, None))[:, None] * U.T) @ B.T / model.scale[None, :]
        c.meta["_Q"] = Q
    return Q


def socp_resistance(contacts, w_ext, mu: float, *, tol: float = RESIST_TOL) -> tuple[bool, float, np.ndarray]:
    """Eq. (2.100) with the ellipsoidal limit surfaces themselves as constraints (no
    linearisation): ``‖Q_i (c_i − F_i ŵ⊥_i)‖ <= μ F_i`` (second-order cones; ``F_i`` the
    variable ``f_i <= f_max`` for a 6DFC), the flat directions of a low-rank model as
    equalities, other contacts by their half-spaces — one small conic QP, Clarabel.
    Same return as :func:`wrench_resistance`."""
    import clarabel
    import scipy.sparse as sp

    Qs = [_ellipsoid_factor(c) if mu > 0 else None for c in contacts]
    # objective, scaling S, equalities, force bounds and the polyhedral contacts' rows
    m = qp_matrices_outer(contacts, w_ext, mu, conic=frozenset(i for i, Q in enumerate(Qs) if Q is not None))
    S = m["S"]
    nvar = len(S)
    parts = [
        (m["A"], m["b"], clarabel.ZeroConeT),
        (m["G"], m["h"], clarabel.NonnegativeConeT),
    ]
    k = 0
    for c, Q in zip(contacts, Qs, strict=True):
        if Q is not None:  # s = b − A x ∈ SOC: [μ F; Q (c − F ŵ⊥)], F = f_i for a cone
            rows = np.zeros((1 + len(Q), nvar))
            rows[1:, k : k + 6] = -Q
            Qn = Q @ c.normal
            if c.cone:
                rows[0, k + 6] = -mu
                rows[1:, k + 6] = Qn
                rhs = np.zeros(1 + len(Q))
            else:
                rhs = np.concatenate([[mu * c.force], -c.force * Qn])
            parts.append((rows * S, rhs, clarabel.SecondOrderConeT))
        k += 6 + c.cone
    parts = [(a, b, cone) for a, b, cone in parts if a is not None and len(a)]
    A_all = np.vstack([a for a, _, _ in parts])
    b_all = np.concatenate([b for _, b, _ in parts])
    cones = [cone(len(a)) for a, _, cone in parts]
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-10
    settings.tol_feas = 1e-10
    solver = clarabel.DefaultSolver(
        sp.triu(sp.csc_matrix(m["P"])).tocsc(), m["q"], sp.csc_matrix(A_all), b_all, cones, settings
    )
    sol = solver.solve()
    y = np.array(sol.x)
    status = str(sol.status)
    if status not in ("Solved", "AlmostSolved"):
        # Clarabel stalls now and then on low-rank (planar) models; its last iterate is
        # still usable when it satisfies the constraints (s = b − A x in the cones)
        feasible = np.isfinite(y).all() and _in_cones(b_all - A_all @ y, cones, [len(a) for a, _, _ in parts])
        if not feasible:
            log.debug("Clarabel %s on the SOCP; using the cutting-plane QP", status)
            return wrench_resistance(contacts, w_ext, mu, tol=tol, exact=False)
    resid = float(np.linalg.norm(m["A6"] @ y + m["w"]))
    return resid <= tol, resid, _contact_wrenches(contacts, y * S)

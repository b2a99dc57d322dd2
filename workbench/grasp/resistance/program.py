"""The convex program behind every grasp-resistance question (thesis Eq. 2.100, 4.4;
6DFC Eq. IV.3), assembled once for all solvers.

Each contact i contributes variables ``x_i`` that give its local contact wrench
``c_i = L_i x_i`` (frame C) and its normal force ``f_i = φ_i·x_i``:

* **half-space contacts** (``x_i = (c_i, f_i)``, 7 variables): the outer
  linearisation ``A (c − f ŵ⊥) <= μ f b`` (Eq. 3.28/3.30) — exact for polygonal
  models (point, soft point, REACH) — plus, for a limit-surface model taken as
  itself, either its second-order cone ``‖Q (c − f ŵ⊥)‖ <= μ f`` (ellipsoid,
  replacing the linearisation) or tangent-plane cuts from a :class:`CutStore`
  (other models); ``a s = 0`` rows of flat models are equalities;
* **vertex contacts** (``x_i = α_i >= 0``, one weight per vertex, in newtons):
  ``c_i = Σ_m α_m (μ s_m + ŵ⊥)``, ``f_i = Σ_m α_m`` (6DFW, or any contact asked for
  ``representation="inner"``);
* **frictionless contacts** (μ = 0, any model; ``x_i = f_i``): ``c_i = f_i ŵ⊥``.

Forces: ``f_lo <= f_i <= f_hi`` from :meth:`ContactSet.force_bounds` (a cone from 0,
a sensor interval for a known force); for the minimal-force program the bounds
scale with a variable ``s`` (``f_lo s <= f_i <= f_hi s``).  The residual is
``D (Σ_i G_i c_i + w_ext)`` with the capacity scaling D, and every variable is
scaled to O(1) (``x = S y``) so that one tolerance means the same for forces,
torques and weights.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ... import config
from ...limit_surface.ellipsoid import EllipsoidLS
from ..gws import capacity_scaling
from .cuts import CutStore

REPRESENTATIONS = ("model", "outer", "inner")

#: local-wrench and force maps of a half-space contact's variables (c, f)
_L7 = np.hstack([np.eye(6), np.zeros((6, 1))])
_PHI7 = np.r_[np.zeros(6), 1.0]


@dataclass
class Program:
    """Scaled program data in ``y`` (``x = S y``); rows ``G y <= h``, ``A y = b``,
    second-order cones ``h_k − G_k y ∈ SOC``, bounds ``lb <= y <= ub`` (a known force's
    interval is a bound on its variable: DAQP and HiGHS take bounds natively)."""

    n: int
    A6: np.ndarray  # (6, n) residual map: r = A6 y + w
    w: np.ndarray  # (6,) scaled disturbance
    S: np.ndarray  # (n,) variable scaling
    lb: np.ndarray  # (n,) lower bounds (−inf: free)
    ub: np.ndarray  # (n,) upper bounds (+inf: free)
    G: list = field(default_factory=list)
    h: list = field(default_factory=list)
    A: list = field(default_factory=list)
    b: list = field(default_factory=list)
    soc: list = field(default_factory=list)  # [(rows (k, n), rhs (k,))]
    kinds: list = field(default_factory=list)  # per contact: "vertex" | "halfspace" | "cone" | "cuts"
    starts: list = field(default_factory=list)  # first variable of each contact
    L: list = field(default_factory=list)  # per contact (6, n_i) local wrench map (unscaled x)
    phi: list = field(default_factory=list)  # per contact (n_i,) force map (unscaled x)

    def rows(self, which: str) -> tuple[np.ndarray | None, np.ndarray | None]:
        M, v = (self.G, self.h) if which == "ineq" else (self.A, self.b)
        if not M:
            return None, None
        return np.vstack(M), np.concatenate(v)

    def contact_solution(self, contacts, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N, 6) object-frame contact wrenches and (N,) forces at ``y``."""
        x = y * self.S
        cw, f = [], []
        for c, s, L, phi in zip(contacts, self.starts, self.L, self.phi, strict=True):
            xi = x[s : s + len(phi)]
            cw.append(c.G @ (L @ xi))
            f.append(float(phi @ xi))
        return np.array(cw), np.array(f)


def contact_kind(c, representation: str, mu: float, cone_as_cuts: bool = False) -> str:
    """How contact ``c`` enters the program under ``representation``
    (``cone_as_cuts``: ellipsoids by cutting planes too, the cone solver's fallback)."""
    if mu <= 0:  # no friction: the contact wrench is its normal wrench, c = f ŵ⊥ (any model)
        return "frictionless"
    if representation == "inner" or c.A is None:
        return "vertex"
    if representation == "outer" or c.model is None:
        return "halfspace"
    return "cone" if isinstance(c.model, EllipsoidLS) and not cone_as_cuts else "cuts"


def assemble(
    contacts,
    w_ext: np.ndarray,
    mu: float,
    representation: str,
    cuts: CutStore | None,
    *,
    minforce: str | None = None,
    f_max: float | None = None,
    cone_as_cuts: bool = False,
) -> Program:
    """The program for ``contacts`` (validated), ``w_ext`` (6,), friction ``mu``.

    minforce : None (resistance: forces within their bounds, the residual minimised),
        "scale" (one extra variable ``s``: bounds ``f_lo s <= f <= f_hi s``) or "sum"
        (every force free in ``[0, f_max]``, Eq. 4.4).
    f_max : per-contact force cap of the "sum" program [N] (None: uncapped).
    cone_as_cuts : ellipsoidal models by cutting planes instead of their cones.
    """
    kinds = [contact_kind(c, representation, mu, cone_as_cuts) for c in contacts]
    arm = max(float(np.linalg.norm(c.t)) for c in contacts)
    D = capacity_scaling(np.vstack([c.vertices(mu) for c in contacts]), arm)
    sf, st = 1.0 / D[0], 1.0 / D[3]
    size = {"frictionless": 1, "halfspace": 7, "cone": 7, "cuts": 7}
    sizes = [len(c.friction) if k == "vertex" else size[k] for c, k in zip(contacts, kinds, strict=True)]
    n_x = int(sum(sizes))
    n = n_x + (minforce == "scale")
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int)
    S = np.ones(n)
    lb = np.full(n, -np.inf)
    ub = np.full(n, np.inf)
    A6 = np.zeros((6, n))
    if minforce == "scale":
        lb[-1] = 0.0  # the force scale s >= 0
    prog = Program(n, A6, w_ext * D, S, lb, ub, kinds=kinds, starts=list(starts))
    for c, kind, s0, m in zip(contacts, kinds, starts, sizes, strict=True):
        sl = slice(s0, s0 + m)
        if kind == "vertex":
            U = mu * c.friction + c.normal  # (M, 6) unit-force vertices
            L, phi = U.T, np.ones(m)
            S[sl] = sf
            lb[sl] = 0.0
        elif kind == "frictionless":  # x = f: a 6-by-1 map onto ŵ⊥ (a polytope with an
            # empty interior would leave active-set solvers a degenerate face)
            L, phi = c.normal[:, None].astype(float), np.ones(1)
            S[sl] = sf
        else:
            L, phi = _L7, _PHI7
            S[s0 : s0 + 3], S[s0 + 3 : s0 + 6], S[s0 + 6] = sf, st, sf
            _wrench_rows(prog, c, kind, mu, s0, n, cuts)
        prog.L.append(L)
        prog.phi.append(phi)
        A6[:, sl] = (D[:, None] * (c.G @ L)) * S[sl]
        _force_rows(prog, c, kind, phi, s0, n, minforce, f_max)
    # scale the collected rows into y and normalise inequality rows (quadprog is
    # sensitive to row scale; normalising leaves the feasible set unchanged)
    prog.G = [g * S for g in prog.G]
    prog.A = [a * S for a in prog.A]
    prog.soc = [(r * S, rhs) for r, rhs in prog.soc]
    prog.lb, prog.ub = lb / S, ub / S  # bounds on y = x / S
    if prog.G:
        G, h = np.vstack(prog.G), np.concatenate(prog.h)
        gn = np.linalg.norm(G, axis=1)
        gn[gn == 0] = 1.0
        prog.G, prog.h = [G / gn[:, None]], [h / gn]
    return prog


def _wrench_rows(prog: Program, c, kind: str, mu: float, s0: int, n: int, cuts: CutStore | None) -> None:
    """Rows of a half-space contact: ``A_in c − f (μ b + A_in ŵ⊥) <= 0`` (+ cuts), the
    flat directions ``A_eq c − f A_eq ŵ⊥ = 0``, and the ellipsoid's cone."""
    A_in, b_in, An_in, A_eq, An_eq = c.halfspaces
    if kind == "cone":
        A_in, b_in, An_in = A_in[:0], b_in[:0], An_in[:0]
    if kind == "cuts" and cuts is not None:
        A_c, b_c = cuts.rows(c.model)
        if len(A_c):
            A_in = np.vstack([A_in, A_c])
            b_in = np.concatenate([b_in, b_c])
            An_in = np.concatenate([An_in, A_c @ c.normal])
    if len(A_in):
        row = np.zeros((len(A_in), n))
        row[:, s0 : s0 + 6] = A_in
        row[:, s0 + 6] = -(mu * b_in + An_in)
        prog.G.append(row)
        prog.h.append(np.zeros(len(A_in)))
    if len(A_eq):
        row = np.zeros((len(A_eq), n))
        row[:, s0 : s0 + 6] = A_eq
        row[:, s0 + 6] = -An_eq
        prog.A.append(row)
        prog.b.append(np.zeros(len(A_eq)))
    if kind == "cone":  # [μ f; Q (c − f ŵ⊥)] ∈ SOC, written as rhs − rows x
        Q = c.model.factor
        rows = np.zeros((1 + len(Q), n))
        rows[0, s0 + 6] = -mu
        rows[1:, s0 : s0 + 6] = -Q
        rows[1:, s0 + 6] = Q @ c.normal
        prog.soc.append((rows, np.zeros(1 + len(Q))))


def _force_rows(
    prog: Program, c, kind: str, phi: np.ndarray, s0: int, n: int, minforce: str | None, f_max: float | None
) -> None:
    """``f_lo (s) <= φ x <= f_hi (s)``, or an equality when the interval is a point; a
    bound on the force variable itself when it has one and the bounds are fixed."""
    lo, hi = c.force_bounds()
    if minforce == "sum":
        lo, hi = 0.0, (np.inf if f_max is None else float(f_max))
    if kind != "vertex" and minforce != "scale" and lo < hi:
        k = s0 + len(phi) - 1  # the force variable (last of the contact's block)
        prog.lb[k], prog.ub[k] = lo, hi
        return
    row = np.zeros(n)
    row[s0 : s0 + len(phi)] = phi
    scale_col = n - 1 if minforce == "scale" else None
    if lo == hi:
        eq = row.copy()
        if scale_col is not None:
            eq[scale_col] = -lo
            prog.A.append(eq[None])
            prog.b.append(np.zeros(1))
        else:
            prog.A.append(eq[None])
            prog.b.append(np.array([lo]))
        return
    if np.isfinite(hi):
        up = row.copy()
        rhs = hi
        if scale_col is not None:
            up[scale_col], rhs = -hi, 0.0
        prog.G.append(up[None])
        prog.h.append(np.array([rhs]))
    if lo > 0 or not np.all(prog.lb[s0 : s0 + len(phi)] >= 0):
        down = -row
        rhs = -lo
        if scale_col is not None:
            down[scale_col], rhs = lo, 0.0
        prog.G.append(down[None])
        prog.h.append(np.array([rhs]))


def contact_violations(
    prog: Program, contacts, y: np.ndarray, mu: float
) -> list[tuple[int, np.ndarray, float]]:
    """For contacts refined by cuts: ``(i, s, f(s))`` of each whose frictional wrench
    ``s = (c/f − ŵ⊥)/μ`` (μ = 1, unit force) lies outside its model by more than
    ``config.TOL.cut_rtol``."""
    x = y * prog.S
    out = []
    for i, (c, kind) in enumerate(zip(contacts, prog.kinds, strict=True)):
        if kind != "cuts":
            continue
        s0 = prog.starts[i]
        ci, f = x[s0 : s0 + 6], x[s0 + 6]
        if f <= 1e-12 * max(c.force, 1e-300):
            continue
        s = (ci / f - c.normal) / mu
        val = float(c.model.value(s))
        if val > 1.0 + config.TOL.cut_rtol:
            out.append((i, s, val))
    return out


def add_cuts(cuts: CutStore, contacts, violations) -> None:
    """Tangent plane at the ray point ``s f(s)^(-1/d)`` (Eq. 3.22–3.24) for each violation."""
    for i, s, val in violations:
        model = contacts[i].model
        s_star = s * val ** (-1.0 / model.degree)
        g = model.gradient(s_star)
        g = g / np.linalg.norm(g)
        cuts.add(model, g, float(g @ s_star))

"""The convex program behind every grasp-resistance question (thesis Eqs. 2.100, 4.4;
6DFC Eq. IV.3), assembled once for all solvers.

Each contact i contributes variables ``x_i`` that give its local contact wrench
``c_i = L_i x_i + f_i n_i`` (frame C) and its normal force ``f_i = Φ_i·x`` (its own
variable, or ``F_i σ_g`` in a force group, below):

* **half-space contacts** (``x_i = (z_i, f_i)``): the frictional part on the set's
  affine hull, ``c − f ŵ⊥ = N z`` (``N`` (6, d) from :attr:`ContactSet.halfspaces`:
  d = 2 for a point contact, 3 for a soft point, 6 for a full-dimensional model), and
  the outer linearisation ``A N z <= μ f b`` (Eqs. 3.28, 3.30) — exact for polygonal
  models (point, soft point, REACH) — plus, for a limit-surface model taken as itself,
  either its second-order cone ``‖Q N z‖ <= μ f`` (ellipsoid, replacing the
  linearisation) or tangent-plane cuts from a :class:`CutStore` (other models);
* **vertex contacts** (``x_i = α_i >= 0``, one weight per vertex, in newtons):
  ``c_i = Σ_m α_m (μ s_m + ŵ⊥)``, ``f_i = Σ_m α_m`` (6DFW, or any contact asked for
  ``representation="inner"``);
* **frictionless contacts** (μ = 0, any model; ``x_i = f_i``): ``c_i = f_i ŵ⊥``.

Forces: ``f_lo <= f_i <= f_hi`` from :meth:`ContactSet.force_bounds` (a cone from 0,
a sensor interval for a known force); for the minimal-force program the bounds
scale with a variable ``s`` (``f_lo s <= f_i <= f_hi s``).  The known-force contacts
of one force ``group`` (a REACH jaw's elements) share one variable σ_g in
``[1 − r, 1]`` (``[(1 − r) s, s]``) and ``f_i = F_i σ_g``: a half-space contact of a
group has no force variable of its own, which keeps the program as small as with
fixed forces.  The residual is
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
#: kinds whose variables are (z, f) on the set's affine hull: c = N z + f ŵ⊥
_HALFSPACE_KINDS = ("halfspace", "cone", "cuts")


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
    L: list = field(default_factory=list)  # per contact (6, n_i): c = L x_i (+ f ŵ⊥, half-space kinds)
    Phi: np.ndarray | None = None  # (N, n) normal forces f = Phi x (unscaled x)

    def rows(self, which: str) -> tuple[np.ndarray | None, np.ndarray | None]:
        M, v = (self.G, self.h) if which == "ineq" else (self.A, self.b)
        if not M:
            return None, None
        return np.vstack(M), np.concatenate(v)

    def forces(self, y: np.ndarray) -> np.ndarray:
        """(N,) normal forces at ``y``."""
        return self.Phi @ (y * self.S)

    def contact_solution(self, contacts, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N, 6) object-frame contact wrenches and (N,) forces at ``y``."""
        x = y * self.S
        f = self.forces(y)
        cw = [
            c.G @ (L @ x[s : s + L.shape[1]] + (fi * c.normal if k in _HALFSPACE_KINDS else 0.0))
            for c, k, s, L, fi in zip(contacts, self.kinds, self.starts, self.L, f, strict=True)
        ]
        return np.array(cw), f


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
    groups = _force_groups(contacts) if minforce != "sum" else {}  # "sum": every force free
    gcol = {g: k for k, g in enumerate(groups)}
    arm = float(np.sqrt(max(c.t @ c.t for c in contacts)))
    D = capacity_scaling(np.vstack([c.vertices(mu) for c in contacts]), arm)
    sizes = _block_sizes(contacts, kinds, gcol)
    n_x = int(sum(sizes))
    n = n_x + len(groups) + (minforce == "scale")
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int)
    S = np.ones(n)
    lb = np.full(n, -np.inf)
    ub = np.full(n, np.inf)
    A6 = np.zeros((6, n))
    if minforce == "scale":
        lb[-1] = 0.0  # the force scale s >= 0
    N_c = len(contacts)
    prog = Program(n, A6, w_ext * D, S, lb, ub, kinds=kinds, starts=list(starts), Phi=np.zeros((N_c, n)))
    setup = _Setup(mu, cuts, D, n_x, gcol, minforce, f_max)
    for i, (c, s0, m) in enumerate(zip(contacts, starts, sizes, strict=True)):
        _contact_block(prog, setup, i, c, slice(s0, s0 + m))
    for g, r in groups.items():
        _group_rows(prog, n_x + gcol[g], r, minforce)
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


def _block_sizes(contacts, kinds: list[str], gcol: dict) -> list[int]:
    """The number of variables of each contact: its vertex weights, its force (frictionless),
    or z (d,) and, outside a force group, f."""
    sizes = []
    for c, k in zip(contacts, kinds, strict=True):
        if k == "vertex":
            sizes.append(len(c.friction))
        elif k == "frictionless":
            sizes.append(1)
        else:  # z (d,) and, outside a force group, f
            sizes.append(c.halfspaces[2].shape[1] + (c.group not in gcol))
    return sizes


@dataclass(frozen=True)
class _Setup:
    """What every contact's block of :func:`assemble` shares."""

    mu: float
    cuts: CutStore | None
    D: np.ndarray  # (6,) capacity scaling of the residual
    n_x: int  # the contacts' variables (the groups' σ and the scale s follow)
    gcol: dict  # {group: its σ's column after n_x}
    minforce: str | None
    f_max: float | None

    @property
    def sf(self) -> float:
        """Scale of a force variable [N]."""
        return 1.0 / self.D[0]

    @property
    def st(self) -> float:
        """Scale of a torque variable [N m]."""
        return 1.0 / self.D[3]


def _contact_block(prog: Program, setup: _Setup, i: int, c, sl: slice) -> None:
    """Contact ``i`` (``c``, its variables ``sl``) into ``prog``: its wrench map ``L``, force
    row of Φ, scaling, residual columns, wrench rows and force rows."""
    kind = prog.kinds[i]
    S, sf = prog.S, setup.sf
    gc = setup.n_x + setup.gcol[c.group] if c.group in setup.gcol else None  # the group's σ column
    if kind == "vertex":
        U = setup.mu * c.friction + c.normal  # (M, 6) unit-force vertices
        L = U.T
        prog.Phi[i, sl] = 1.0
        S[sl] = sf
        prog.lb[sl] = 0.0
    elif kind == "frictionless":  # x = f: a 6-by-1 map onto ŵ⊥ (a polytope with an
        # empty interior would leave active-set solvers a degenerate face)
        L = c.normal[:, None].astype(float)
        prog.Phi[i, sl] = 1.0
        S[sl] = sf
    else:
        L, fcol, fcoef = _halfspace_block(prog, setup, c, sl, gc)
        prog.Phi[i, fcol] = fcoef
        _wrench_rows(prog, c, kind, setup.mu, sl.start, fcol, fcoef, setup.cuts)
    prog.L.append(L)
    DG = setup.D[:, None] * c.G
    prog.A6[:, sl] = (DG @ L) * S[sl]
    if kind in _HALFSPACE_KINDS:  # the normal wrench f ŵ⊥ through the force's column
        prog.A6[:, fcol] += (DG @ c.normal) * (fcoef * S[fcol])
    if gc is None:
        _force_rows(prog, c, kind, prog.Phi[i], sl, (setup.minforce, setup.f_max))
    elif kind in ("vertex", "frictionless"):  # their force variables equal F_i σ_g
        row = np.zeros(prog.n)
        row[sl] = 1.0
        row[gc] = -c.force
        prog.A.append(row[None])
        prog.b.append(np.zeros(1))


def _halfspace_block(
    prog: Program, setup: _Setup, c, sl: slice, gc: int | None
) -> tuple[np.ndarray, int, float]:
    """The scaling of a half-space contact's variables ``sl``; returns its wrench map ``L``
    (6, m) and its force ``f = fcoef · x[fcol]`` (its own variable, the block's last, or
    ``F_i σ_g`` in the force group whose σ is column ``gc``)."""
    S, s0, m = prog.S, sl.start, sl.stop - sl.start
    _, _, N, nrm = c.halfspaces
    d = N.shape[1]
    # z in newtons or newton-metres after scaling: a basis column is a force
    # or a torque direction for every model here (mixed ones get a blend)
    S[s0 : s0 + d] = setup.sf * nrm[0] + setup.st * nrm[1]
    L = N if m == d else np.hstack([N, np.zeros((6, 1))])
    if gc is None:  # its own force variable, the block's last
        fcol, fcoef = s0 + d, 1.0
        S[fcol] = setup.sf
    else:  # f_i = F_i σ_g
        fcol, fcoef = gc, c.force
    return L, fcol, fcoef


def _force_groups(contacts) -> dict:
    """{group: r} of the contacts' force groups (insertion order), checked: one
    reading has one accuracy, and a group is one jaw — its contacts' normal forces
    must not cancel (two opposing jaws in one group, e.g. a jaw mirrored with
    ``moved`` without a new ``group=``, would share one reading silently)."""
    members = [c for c in contacts if c.group is not None]
    if not members:
        return {}
    groups: dict = {}
    for c in members:
        r = groups.setdefault(c.group, c.rtol)
        if r != c.rtol:
            raise ValueError(
                f"force group {c.group!r} mixes force accuracies {r} and {c.rtol}: the contacts of "
                "one group share one sensor reading (give them one force_rtol)"
            )
    f = np.array([c.force for c in members])
    push = np.einsum(
        "kij,kj->ki", np.array([c.R for c in members]), np.array([c.normal[:3] for c in members])
    )
    push *= f[:, None]
    index = {g: k for k, g in enumerate(groups)}
    label = np.array([index[c.group] for c in members])
    for k, g in enumerate(groups):
        sel = label == k
        net, tot = float(np.linalg.norm(push[sel].sum(axis=0))), float(f[sel].sum())
        if tot > 0 and net < config.TOL.group_min_net_push * tot:
            raise ValueError(
                f"force group {g!r}: its contacts' normal forces cancel (net {net:.3g} N of "
                f"{tot:.3g} N pressed): a group is one jaw's reading, and this one spans opposing jaws. "
                "Give the other jaw its own group (ContactSet.moved(R, t, group='jaw-2') or "
                "dataclasses.replace(c, group=...))"
            )
    return groups


def _group_rows(prog: Program, col: int, r: float, minforce: str | None) -> None:
    """σ_g in ``[1 − r, 1]`` (bounds), or ``[(1 − r) s, s]`` (rows) for the minimal-force
    program; an equality when r = 0."""
    if minforce != "scale":
        if r > 0:
            prog.lb[col], prog.ub[col] = 1.0 - r, 1.0
        else:
            row = np.zeros(prog.n)
            row[col] = 1.0
            prog.A.append(row[None])
            prog.b.append(np.ones(1))
        return
    row = np.zeros(prog.n)
    row[col], row[-1] = 1.0, -1.0  # σ − s
    if r == 0:
        prog.A.append(row[None])
        prog.b.append(np.zeros(1))
        return
    down = np.zeros(prog.n)
    down[col], down[-1] = -1.0, 1.0 - r  # (1 − r) s − σ
    prog.G.append(np.vstack([row, down]))
    prog.h.append(np.zeros(2))
    prog.lb[col] = 0.0


def _wrench_rows(
    prog: Program, c, kind: str, mu: float, s0: int, fcol: int, fcoef: float, cuts: CutStore | None
) -> None:
    """Rows of a half-space contact on its affine hull, ``c − f ŵ⊥ = N z``:
    ``A N z − μ f b <= 0`` (+ cuts ``a s <= b`` likewise), or the ellipsoid's cone
    ``[μ f; Q N z] ∈ SOC``; ``f = fcoef · x[fcol]`` (its own variable, or ``F_i σ_g``
    in a force group)."""
    AN, b_in, N, _ = c.halfspaces
    d = N.shape[1]
    if kind == "cone":
        AN, b_in = AN[:0], b_in[:0]
    if kind == "cuts" and cuts is not None:
        A_c, b_c = cuts.rows(c.model)
        if len(A_c):
            AN = np.vstack([AN, A_c @ N])
            b_in = np.concatenate([b_in, b_c])
    if len(AN):
        row = np.zeros((len(AN), prog.n))
        row[:, s0 : s0 + d] = AN
        row[:, fcol] = -mu * fcoef * b_in
        prog.G.append(row)
        prog.h.append(np.zeros(len(AN)))
    if kind == "cone":  # written as rhs − rows x
        Q = c.model.factor
        rows = np.zeros((1 + len(Q), prog.n))
        rows[0, fcol] = -mu * fcoef
        rows[1:, s0 : s0 + d] = -Q @ N
        prog.soc.append((rows, np.zeros(1 + len(Q))))


def _force_rows(
    prog: Program, c, kind: str, phi: np.ndarray, sl: slice, bounds: tuple[str | None, float | None]
) -> None:
    """``f_lo (s) <= φ x <= f_hi (s)``, or an equality when the interval is a point; a
    bound on the force variable itself when it has one and the bounds are fixed
    (a contact with its own force variable or weights: not in a force group).  ``sl``: the
    contact's variables; ``bounds``: (minforce, f_max) of :func:`assemble`."""
    minforce, f_max = bounds
    s0, m, n = sl.start, sl.stop - sl.start, prog.n
    lo, hi = c.force_bounds()
    if minforce == "sum":
        lo, hi = 0.0, (np.inf if f_max is None else float(f_max))
    if kind != "vertex" and minforce != "scale" and lo < hi:
        k = s0 + m - 1  # the force variable (last of the contact's block)
        prog.lb[k], prog.ub[k] = lo, hi
        return
    row = phi.copy()
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
    if lo > 0 or not np.all(prog.lb[s0 : s0 + m] >= 0):
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
        s0, L = prog.starts[i], prog.L[i]
        f = float(prog.Phi[i] @ x)
        # a force of 1e-12 of its bound is the solver's zero (1e-300: a zero bound stays a guard, not a NaN)
        if f <= 1e-12 * max(c.force, 1e-300):
            continue
        s = (L @ x[s0 : s0 + L.shape[1]]) / (f * mu)  # (c/f − ŵ⊥)/μ
        val = float(c.model.value(s))
        if val > 1.0 + config.TOL.cut_rtol:
            out.append((i, s, val))
    return out


def add_cuts(cuts: CutStore, contacts, violations) -> None:
    """Tangent plane at the ray point ``s f(s)^(-1/d)`` (Eqs. 3.22–3.24) for each violation."""
    for i, s, val in violations:
        model = contacts[i].model
        s_star = s * val ** (-1.0 / model.degree)
        g = model.gradient(s_star)
        g = g / np.linalg.norm(g)
        cuts.add(model, g, float(g @ s_star))

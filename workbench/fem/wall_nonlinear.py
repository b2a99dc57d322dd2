"""Geometrically nonlinear wall squeeze: total Lagrangian St. Venant–Kirchhoff, load stepping.

The linear wall (:mod:`workbench.fem.wall`) assumes small displacements.  A disposable cup
closes ~20 mm at 8–10 N (measured map, thesis §4.3.3.1) — half its radius — so
rotations are not small there.  Strains stay small (a 0.5 mm wall bent to a few
centimetres' radius: ε ≈ t / 2ρ ≲ 1 %), which is the range of St. Venant–Kirchhoff:

    E = ½ (FᵀF − I),   S = λ tr(E) I + 2μ E,   P = F S                        (Green strain, 2nd / 1st Piola)
    dP[δF] = δF S + F (λ tr(δE) I + 2μ δE),   δE = sym(Fᵀ δF)                   (consistent tangent)

on the same triquadratic mesh, Gauss rule and clamps as the linear wall
(:func:`workbench.fem.wall.build_wall`).  The weak form is assembled by
:func:`workbench.fem.svk.svk_tangent`, a Numba element loop (node pair by node pair) instead of
scikit-fem's form language — for a 27-node hex with 27 Gauss points the latter evaluates the form once per
(i, j) basis pair (6,561 times), orders of magnitude slower per tangent
(``results/benchmarks/newton.json``; docs/decisions.md).  ``tests/`` checks it against a scikit-fem
``BilinearForm`` / ``LinearForm`` of the same equations.  Newton's linear systems are
factored by :class:`workbench.fem.sparse_factor.Refactor` (Cholesky, one symbolic analysis per
grasp: the contact set pins dofs without changing the pattern).

The jaws are rigid frictionless planes normal to the grasp axis, which must be the
mesh's x axis (build the wall in that frame: :func:`grasp_frame_wall`); a footprint
node in contact has its x displacement prescribed (Dirichlet), one released when
its reaction turns tensile, one added when it passes a jaw.  Both jaws travel the
same distance from their first touch (displacement control, so snap-through is
followed); the jaw forces are reported and are equal for a grasp through the axis
of an axisymmetric wall.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .sparse_factor import Refactor, nested_dissection, restrict_order
from .svk import svk_tangent
from .wall import Wall, check_wall, turn_matrix

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class NonlinearSqueeze:
    """The answer of :func:`squeeze_nonlinear`: one load curve, arrays read-only.

    status : why the curve stops — ``"reached"`` (the mean jaw force reached the target),
        ``"on_clamp"`` (a jaw would pass a clamped node of its footprint: it rests on the base,
        the grasp is rigid from there) or ``"max_closing"`` (the closing reached
        ``max_closing`` below the target force);
    reason : None when reached, else the same in words;
    closing : (k,) [m] the load curve's closings (both jaws together), from 0;
    jaw_forces : (k, 2) [N] both jaws' forces at each closing, from 0;
    stiffness : force / closing at the target force [N/m] (linear interpolation on the
        curve; NaN when the curve stops below it);
    work : ∫ f dΔ up to the target force [J] (NaN likewise);
    newton_iterations : Newton iterations of all steps; on_clamp : ``status == "on_clamp"``;
    lu_fallbacks : Newton steps whose tangent was not positive definite (factored by SuperLU
        instead of Cholesky: :class:`workbench.fem.sparse_factor.Refactor`);
    seconds : the solve's wall time [s].
    """

    status: str
    reason: str | None
    closing: np.ndarray
    jaw_forces: np.ndarray
    stiffness: float
    work: float
    newton_iterations: int
    on_clamp: bool
    lu_fallbacks: int
    seconds: float

    def __post_init__(self) -> None:
        for name in ("closing", "jaw_forces"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)


#: the words of each :attr:`NonlinearSqueeze.status` but "reached"
_STOPPED = {
    "on_clamp": "a jaw reached a clamped node of its footprint (the base) below the target force",
    "max_closing": "the closing reached max_closing below the target force",
}


def squeeze_nonlinear(
    wall: Wall,
    centre: np.ndarray,
    *,
    jaw: tuple[float, float] = (0.02, 0.04),
    force: float = 10.0,
    max_closing: float = 0.03,
    step: float = 1e-3,
    newton_tol: float = 1e-7,
    max_newton: int = 40,
) -> NonlinearSqueeze:
    """Close two rigid jaws along x through ``centre`` (3,) [m] on a nonlinear wall.

    wall : built in the grasp frame (x = grasp axis; :func:`grasp_frame_wall`);
    jaw : (width, length) [m]; the closing grows by ``step`` [m] (both jaws together)
    until the mean jaw force exceeds ``force`` [N] or the closing reaches
    ``max_closing`` [m]; each step's Newton iterations stop when the largest displacement
    increment is below ``newton_tol`` × the closing, or after ``max_newton``.  Returns a
    :class:`NonlinearSqueeze`: the load curve, the stiffness and work at ``force``, why the
    curve stopped, the Newton counts and seconds.
    """
    check_wall(wall, "squeeze_nonlinear(wall, centre) with wall, centre = grasp_frame_wall(...)")
    if not (np.isfinite(force) and force > 0):
        raise ValueError(f"force must be a positive jaw force [N]; got {force}")
    if not (0 < step < max_closing):
        raise ValueError(f"need 0 < step < max_closing [m]; got {step}, {max_closing}")
    t0 = time.perf_counter()
    sv = _Solve(wall, newton_tol, max_newton)
    sides = _jaw_sides(sv, centre, jaw)
    active = [np.zeros(0, dtype=int), np.zeros(0, dtype=int)]
    closing, forces, on_clamp = [0.0], [np.zeros(2)], False
    while closing[-1] < max_closing and np.mean(forces[-1]) < force:
        d = closing[-1] + step
        if any(d / 2 > stop for *_, stop in sides):
            on_clamp = True  # the jaw would pass the clamped base: it rests on it from here
            break
        f = _closing_step(sv, sides, active, centre, d)
        closing.append(d)
        forces.append(f)
        log.info("squeeze_nonlinear: closing %.2f mm, jaw forces %.3f %.3f N", d * 1e3, *f)
    reached = bool(np.mean(forces[-1]) >= force)
    closing, forces = np.array(closing), np.array(forces)
    stiff, work = curve_stiffness(closing, forces, force)
    status = "on_clamp" if on_clamp else ("reached" if reached else "max_closing")
    return NonlinearSqueeze(
        status=status,
        reason=_STOPPED.get(status),
        closing=closing,
        jaw_forces=forces,
        stiffness=stiff,
        work=work,
        newton_iterations=sv.iters,
        on_clamp=on_clamp,
        lu_fallbacks=0 if sv.chol is None else sv.chol.fallbacks,
        seconds=time.perf_counter() - t0,
    )


class _Solve:
    """The state of one :func:`squeeze_nonlinear`: the wall's dofs, the displacement ``u`` (N,)
    and the one Cholesky pattern of the grasp."""

    def __init__(self, wall: Wall, newton_tol: float, max_newton: int) -> None:
        from .wall import components

        self.b = b = wall.basis
        self.mu, self.lam = wall.material.mu, wall.material.lam
        self.comp = components(b)
        self.fixed = np.ones(b.N, dtype=bool)
        self.fixed[wall.free] = False
        self.outer_x = wall.outer_dofs[:, 0]  # x dofs of the outer-surface nodes
        self.X = wall.outer_xyz
        self.u, self.u_prev = np.zeros(b.N), np.zeros(b.N)
        self.cache: dict = {}
        self.unclamped, self.chol = np.flatnonzero(~self.fixed), None  # contact pins some of these dofs
        self.iters = 0
        self.newton_tol, self.max_newton = newton_tol, max_newton

    def residual(self) -> np.ndarray:
        """(N,) internal force at ``u``."""
        _, r = svk_tangent(self.b, self.u, self.mu, self.lam, self.cache, tangent=False)
        return r

    def newton(self, bc: np.ndarray, target: np.ndarray, d: float) -> None:
        """Newton to equilibrium with the dofs ``bc`` (N,) bool prescribed to ``target`` (N,)
        [m], at the closing ``d`` [m] (the steps' tolerance is relative to it)."""
        u, b = self.u, self.b
        fr = np.flatnonzero(~bc)
        for _ in range(self.max_newton):
            K, r = svk_tangent(b, u, self.mu, self.lam, self.cache)
            if self.chol is None:  # one order and symbolic Cholesky per grasp, for every contact set
                self.chol = Refactor(K, self.unclamped, restrict_order(nested_dissection(K), self.unclamped))
            du = np.zeros(b.N)
            du[bc] = target[bc] - u[bc]
            rhs = -r - K @ du  # du is 0 on the free dofs: -r - K_fb du_b there
            rhs[bc] = du[bc]
            du[self.unclamped] = self.chol.factor(K, pinned=bc[self.unclamped]).solve(rhs[self.unclamped])
            u += du
            self.iters += 1
            log.debug("newton: max |du| %.3e, |r_free| %.3e", np.abs(du).max(), np.linalg.norm(r[fr]))
            if np.abs(du).max() < self.newton_tol * d:
                break
        else:
            log.warning("squeeze_nonlinear: Newton did not converge at closing %.3g mm", d * 1e3)


def _jaw_sides(sv: _Solve, centre: np.ndarray, jaw: tuple[float, float]) -> list[tuple]:
    """Per jaw (the +x side's first): ``(s, footprint nodes, reach, stop)`` — its side ±1, its
    footprint's outer nodes that are not clamped, the distance [m] from ``centre`` along x to
    its first touch, and its travel [m] to a clamped node of its footprint (inf: none)."""
    rel = sv.X - centre
    in_print = (np.abs(rel[:, 1]) <= jaw[0] / 2) & (np.abs(rel[:, 2]) <= jaw[1] / 2)
    sides = []
    for s in (1.0, -1.0):  # jaw on the +x side moves along -x
        cand = np.flatnonzero(in_print & (s * rel[:, 0] > 0))
        if cand.size == 0:
            raise ValueError("no wall under a jaw: the grasp axis misses the object")
        # a clamped node under a jaw (the base) does not move: the jaw stops on it
        pinned = sv.fixed[sv.outer_x[cand]]
        reach = float((s * rel[cand, 0]).max())  # first touch at the outermost node
        stop = float(reach - (s * rel[cand[pinned], 0]).max()) if pinned.any() else np.inf
        sides.append((s, cand[~pinned], reach, stop))
    assert (sv.comp[sv.outer_x] == 0).all()
    return sides


def _closing_step(sv: _Solve, sides: list[tuple], active: list, centre: np.ndarray, d: float) -> np.ndarray:
    """Both jaws closed to ``d`` [m]: Newton to equilibrium on a contact set, then the set
    updated, until it holds (at most 20 sets); ``active`` (per jaw, footprint positions in
    contact) is updated in place.  Returns the (2,) jaw forces [N]."""
    X, outer_x = sv.X, sv.outer_x
    planes = [centre[0] + s * (reach - d / 2) for s, _, reach, _ in sides]
    sv.u, sv.u_prev = sv.u + (sv.u - sv.u_prev), sv.u  # predictor: the last step's increment again
    for _ in range(20):  # contact set for this step: Newton to equilibrium, then update
        bc = sv.fixed.copy()
        target = np.zeros(sv.b.N)
        for (_, cand, _, _), act, plane in zip(sides, active, planes, strict=True):
            bc[outer_x[cand[act]]] = True
            target[outer_x[cand[act]]] = plane - X[cand[act], 0]
        sv.newton(bc, target, d)
        r = sv.residual()
        changed = False
        for j, ((s, cand, _, _), plane) in enumerate(zip(sides, planes, strict=True)):
            act = active[j]
            react = r[outer_x[cand]]  # internal force; the jaw pushes with -s along x
            pos = X[cand, 0] + sv.u[outer_x[cand]]
            keep = act[s * react[act] < 0]  # still pressed
            # passing the jaw by more than 1e-9 of the closing: contact, not round-off
            new = np.union1d(keep, np.flatnonzero(s * (pos - plane) > 1e-9 * d))  # or passing the jaw
            changed |= not np.array_equal(new, act)
            active[j] = new
        if not changed:
            break
    r = sv.residual()
    return np.array(
        [-s * r[outer_x[cand[act]]].sum() for (s, cand, _, _), act in zip(sides, active, strict=True)]
    )


def curve_stiffness(
    closing: np.ndarray, jaw_forces: np.ndarray, force: float, e_scale: float = 1.0
) -> tuple[float, float]:
    """Secant stiffness ``force / Δ`` [N/m] and work ``∫ f dΔ`` [J] at ``force`` [N] on a
    load curve: ``closing`` (k,) [m] from 0, ``jaw_forces`` (k, 2) [N] (their mean is f).

    e_scale : the curve of the same wall with Young's modulus × ``e_scale`` — the St.
    Venant–Kirchhoff displacements depend on f / E only (ν fixed), so that curve is
    ``e_scale × f`` at the same closings.  (NaN, NaN) when the curve stops below ``force``.
    """
    (work,), (d_at,) = curve_work(closing, jaw_forces, [force], e_scale=e_scale)
    return float(force / d_at), float(work)


def curve_work(
    closing: np.ndarray,
    jaw_forces: np.ndarray,
    forces,
    *,
    e_scale: float = 1.0,
    rigid_beyond: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Work ``∫_0^Δ(f) f dΔ`` [J] and closing ``Δ(f)`` [m] at each of ``forces`` (m,) [N]
    on a load curve (``closing`` (k,) [m] from 0, ``jaw_forces`` (k, 2) [N], their mean f;
    ``e_scale`` as :func:`curve_stiffness`), linear between the curve's points (exact for
    a linear spring: ``f² / 2s``) — the work of thesis Eq. 4.5 from the force–deflection
    curve instead of a stiffness (§4.3.5).

    A force above the curve's last point: NaN (not reached), or with ``rigid_beyond`` —
    the curve stopped because a jaw came to rest on a clamped base (``on_clamp`` of
    :func:`squeeze_nonlinear`) — the work and closing at the curve's end (no further
    travel).  Forces <= 0 do no work.
    """
    closing = np.asarray(closing, float)
    fm = e_scale * np.asarray(jaw_forces, float).mean(axis=1)
    if closing.ndim != 1 or fm.shape != closing.shape or closing.size < 2 or closing[0] != 0.0:
        raise ValueError(f"need closing (k,) from 0 and jaw_forces (k, 2); got {closing.shape}, {fm.shape}")
    f = np.atleast_1d(np.asarray(forces, float))
    if np.isnan(f).any():
        raise ValueError("forces must not be NaN (an unresisted grasp has no forces)")
    cum = np.r_[0.0, np.cumsum(0.5 * (fm[1:] + fm[:-1]) * np.diff(closing))]  # ∫ f dΔ at each point
    work, d_at = np.full(f.shape, np.nan), np.full(f.shape, np.nan)
    for i, fi in enumerate(f):
        if fi <= 0:
            work[i], d_at[i] = 0.0, 0.0
        elif fi <= fm[-1]:
            k = max(int(np.argmax(fm >= fi)), 1)  # first point at or above fi
            a = (fi - fm[k - 1]) / (fm[k] - fm[k - 1])
            d_at[i] = closing[k - 1] + a * (closing[k] - closing[k - 1])
            work[i] = cum[k - 1] + 0.5 * (fm[k - 1] + fi) * (d_at[i] - closing[k - 1])
        elif rigid_beyond:
            work[i], d_at[i] = cum[-1], closing[-1]
    return work, d_at


def grasp_frame_wall(geo: Any, material: Any, a: np.ndarray, b: np.ndarray, n_theta: int = 48) -> tuple:
    """The wall of :class:`workbench.fem.object_wall.WallGeometry` ``geo`` built in the frame of the
    grasp from jaw point ``a`` (3,) to ``b`` (3,) [m] (horizontal axis): x is the grasp
    axis, z stays vertical.  Returns ``(wall, centre)``: the built wall and the grasp's
    midpoint (3,) in that frame, as :func:`squeeze_nonlinear` takes them."""
    ax = np.asarray(b, float) - np.asarray(a, float)
    ang = float(np.arctan2(ax[1], ax[0]))
    wall = geo.build(material, n_theta=n_theta, turn=ang)
    return wall, turn_matrix(ang) @ ((np.asarray(a, float) + np.asarray(b, float)) / 2)


__all__ = [
    "NonlinearSqueeze",
    "curve_stiffness",
    "curve_work",
    "grasp_frame_wall",
    "squeeze_nonlinear",
    "svk_tangent",
]

"""Finite-strain pad (``fidelity="nonlinear"``): neo-Hookean layer, frictionless
augmented-Lagrangian contact, load stepping.

Strain energy (decoupled compressible neo-Hookean, e.g. Bonet & Wood, *Nonlinear
Continuum Mechanics for FEA*, §6.5):

    W = μ/2 (J^(-2/3) I₁ − 3) + K/2 (ln J)²,   I₁ = F:F,  J = det F,

whose small-strain limit is exactly the linear split of ``elasticity.py``
(``μ/2(Ī₁−3) → μ dev ε:dev ε``, ``K/2 (ln J)² → K/2 (tr ε)²``).  The isochoric
part is integrated with 2×2×2 Gauss points; the volumetric part with a blend
of one point (SRI, as the linear pad) and 2×2×2 points, by default all 2×2×2:
pure SRI has hourglass modes at finite strain (see :class:`NonlinearPad`).

First Piola stress and its consistent tangent ``dP[δF]`` (a = J^(-2/3)):

    P_iso = μ a (F − I₁/3 F⁻ᵀ)
    dP_iso = μ a [δF − ⅔(F⁻ᵀ:δF)(F − I₁/3 F⁻ᵀ) − ⅔(F:δF) F⁻ᵀ + I₁/3 F⁻ᵀδFᵀF⁻ᵀ]
    P_vol = K ln J F⁻ᵀ,   dP_vol = K (F⁻ᵀ:δF) F⁻ᵀ − K ln J F⁻ᵀδFᵀF⁻ᵀ

Contact: face node i (jaw motion δ along +z) at ``x_i = X_i + δ e_z + u_i`` has
gap ``g_i = d(x_i)`` (signed distance to the rigid obstacle, evaluated in the
*current* configuration, so finite sliding is allowed) and multiplier
``λ_i = max(0, λ̄_i − k_i g_i)`` with nodal penalty ``k_i = penalty · E A_i / h_z``;
Newton solves equilibrium for fixed λ̄ (tangent ``K_T + Σ (k_i n_i n_iᵀ − λ_i ∇n_i)``
with the obstacle curvature ``∇n = ∇²d`` by central differences), then
``λ̄ ← λ`` (Uzawa) until the largest penetration is below ``gap_tol · δ``.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementHex1

from ..groups import checked_group
from ._kernels import _neo_hookean_element_loop
from .contact import ContactSolution, face_gaps
from .elasticity import GAUSS_1, GAUSS_2, basis
from .extract import face_grid, quad_vector_areas, tributary_areas
from .material import Material
from .pad import PadGeometry, top_face_nodes
from .sparse_factor import Refactor, csr_slots, nested_dissection

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class NonlinearControls:
    """How :meth:`NonlinearPad.solve` iterates (its defaults are every experiment's).

    penalty : nodal penalty ``k_i = penalty · E A_i / h_z`` of the augmented Lagrangian;
    gap_tol : allowed penetration as a fraction of the jaw displacement;
    newton_rtol : Newton's residual tolerance relative to the internal and contact forces;
    max_newton : Newton iterations per Uzawa update; max_uzawa : Uzawa updates per load step;
    max_bisections : halvings of a failed load step before ``RuntimeError``."""

    penalty: float = 10.0
    gap_tol: float = 1e-3
    newton_rtol: float = 1e-7
    max_newton: int = 25
    max_uzawa: int = 30
    max_bisections: int = 5

    def __post_init__(self) -> None:
        for name in ("penalty", "gap_tol", "newton_rtol"):
            value = getattr(self, name)
            number = isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)
            if not (number and np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a finite number > 0; got {value!r}")
        for name, what in (
            ("gap_tol", "a fraction of the jaw displacement"),
            ("newton_rtol", "a relative tolerance"),
        ):
            if getattr(self, name) >= 1:
                raise ValueError(f"{name} must be < 1 ({what}); got {getattr(self, name)!r}")
        for name, least in (("max_newton", 1), ("max_uzawa", 1), ("max_bisections", 0)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < least:
                raise ValueError(f"{name} must be an integer >= {least}; got {value!r}")


class _Quadrature:
    """Shape-function gradients (e, q, 8, 3), weights × det J (e, q) and node ids (e, 8)
    of trilinear hexes for one quadrature rule."""

    def __init__(self, mesh, rule) -> None:
        sb = Basis(mesh, ElementHex1(), quadrature=rule)
        G = np.stack([sb.basis[a][0].grad for a in range(8)], axis=0)
        self.G = np.ascontiguousarray(G.transpose(2, 3, 0, 1))
        self.dx = np.ascontiguousarray(sb.dx)
        self.nodes = sb.element_dofs.T


class NonlinearPad:
    """Mesh, bases and dof maps of the layer; ``solve`` presses it into an obstacle."""

    def __init__(self, geometry: PadGeometry, material: Material, *, stabilization: float = 1.0) -> None:
        """stabilization : fraction β of the volumetric energy integrated with 2×2×2
        points, the rest with one point (β = 0: pure SRI as in the linear pad; β = 1:
        full integration).  Measured on a 16 × 20 × 5 mm pad under a R 15 mm cylinder
        at ν = 0.49: pure SRI develops negative tangent eigenvalues (hourglass modes)
        and Newton stalls at 52% layer compression, β = 0.05 at 54%, β = 0.25 at
        59%; β = 1 reaches 60%.  The price is volumetric locking, 4% on the Lamé
        cylinder at ν = 0.49 (``fem-validation`` reports the small-strain offset)."""
        if not 0.0 <= stabilization <= 1.0:
            raise ValueError(f"stabilization must be in [0, 1]; got {stabilization}")
        self.geometry, self.material = geometry, material
        self.stabilization = stabilization
        self.mesh = geometry.mesh()
        self.b2 = basis(self.mesh, GAUSS_2)
        q2 = _Quadrature(self.mesh, GAUSS_2)
        m = material
        # (quadrature, μ, K) per rule: the 2×2×2 points carry the isochoric part and
        # the fraction β of the volumetric one, the centre point the rest (if any)
        self._rules = [(q2, m.mu, stabilization * m.bulk)]
        if stabilization < 1:
            self._rules.append((_Quadrature(self.mesh, GAUSS_1), 0.0, (1.0 - stabilization) * m.bulk))
        # global dof of (element, local node, component)
        self._edofs = np.ascontiguousarray(self.b2.nodal_dofs.T[q2.nodes], dtype=np.int64)  # (e, 8, 3)
        ne = self._edofs.shape[0]
        self._rows = np.broadcast_to(self._edofs.reshape(ne, 24, 1), (ne, 24, 24)).ravel()
        self._cols = np.broadcast_to(self._edofs.reshape(ne, 1, 24), (ne, 24, 24)).ravel()
        # the tangent's CSR pattern once: each element-matrix entry's slot in K.data (duplicates
        # share one), so every tangent is a bincount into it instead of a COO -> CSR conversion
        self._slot, self._indices, self._indptr = csr_slots(self._rows, self._cols, self.b2.N)
        z = self.mesh.p[2]
        self.face = top_face_nodes(self.mesh.p, geometry.thickness)
        nodal = self.b2.nodal_dofs
        fixed = np.zeros(self.b2.N, dtype=bool)
        fixed[nodal[:, np.isclose(z, 0.0)].ravel()] = True
        self.free = np.flatnonzero(~fixed)
        # one fill-reducing order of the free tangent's graph (the element connectivity: the
        # contact blocks stay inside each node's own 3x3 block), used by every Newton solve
        self.face_dofs = nodal[:, self.face].T  # (n, 3) global dofs of the face nodes
        shape = (self.b2.N, self.b2.N)
        pattern = sp.csr_matrix((np.ones(self._indices.size), self._indices, self._indptr), shape=shape)
        self._order = nested_dissection(pattern[self.free][:, self.free])
        # where each face node's 3x3 block sits in the tangent's CSR values: the contact blocks are
        # added there, so K + K_c keeps the pattern and one symbolic Cholesky serves every Newton step
        at = sp.csr_matrix(
            (np.arange(self._indices.size, dtype=float), self._indices, self._indptr), shape=shape
        )
        fd = self.face_dofs
        slots = np.asarray(at[np.repeat(fd, 3, axis=1).ravel(), np.tile(fd, (1, 3)).ravel()])
        self._face_block_slot = slots.astype(np.int64).reshape(-1, 3, 3)  # (n, 3, 3)
        # face quads and tributary areas of the undeformed face (penalty scaling)
        self.face_xy = self.mesh.p[:2, self.face].T
        self._quads, self.area0 = face_grid(self.face_xy)

    def _internal(self, u: np.ndarray) -> tuple[np.ndarray, sp.csr_matrix]:
        """Internal force vector (3N,) and tangent stiffness (3N × 3N) at displacement u,
        element by element (``fem._kernels._neo_hookean_element_loop``), one pass per
        quadrature rule; RuntimeError if an element is inverted (det F ≤ 0)."""
        r = np.zeros(u.size)
        data = np.zeros(self._indices.size)
        for q, mu, kappa in self._rules:
            jmin = _neo_hookean_element_loop(q.G, q.dx, self._edofs, u, mu, kappa, self._slot, data, r)
            if not jmin > 0:
                raise RuntimeError("an element inverted (det F <= 0); reduce the load step")
        return r, sp.csr_matrix((data, self._indices, self._indptr), shape=(u.size, u.size))

    def _valid(self, u: np.ndarray) -> bool:
        ue = u[self._edofs]
        return all(
            (np.linalg.det(np.einsum("eac,eqal->eqcl", ue, q.G) + np.eye(3)) > 0).all()
            for q, _, _ in self._rules
        )

    def _step(self, obstacle, delta, u, lam_bar, k, X0, opts) -> tuple:
        """Equilibrium at jaw displacement ``delta`` from the start ``(u, λ̄)``; returns
        ``(u, λ, normals, penetration, newton_iterations)`` or raises ``RuntimeError``."""
        h = self.geometry.thickness
        hz = opts["hz"]
        newton_total = 0
        u = u.copy()
        for _uz in range(opts["max_uzawa"]):
            for it in range(opts["max_newton"]):
                uf = u[self.face_dofs]
                gap, nrm = obstacle.signed_distance(X0 + [0, 0, delta] + uf)
                lam = np.maximum(0.0, lam_bar - k * gap)
                r, K = self._internal(u)
                f_c = np.zeros(self.b2.N)
                np.add.at(f_c, self.face_dofs.ravel(), (lam[:, None] * nrm).ravel())
                res = (r - f_c)[self.free]
                act = lam > 0
                # consistent contact tangent k n nᵀ − λ ∇n (∇n = ∇²d, the obstacle's
                # curvature, by central differences of the normal field); the curvature
                # term is left out on the first iteration, where λ comes from the raw
                # load increment, is far too large and would make the tangent indefinite
                geo = 0.0
                if it > 0:
                    # central-difference step of the gap's normal: ~cbrt(machine epsilon) x thickness
                    xa, eps = X0[act] + [0, 0, delta] + uf[act], 1e-6 * h
                    cols = [
                        obstacle.signed_distance(xa + eps * e)[1] - obstacle.signed_distance(xa - eps * e)[1]
                        for e in np.eye(3)
                    ]
                    dn = np.stack(cols, axis=2) / (2 * eps)  # (m, 3, 3): dn_i/dx_j
                    geo = lam[act, None, None] * 0.5 * (dn + dn.transpose(0, 2, 1))
                blocks = k[act, None, None] * nrm[act, :, None] * nrm[act, None, :] - geo
                K.data[self._face_block_slot[act]] += blocks  # K + K_c, one node's block each
                if opts["chol"] is None:  # the symbolic analysis once per solve
                    opts["chol"] = Refactor(K, self.free, self._order)
                du = opts["chol"].factor(K).solve(-res)
                # cap the step (a fresh contact can ask for large jumps), back off while
                # an element would invert
                du *= min(1.0, 0.25 * hz / max(np.abs(du).max(), 1e-300))
                for _ in range(8):
                    trial = u.copy()
                    trial[self.free] += du
                    if self._valid(trial):
                        break
                    du *= 0.5
                else:
                    raise RuntimeError(f"elements invert at delta = {delta:.3g} m")
                u = trial
                newton_total += 1
                log.debug(
                    "newton %d: |res| %.3e, active %d, |du| %.3e",
                    it,
                    np.abs(res).max(),
                    act.sum(),
                    np.abs(du).max(),
                )
                ref = max(np.abs(r[self.free]).max(), np.abs(f_c).max(), 1e-30)
                if np.abs(res).max() <= opts["newton_rtol"] * ref and np.abs(du).max() <= 1e-9 * h:
                    break
            else:
                raise RuntimeError(f"Newton did not converge at delta = {delta:.3g} m")
            uf = u[self.face_dofs]
            gap, nrm = obstacle.signed_distance(X0 + [0, 0, delta] + uf)
            lam_bar = np.maximum(0.0, lam_bar - k * gap)
            pen = float(max(0.0, -gap.min()))
            if pen <= opts["gap_tol"] * delta:  # relative to δ: the force error is ~pen/δ
                return u, lam_bar, nrm, pen, newton_total
        raise RuntimeError(f"augmented Lagrangian did not converge at delta = {delta:.3g} m")

    def solve(
        self,
        obstacle,
        deltas,
        *,
        step: float | None = None,
        controls: NonlinearControls | None = None,
    ) -> dict[float, ContactSolution]:
        """Solutions at each jaw displacement in ``deltas`` [m] (increasing).

        Load steps of at most ``step`` (default h/10), each started from a secant
        predictor; a step that fails (Newton, inversion, Uzawa) is retried with half
        the increment up to ``controls.max_bisections`` times before ``RuntimeError``.
        controls : the augmented Lagrangian's and Newton's settings (:class:`NonlinearControls`;
        default its defaults).
        """
        c = checked_group(
            controls, NonlinearControls, "controls", hint="pass NonlinearControls(penalty=..., gap_tol=...)"
        )
        g, h = self.geometry, self.geometry.thickness
        deltas = sorted(float(d) for d in deltas)
        step = h / 10 if step is None else step
        max_bisections = c.max_bisections
        hz = float(np.diff(np.unique(np.round(self.mesh.p[2], 12))).min())
        opts = {
            "hz": hz,
            "max_uzawa": c.max_uzawa,
            "max_newton": c.max_newton,
            "newton_rtol": c.newton_rtol,
            "gap_tol": c.gap_tol,
            "chol": None,  # sparse_factor.Refactor of the tangent's free block, built on first use
        }
        k = c.penalty * self.material.E * self.area0 / hz  # (n,) nodal penalty stiffness [N/m]
        X0 = np.column_stack([self.face_xy, np.full(self.face.size, h)])
        for d in deltas:
            face_gaps(g, self.face_xy, obstacle, d)  # deeper-than-layer check up front
        u = np.zeros(self.b2.N)
        lam_bar = np.zeros(self.face.size)
        u_old, d_old, d_cur = u.copy(), 0.0, 0.0
        # the state at δ = 0: stress-free unless the obstacle already overlaps the face
        gap0, nrm = face_gaps(g, self.face_xy, obstacle, 0.0)[1:]
        its, pen = 0, 0.0
        # a round-off overlap (an obstacle vertex placed exactly on the face) is contact, not a
        # load: stepping on it asks Newton to resolve a ~1e-18 m residual and it fails to converge
        if (gap0 < -1e-9 * h).any():
            u, lam_bar, nrm, pen, its = self._step(obstacle, 0.0, u, lam_bar, k, X0, opts)
            u_old = u.copy()
        out: dict[float, ContactSolution] = {}
        for target in deltas:
            inc = min(step, target - d_cur)
            # load steps reach the target exactly, not one round-off step short of it
            while d_cur < target - 1e-12 * h:
                t0 = time.perf_counter()
                delta = min(d_cur + inc, target)
                start = u
                if d_cur > d_old:  # secant predictor from the last two converged states
                    pred = u + (u - u_old) * (delta - d_cur) / (d_cur - d_old)
                    start = pred if self._valid(pred) else u
                try:
                    u_new, lam_new, nrm, pen, its = self._step(obstacle, delta, start, lam_bar, k, X0, opts)
                except RuntimeError as exc:
                    inc *= 0.5
                    if inc < step / 2**max_bisections:
                        raise RuntimeError(
                            f"{exc}; no convergence with load steps down to {2 * inc:.3g} m"
                        ) from exc
                    log.info("%s: retrying with a load step of %.3g m", exc, inc)
                    continue
                u_old, d_old = u, d_cur
                u, lam_bar, d_cur = u_new, lam_new, delta
                log.info("delta %.4g m: %d Newton iterations, %.1f s", delta, its, time.perf_counter() - t0)
                inc = min(step, 2 * inc)  # grow back after a bisection
            uf = u[self.face_dofs]
            x = X0 + [0, 0, target] + uf
            out[target] = ContactSolution(lam_bar.copy(), nrm, uf.copy(), x, its, "neo-Hookean AL", pen)
        return out

    def deformed_areas(self, sol: ContactSolution) -> np.ndarray:
        """(n,) tributary areas of the deformed face (for Cauchy pressures λ / a)."""
        qa = np.linalg.norm(quad_vector_areas(sol.x[self._quads]), axis=1)
        return tributary_areas(self._quads, qa, self.face.size)

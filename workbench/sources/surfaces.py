"""Parametric contact surfaces (thesis Table 3.1, Example 3.2.5), their
adaptive quadrature and their triangle meshes.

Continuous wrenches (Eqs. 3.1–3.5) are integrated by h-adaptive tensor
Gauss-Legendre cubature: each cell's integral is compared with the sum over its
four children and the cells with the largest differences are refined (maximum
marking) until the summed estimate meets the tolerance.  The friction
integrand has point singularities where the tangential slip vanishes (the slip
direction jumps); adaptivity isolates them in a few small cells instead of
refining everywhere.  The cell integrals reuse the discrete 6DFW kernel: a
cell's Gauss points *are* a tiny contact profile.
"""

from __future__ import annotations

import logging
import math
import numbers
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Any

import numpy as np

from .. import _kernels, config
from ..kernel_launch import launch
from ..profile import ContactProfile, pca_box_longest_side
from ..twists import canonical_twists
from ..units import check_extent
from ..wrench import check_mu, check_twists

Array = np.ndarray
log = logging.getLogger(__name__)

#: Relative accuracy of the central-difference ``σ_u, σ_v`` of a surface without analytic
#: ones (step 1e-6 of the parameter range: rounding ~ε/1e-6 ≈ 2e-10 of ``|σ| / range``,
#: truncation ~1e-12 of ``range² |σ‴|``; a flat disk's F and area come out 1.7e-11 low).
#: The noise does not shrink as cells are refined, so no quadrature of such a surface can
#: meet a tighter tolerance: its effective tolerance is ``max(rtol, CENTRAL_DIFFERENCE_RTOL)``
#: (:func:`surface_moments`, :func:`surface_wrenches`).
CENTRAL_DIFFERENCE_RTOL = 1e-10


@dataclass(frozen=True, eq=False)
class ParametricSurface:
    """A contact surface ``σ(u, v)`` on ``[u0, u1] × [v0, v1]`` with a pressure.

    sigma : callable ``(u, v) -> (..., 3)`` [m], vectorized over arrays.
    sigma_u, sigma_v : optional analytic partial derivatives (else central
        differences, ``CENTRAL_DIFFERENCE_RTOL`` ~1e-10 relative accuracy, which bounds the
        tolerance of every integral of the surface from below).
    pressure : optional callable ``(u, v, xyz) -> (...)`` [Pa]; uniform 1 Pa if
        None.  ``pressure_scale`` multiplies it.  Its values must be finite and >= 0, and
        not zero at every quadrature point (ValueError where they are evaluated).
    flip : flip ``σ_u × σ_v`` so normals point outward from the object.
    allow_scale : accept a surface longer than ``config.TOL.max_object_extent_m`` (2 m, the
        thesis's S1-S6 up to rounding).  Without it such a surface raises ``ValueError`` where
        it is first integrated or meshed (:func:`surface_moments`, :func:`mesh_surface`): it is
        almost surely in millimetres — the rule of a ``ContactProfile``'s size
        (:func:`workbench.units.check_extent` on ``length_scale``), read at call time.
    """

    name: str
    sigma: Callable[[Array, Array], Array]
    u_range: tuple[float, float]
    v_range: tuple[float, float]
    sigma_u: Callable[[Array, Array], Array] | None = None
    sigma_v: Callable[[Array, Array], Array] | None = None
    pressure: Callable[[Array, Array, Array], Array] | None = None
    pressure_scale: float = 1.0
    flip: bool = False
    description: str = field(default="", compare=False)
    allow_scale: bool = field(default=False, kw_only=True)

    def __post_init__(self) -> None:
        for rng_name in ("u_range", "v_range"):
            lo, hi = getattr(self, rng_name)
            if not (np.isfinite(lo) and np.isfinite(hi) and hi > lo):
                raise ValueError(f"{rng_name} must be finite with lo < hi; got {(lo, hi)}")
        if not (np.isfinite(self.pressure_scale) and self.pressure_scale > 0):
            raise ValueError(f"pressure_scale must be > 0; got {self.pressure_scale}")

    # ---------------------------------------------------------- evaluation
    @property
    def analytic_derivatives(self) -> bool:
        """Whether ``σ_u`` and ``σ_v`` are given (else central differences)."""
        return self.sigma_u is not None and self.sigma_v is not None

    def _vectors(self, fn: Callable[[Array, Array], Array], u: Array, v: Array, what: str) -> Array:
        """``fn(u, v)`` as float (u.shape + (3,)); ValueError naming ``what`` otherwise."""
        out = np.asarray(fn(u, v), dtype=float)
        if out.shape != np.shape(u) + (3,):
            raise ValueError(
                f"surface {self.name!r}: {what} must map u, v of shape {np.shape(u)} to (x, y, z) of shape "
                f"{np.shape(u) + (3,)} [m]; got shape {out.shape}. Stack the coordinates on the last "
                "axis, e.g. np.stack(np.broadcast_arrays(x, y, z), axis=-1)"
            )
        return out

    def derivatives(self, u: Array, v: Array) -> tuple[Array, Array]:
        """``σ_u, σ_v`` at (u, v), analytic if given else central differences."""
        if self.analytic_derivatives:
            return self._vectors(self.sigma_u, u, v, "sigma_u"), self._vectors(self.sigma_v, u, v, "sigma_v")
        # central-difference step: ~cube root of machine epsilon times the range (~1e-10 accuracy)
        hu = 1e-6 * (self.u_range[1] - self.u_range[0])
        hv = 1e-6 * (self.v_range[1] - self.v_range[0])
        sig = self.sigma
        su = (self._vectors(sig, u + hu, v, "sigma") - self._vectors(sig, u - hu, v, "sigma")) / (2 * hu)
        sv = (self._vectors(sig, u, v + hv, "sigma") - self._vectors(sig, u, v - hv, "sigma")) / (2 * hv)
        return su, sv

    def evaluate(self, u: Array, v: Array) -> tuple[Array, Array, Array, Array]:
        """Points, unit normals, area density ``|σ_u × σ_v|`` and pressure at (u, v).

        u, v : (P,) float.  Returns xyz (P, 3), n (P, 3), jac (P,), p (P,).
        Where ``jac = 0`` (poles, apexes) the normal is set to 0; such points
        carry zero weight.
        """
        xyz = self._vectors(self.sigma, u, v, "sigma")
        su, sv = self.derivatives(u, v)
        cr = np.cross(su, sv)
        jac = np.linalg.norm(cr, axis=-1)
        n = cr / np.where(jac > 0, jac, 1.0)[..., None]
        if self.flip:
            n = -n
        if self.pressure is None:
            p = np.full(jac.shape, self.pressure_scale)
        else:
            p = self.pressure_scale * np.broadcast_to(np.asarray(self.pressure(u, v, xyz), float), jac.shape)
            bad = ~(np.isfinite(p) & (p >= 0))
            if bad.any():
                k = int(np.argmax(bad))
                raise ValueError(
                    f"surface {self.name!r}: the pressure must be finite and >= 0 [Pa] (a contact only "
                    f"pushes, CONVENTIONS.md); got {p.flat[k]:g} at (u, v) = ({np.ravel(u)[k]:g}, "
                    f"{np.ravel(v)[k]:g}), {int(bad.sum())} of {p.size} points. Fix the pressure callable "
                    "(e.g. clip it at 0)"
                )
        return xyz, n, jac, p

    def with_pressure_scale(self, scale: float) -> ParametricSurface:
        """Copy with the pressure multiplied by ``scale``."""
        return replace(self, pressure_scale=self.pressure_scale * float(scale))

    def normalized(self) -> ParametricSurface:
        """Copy with ``p̂ = p / F`` so that ``∫ p̂ dS = 1`` (§3.2.2)."""
        return self.with_pressure_scale(1.0 / surface_moments(self).F)

    @property
    def length_scale(self) -> float:
        """Longest side ``l_s`` of the PCA-aligned bounding box [m] (§3.3.2)."""
        return _length_scale(self)


# ------------------------------------------------------------------ quadrature
@lru_cache(maxsize=16)
def _gauss(order: int) -> tuple[Array, Array]:
    x, w = np.polynomial.legendre.leggauss(order)
    uu, vv = np.meshgrid(x, x, indexing="ij")
    ww = np.outer(w, w)
    return np.column_stack([uu.ravel(), vv.ravel()]), ww.ravel()


def _cell_points(surface: ParametricSurface, cells: Array, order: int):
    """Gauss points of cells (m, 4) = [u0, u1, v0, v1].

    Returns xyz (m*q, 3), normals (m*q, 3), area weights ``w_gl |σ_u × σ_v|``
    (m*q,) and pressures (m*q,).
    """
    nodes, weights = _gauss(order)
    hu = 0.5 * (cells[:, 1] - cells[:, 0])
    hv = 0.5 * (cells[:, 3] - cells[:, 2])
    u = (cells[:, 0] + hu)[:, None] + hu[:, None] * nodes[None, :, 0]
    v = (cells[:, 2] + hv)[:, None] + hv[:, None] * nodes[None, :, 1]
    xyz, n, jac, p = surface.evaluate(u.ravel(), v.ravel())
    da = (weights[None, :] * (hu * hv)[:, None]).ravel() * jac
    return xyz, n, da, p


class _CellGeometry:
    """The Gauss points of quadrature cells, each cell evaluated once per instance and kept in
    flat arrays the wrench kernel reads in place (a cell = a segment of ``q`` points).

    The adaptive quadrature of a twist chunk re-visits the cells other twists and chunks
    refined into — measured over 1,000 twists at rtol 1e-4, S1 asked for 118,420 cells of
    which 14,902 differ, S4 262,258 of 21,659 — and evaluating the surface (its Python
    callables) and gathering the points cost far more than the wrench kernel on them.  A cell is
    named by its id from :func:`_adaptive` (``cell_ids=True``; one instance per set of
    initial cells, so an id is one cell's bounds) and looked up in a hash table by a kernel:
    hashing the bounds' bytes in a Python dict was a large share of the quadrature's CPU time,
    the ids and the kernel's table a small one (docs/decisions.md).  A
    cell deeper than the ids reach (a negative id) is keyed by its bounds (u0, u1, v0, v1),
    bit for bit: children are midpoints of their parent's, so a cell reached twice has the
    same bytes.  Holds at most ``max_cells`` cells (or one call's): when a call's new cells do
    not fit, it starts afresh.

    Arrays per segment: ``ids`` (its cell's key).  Per point: ``r = xyz - center`` (the torque
    arm), ``n``, ``dw = w_gl |σ_u × σ_v| p``.
    """

    def __init__(self, surface: ParametricSurface, order: int, center: Array, max_cells: int) -> None:
        self.surface, self.order, self.center, self.max_cells = surface, order, center, max_cells
        self.q = order * order
        self.ids = np.empty(64, dtype=np.int64)  # capacity doubles, as that of cols
        self.cols = np.empty((7, 64 * self.q))  # rx, ry, rz, nx, ny, nz, dw
        self._clear()

    def _clear(self) -> None:
        self.n = 0  # cells held
        self.table = np.full((2, 64), -1, dtype=np.int64)  # _kernels._cell_slots'
        self.deep: dict[bytes, int] = {}  # bounds -> key (< -1) of a cell without an id

    def _keys(self, cells: Array, ids: Array) -> Array:
        """(m,) the cells' ids, each negative one (a cell too deep for an id) replaced by a key
        < -1 of its bounds (-1 marks empty entries of the table)."""
        if ids.size == 0 or ids.min() >= 0:
            return ids
        deep = np.flatnonzero(ids < 0)
        ids = ids.copy()
        bounds = np.ascontiguousarray(cells[deep], dtype=np.float64).view(np.dtype((np.void, 32))).ravel()
        ids[deep] = [self.deep.setdefault(key, -2 - len(self.deep)) for key in bounds.tolist()]
        return ids

    def _slots(self, keys: Array) -> tuple[Array, Array]:
        """(m,) slots of keys (m,), adding the missing ones; (k,) rows of the k added."""
        size = self.table.shape[1]
        if 2 * (self.n + keys.size) > size:  # under half full after the call: short probes
            size = 1 << int(2 * (self.n + keys.size)).bit_length()
            self.table = np.full((2, size), -1, dtype=np.int64)
            held = self.ids[: self.n]  # distinct: re-added at their slots 0..n-1
            _kernels._cell_slots(self.table, held, 0, np.empty_like(held), np.empty_like(held))
        slots, rows = np.empty_like(keys), np.empty_like(keys)
        k = _kernels._cell_slots(self.table, keys, self.n, slots, rows)
        return slots, rows[:k]

    def segments(self, cells: Array, ids: Array) -> tuple[Array, Array]:
        """(m,) first and one-past-last point in :attr:`cols` of each of cells (m, 4) with
        ids (m,) int64 (:func:`_adaptive`'s, negative for a cell without one)."""
        ids = np.asarray(ids, dtype=np.int64)
        keys = self._keys(cells, ids)
        slots, new = self._slots(keys)
        if new.size and self.n + new.size > self.max_cells:
            self._clear()  # full: start afresh (every cell of this call is new then)
            keys = self._keys(cells, ids)
            slots, new = self._slots(keys)
        if new.size:  # slots n.. in order of first appearance, as a dict of the cells did
            self._store(cells[new], keys[new])
        lo = slots * self.q
        return lo, lo + self.q

    def _store(self, cells: Array, keys: Array) -> None:
        """Evaluate cells (k, 4) with keys (k,) into the next k segments."""
        xyz, n, da, p = _cell_points(self.surface, cells, self.order)
        start, stop = self.n, self.n + cells.shape[0]
        a, b = start * self.q, stop * self.q
        if stop > self.ids.size:
            size = max(2 * self.ids.size, stop)
            self.ids = np.concatenate([self.ids[:start], np.empty(size - start, dtype=np.int64)])
            grown = np.empty((7, size * self.q))
            grown[:, :a] = self.cols[:, :a]
            self.cols = grown
        self.ids[start:stop] = keys
        self.cols[0:3, a:b] = (xyz - self.center).T
        self.cols[3:6, a:b] = n.T
        self.cols[6, a:b] = da * p
        self.n = stop


#: Cell ids (:func:`_adaptive` with ``cell_ids=True``): the i-th of m initial cells is m + i
#: and child k of cell c (:func:`_split`'s order) is 4c + k, a 4-ary heap numbering unique
#: across levels (a level-L id lies in [m 4^L, 2m 4^L)).  Ids stay below _ID_LIMIT (int64 cannot
#: overflow): a child past it gets a negative id (none), as do its descendants (4c + k < 0 for
#: c < 0) — with 16 initial cells, those of level 29 and deeper (widths < 2e-9 of the initial
#: cells').
_ID_LIMIT = 2**62


def _split_ids(ids: Array) -> Array:
    """(m,) cell ids -> (4m,) their children's, children of cell i at rows 4i..4i+3 (as :func:`_split`)."""
    kids = (4 * ids[:, None] + np.arange(4)).ravel()
    if ids.size and ids.max() >= _ID_LIMIT // 4:  # rare: not tested per child
        kids[np.repeat(ids >= _ID_LIMIT // 4, 4)] = -1
    return kids


def _split(cells: Array) -> Array:
    """(m, 4) cells -> (4m, 4) children, children of cell i at rows 4i..4i+3."""
    u0, u1, v0, v1 = cells.T
    um, vm = 0.5 * (u0 + u1), 0.5 * (v0 + v1)
    kids = np.empty((cells.shape[0], 4, 4))
    # child k: u half k % 2, v half k // 2 (columns u_lo, u_hi, v_lo, v_hi)
    for k, (ua, ub, va, vb) in enumerate(
        ((u0, um, v0, vm), (um, u1, v0, vm), (u0, um, vm, v1), (um, u1, vm, v1))
    ):
        kids[:, k, 0], kids[:, k, 1], kids[:, k, 2], kids[:, k, 3] = ua, ub, va, vb
    return kids.reshape(-1, 4)


@lru_cache(maxsize=256)
def _initial_cells(surface: ParametricSurface, n_cells: int = 16) -> Array:
    """Roughly square initial cells in physical space."""
    lu, lv = _side_lengths(surface)
    nu = int(np.clip(round(np.sqrt(n_cells * lu / max(lv, 1e-300))), 1, n_cells))
    nv = max(1, n_cells // nu)
    ue = np.linspace(*surface.u_range, nu + 1)
    ve = np.linspace(*surface.v_range, nv + 1)
    U0, V0 = np.meshgrid(ue[:-1], ve[:-1], indexing="ij")
    U1, V1 = np.meshgrid(ue[1:], ve[1:], indexing="ij")
    return np.column_stack([U0.ravel(), U1.ravel(), V0.ravel(), V1.ravel()])


#: a pass of :func:`_adaptive` splits the cells of an unconverged group whose error is at least
#: this fraction of the group's worst cell's
_REFINE_ETA = 0.1


def _adaptive(
    evaluate: Callable[[Array, Array], Array],
    init_cells: Array,
    n_groups: int,
    scale: Array,
    tol: float,
    max_passes: int,
    setting: str = "rtol",
    cell_ids: bool = False,
) -> tuple[Array, Array, int]:
    """Adaptive cubature of ``n_groups`` vector integrands sharing a domain.

    evaluate(cells (m, 4), groups (m,)) -> (m, q) integrals per cell.
    scale : (n_groups, q) component scales; the error of a cell is
    ``max_j |fine_j - coarse_j| / scale_j`` and a group converges when its
    summed error is <= tol; each pass splits the cells of the open groups whose error is at
    least :data:`_REFINE_ETA` times their group's worst, up to ``config.TOL.quadrature_max_cells``
    cells (read now).  Returns integrals (G, q), error estimates (G,)
    and the number of integrand cells evaluated.  setting : where ``tol`` came from
    (named by the warning when the cell cap stops the refinement).  cell_ids : call
    ``evaluate(cells, groups, ids)`` instead, ids (m,) int64 naming each cell among the
    descendants of ``init_cells`` (negative: none, :data:`_ID_LIMIT`).
    """
    block = config.TOL.quadrature_eval_block
    max_cells = config.TOL.quadrature_max_cells
    eta = _REFINE_ETA
    raw_evaluate = evaluate

    def evaluate(c: Array, g: Array, ids: Array) -> Array:  # bounded temporaries
        def part(i: int, j: int) -> Array:
            return raw_evaluate(c[i:j], g[i:j], ids[i:j]) if cell_ids else raw_evaluate(c[i:j], g[i:j])

        if c.shape[0] <= block:
            return part(0, c.shape[0])
        return np.concatenate([part(i, i + block) for i in range(0, c.shape[0], block)])

    def evaluate_kids(c: Array, g: Array, ids: Array) -> Array:  # (m, 4, q) of cells' children
        return evaluate(_split(c), np.repeat(g, 4), _split_ids(ids)).reshape(-1, 4, q)

    m0 = init_cells.shape[0]
    cells = np.tile(init_cells, (n_groups, 1))
    groups = np.repeat(np.arange(n_groups), m0)
    ids = m0 + np.arange(n_groups * m0, dtype=np.int64) % m0  # as np.tile(init_cells, ...)
    coarse = evaluate(cells, groups, ids)
    q = coarse.shape[1]
    kids = evaluate_kids(cells, groups, ids)
    n_eval = 5 * cells.shape[0]
    for _ in range(max_passes):
        fine = kids.sum(axis=1)
        err = (np.abs(fine - coarse) / scale[groups]).max(axis=1)
        total = np.bincount(groups, err, minlength=n_groups)
        open_groups = total > tol
        if not open_groups.any():
            break
        worst = np.zeros(n_groups)
        np.maximum.at(worst, groups, err)
        mark = open_groups[groups] & (err >= eta * worst[groups])
        if cells.shape[0] + 3 * int(mark.sum()) > max_cells:
            log.warning(
                "adaptive quadrature stopped at the %d-cell cap (config.TOL.quadrature_max_cells) with "
                "error estimate %.3g > %.3g (%s): the integrand is too rough for this tolerance; loosen "
                "it or raise the cap",
                cells.shape[0],
                float(total.max()),
                tol,
                setting,
            )
            break
        new_cells = _split(cells[mark])
        new_groups = np.repeat(groups[mark], 4)
        new_ids = _split_ids(ids[mark])
        new_coarse = kids[mark].reshape(-1, q)
        new_kids = evaluate_kids(new_cells, new_groups, new_ids)
        n_eval += 4 * new_cells.shape[0]
        keep = ~mark
        cells = np.concatenate([cells[keep], new_cells])
        groups = np.concatenate([groups[keep], new_groups])
        ids = np.concatenate([ids[keep], new_ids])
        coarse = np.concatenate([coarse[keep], new_coarse])
        kids = np.concatenate([kids[keep], new_kids])
    fine = kids.sum(axis=1)
    err = (np.abs(fine - coarse) / scale[groups]).max(axis=1)
    values = np.zeros((n_groups, q))
    np.add.at(values, groups, fine)
    return values, np.bincount(groups, err, minlength=n_groups), n_eval


@dataclass(frozen=True)
class SurfaceMoments:
    """Twist-independent integrals of a surface (Eqs. 3.1, 3.2)."""

    F: float  # ∫ p dS [N]
    area: float  # ∫ dS [m²]
    pressure_center: Array  # (3,) o, Eq. 3.1
    normal_wrench: Array  # (6,) w⊥ about o, Eq. 3.2
    error: float  # relative error estimate


def _effective_tol(surface: ParametricSurface, tol: float, setting: str) -> tuple[float, str]:
    """``max(tol, CENTRAL_DIFFERENCE_RTOL)`` for a surface without analytic derivatives (the
    noise of its central differences does not refine away), else ``tol``; and the setting
    named, for the quadrature's warning."""
    if surface.analytic_derivatives or tol >= CENTRAL_DIFFERENCE_RTOL:
        return tol, setting
    log.debug(
        "surface %r has central-difference derivatives (~%.0e accurate): %s raised to %.0e",
        surface.name,
        CENTRAL_DIFFERENCE_RTOL,
        setting,
        CENTRAL_DIFFERENCE_RTOL,
    )
    return CENTRAL_DIFFERENCE_RTOL, (
        f"{setting}, raised to the {CENTRAL_DIFFERENCE_RTOL:.0e} accuracy of surface {surface.name!r}'s "
        "central-difference derivatives: supply sigma_u and sigma_v for a tighter one"
    )


def check_rtol(rtol: Any, what: str = "rtol", default: str | None = None) -> float:
    """``rtol`` as a float if it is a relative tolerance of the surface quadrature, a finite number
    > 0, else ValueError naming ``what`` (an argument, or an experiment's config key) — the one
    rule of that quantity (``default``: the ``config.TOL`` field that None stands for, named in
    the message).  0 can never be met: every integral would refine to its cell cap."""
    ok = isinstance(rtol, numbers.Real) and not isinstance(rtol, bool)
    if not (ok and math.isfinite(rtol) and rtol > 0):
        none = "" if default is None else f" (or None: config.TOL.{default})"
        raise ValueError(
            f"{what} must be a relative tolerance > 0{none}, a finite number such as 1e-6 (0 can never be "
            f"met: the quadrature would refine to its cell cap); got {rtol!r}"
        )
    return float(rtol)


def surface_moments(surface: ParametricSurface, rtol: float | None = None) -> SurfaceMoments:
    """``F``, area, pressure center ``o`` and normal wrench ``w⊥`` of a surface (``rtol``:
    default ``config.TOL.moments_rtol``, read now).  A surface without analytic ``σ_u, σ_v``
    is integrated to ``max(rtol, CENTRAL_DIFFERENCE_RTOL)``: its central differences are no
    more accurate (module constant).  ValueError for a pressure that is zero at every point
    of the initial quadrature cells."""
    check_size(surface)
    if rtol is None:
        rtol, setting = config.TOL.moments_rtol, f"config.TOL.moments_rtol = {config.TOL.moments_rtol:g}"
    else:
        rtol = check_rtol(rtol, default="moments_rtol")
        setting = f"surface_moments(rtol={rtol:g})"
    # resolved before the cache: a changed tolerance is another entry, never a stale one
    return _surface_moments(surface, *_effective_tol(surface, rtol, setting))


@lru_cache(maxsize=128)
def _surface_moments(surface: ParametricSurface, rtol: float, setting: str) -> SurfaceMoments:
    order = config.TOL.quadrature_order

    def evaluate(cells: Array, groups: Array) -> Array:
        xyz, n, da, p = _cell_points(surface, cells, order)
        dw = da * p
        cols = np.column_stack([dw, da, dw[:, None] * xyz, dw[:, None] * n, dw[:, None] * np.cross(xyz, n)])
        return cols.reshape(cells.shape[0], -1, cols.shape[1]).sum(axis=1)

    init = _initial_cells(surface)
    rough = evaluate(init, np.zeros(init.shape[0], int)).sum(axis=0)
    if not rough[0] > 0:
        raise ValueError(
            f"surface {surface.name!r}: the pressure is zero at every quadrature point of its "
            f"{len(init)} initial cells ({'zero area' if not rough[1] > 0 else 'F = 0'}): no normal force, "
            "so no pressure centre or limit surface. Give a pressure that is > 0 on part of the surface"
        )
    L = max(_length_scale(surface), float(np.abs(rough[2:5] / rough[0]).max()))
    scale = np.array([rough[0], rough[1]] + [rough[0] * L] * 3 + [rough[0]] * 3 + [rough[0] * L] * 3)
    vals, err, _ = _adaptive(
        evaluate, init, 1, scale[None, :], rtol, config.TOL.quadrature_max_passes, setting=setting
    )
    v = vals[0]
    F = float(v[0])
    o = v[2:5] / F
    fn = v[5:8]
    tn = v[8:11] - np.cross(o, fn)  # ∫ p (σ - o) × n = ∫ p σ × n - o × ∫ p n
    return SurfaceMoments(F, float(v[1]), o, -np.concatenate([fn, tn]), float(err[0]))


def surface_wrenches(
    surface: ParametricSurface,
    twists: Any,
    mu: float = 1.0,
    *,
    rtol: float | None = None,
    return_error: bool = False,
) -> Array | tuple[Array, Array]:
    """Continuous frictional wrenches, Eqs. 3.3–3.5, about the pressure center.

    twists : (K, 6) float about ``o`` (see :func:`surface_moments`).
    rtol : target error (default ``config.TOL.quadrature_rtol``, read now), scaled per
        component by ``μF`` (forces) and ``μF l_s`` (torques); the integrator aims at
        ``config.TOL.quadrature_safety * rtol`` because its estimate is heuristic near slip
        singularities — and at no less than ``CENTRAL_DIFFERENCE_RTOL`` on a surface without
        analytic ``σ_u, σ_v`` (:func:`surface_moments`).
    Returns (K, 6) wrenches and, with ``return_error=True``, the (K,) error
    estimates (summed fine-vs-coarse differences) in the same scaled units.
    """
    xi, single = check_twists(twists)
    mu_f = check_mu(mu)
    if rtol is None:
        rtol, setting = config.TOL.quadrature_rtol, "config.TOL.quadrature_rtol"
    else:
        rtol, setting = check_rtol(rtol, default="quadrature_rtol"), "surface_wrenches(rtol=...)"
    safety = config.TOL.quadrature_safety
    target, setting = _effective_tol(
        surface, safety * rtol, f"{setting} = {rtol:g} x config.TOL.quadrature_safety = {safety:g}"
    )
    mom = surface_moments(surface)
    order = config.TOL.quadrature_order
    rtol2 = config.TOL.tangential_velocity_rtol**2

    geometry = _CellGeometry(surface, order, mom.pressure_center, config.TOL.quadrature_cache_cells)

    def evaluate(cells: Array, groups: Array, ids: Array, twists: Array) -> Array:
        out = np.empty((cells.shape[0], 6))
        seg_lo, seg_hi = geometry.segments(cells, ids)
        launch(
            _kernels._fw_segments,
            cells.shape[0] * geometry.q,
            *(twists, groups.astype(np.int64), seg_lo, seg_hi, *geometry.cols, 1.0, rtol2, out),
        )
        return out

    ls = _length_scale(surface)
    scale = np.array([mom.F] * 3 + [mom.F * ls] * 3)
    init = _initial_cells(surface)
    chunk = config.TOL.quadrature_twist_chunk
    vals = np.empty((xi.shape[0], 6))
    err = np.empty(xi.shape[0])
    for start in range(0, xi.shape[0], chunk):
        part = xi[start : start + chunk]

        def evaluate_part(cells: Array, groups: Array, ids: Array, part: Array = part) -> Array:
            return evaluate(cells, groups, ids, part)

        vals[start : start + len(part)], err[start : start + len(part)], _ = _adaptive(
            evaluate_part,
            init,
            part.shape[0],
            np.tile(scale, (part.shape[0], 1)),
            target,
            config.TOL.quadrature_max_passes,
            setting=setting,
            cell_ids=True,
        )
    vals *= mu_f
    if single:
        vals, err = vals[0], err[0]
    return (vals, err) if return_error else vals


def surface_w_max(surface: ParametricSurface, mu: float = 1.0, *, rtol: float | None = None) -> Array:
    """(6,) exact ``w_max`` of a continuous surface via the canonical twists (``rtol``: see
    :func:`surface_wrenches`)."""
    w = surface_wrenches(surface, canonical_twists(), mu, rtol=rtol)
    return -np.diag(w) + 0.0


def wrench_error_rate(w_max_approx: Any, w_max_true: Any) -> float:
    """The wrench error rate of §3.5.1.2 (Fig 3.8): the mean over the six components of
    ``|w_max,approx − w_max,true| / w_max,true``, e.g. a meshed surface's ``w_max``
    (:func:`workbench.wrench.w_max`) against the continuous one's (:func:`surface_w_max`);
    both (6,), the truth's every component > 0 (a planar contact's degenerate components have
    no relative error)."""
    approx = np.asarray(w_max_approx, dtype=np.float64)
    true = np.asarray(w_max_true, dtype=np.float64)
    if (
        approx.shape != (6,)
        or true.shape != (6,)
        or not (np.isfinite(approx).all() and np.isfinite(true).all())
    ):
        raise ValueError(
            f"w_max_approx and w_max_true must be finite (6,) maxima; got shapes {approx.shape} and "
            f"{true.shape} — pass w_max(profile, mu) and surface_w_max(surface, mu)"
        )
    if not (true > 0).all():
        raise ValueError(
            f"w_max_true must be > 0 in every component (the rate divides by it); got {true.tolist()} — "
            "friction mu > 0, and a non-planar surface (a planar one's f_z, tau_x, tau_y are 0)"
        )
    return float(np.mean(np.abs(approx - true) / true))


# ---------------------------------------------------------------- geometry
def _grid(surface: ParametricSurface, nu: int, nv: int) -> tuple[Array, Array, Array]:
    u = np.linspace(*surface.u_range, nu + 1)
    v = np.linspace(*surface.v_range, nv + 1)
    U, V = np.meshgrid(u, v, indexing="ij")
    return U, V, surface._vectors(surface.sigma, U.ravel(), V.ravel(), "sigma").reshape(nu + 1, nv + 1, 3)


@lru_cache(maxsize=256)
def _side_lengths(surface: ParametricSurface) -> tuple[float, float]:
    """Mean physical lengths of the u- and v-parameter lines."""
    _, _, P = _grid(surface, 32, 32)
    lu = np.linalg.norm(np.diff(P, axis=0), axis=2).sum(axis=0).mean()
    lv = np.linalg.norm(np.diff(P, axis=1), axis=2).sum(axis=1).mean()
    return float(lu), float(lv)


@lru_cache(maxsize=256)
def _length_scale(surface: ParametricSurface) -> float:
    _, _, P = _grid(surface, 64, 64)
    return pca_box_longest_side(P.reshape(-1, 3))


def check_size(surface: ParametricSurface) -> float:
    """``surface.length_scale`` [m] if it is a plausible contact size, else ``ValueError`` naming
    the likely unit and the fix: the rule of a ``ContactProfile``'s size
    (:func:`workbench.units.check_extent`, upper limit ``config.TOL.max_object_extent_m``; no lower
    one: contacts can be tiny), waived by ``ParametricSurface(..., allow_scale=True)``."""
    if not isinstance(surface, ParametricSurface):
        raise ValueError(
            f"surface must be a ParametricSurface; got {type(surface).__name__} — build one with "
            "ParametricSurface(name, sigma, u_range, v_range, ...)"
        )
    return check_extent(
        _length_scale(surface),
        f"surface {surface.name!r} (l_s, the longest side of its PCA box)",
        allow_scale=surface.allow_scale,
        check_lower=False,
        fix="give sigma in metres (scale its points by {factor:g}: a 10 mm disc has radius 0.01)",
        override="ParametricSurface(..., allow_scale=True)",
    )


def _collapsed_edges(surface: ParametricSurface) -> tuple[bool, bool, bool, bool]:
    """Which parameter-domain edges map to a single point (u0, u1, v0, v1)."""
    _, _, P = _grid(surface, 16, 16)
    L = _length_scale(surface)

    def collapsed(edge: Array) -> bool:
        # an edge collapsed to a point (a pole) to round-off of the surface's size L
        return bool(np.ptp(edge, axis=0).max() <= 1e-12 * L)

    return collapsed(P[0]), collapsed(P[-1]), collapsed(P[:, 0]), collapsed(P[:, -1])


def _grid_size(surface: ParametricSurface, n_elements: int) -> tuple[int, int]:
    """Grid (nu, nv) whose triangle count is closest to ``n_elements`` with
    cells as square as possible in physical space."""
    lu, lv = _side_lengths(surface)
    cu0, cu1, cv0, cv1 = _collapsed_edges(surface)
    best = None
    for nu in range(1, n_elements + 1):
        for nv in {max(1, n_elements // (2 * nu)), max(1, -(-n_elements // (2 * nu)))}:
            count = 2 * nu * nv - nv * (cu0 + cu1) - nu * (cv0 + cv1)
            if count <= 0:
                continue
            miss = abs(count - n_elements)
            aspect = abs(np.log((lu / nu) / (lv / nv)))
            # within 3% of the target: prefer square cells; otherwise the closest count
            outside = miss > max(2, 0.03 * n_elements)
            key = (outside, miss if outside else aspect, miss)
            if best is None or key < best[0]:
                best = (key, nu, nv)
    return best[1], best[2]


def check_n_elements(n_elements: int) -> int:
    """``n_elements`` as an int if a mesh can have that many triangles (>= 2), else a
    ``ValueError`` (:func:`mesh_surface`'s rule, also called by the experiments' ``check_config``)."""
    if int(n_elements) < 2:
        raise ValueError(f"n_elements must be >= 2 (triangles of the contact mesh); got {n_elements}")
    return int(n_elements)


def mesh_surface(surface: ParametricSurface, n_elements: int) -> tuple[Array, Array, Array]:
    """Triangle mesh of a parametric surface with ~``n_elements`` triangles.

    A (nu × nv) parameter grid, quads split along alternating diagonals,
    triangles on collapsed edges (poles, apexes) dropped, winding set so the
    face normal agrees with the surface normal.  Returns vertices (V, 3),
    faces (T, 3) int and the parametric centroid of each face (T, 2).
    """
    check_n_elements(n_elements)
    check_size(surface)
    nu, nv = _grid_size(surface, int(n_elements))
    U, V, P = _grid(surface, nu, nv)
    idx = np.arange((nu + 1) * (nv + 1)).reshape(nu + 1, nv + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    alt = ((np.arange(nu)[:, None] + np.arange(nv)[None, :]) % 2 == 1).ravel()
    t1 = np.where(alt[:, None], np.column_stack([a, b, d]), np.column_stack([a, b, c]))
    t2 = np.where(alt[:, None], np.column_stack([b, c, d]), np.column_stack([a, c, d]))
    faces = np.vstack([t1, t2])
    verts = P.reshape(-1, 3)
    tri = verts[faces]
    cr = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area2 = np.linalg.norm(cr, axis=1)
    keep = area2 > config.TOL.degenerate_area_rtol * np.median(area2)
    faces, cr = faces[keep], cr[keep]
    uv = np.column_stack([U.ravel(), V.ravel()])[faces].mean(axis=1)
    _, n_surf, _, _ = surface.evaluate(uv[:, 0], uv[:, 1])
    wrong = np.einsum("ij,ij->i", cr, n_surf) < 0
    faces[wrong] = faces[wrong][:, ::-1]
    return verts, faces, uv


def mesh_profile(
    surface: ParametricSurface, n_elements: int, *, pressure_scale: float = 1.0
) -> ContactProfile:
    """ContactProfile of :func:`mesh_surface` with the pressure at each
    triangle's parametric centroid (flat triangles: centroid, face normal, area)."""
    verts, faces, uv = mesh_surface(surface, n_elements)
    _, _, _, p = surface.evaluate(uv[:, 0], uv[:, 1])
    return ContactProfile.from_mesh(verts, faces, p * pressure_scale, allow_scale=surface.allow_scale)


def project_to_plane(surface: ParametricSurface, normal: Any, name: str | None = None) -> ParametricSurface:
    """Planar area contact of a surface: its orthogonal projection onto the
    plane through the origin with unit ``normal``, uniform pressure (§3.5.1.1).

    The projected region is parametrised by the same ``(u, v)``, which is
    valid when the projection is injective (true for S1-S6 onto the xz-plane).
    """
    nrm = np.asarray(normal, dtype=float)
    nrm = nrm / np.linalg.norm(nrm)

    def proj(x: Array) -> Array:
        x = np.asarray(x, float)
        return x - (x @ nrm)[..., None] * nrm

    su = sv = None
    if surface.sigma_u is not None and surface.sigma_v is not None:
        su = lambda u, v: proj(surface.sigma_u(u, v))  # noqa: E731
        sv = lambda u, v: proj(surface.sigma_v(u, v))  # noqa: E731
    um, vm = np.mean(surface.u_range), np.mean(surface.v_range)
    _, n_orig, _, _ = surface.evaluate(np.array([um]), np.array([vm]))
    plane = ParametricSurface(
        name or f"{surface.name}-planar",
        lambda u, v: proj(surface.sigma(u, v)),
        surface.u_range,
        surface.v_range,
        su,
        sv,
        None,
        1.0,
        False,
        f"projection of {surface.name} onto the plane normal to {nrm.tolist()}",
        allow_scale=surface.allow_scale,
    )
    _, n_plane, _, _ = plane.evaluate(np.array([um]), np.array([vm]))
    if float(n_plane[0] @ nrm) * float(n_orig[0] @ nrm) < 0:
        plane = replace(plane, flip=True)
    return plane

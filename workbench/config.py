"""Tolerances, defaults, run settings and Numba flags — the one place they live.

Every field carries a comment saying why it has its value and its rule beside its default.
Library code reads ``config.TOL.<field>`` and ``config.DEFAULTS.<field>`` (numerics: tolerances,
model defaults, solver knobs) and ``config.RUN.<field>`` (run settings: clusters, the scheduler,
sweeps, progress bars) when a function runs (never as a default argument bound at import), so
:func:`override` (a block, e.g. in a test) and :func:`configure` (the rest of the process) change
what every later call uses.  Kernels import ``NUMBA_FLAGS`` / ``NUMBA_FLAGS_PARALLEL`` /
``NUMBA_FLAGS_IEEE`` from here and nowhere else, so a user (or CI) can switch caching or
threading off in one spot, e.g. ``WORKBENCH_NUMBA_PARALLEL=0``.

Both check each value when it is set (the field's rule: its type, finite, its range or choices
as the field's comment implies) and raise ValueError naming the field, what it expects and what
it got.
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, fields, replace
from typing import Any


def _env_flag(name: str, default: bool) -> bool:
    value = os.environ.get(name)
    if value is None:
        return default
    return value.strip().lower() not in {"0", "false", "no", "off", ""}


# fastmath subset: 'reassoc' lets LLVM vectorize the per-twist reductions over
# elements, 'contract' allows FMA, 'arcp'/'nsz' allow reciprocal tricks and
# ignore the sign of zero.  'nnan'/'ninf' are deliberately *not* set: the
# kernels rely on IEEE semantics of max()/select to keep zero-velocity
# elements at exactly zero.
FASTMATH: frozenset[str] = frozenset({"reassoc", "contract", "arcp", "nsz"})

# On-disk caching of compiled kernels (a new process loads them instead of compiling again).
CACHE: bool = _env_flag("WORKBENCH_NUMBA_CACHE", True)

# prange over twists in the batched kernels; off for debugging / profiling.
PARALLEL: bool = _env_flag("WORKBENCH_NUMBA_PARALLEL", True)

NUMBA_FLAGS: dict = {"fastmath": set(FASTMATH), "cache": CACHE, "nogil": True}
NUMBA_FLAGS_PARALLEL: dict = {**NUMBA_FLAGS, "parallel": PARALLEL}
# Kernels that redo a NumPy routine's arithmetic bit for bit (fem's point-triangle distance:
# trimesh's closest_point, pair by pair), and the quartic fit's interior point (a process that
# compiled its fastmath kernels got other round-off than one that loaded them from Numba's
# cache, and a fit through its data amplified it to 2e-8, so a row depended on where it ran):
# no fastmath, as NumPy rounds each product and sum on its own ('contract' would fuse them into
# FMAs, 'reassoc' reorder the sums), and NumPy's error model (x / 0 is ±inf or NaN as NumPy gives
# it, where Numba's default raises).
NUMBA_FLAGS_IEEE: dict = {**NUMBA_FLAGS, "fastmath": False, "error_model": "numpy"}


# --- what override()/configure() accept, field by field (from each field's comment) -----
# A rule returns the value to store (ints of a float field as float) or raises with what it
# expected (as _Reject); _check adds the field, what it got and the fix.


class _Reject(Exception):
    """A value a field's rule does not accept; the message says what it expects."""


def _real(lo: float | None = None, *, lo_open: bool = False, hi: float | None = None, hi_open: bool = False):
    """A finite real number (an int is fine, a bool is not) in the interval given."""
    lo_s = "" if lo is None else f"{'>' if lo_open else '>='} {lo:g}"
    hi_s = "" if hi is None else f"{'<' if hi_open else '<='} {hi:g}"
    expect = "a finite number" + (f" {lo_s}" if lo_s else "") + (" and" if lo_s and hi_s else "")
    expect += f" {hi_s}" if hi_s else ""

    def rule(v: Any) -> float:
        if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v):
            raise _Reject(expect)
        if lo is not None and (v <= lo if lo_open else v < lo):
            raise _Reject(expect)
        if hi is not None and (v >= hi if hi_open else v > hi):
            raise _Reject(expect)
        return float(v)

    return rule


def _count(minimum: int):
    """An int (not a bool) >= minimum."""
    expect = f"an int >= {minimum}"

    def rule(v: Any) -> int:
        if isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < minimum:
            raise _Reject(expect)
        return int(v)

    return rule


def _choice(names: Callable[[], tuple[str, ...]]):
    """One of the strings ``names()`` (a callable: solver lists are read when checked)."""

    def rule(v: Any) -> str:
        valid = names()
        if not isinstance(v, str) or v not in valid:
            raise _Reject(f"one of {list(valid)}")
        return v

    return rule


def _solver_choice(names: tuple[str, ...]):
    """One of the solver names ``names`` (upper case), in any case, stored in upper case (as the
    fits' own check, ``limit_surface.sdp_solver.check_fit_solver``, reads them)."""

    def rule(v: Any) -> str:
        if not isinstance(v, str) or v.upper() not in names:
            raise _Reject(f"one of {list(names)} (any case)")
        return v.upper()

    return rule


def _flag(v: Any) -> bool:
    if not isinstance(v, bool):
        raise _Reject("True or False")
    return v


def _reals(n: int, each: Callable[[Any], float], ordered: bool = False, what: str = ""):
    """A tuple of ``n`` numbers each passing ``each`` (non-decreasing if ``ordered``)."""
    expect = f"a tuple of {n} {what}" + (" with lo <= hi" if ordered else "")

    def rule(v: Any) -> tuple[float, ...]:
        if isinstance(v, str | bytes) or not hasattr(v, "__len__") or len(v) != n:
            raise _Reject(expect)
        try:
            out = tuple(each(x) for x in v)
        except _Reject:
            raise _Reject(expect) from None
        if ordered and list(out) != sorted(out):
            raise _Reject(expect)
        return out

    return rule


def _saturation(v: Any) -> float:
    """Dask's worker saturation: a number >= 1 (tasks ahead per thread) or inf (all)."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real) or math.isnan(v) or v < 1:
        raise _Reject("a number >= 1 (tasks per worker thread) or math.inf (no queue on the scheduler)")
    return float(v)


def _cell_fraction(v: Any) -> float:
    """A coarsening cell as a fraction of a contact's l_s: 0 (none) or in [0.001, 0.5]."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real) or not (v == 0 or 1e-3 <= v <= 0.5):
        raise _Reject(
            "0 (the contact itself) or a fraction of the contact's size l_s in [0.001, 0.5] (e.g. 0.15: "
            "~3 mm cells on a 20 mm contact; not millimetres or metres)"
        )
    return float(v) + 0.0  # -0.0 is 0.0 (one cache key)


def _author_weights(v: Any) -> tuple[float, ...]:
    """(λ, ω_w, ω_t) of the author's objective: finite, >= 0, ω_w > 0 (the fit refuses ω_w = 0:
    the zero function is then optimal)."""
    expect = "a tuple of 3 finite numbers >= 0 (lambda, omega_w, omega_t) with omega_w > 0"
    try:
        out = _reals(3, _NONNEG)(v)
    except _Reject:
        raise _Reject(expect) from None
    if out[1] <= 0:
        raise _Reject(expect)
    return out


def _qp_solvers() -> tuple[str, ...]:
    from qpsolvers import available_solvers  # the dense QP solvers grasp resistance can call

    return tuple(available_solvers)


_POS = _real(0.0, lo_open=True)  # a magnitude that must be positive (0 breaks its meaning)
_NONNEG = _real(0.0)  # a magnitude for which 0 means "off" / "exact"
_FRACTION = _real(0.0, hi=1.0)
_PITCHES = _reals(2, _real(), ordered=True, what="finite numbers (lo, hi) [l_s]")


def _field(default: Any, rule: Callable[[Any], Any]) -> Any:
    """A config field with its default and its rule beside it (``dataclasses.field`` metadata)."""
    return field(default=default, metadata={"rule": rule})


@dataclass(frozen=True)
class Tolerances:
    """Numerical tolerances of the workbench (trimesh ``tol`` style)."""

    # |v_t| <= rtol * |v| at an element => the element sticks (direction
    # undetermined) and contributes zero friction.  1e-12 sits ~4 decades above
    # the rounding noise of v - (v.n)n (~1e-16 |v|), so cancellation noise is
    # never turned into a spurious unit direction, while any physically
    # resolved slip (>= 1e-12 of the element speed) is kept.
    tangential_velocity_rtol: float = _field(1e-12, _NONNEG)  # 0: only exactly zero slip sticks

    # Normals whose length differs from 1 by at most this are renormalised
    # silently (float32 exports, rounding); anything further is rejected
    # unless the caller asks for renormalisation explicitly.
    normal_unit_atol: float = _field(1e-6, _NONNEG)  # 0: no silent renormalisation

    # An element whose area is <= this fraction of the median element area is
    # degenerate (sliver/collapsed triangle) and is rejected or dropped.
    degenerate_area_rtol: float = _field(1e-12, _NONNEG)

    # Predictions (or measurements) closer than this relative gap rank as ties in
    # workbench.stats.rank_correlation: mirror-symmetric grasps give equal predictions up to
    # the solver's accuracy (last bits for a linear solve, ~1e-11 for the nonlinear wall's
    # Newton curves), and Spearman would break such near-ties by that noise.  1e-9 sits two
    # decades above it and far below any gap between distinct grasps (>= 1e-4 measured).
    rank_tie_rtol: float = _field(1e-9, _real(0.0, hi=1e-3))  # 0: only exact ties; a larger gap is not noise

    # Default relative tolerance of the adaptive surface quadrature for
    # wrenches (error scaled by mu*F for forces and mu*F*l_s for torques).
    quadrature_rtol: float = _field(1e-5, _POS)  # 0 can never be met: every call would run to the cell cap

    # Tolerance for twist-independent surface moments (F, o, w_perp); the
    # integrands are smooth, so this is cheap.
    moments_rtol: float = _field(1e-12, _POS)

    # Maximum refinement passes of the adaptive quadrature before it reports
    # (via its error estimate) that it did not converge.
    quadrature_max_passes: int = _field(40, _count(1))

    # Cap on quadrature leaf cells per call (~16 points each): bounds memory
    # (~100 MB) when an integrand is too rough for the requested tolerance; the
    # returned error estimate then says how far from converged it is.
    quadrature_max_cells: int = _field(100_000, _count(1))

    # The adaptive quadrature aims at safety * rtol: its fine-vs-coarse
    # estimate under-states the true error by up to ~2.2x in cells holding a
    # slip singularity (measured over 1,500 twists on S1-S6), so 1/4 keeps the
    # true error below rtol with margin.
    quadrature_safety: float = _field(0.25, _POS)

    # Twists integrated together by the adaptive quadrature; each chunk shares
    # the quadrature_max_cells budget.
    quadrature_twist_chunk: int = _field(8, _count(1))

    # Cells evaluated per integrand call (bounds temporaries to ~20 MB).
    quadrature_eval_block: int = _field(8192, _count(1))

    # Quadrature cells whose Gauss points one surface_wrenches call keeps (1 KB each at
    # order 4: ~100 MB): the twists' adaptive refinements revisit the same cells, and the
    # surface's evaluation costs far more than the wrench kernel (surfaces._CellGeometry).
    quadrature_cache_cells: int = _field(100_000, _count(0))

    # Gauss-Legendre points per direction per quadrature cell.
    quadrature_order: int = _field(4, _count(1))

    # Number of significant principal components of normalised wrenches =
    # the smallest k whose components retain this fraction of the variance
    # (the common retention rule; thesis §3.5.1.1 gives no criterion).
    # accepts: a fraction of the variance kept
    pca_retained_variance: float = _field(0.99, _real(0.0, lo_open=True, hi=1.0))

    # Secondary count reported next to it: components that each explain at
    # least this fraction of the variance (std >= 10% of the total's).
    pca_significant_fraction: float = _field(0.01, _FRACTION)

    # Wrench-space components with w_max_i <= this * max(w_max) are
    # degenerate (planar/line contacts), CONVENTIONS.md "Limit surfaces".
    degenerate_wmax_rtol: float = _field(1e-9, _NONNEG)

    # PCA subspace of normalised wrenches: directions whose std is below this
    # fraction of the largest std are dropped (planar -> 3D, line -> 2D;
    # §3.3.4.2 "explained variances less than a small value ε").
    subspace_rtol: float = _field(1e-6, _NONNEG)

    # Grid downsampling of normalised wrenches (|w_i| <= 1): distances to a cell's mean
    # (and cell coordinates, in cell widths) closer than this are ties.  Mirror-image
    # wrenches of a symmetric contact tie to ~1e-16 and a 1e-14 pressure perturbation moves
    # them ~1e-14; breaking such ties by round-off swapped training twists and moved 6DLS
    # models by percents.  1e-9 is five decades above that and below any real gap.
    downsample_tie_atol: float = _field(1e-9, _NONNEG)

    # A quartic fit's least-squares rows determine a coefficient when the QR's diagonal entry
    # for it is above this fraction of the largest: repeated wrenches (100 distinct ones given
    # twice pass the 126-row count) leave ~1e-16; the whitened bottle fits, above ~1e-4.  Below
    # it the fit is logged and recorded as underdetermined (info["underdetermined"]).
    quartic_rank_rtol: float = _field(1e-10, _NONNEG)
    # A quartic fit whose mean Eq. 3.18 error over its own training wrenches is above this is
    # logged and recorded (info["warning"]): fits through their data have ~0.002-0.03 (S1-S6,
    # FEM and grasp contacts); a rank-4 set with 3e-7-1e-6 noise in its two other directions
    # gave 0.09-1.0 with status optimal (a new-user trial): points off the kept subspace by
    # about TOL.flat_axis are charged the dropped directions' ‖Cᵀx̂‖⁴ / flat⁴
    quartic_train_error_warn: float = _field(0.05, _POS)
    # Fitted wrenches whose mean is farther from 0 than this fraction of their RMS size (both
    # after Eq. 3.10's normalisation) are logged as not centred: a frictional set is symmetric
    # about 0.  On 16 gripper contacts the training sets gave 0.004-0.22 (thesis-code's
    # downsampled grid the most), the same sets plus the contact's normal force (a total contact
    # wrench) 0.85-0.97; 21 symmetric samples exceed 0.42 once in a thousand
    wrench_offset_warn: float = _field(0.5, _POS)

    # The quartic fit's own interior point (limit_surface/sos_ipm.py) stops when the duality gap
    # Σ tr(X Z) is below sos_ipm_gap of the objective ½‖R a − c‖² or below sos_ipm_gap_floor ×
    # ½‖c‖² (a fit through its data, objective ~0), and the dual residual below sos_ipm_residual
    # of 1 + max|Rᵀc|: Clarabel's default tolerances (1e-8) for the gap and residual.  The floor:
    # on exact wrenches of a quartic whose scales differ 1,500-fold (a new-user trial, seeds
    # 10-13 and 100-102) a floor of 1e-16 left held-out errors 10-100x Clarabel's (its conic form
    # bounds ‖R a − c‖, not its square: the coefficients of a near-interpolating fit need the
    # gap far smaller); 1e-20 matched or beat them; 1e-22 stalled in round-off.
    sos_ipm_gap: float = _field(1e-8, _POS)
    sos_ipm_gap_floor: float = _field(1e-20, _POS)
    sos_ipm_residual: float = _field(1e-8, _POS)
    sos_ipm_max_iter: int = _field(60, _count(1))  # Mehrotra's method needs ~10-25
    # the interior point's Schur matrix, when round-off near the optimum leaves it unfactorable, is
    # factored with this fraction of its largest diagonal entry added (then 100x more, up to 1e6x),
    # and its solves refined against the matrix itself
    sos_ipm_regularisation: float = _field(1e-14, _POS)
    # fraction of the step to the cone's boundary taken (an interior point stays interior)
    sos_ipm_step: float = _field(0.99, _real(0.0, lo_open=True, hi=1.0, hi_open=True))

    # Semi-axis (normalised units) given to dropped directions so every
    # returned A_e is positive definite: the model is "flat" to this thickness.
    flat_axis: float = _field(1e-6, _POS)  # keeps A_e positive definite

    # -alpha log det(A_e) penalty of the SDP ellipsoid (Eq. 3.12), as alpha =
    # this * K.  Off: the thesis adds it so det A_e > 0 when the wrenches span a
    # subspace, which the PCA subspace already ensures; 1e-6 (the old value)
    # changed Eq. 3.18 by < 1e-5 and 1e-3 and more only raise it
    # (results/ls-fitting/summary.json -> sdp_log_det_effect).
    sdp_alpha_per_wrench: float = _field(0.0, _NONNEG)  # 0: off

    # support_error: the exact surface points of the canonical normals ±e_i reach
    # w_max_i exactly for a model normalised by the exact w_max, and more for one
    # normalised by sampled maxima (up to 39 % on a bumpy 40-element contact, 400
    # thesis twists).  Below 1 - this, wrenches_of belongs to another contact, μ or
    # force (refused); above 1 + this, a warning is logged.
    support_wmax_mismatch: float = _field(0.2, _NONNEG)

    # A w_max given to a fitter is the exact maxima of the wrenches' contact
    # (analytic: the canonical twists reach them), so no wrench may exceed it by
    # more than rounding; beyond this relative margin the w_max belongs to another
    # contact, μ, force or unit and the fit is refused.
    given_wmax_rtol: float = _field(1e-6, _NONNEG)

    # Eigenvalue floor (relative to the largest) used when a least-squares
    # ellipsoid comes out indefinite and is projected to the PD cone.
    ellipsoid_eig_floor: float = _field(1e-8, _POS)  # the projection must be positive definite
    # A cvxpy solver's SDP ellipsoid (Eq. 3.11) whose smallest eigenvalue is at most this far below
    # 0 (relative to the largest) is the singular optimum of an indefinite least squares, reached
    # to the solver's accuracy: its small eigenvalues are raised to ellipsoid_eig_floor; further
    # below, the solve failed and the projected least squares answers.  Clarabel's such iterates
    # came within 1e-9 of singular on gripper contacts and synthetic hyperboloids.
    sdp_singular_rtol: float = _field(1e-6, _POS)

    # |omega| below this (relative to |v|/l) classifies a twist as a pure
    # translation when converting to Plücker coordinates.
    translation_omega_atol: float = _field(1e-12, _NONNEG)

    # --- grasp resistance (workbench.grasp.resistance) ----------------------
    # A disturbance counts as resisted iff the smallest residual ‖D (Σ G c + w)‖
    # over the contact model is <= this, with D dividing forces by the grasp's
    # largest contact force and torques by its largest contact torque (so the
    # residual is relative).  1e-5 is what every solver route reaches reliably:
    # DAQP's proximal mode is accurate to ~1e-6 on the rank-6 Hessian, quadprog,
    # Clarabel and HiGHS to < 1e-8 (benchmarks/bench_grasp.py).  One value for
    # every entry point (resists, wrench_resistance, resists_lp,
    # min_grasp_force's feasibility check, q_robust, the exact 6DFW solver).
    # accepts: a residual is never exactly 0; 0.1 of F is no verdict
    resist_rtol: float = _field(1e-5, _real(0.0, lo_open=True, hi=0.1))

    # A known-force contact (6DLS, planar/nonplanar 3DLS, 6DFW, REACH) is read by
    # a force sensor (§4.1.3.2): its normal force lies in [F(1-r), F].  Without
    # the interval two jaws whose forces differ by 0.02 % cannot balance along
    # the grasp axis and every such grasp fails (planar/3DLS models have no
    # normal freedom at all).  The reading bounds the force from above, so the
    # model never credits more friction than the measured force gives (the
    # analytic limits 2 mu F stay exact).  1 % is the accuracy class of strain-
    # gauge jaw force sensors (~1 % of full scale).  0 restores the exact force.
    # The reading is the jaw's: the elements of a REACH jaw share one factor in
    # [1-r, 1] (ContactSet.group), they do not redistribute the pressure.
    # accepts: [F(1 - r), F] with F(1 - r) > 0
    known_force_rtol: float = _field(1e-2, _real(0.0, hi=1.0, hi_open=True))

    # A force group is one jaw: its contacts' net normal force must be at least this
    # fraction of the force they press with (a jaw wrapped ±1 rad around a cylinder:
    # sin(1)/1 = 0.84; two opposing jaws in one group: ~0).  Below it the group is
    # rejected as spanning opposing jaws.
    group_min_net_push: float = _field(0.3, _FRACTION)

    # A contact wrench may exceed its limit-surface model by this (relative f)
    # before the cutting-plane refinement adds a tangent plane (Kelley).
    cut_rtol: float = _field(1e-4, _POS)

    # The object settled between the jaws (workbench.grasp.settle) when the normal forces'
    # torque normal to the closing axis is at most this × force × pad size: 1e-3 of a 20 N
    # jaw on a 28 mm pad is 0.6 mN·m, a thousandth of what friction on it can hold.
    settle_torque_rtol: float = _field(1e-3, _POS)  # a solver's torque is never exactly 0

    # A profile's element centres count as one line (or one point) for the planar model's
    # PCA plane when the second singular value of their spread is at most this fraction of
    # the first (round-off of centres on a line; workbench.grasp.models.planar_profile).
    planar_collinear_rtol: float = _field(1e-9, _real(0.0, hi=1.0, hi_open=True))  # 0: exactly collinear only

    # Cutting-plane rounds before an unconverged refinement defers to the
    # conservative inner-vertex LP (resistance) or reports a lower bound (minimal
    # force).  Resistance takes a median of 7 rounds in the sensitivity scenes; the
    # minimal force on a quartic 6DLS, which drives the contact wrenches onto the
    # surface, 39-41 on the elliptic-cylinder scene (Kelley converges linearly).
    max_cut_rounds: int = _field(100, _count(0))  # 0: no refinement, the inner vertices decide at once

    # Cuts kept per limit-surface model in a CutStore (oldest dropped first; any
    # subset of tangent planes is still an outer approximation).
    max_stored_cuts: int = _field(2000, _count(1))

    # Relative Tikhonov term on the rank-6 Hessian of the dense QPs (quadprog
    # and DAQP need a strictly convex objective); it biases the residual by
    # O(1e-9), four decades below resist_rtol.
    qp_ridge: float = _field(1e-9, _POS)  # quadprog and DAQP need a strictly convex objective

    # Largest bounding-box side [m] of a FEM object mesh beyond which mm-read-as-m is assumed.
    max_object_extent_m: float = _field(2.0, _POS)

    # Smallest accepted largest side [m] (0.1 mm): below it, a double mm -> m scaling is assumed.
    min_object_extent_m: float = _field(1e-4, _NONNEG)  # 0: no lower limit
    # An object mesh whose thinnest bounding-box side is below this fraction of its longest is
    # flat (no volume to grasp; its convex hull's volume, which judges a mass, is ~0): refused.
    # A sheet of paper is 3e-4 of its length, a credit card 9e-3.
    min_mesh_aspect: float = _field(1e-4, _FRACTION)
    # A dense QP's residual above resist_rtol but within this factor of it is checked by the
    # exact residual LP (HiGHS), which decides when it resists: DAQP stopping at its own
    # tolerance left 4.2x the band on a grasp that quadprog, proxqp, Clarabel and HiGHS all
    # resist.  Each check is a second solve, so the factor stays near that case.
    qp_recheck_factor: float = _field(10.0, _real(1.0))

    # Relative slack of both extent limits (workbench.units.check_extent): a size
    # at a limit passes even with rounding on top — the thesis's surfaces S1-S6
    # are exactly 2 m long and their mesh profiles measure 2(1 + 2e-16) m.
    extent_limit_rtol: float = _field(1e-9, _NONNEG)

    # Region tests of the point-triangle distance of fem.obstacles.MeshObstacle (Ericson's, as
    # trimesh.triangles.closest_point): a dot product below this counts as zero.  They run in
    # the query-centred frame scaled by the mesh's mean edge, so this is relative to the edge
    # (squared); 1e-13 is trimesh's tol.zero, with which the distances were computed before
    # fem._kernels took over (the same numbers, bit for bit).
    point_triangle_zero: float = _field(1e-13, _NONNEG)

    # Two eigenvalues of a point set's covariance within this fraction of the
    # largest are equal (workbench.profile.pca_box_longest_side): rounding makes
    # exactly equal ones differ by ~1e-15, so 1e-8 catches them with 7 decades to
    # spare, while the PCA axes of any spread above it are resolved to
    # ~1e-16/gap rad (l_s then moves by <= ~1e-8 relative under rotation).
    pca_degenerate_rtol: float = _field(1e-8, _NONNEG)

    # ContactProfile logs a warning when elements carrying more than this
    # fraction of F have normals pointing away from the force-weighted mean
    # normal (n_i . n_mean < 0): the signature of half-flipped mesh normals.
    # A jaw wrapping less than ±100° of the object stays below 10 % under
    # uniform pressure ((α - 90°)/α at half-angle α), so real contacts pass.
    flipped_normal_force_fraction: float = _field(0.1, _FRACTION)

    # A ContactProfile's total area may be at most this multiple of the surface area of the
    # box its element centres span (their PCA box, each side grown by the centres' mean
    # spacing: an element reaches past its centre): a patch of a convex surface is part of
    # the boundary of its own convex hull, which lies in the box, so its area is at most the
    # box's surface (surface area is monotone under inclusion of convex bodies; a flat patch
    # reaches half of it).  10 leaves room for ridged (non-convex) surfaces, graded meshes
    # whose coarse edge elements reach past the box, and synthetic clouds of overlapping
    # elements (tests/naive.py's reach 5); areas in mm² or cm² beside centres in m are 1e6 or
    # 1e4 over.
    profile_area_box_ratio: float = _field(10.0, _real(1.0))  # below 1 refuses a patch on a convex surface

    # --- minimal work (workbench.grasp.stiffness_map, thesis §4.3) ----------
    # A stiffness >= this [N/m] means "rigid: no measurable deflection" (the
    # measured maps write 8e10).  Their largest finite value is 1.9e5 N/m (shampoo,
    # 0.05 mm at 10 N), so 1e10 sits 4.7 decades above any measurement and below
    # the maps' rigid marker.
    rigid_stiffness_threshold: float = _field(1e10, _POS)
    # Below this [N/m] a stiffness is taken for a unit slip (N/mm read as N/m): at 10 N
    # the jaw would close 1 m.  The softest measured grasp is ~140 N/m (a mustard wall).
    min_plausible_stiffness: float = _field(10.0, _NONNEG)
    # A grasp location pair whose axis is more than this [deg] from the surface normal at
    # either point is flagged non-antipodal (the flat jaw meets the wall on an edge).  The
    # measured maps' grasps reach 37° (tapered cups and bottles on a faceted mesh);
    # beyond 90° the jaw would press the wall from inside, and the grasp fails.
    antipodal_max_deg: float = _field(45.0, _real(0.0, hi=180.0))

    # Heaviest object mass [kg] a gravity wrench accepts: above a parallel-jaw gripper's
    # payload (a few kg; 10 N per jaw at mu 0.5 holds 1 kg), so a larger number is taken for
    # grams — a filled 0.27 kg bottle given as 270, a 50 g cup as 50.  Raise it for heavy parts.
    max_plausible_mass_kg: float = _field(20.0, _POS)

    # A centre of mass lies in the convex hull of the object's mass (a weighted mean of its
    # points), so a com outside the mesh's convex hull by more than this fraction of the
    # object's largest bounding-box side is refused (grasp.robust.check_com).  The slack is for
    # a mesh whose facets cut inside the real surface (a 16-gon's flats lie 2 % of the radius
    # inside its circle, an 8-gon's 8 %) and a measured com known to a few mm; a com in
    # millimetres, or on the wrong side of an 80 mm box, is far beyond it.
    com_hull_rtol: float = _field(0.05, _NONNEG)  # 0: exactly inside the mesh's hull

    # An engine trial's grasp points p1, p2 must lie on the object's surface within this [m]
    # (engine_trials: the pads start a 0.5 mm gap before them and close by force; a point 10 mm
    # off the surface leaves a jaw closing on nothing, judged "touched nothing" only after the
    # whole simulation).  A mesh's facets may cut a few tenths of a mm inside a round surface.
    engine_grasp_point_max_offset_m: float = _field(2e-3, _POS)
    # The fewest recorded poses an engine trial's verdict may read in each judged phase (lift,
    # turn, hold; a disturbance's ramp and hold): held, drift and turn are read from the recorded
    # poses only, so a record_every that leaves a phase a handful of them judges what it did not see.
    engine_min_samples_per_phase: int = _field(20, _count(1))
    # The narrowest grasp [m] between its two contact points (sources.jaws.check_grasp): closer,
    # p1 and p2 are one point given twice and the line the jaws close along is undefined.
    min_grasp_width_m: float = _field(1e-4, _POS)  # 0 would accept one point given twice

    # Largest closing of a linear wall squeeze, as a fraction of the object's width, before a
    # warning that the small-deflection model is stretched (fem.wall.squeeze; the nonlinear
    # wall follows larger ones).
    linear_closing_max_fraction: float = _field(0.1, _POS)

    # Largest angle [deg] between a grasp's axis and the line p1 -> p2 (check_grasp): parallel
    # jaws close along the line through both contacts; a grasp dict whose axis points elsewhere
    # was put together by hand (the sampler's axes are that line to round-off).
    grasp_axis_max_deg: float = _field(1.0, _real(0.0, hi=180.0))
    # (the other physical inputs' plausible ranges: workbench.plausible.RANGES)

    # Round-off of a computed friction-wrench component, relative to the largest w_max: the wrench
    # kernel resolves an element's slip direction from |v_t| > tangential_velocity_rtol |v|, where
    # the rounding of v - (v.n)n turns it by up to eps/1e-12 = 2.2e-4, so a component that is 0 in
    # exact arithmetic (a flat contact's f_n) can come out at ~1e-4 mu F.  w_max entries down to -this x
    # max(w_max) are set to 0, further below refused (the author's +xi sign); wrenches may exceed
    # a given exact w_max by this much (normalize.prepare).
    # accepts: 0: exact arithmetic; 1: any w_max down to -max
    wrench_roundoff_rtol: float = _field(1e-3, _real(0.0, hi=1.0))
    # A jaw profile given for a grasp lies in the pad's footprint: its pressure centre within half
    # the pad's diagonal of the jaw point in the pad plane, times 1 + this (an FEM pad's loaded face
    # bulges sideways and its elements move with it: 10 % is 2.2 mm on the 20 x 40 mm pad, under
    # half its 5 mm layer).
    jaw_profile_plane_rtol: float = _field(0.1, _NONNEG)  # 0: exactly the footprint's circumscribed circle
    # ... and at most this x half the pad's diagonal deeper into the object than the jaw point:
    # the pad touches first at or before the grasp point (a surface point under its centre) and
    # the contact lies within the jaw's advance from that touch (< 0.9 x the FEM layer: 0.2 on
    # the 20 x 40 x 5 mm pad; REACH closes 1 mm).  REACH on antipodal grasps of the thesis objects
    # (20 x 40 and 8 x 20 mm pads): at most 0.35 mm deeper.  Towards the jaw there is no bound: a
    # pad stopped by a rim or a tilted face sat up to 15.8 mm behind the grasp point there.
    jaw_profile_depth_rtol: float = _field(0.5, _POS)  # 0 refuses every curved contact
    # A profile from a source whose pressure distribution changes with force (the FEM pad: on a
    # curved face the contact radius grows as F^(1/3), Hertz) scaled to a reading more than this
    # factor from the one it was made at, either way, is warned about: at 1.1^3 its torsional
    # capacity per newton is already ~10 % off.
    profile_force_ratio_warn: float = _field(1.331, _real(1.0))  # 1: warn at any scaling
    # A pad's press first keeps, in one compiled pass, the faces and sub-triangles that may pass
    # its tests with every bound widened by this [m], then tests those exactly: far above the
    # round-off of a coordinate (~1e-17 m on a 10 cm object), so the kept ones are the same.
    prefilter_margin_m: float = _field(1e-9, _POS)
    # A jaw's ``up`` within this angle [deg] of its approach is warned about (sources.reach): the
    # pad's turn about the approach is then set by up's small part across it, so a slight change of
    # up or of the axis turns the pad far (at 1e-9 rad the last digits of up decide it).
    jaw_up_warn_deg: float = _field(1.0, _real(0.0, hi=90.0))  # 0: never warn
    # The most sub-triangles a REACH press's refinement may make (sources.reach): ~200 bytes each
    # while they are made; a thesis bottle at 1 mm makes at most 0.62 M, a millimetre mesh taken
    # for metres billions (a MemoryError, not a message, without this bound).
    max_sub_triangles: float = _field(2e7, _POS)


TOL = Tolerances()

#: Kinds of training-wrench sampler (limit_surface.cache.SamplerSpec; here so that
#: ``Defaults.ls_training_sampler`` is checked when set without importing the fitters).
SAMPLER_KINDS = ("thesis", "6dfc", "thesis-code", "mix")


@dataclass(frozen=True)
class Defaults:
    """Defaults of samplers and experiments (thesis values where it has them)."""

    # Thesis §3.3.2: q is uniform in a ball of radius 0.25 * l_s around o.
    twist_radius_factor: float = _field(0.25, _NONNEG)  # 0: every rotation axis through o
    # Pitch h ~ U[lo, hi] * l_s.  The thesis (§3.3.2) draws h in [-2, 2] with no
    # unit in the text (its nomenclature: m/rad); on S1-S6 (l_s = 2) that is
    # [-1, 1] l_s, kept here so it stays scale covariant.  It is *not* what the
    # author's code does on the FEM contacts: their data are in millimetres, so a
    # literal ±2 is ±2 mm ≈ ±0.1 l_s on a 20 mm contact, and the code itself uses
    # only {0, ±0.25 mean side} (twists_author.py).  On mm-scale FEM profiles this
    # sampler therefore draws far more screw-like twists than the author's.
    # Consequence, measured on the fem-fitting quick profiles (uniform-normal
    # radial error of the quartic, README "Reproduction protocols"): trained on
    # this sampler 0.049, with ±0.1 l_s 0.035, on the author's grid 0.018.
    pitch_range: tuple[float, float] = _field((-1.0, 1.0), _PITCHES)
    # Training wrenches of the limit surfaces of grasp analysis (SamplerSpec kinds):
    # "mix" = the thesis sampler's 600 (§3.3.2) plus the author's grid, downsampled
    # (the thesis-code protocol).  Chosen on the sensitivity scene against the noise-free exact
    # margins (results/sensitivity -> training_distribution): median |log ratio|
    # ellipsoid thesis 0.019, thesis-code 0.022, mix 0.014; quartic 0.004 / 0.004 /
    # 0.002 (the bisection's resolution is 0.002).  Confirmed on the grasp dataset's gripper
    # contacts against the exact 6DFW margins (results/benchmarks/training_sampler_margins.json):
    # ellipsoid mix 0.057, thesis 0.093, 6dfc 0.088, thesis-code 0.049.
    ls_training_sampler: str = _field("mix", _choice(lambda: SAMPLER_KINDS))
    # Cell side, as a fraction of the contact's l_s, of the coarsened contact whose 6DFWs train
    # those limit surfaces (SamplerSpec.cell_fraction; workbench.coarsen): 0 = the contact itself,
    # else in [0.001, 0.5].  A coarser contact trades margin error for build time
    # (results/benchmarks/training_sampler_margins.json: the grasp dataset's contacts against
    # their exact 6DFW margins); relative, so that a scaled contact is coarsened alike (the
    # thesis's 3 mm FEM elements, §3.5.2, are ~0.15 l_s of its 20 mm contacts).  Above 0.5 a
    # contact is two or three cells (torsion 4x off in a trial); at 0.3 its torsional friction is
    # already 5 % low.
    ls_training_cell_fraction: float = _field(0.0, _cell_fraction)
    # Seed used by experiments when none is given.
    seed: int = _field(0, _count(0))  # numpy seeds are non-negative
    # Weight beta_0 of the normal (twist) rows of the quartic fit: each sampled
    # wrench's twist is its outward normal (maximum dissipation), and the rows
    # (beta/4)(grad f - 4 n/(n.x)) get beta = beta_0 sqrt(L/K), so they carry a
    # fixed total weight of beta_0^2 L value rows: a prior that fills the gaps
    # of small samples and fades as K grows.  0.5 was chosen on validation
    # samples (seeds 777,000+) of S1-S6, never on the reported held-out sets.
    quartic_normal_weight: float = _field(0.5, _NONNEG)
    # The quartic fit's (Eq. 3.17) solver where none is named: "IPM" (limit_surface/sos_ipm.py:
    # Clarabel's optimum to its tolerances, faster: results/benchmarks/limit_surface.json; Clarabel
    # is its checked fallback)
    # or a conic solver with semidefinite support ("CLARABEL", "SCS").
    quartic_solver: str = _field("IPM", _solver_choice(("IPM", "CLARABEL", "SCS")))
    # The SDP ellipsoid's (Eq. 3.11 with A ⪰ 0) solver where none is named: "IPM" (the same
    # interior point with one r × r block; Clarabel through cvxpy is its checked fallback), or
    # "CLARABEL" / "SCS" through cvxpy.  Eq. 3.12's log-det term needs a cvxpy solver.
    ellipsoid_solver: str = _field("IPM", _solver_choice(("IPM", "CLARABEL", "SCS")))
    # (λ, ω_w, ω_t) of the author's fitting objective (limit_surface/author_objective.py):
    # regulariser ‖A‖, L1 value residuals, twist-direction residuals — the values
    # of the author's exampleFEM.m, exampleParametricSurface.m and
    # exampleMeshedSurface.m (all three use 1 / 10 / 1).
    author_fit_weights: tuple[float, float, float] = _field((1.0, 10.0, 1.0), _author_weights)
    # Median value on its training wrenches below which an author-objective fit is reported
    # (logged, info["warning"]) as collapsed toward f = 0: the twist term rewards a small
    # gradient, and weights like (0.1, 1, 5) bought a lower objective with ||a|| = 3e-8 (a
    # new-user trial).  A fit through its data has median ~1.
    author_fit_collapse_below: float = _field(0.5, _NONNEG)

    # REACH profiles (sources/reach.py): surface elements whose outward normal has
    # less than this component against the approach (within ~6 deg of parallel to
    # it) get no Winkler pressure — their area under the pad vanishes; without it
    # a box's side walls carried up to 9 % of the jaw force sideways.
    reach_min_facing: float = _field(0.1, _FRACTION)  # a cosine against the approach
    # A pad's press reads the fine surface through a grid (sources/surface_index.py) whose
    # cells are this many sub-triangle edges wide: smaller cells hug the pad's box closer but
    # cost more cells to test.  Speed only: the profile does not depend on it.
    surface_index_cells: float = _field(3.0, _POS)  # times max_edge

    # The largest turn [rad] of a free object between the jaws (workbench.grasp.settle)
    # before the fingers, not the pads, would stop it.  The YuMi trials' jaws sit up to
    # 9.4 deg off the faces; 20 deg leaves room for a pose perturbation on top.
    # accepts: radians; 0: no turn (each jaw pressed alone)
    settle_max_tilt: float = _field(0.35, _real(0.0, hi=1.5708))
    # The settle's first guess [m]: the patches pressed this deep (wider than at the force,
    # their net normals steadier) give the turn that makes the pads flush with them; the solve
    # then starts there.  A thin patch's net normal can swing as elements enter and leave it.
    settle_start_closing: float = _field(5e-4, _POS)  # metres
    # The settle's solver steps (workbench.grasp.settle; one press of both pads each) before it
    # stops where it stands (its torque then judged against settle_torque_rtol like any other):
    # a smooth contact settles in 2-5, one whose contact set keeps changing may stall
    # (docs/decisions.md: converged shares and costs at 12, 20, 30 and 45).
    settle_max_steps: int = _field(20, _count(1))
    # A direction of turn along which the settle's torque stiffness is below this fraction of
    # the stiffest one is neutral (a round object turning about its own axis: the contact
    # rolls round it); the settle takes no step along it rather than chase the facets' torque
    # noise there (the torque it leaves is reported, and judged against settle_torque_rtol).
    settle_neutral_stiffness: float = _field(0.05, _FRACTION)
    # ... unless the torque along it is above this (relative to force x pad size, as
    # settle_torque_rtol): a faceted round object's noise stays below it, a real torque does not.
    settle_neutral_torque: float = _field(0.01, _POS)

    # Pose robustness (workbench.grasp.pose_robust, 6DFC §V-B.1): the gripper pose is
    # perturbed in its own frame by a translation ~ N(0, sigma_trans²) per axis [m] and a
    # rotation exp([xi]x), xi ~ N(0, sigma_rot²) per axis [rad] (ipc-graspsim's GaussianPoseRV
    # construction), and the contact recomputed.  6DFC Fig. 3: mAP and mAR best at
    # N_r = 10 samples and sigma_r = 0.003 m.
    pose_samples: int = _field(10, _count(1))
    pose_sigma_trans: float = _field(0.003, _NONNEG)  # metres; 0: no translation noise
    pose_sigma_rot: float = _field(0.003, _NONNEG)  # radians; 0: no rotation noise

    # Dense QP solver of wrench resistance: "auto" = quadprog up to
    # qp_auto_large variables, DAQP above: both agree with the exact LP on every case,
    # and DAQP's time grows far more slowly with the variables (benchmarks/bench_grasp.py,
    # results/benchmarks/grasp.json "qp_solvers"; docs/decisions.md).
    qp_solver: str = _field("auto", _choice(lambda: ("auto", *_qp_solvers())))
    qp_auto_large: int = _field(48, _count(0))
    # Tried (and recorded in the result) when the chosen QP solver returns nothing.
    qp_fallback_solver: str = _field("clarabel", _choice(_qp_solvers))
    # HiGHS presolve on the workbench's LPs (grasp/resistance/solvers: MinLP, the minimal-force
    # LPs, and highs_lp, the residual LPs of vertex sets and the exact column LPs): off.
    # They are small and dense (2 jaws x 200 directions: 407 rows, 26 columns; HiGHS
    # gets the dual, 26 x 407; sensitivity's: 10 rows, ~420 to ~1,200 columns), so presolve
    # cannot shrink them and only adds its own time; the optimum is the same (the
    # measurements: docs/decisions.md).
    lp_presolve: bool = _field(False, _flag)
    # HiGHS's simplex scaling of that model (simplex_scale_strategy: 0 off, 2 its
    # default equilibration) and its dual feasibility tolerance.  In the dual HiGHS
    # solves, the LP's polyhedral rows G y <= h (the C_outer facets) are the dual's
    # dual-feasibility conditions: unscaled at HiGHS's default 1e-7 they were violated by
    # up to 8.8e-8, which moved Σf by up to 5.1e-3 relative (on the grasps of
    # minimal-work's three measured objects: the facets are nearly parallel to the light
    # objects' small gravity wrench); at 1e-9 by 1.8e-13, Σf within 1.7e-10 of the
    # equilibrated solve.  The rows are already scaled by D (gws.capacity_scaling), so
    # HiGHS's own equilibration only adds time (docs/decisions.md).
    lp_scale_strategy: int = _field(0, _count(0))  # HiGHS checks its own range [0, 5]
    lp_dual_feasibility_tolerance: float = _field(1e-9, _POS)
    # Clarabel's KKT factorisation in the SOS-convex quartic fits (limit_surface/
    # quartic.py, through cvxpy): "faer" (supernodal) on max_threads threads, or
    # "qdldl".  faer on one thread is the fastest of the three, with the same optimum
    # (docs/decisions.md); one thread also keeps Dask workers (one core each) from
    # oversubscribing.
    quartic_kkt_method: str = _field("faer", _choice(lambda: ("faer", "qdldl")))
    quartic_kkt_threads: int = _field(1, _count(1))
    # Clarabel's iterative refinement steps per KKT solve in those fits (its default: up to
    # 10).  One step gives the optimal residual of ten in less time; none is faster still
    # but leaves the residual visibly off (docs/decisions.md).
    quartic_kkt_refinement: int = _field(1, _count(0))
    # Directions of the 6DLS/6DFC linearisation (Eqs. 3.19–3.24) when a caller
    # asks for representation="inner" or "outer".
    linearization_M: int = _field(200, _count(1))

    # ε of the jaw displacement d_i = f_i / s_i + ε (Eq. 4.5) [m]: what a rigid
    # contact (s = inf) is credited, so that W = ε Σ f on rigid objects (the
    # minimal-force metric).  The thesis gives no value ("a small positive
    # number"); 5e-5 m is the smallest deflection any measured map resolved
    # (shampoo, 0.052 mm at the 10 N target force, §4.3.3.1): a region reported
    # rigid deflected less than that.
    work_eps: float = _field(5e-5, _POS)  # "a small positive number" (thesis Eq. 4.5)

    # Inner-loop iterations (elements x twists, points x monomials, ...) from which a parallel
    # (prange) kernel call runs on Numba's threads; below, on the calling thread alone (a
    # thread mask of one, the same compiled kernel: workbench.kernel_launch).  Below it a
    # call's serial work is small beside what a parallel region can cost to start when another
    # process holds the other core (docs/decisions.md).
    parallel_min_work: int = _field(50_000, _count(0))

    # Right-hand sides from which a sparse factor with row copies of L and U
    # (workbench.fem.sparse_factor.factor_spd(blocked=True): the thin walls) solves them together in
    # workbench.fem._kernels (each factor entry read once for all of them) instead of SuperLU's column
    # by column: from about this many columns on, the row kernels are the faster
    # (docs/decisions.md).
    blocked_solve_min_rhs: int = _field(16, _count(0))


DEFAULTS = Defaults()


@dataclass(frozen=True)
class RunSettings:
    """How runs are executed — Dask clusters, the scheduler, sweeps, progress bars — never what they
    compute: no number in a result depends on these (the checkpoints key rows without them)."""

    # Rows of one experiment from which it runs them on a local Dask cluster (one worker per
    # core) when its ``workers`` setting is 0 (auto): below it a cluster's start (seconds, with
    # the workers' imports) outweighs what a second core saves.
    cluster_min_rows: int = _field(24, _count(0))

    # Tasks a local cluster's scheduler hands a worker ahead, per thread (Dask's
    # distributed.scheduler.worker-saturation; inf: all of them at once, Dask's work stealing
    # balancing the tail).  Dask's default 1.1 keeps the rest on the scheduler and sends one
    # when one finishes: a worker -> scheduler -> worker round trip a row, but the rows go to
    # whichever worker is free, longest first.  Rows here are long and uneven, and handing
    # them all out at submit splits them by count, which costs far more than the round trips
    # (benchmarks/bench_sweep.py, results/benchmarks/sweep.json; docs/decisions.md).  An
    # existing cluster (--scheduler) keeps its own setting.
    cluster_worker_saturation: float = _field(1.1, _saturation)

    # Grasps to run from which fem-fitting gives each task a grasp's profiles (its jaw
    # displacements solved once, in order) instead of one profile (which solves the
    # displacements before it again: a small but real share of a full run, docs/decisions.md);
    # below it one profile a task keeps both workers busy on short runs.  Changes no number,
    # only the timings.
    grasp_tasks_from: int = _field(64, _count(1))

    # Seconds a sweep on an existing cluster (--scheduler) waits for the scheduler to answer
    # and then for its first worker, before it stops with an error saying which: a scheduler
    # with no workers would otherwise hold the sweep at 0 % without a word.
    scheduler_wait_s: float = _field(30.0, _POS)

    # Seconds a run on Dask (an experiment's rows, a sweep's points) waits with tasks pending and
    # no worker in the cluster before it stops with an error: workers that died with their
    # nannies (the memory of the machine exhausted) would otherwise hold the driver forever.
    # Rows and points finished by then are kept (a re-run resumes).
    cluster_no_worker_s: float = _field(120.0, _POS)

    # Seconds a sweep's TCP probe of a --scheduler host:port waits before the Dask client is
    # made: a refused connection (nothing listens there) or an unknown host then stops the
    # sweep at once instead of after scheduler_wait_s; a probe that times out (a firewall
    # dropping packets) leaves the answer to the client's own wait.
    scheduler_probe_s: float = _field(2.0, _POS)

    # Close column names a sweep suggests for a --plot METRIC that is not a number column of
    # its table (difflib), instead of listing its every column (~200 for some experiments).
    sweep_column_hints: int = _field(5, _count(1))

    # A sweep whose first this-many finished points all failed stops (the rest cancelled),
    # printing the last error: a setting that fails every point (a 10,000-point grid, each
    # point failing after seconds) would otherwise run to the end.  0: never stop.
    sweep_stop_after_failures: int = _field(5, _count(0))

    # Seconds an automatic progress bar (progress=None on a terminal: grasp sampling) waits
    # before it appears, so that short calls print nothing.
    progress_delay_s: float = _field(2.0, _NONNEG)  # 0: a bar at once

    # A sweep plot's axis is logarithmic when its grid is geometric: its largest log-step at most
    # this many times its smallest (a 1-2-5 series passes, 1, 2, 3 does not) ...
    sweep_log_step_spread: float = _field(1.5, _real(1.0))  # a ratio of log-steps: >= 1

    # ... and it spans more than this ratio (a decade; also the y axis's rule) ...
    sweep_log_min_span: float = _field(10.0, _real(1.0, lo_open=True))  # a ratio of values: > 1

    # ... or steps by at least this ratio (25, 50, 100)
    sweep_log_min_step: float = _field(2.0, _real(1.0, lo_open=True))


RUN = RunSettings()


#: field name -> rule, read from each field of Tolerances, Defaults and RunSettings (tests/test_config.py
#: checks every field has one).
_RULES: dict[str, Callable[[Any], Any]] = {
    f.name: f.metadata["rule"] for cls in (Tolerances, Defaults, RunSettings) for f in fields(cls)
}


#: the three owners of the settings, by the module-level name each current instance lives at
_OWNERS = (("TOL", Tolerances), ("DEFAULTS", Defaults), ("RUN", RunSettings))


def check_value(name: str, value: Any, what: str | None = None) -> Any:
    """``value`` as stored for the Tolerances/Defaults/RunSettings field ``name`` — the one rule
    of that quantity, also for a function that takes it as an argument (``what``: how the message
    names it, default "config field <name>"); ValueError (expected, got, fix) when it does not fit."""
    try:
        return _RULES[name](value)
    except _Reject as exc:
        default = next(getattr(cls, name) for _, cls in _OWNERS if hasattr(cls, name))
        raise ValueError(
            f"{what or 'config field ' + name} must be {exc}; got {value!r} ({type(value).__name__}). "
            f"Pass such a value, e.g. its default {name}={default!r}"
        ) from None


def _split(values: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """``values`` checked and by owner (``{"TOL": {...}, "DEFAULTS": {...}, "RUN": {...}}``);
    ValueError for other names and for a value its field does not accept."""
    owner = {f.name: key for key, cls in _OWNERS for f in fields(cls)}
    unknown = sorted(set(values) - set(owner))
    if unknown:
        from difflib import get_close_matches

        close = {k: get_close_matches(k, owner, n=1) for k in unknown}
        hints = "; ".join(f"did you mean {c[0]!r} for {k!r}?" for k, c in close.items() if c)
        raise ValueError(
            f"unknown tolerance/default/run-setting names {unknown}"
            + (f" ({hints})" if hints else "")
            + "; the fields of config.Tolerances, config.Defaults and config.RunSettings are the "
            "names to use (e.g. resist_rtol, quadrature_rtol, work_eps, cluster_min_rows)"
        )
    out: dict[str, dict[str, Any]] = {key: {} for key, _ in _OWNERS}
    for k, v in values.items():
        out[owner[k]][k] = check_value(k, v)
    return out


def configure(**values: Any) -> None:
    """Set tolerances, defaults and run settings by field name for the rest of this process,
    e.g. ``config.configure(resist_rtol=1e-8)``.  An experiment's rows on Dask workers (other
    processes) compute under the same settings: :func:`workbench.runner.parallel.map_rows` passes
    :func:`changed` with every task, and checkpoints key their rows by ``changed(numbers_only=True)``."""
    for key, new in _split(values).items():
        if new:
            globals()[key] = replace(globals()[key], **new)


def changed(numbers_only: bool = False) -> dict[str, Any]:
    """The fields this process set away from their defaults (``configure`` / ``override``), by
    name: what a worker process needs to run as this one does.  ``numbers_only``: the
    tolerances and defaults alone — what a cached result's key holds beside its inputs (the run
    settings change how a run is executed, never its numbers)."""
    owners = _OWNERS[:2] if numbers_only else _OWNERS
    return {
        f.name: getattr(globals()[key], f.name)
        for key, cls in owners
        for f in fields(cls)
        if getattr(globals()[key], f.name) != f.default
    }


@contextmanager
def override(**values: Any) -> Iterator[None]:
    """Tolerances, defaults and run settings changed by field name inside a ``with`` block,
    restored after (also on an exception): ``with config.override(quadrature_rtol=1e-6): ...``."""
    before = {key: globals()[key] for key, _ in _OWNERS}
    configure(**values)
    try:
        yield
    finally:
        globals().update(before)

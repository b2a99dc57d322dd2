"""An object's measured stiffness as a function on its surface (thesis §4.3.3.1).

The thesis measures the stiffness ``s = f⊥ / (l_s − l_e)`` [N/m] at the contact
points of antipodal grasps and "interpolates" it over the object (Fig. 4.13) without
saying how.  :class:`StiffnessMap` holds the measured points and values and answers
the stiffness anywhere:

* a location is **rigid** (``np.inf``) iff its nearest measured point is rigid
  (``s >= rigid_threshold``; the measured maps write 8e10 for "no measurable
  deflection") — rigid regions (caps, folds) are not averaged with soft ones;
* otherwise ``log s`` is interpolated over the non-rigid measured points by a
  radial basis function, the *cubic* kernel ``φ(r) = r³`` plus a linear polynomial
  (``scipy.interpolate.RBFInterpolator``, smoothing 0): exact at the measured
  points, C² between them (the 3D analogue of a natural cubic spline), and without
  a shape parameter, so the field does not change when all lengths are scaled
  (a scaled copy of the object gives the same field; the points themselves must
  be in metres, CONVENTIONS.md) — Gaussian or
  multiquadric kernels would need a width tuned per object.  Among the scale-free
  kernels it predicted held-out grasps best on the measured maps (leave-one-out
  median ``|log(s_pred / s)|`` cup / mustard / shampoo: cubic 0.063 / 0.095 / 0.077,
  linear 0.047 / 0.188 / 0.145, thin-plate 0.072 / 0.128 / 0.109; a constant
  0.32 / 0.26 / 0.43).  Stiffness spans decades (400 N/m on a cup's side wall to
  2e5 N/m on a bottle's shoulder), hence ``log s``;
* the result is clamped to the measured ``[min, max]`` of ``log s``, so the map
  never extrapolates beyond the data (the linear trend of the cubic spline would).

Distances are straight lines in 3D, not geodesics on the surface: points across a
thin object influence each other (a grasp's two jaw points carry one value anyway).
:func:`leave_one_out` measures how well the scheme predicts a held-out grasp.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import RBFInterpolator
from scipy.spatial import cKDTree

from .. import config
from ..units import check_extent

log = logging.getLogger(__name__)

__all__ = ["StiffnessMap", "check_stiffness", "leave_one_out"]

#: kernel of the log-stiffness interpolation (module docstring)
RBF_KERNEL = "cubic"


def check_stiffness(values, n: int, where: str, *, fix: str, rigid: str = "np.inf") -> np.ndarray:
    """(n,) float stiffness [N/m], one per ``where`` ("point", "contact"), each > 0 (``rigid``
    says how a rigid one is written), or a ``ValueError`` naming the shape or the value
    and ``fix`` (how to get the right shape)."""
    try:
        s = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(
            f"stiffness must be (n,) = ({n},) numbers, one value per {where} [N/m]; got "
            f"{type(values).__name__} ({fix})"
        ) from None
    if s.shape != (n,):
        raise ValueError(
            f"stiffness must be (n,) = ({n},), one value per {where} [N/m]; got shape {s.shape} ({fix})"
        )
    bad = np.isnan(s) | (s <= 0)
    if bad.any():
        k = int(np.argmax(bad))
        raise ValueError(
            f"stiffness must be > 0 [N/m] ({rigid} for a rigid {where}); got {s[k]} at {where} {k}"
        )
    finite = np.flatnonzero(s < config.TOL.rigid_stiffness_threshold)  # not inf, not a rigid marker
    if len(finite):
        # the softest and the stiffest measurable value by the one stiffness rule: below
        # TOL.min_plausible_stiffness refused (a value in N/mm), under 100 N/m warned
        from workbench.plausible import check

        for k in {int(finite[np.argmin(s[finite])]), int(finite[np.argmax(s[finite])])}:
            check("stiffness", float(s[k]), f"stiffness at {where} {k} [N/m]")
    return s


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, copy=True)
    a.flags.writeable = False
    return a


def _spans_3d(P: np.ndarray) -> bool:
    """Whether points (k, 3) determine a linear polynomial in 3D (4 non-coplanar)."""
    if len(P) < 4:
        return False
    sv = np.linalg.svd(P - P.mean(axis=0), compute_uv=False)
    # points spanning a plane only (third singular value at round-off): no volume to interpolate in
    return bool(sv[2] > 1e-9 * sv[0])


@dataclass(frozen=True, eq=False)
class StiffnessMap:
    """Measured stiffness at points of an object's surface, interpolated between them
    (scheme in the module docstring).

    points : (m, 3) float — measured contact points [m], object frame.
    stiffness : (m,) float — stiffness at each point [N/m]; a value
        ``>= rigid_threshold`` (or ``+inf``) marks a rigid point.
    grasp : (m,) int — the measured grasp each point belongs to (its jaws share one
        value; :func:`leave_one_out` holds a grasp out as a whole); None: every point
        its own grasp.
    rigid_threshold : [N/m]; None reads ``config.TOL.rigid_stiffness_threshold`` at
        construction.

    Call it on (k, 3) points for (k,) stiffness, ``np.inf`` where rigid.  The arrays
    are read-only copies; the interpolator is built once at construction from them
    (derived from immutable fields, never changed afterwards).  Equality is identity
    (``eq=False``: arrays do not compare as booleans).
    """

    points: np.ndarray
    stiffness: np.ndarray
    grasp: np.ndarray | None = None
    rigid_threshold: float | None = None
    _tree: cKDTree = field(init=False, repr=False, compare=False)
    _rbf: RBFInterpolator | None = field(init=False, repr=False, compare=False)
    _log_range: tuple[float, float] = field(init=False, repr=False, compare=False)
    _kernel: str | None = field(init=False, repr=False, compare=False)
    _span: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        thr = config.TOL.rigid_stiffness_threshold if self.rigid_threshold is None else self.rigid_threshold
        if isinstance(thr, (bool, np.bool_)) or not np.isscalar(thr) or not (np.isfinite(thr) and thr > 0):
            raise ValueError(
                f"rigid_threshold must be a finite stiffness > 0 [N/m]; got {thr!r} "
                "(the measured maps mark rigid points with 8e10; the default is 1e10)"
            )
        P = np.asarray(self.points, dtype=float)
        if P.ndim != 2 or P.shape[1] != 3 or len(P) == 0:
            raise ValueError(f"points must be (m, 3) with m >= 1 [m]; got shape {P.shape}")
        if not np.isfinite(P).all():
            k = int(np.argmax(~np.isfinite(P).all(axis=1)))
            raise ValueError(f"points must be finite; point {k} is {P[k].tolist()}")
        S = check_stiffness(
            self.stiffness,
            len(P),
            "point",
            fix="a (m, 1) column: pass .ravel(), or use StiffnessMap.from_measured",
            rigid=f"+inf or >= {thr:g}",
        )
        check_extent(
            float(np.ptp(P, axis=0).max()),
            "stiffness map points",
            fix="scale them by {factor:g}",
            override=None,
        )
        if self.grasp is None:
            g = np.arange(len(P))
        else:
            g = np.asarray(self.grasp)
            if g.shape != (len(P),) or g.dtype.kind not in "iu":
                raise ValueError(
                    f"grasp must be (m,) = ({len(P)},) integers (the measured grasp of each point); "
                    f"got shape {g.shape}, dtype {g.dtype}"
                )
        # duplicates: fine when they agree (the RBF sees each location once)
        uniq, first, inv = np.unique(P, axis=0, return_index=True, return_inverse=True)
        inv = inv.ravel()
        if len(uniq) < len(P):
            # repeated locations carry the same measured value (JSON round trip: equal to 1e-9)
            same = np.isclose(S, S[first][inv], rtol=1e-9, atol=0) | (np.isinf(S) & np.isinf(S[first][inv]))
            if not same.all():
                k = int(np.argmax(~same))
                j = int(first[inv[k]])
                raise ValueError(
                    f"points {j} and {k} coincide at {P[k].tolist()} but carry different stiffness "
                    f"{S[j]:g} and {S[k]:g} N/m: merge repeated measurements (e.g. their median) first"
                )
        object.__setattr__(self, "points", _readonly(P))
        object.__setattr__(self, "stiffness", _readonly(S))
        object.__setattr__(self, "grasp", _readonly(g))
        object.__setattr__(self, "rigid_threshold", float(thr))
        object.__setattr__(self, "_tree", cKDTree(self.points))
        object.__setattr__(self, "_span", float(np.ptp(self.points, axis=0).max()))  # the far check's scale
        soft = S < thr
        keep = np.zeros(len(P), dtype=bool)
        keep[first] = True
        fit = soft & keep
        rbf, rng, kernel = None, (np.nan, np.nan), None
        if fit.any():
            logs = np.log(S[fit])
            kernel = RBF_KERNEL if _spans_3d(self.points[fit]) else "linear"
            if kernel != RBF_KERNEL:
                log.info(
                    "stiffness map: %d non-rigid points do not span 3D (a %s spline needs 4 "
                    "non-coplanar ones); the linear kernel interpolates them",
                    int(fit.sum()),
                    RBF_KERNEL,
                )
            rbf = RBFInterpolator(self.points[fit], logs, kernel=kernel, smoothing=0.0)
            rng = (float(logs.min()), float(logs.max()))
        object.__setattr__(self, "_rbf", rbf)
        object.__setattr__(self, "_kernel", kernel)
        object.__setattr__(self, "_log_range", rng)

    @classmethod
    def from_measured(cls, locations, values, rigid_threshold: float | None = None) -> StiffnessMap:
        """The map of a measured file's arrays (``deformable_objects/stiffness_maps/*.json``).

        locations : (2n, 3) float — ``stiffness_locations`` [m]; points ``i`` and
            ``i + n`` are the two jaws of grasp ``i``.
        values : (2n, 1) or (2n,) float — ``stiffness_map`` [N/m]; entries ``i`` and
            ``i + n`` must be equal (one value per grasp).
        rigid_threshold : [N/m]; None: ``config.TOL.rigid_stiffness_threshold``.
        """
        L = np.asarray(locations, dtype=float)
        V = np.asarray(values, dtype=float)
        if L.ndim != 2 or L.shape[1] != 3:
            raise ValueError(f"locations must be (2n, 3) [m]; got shape {L.shape}")
        if len(L) == 0 or len(L) % 2:
            raise ValueError(
                f"locations must hold 2n points (point i and i + n are one grasp's two jaws); got {len(L)}"
            )
        if V.ndim == 2 and V.shape[1] == 1:
            V = V[:, 0]
        if V.shape != (len(L),):
            raise ValueError(
                f"values must be (2n, 1) or (2n,) = ({len(L)},) stiffness [N/m], one per location; "
                f"got shape {np.shape(values)}"
            )
        n = len(L) // 2
        a, b = V[:n], V[n:]
        # the two jaws' readings of one grasp are one number written twice (to 1e-9 after JSON)
        agree = np.isclose(a, b, rtol=1e-9, atol=0) | (a == b)
        if not agree.all():
            k = int(np.argmax(~agree))
            raise ValueError(
                f"values {k} and {k + n} differ ({a[k]:g} vs {b[k]:g} N/m): points i and i + n are one "
                "grasp's two jaws and carry its one value — is the array in another order?"
            )
        grasp = np.tile(np.arange(n), 2)
        return cls(L, V, grasp=grasp, rigid_threshold=rigid_threshold)

    @property
    def kernel(self) -> str | None:
        """RBF kernel in use: ``RBF_KERNEL`` ("cubic"), "linear" when the non-rigid
        points do not span 3D (fewer than 4, or coplanar: the cubic spline's linear
        polynomial is then undetermined; the linear kernel with a constant is
        well-posed for any distinct points), None when every point is rigid."""
        return self._kernel

    @property
    def rigid(self) -> np.ndarray:
        """(m,) bool — measured points that are rigid."""
        return self.stiffness >= self.rigid_threshold

    def __call__(self, points) -> np.ndarray:
        """(k,) stiffness [N/m] at (k, 3) points [m] (a single (3,) point gives (1,));
        ``np.inf`` where the nearest measured point is rigid.  A point farther from every
        measured point than the points' largest extent raises ``ValueError`` (it is off
        the object: another frame or unit), instead of the clamped extrapolation.  That
        check is coarse — it catches a wrong frame or unit, not a point a few centimetres
        off the surface, which gets the clamped value of its neighbourhood."""
        Q = np.asarray(points, dtype=float)
        if Q.ndim == 1:
            Q = Q[None]
        if Q.ndim != 2 or Q.shape[1] != 3:
            raise ValueError(f"points must be finite (k, 3) [m]; got shape {Q.shape}")
        if not np.isfinite(Q).all():
            k = int(np.argmax(~np.isfinite(Q).all(axis=1)))
            raise ValueError(f"points must be finite (k, 3) [m]; point {k} is {Q[k].tolist()}")
        out = np.full(len(Q), np.inf)
        if len(Q) == 0:
            return out
        dist, idx = self._tree.query(Q)
        # a point farther from every measured point than the measured points span is not on
        # this object (another frame or unit): refuse it rather than return a clamped value
        span = self._span
        far = dist > span if span > 0 else np.zeros(len(Q), dtype=bool)  # one point: no scale
        if far.any():
            k = int(np.argmax(dist))
            raise ValueError(
                f"point {k} {Q[k].tolist()} is {dist[k]:.3g} m from the nearest measured point, "
                f"farther than the measured points' extent ({span:.3g} m): it is not on this object — "
                "give points in the map's frame and in metres"
            )
        soft = ~self.rigid[idx]
        if soft.any():
            lo, hi = self._log_range
            out[soft] = np.exp(np.clip(self._rbf(Q[soft]), lo, hi))
        return out


def leave_one_out(smap: StiffnessMap) -> dict:
    """Held-out error of the interpolation: each measured grasp (all points of one
    ``grasp`` label, removed together since they share one value) is predicted from
    the others.

    Returns a dict:

    * ``median_abs_log_error``, ``max_abs_log_error`` — of ``|log(s_pred / s_meas)|``
      over the held-out points that are non-rigid both measured and predicted (NaN
      if none);
    * ``baseline_median_abs_log_error`` — the same for a constant prediction, the
      median of ``log s`` over the other grasps' non-rigid points (an interpolation
      worth having beats it);
    * ``rigid_agreement`` — fraction of held-out points whose rigid flag is predicted
      right;
    * ``n_grasps``, ``n_points``, ``n_compared`` — grasps held out, points predicted,
      points in the log errors.

    A grasp whose removal leaves no point is skipped (a one-grasp map has none).
    """
    if not isinstance(smap, StiffnessMap):
        raise ValueError(f"leave_one_out needs a StiffnessMap; got {type(smap).__name__}")
    errs, base, agree = [], [], []
    labels = np.unique(smap.grasp)
    rigid = smap.rigid
    n_points = n_grasps = 0
    for g in labels:
        out = smap.grasp == g
        if out.all():
            continue
        n_grasps += 1
        rest = StiffnessMap(
            smap.points[~out],
            smap.stiffness[~out],
            grasp=smap.grasp[~out],
            rigid_threshold=smap.rigid_threshold,
        )
        pred = rest(smap.points[out])
        meas = smap.stiffness[out]
        p_rigid = np.isinf(pred)
        agree.append(p_rigid == rigid[out])
        n_points += int(out.sum())
        both = ~p_rigid & ~rigid[out]
        errs.append(np.abs(np.log(pred[both] / meas[both])))
        soft_rest = ~rest.rigid
        if soft_rest.any():
            c = float(np.median(np.log(rest.stiffness[soft_rest])))
            base.append(np.abs(c - np.log(meas[~rigid[out]])))
    e = np.concatenate(errs) if errs else np.empty(0)
    b = np.concatenate(base) if base else np.empty(0)
    a = np.concatenate(agree) if agree else np.empty(0, dtype=bool)
    result = {
        "median_abs_log_error": float(np.median(e)) if e.size else float("nan"),
        "max_abs_log_error": float(e.max()) if e.size else float("nan"),
        "baseline_median_abs_log_error": float(np.median(b)) if b.size else float("nan"),
        "rigid_agreement": float(a.mean()) if a.size else float("nan"),
        "n_grasps": n_grasps,
        "n_points": n_points,
        "n_compared": int(e.size),
    }
    log.debug("stiffness map leave-one-out: %s", result)
    return result

"""ContactProfile: a discretised contact surface with a pressure per element.

A contact profile (thesis §3.2, "profile pair" of §3.3.6.1) is what the FEM
produces and what every friction model consumes: element centers, unit normals
pointing **outward from the object** (into the jaw), element areas and one
pressure per element.  Everything derived (pressure center, ``F``, ``p̂``,
normal wrench, length scale) is cached on first use.

Normals: a normal whose length is within ``config.TOL.normal_unit_atol`` of 1 is
renormalised silently; any other length is rejected with a ``ValueError``
unless ``normalize_normals=True`` is passed (then every non-zero normal is
rescaled; zero normals are always rejected).

Size: the length scale ``l_s`` is computed at construction, and a profile
longer than ``config.TOL.max_object_extent_m`` (2 m) is rejected as a likely unit
mistake unless ``allow_scale=True`` (see :mod:`workbench.units`).

Provenance: a profile source that knows where its profiles hold attaches a
:class:`ProfileSource` (the FEM pad: the reading it was pressed to and the largest it
reaches); rigid motions and pressure scalings keep it, new pressures drop it.  Grasp
analysis checks a reading against it before scaling a profile to that reading
(:func:`workbench.sources.jaws.with_axis_force`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from . import config
from ._row_kernels import (
    _column_ranges,
    _column_sums,
    _row_norms,
    _rows_minus,
    _rows_over,
    _weighted_column_sums,
)
from .units import check_extent, length_factor

__all__ = ["ContactProfile", "ProfileSource", "length_factor", "pca_box_longest_side"]


log = logging.getLogger(__name__)


def pca_box_longest_side(points: np.ndarray) -> float:
    """Longest side ``l_s`` of the PCA-aligned bounding box of points (m, 3) [m]
    (thesis §3.3.2, whose "smallest rectangular cuboid" the principal axes stand in for).

    Invariant under rigid motions, including where the principal axes are not
    unique.  Eigenvalues of the covariance equal within ``config.TOL.pca_degenerate_rtol``
    leave the box free to turn in their eigenspace, and an SVD picks whatever
    rounding selects (under rotation a square's ``l_s`` jumped between its side
    and its diagonal, up to +41 %, a 64-gon disc's by 1e-3).  Such sets are resolved by geometry:

    - two equal eigenvalues (a square or disc patch, any set with a 3-fold or
      higher symmetry axis): the box is turned in their plane to the smallest
      longest side over all turns — the thesis's smallest cuboid among the PCA
      frames — computed exactly on the plane's convex hull;
    - three equal eigenvalues (cube- or sphere-like point clouds, not contact
      patches): the set's diameter, the largest longest side over all frames, an
      upper bound (a cube's corners give its space diagonal, not its side).

    Distinct eigenvalues keep the SVD axes, bit for bit the value of the plain
    PCA box.  Under rigid motion ``l_s`` then changes by rounding only (~1e-15
    relative) except for spectra whose relative gap ``g`` lies just above the
    tolerance: the axes turn by ~1e-16/g rad there, so ``l_s`` moves by up to
    ~1e-8 relative for g ~ 1e-8 (and < 1e-12 once g > 1e-4).
    """
    return _longest_side(*_pca_box(points))


def _pca_box(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The points (m, 3) less their mean, their singular values (k,), principal axes (k, 3) and
    the sides (k,) of their box along those axes."""
    pts = np.ascontiguousarray(points, dtype=np.float64)
    # pts - pts.mean(axis=0), and the extent's max(0) - min(0), to the last bit
    centered = _rows_minus(pts, _column_sums(pts) / len(pts))
    _, s, axes = np.linalg.svd(centered, full_matrices=False)
    return centered, s, axes, _column_ranges(centered @ axes.T)


def _longest_side(centered: np.ndarray, s: np.ndarray, axes: np.ndarray, sides: np.ndarray) -> float:
    """:func:`pca_box_longest_side` from the points' :func:`_pca_box`."""
    lam = s**2
    if lam.size < 2 or lam[0] == 0:
        return float(sides.max())
    equal = np.abs(lam[1:] - lam[:-1]) <= config.TOL.pca_degenerate_rtol * lam[0]  # np.diff
    if not equal.any():
        return float(sides.max())
    if equal.all() and lam.size == 3:
        return _diameter(centered, fallback=float(sides.max()))
    i = 0 if equal[0] else 1  # the equal pair (i, i + 1); the third axis is well defined
    rest = [float(sides[k]) for k in range(lam.size) if k not in (i, i + 1)]
    turned = _min_longest_side_2d(centered @ axes[i : i + 2].T, fallback=float(sides[i : i + 2].max()))
    return max([turned, *rest])


def _min_longest_side_2d(q: np.ndarray, fallback: float) -> float:
    """min over θ of max(w(θ), w(θ + π/2)) for points q (m, 2), w the width along u(θ).

    Between consecutive hull-edge directions (mod π/2) each width is a fixed
    antipodal pair's projection, a concave sinusoid, so the minimum of the larger
    one lies at an edge direction or where the two widths cross; both kinds of
    candidate angle are evaluated exactly."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        v = q[ConvexHull(q).vertices]
    except (QhullError, ValueError):  # collinear or coincident: widths at rounding level
        return fallback
    edges = np.roll(v, -1, axis=0) - v
    lo = np.unique(np.mod(np.arctan2(edges[:, 1], edges[:, 0]), np.pi / 2))
    hi = np.append(lo[1:], lo[0] + np.pi / 2)
    mid = 0.5 * (lo + hi)
    u, up = _directions(mid)
    pu, pp = v @ u.T, v @ up.T  # (k, t) projections on u(θ), u(θ + π/2)
    p1 = v[pu.argmax(axis=0)] - v[pu.argmin(axis=0)]  # w1(θ) = p1 · u(θ) on the interval
    p2 = v[pp.argmax(axis=0)] - v[pp.argmin(axis=0)]  # w2(θ) = p2 · u(θ + π/2) = q2 · u(θ)
    d = p1 - np.column_stack([p2[:, 1], -p2[:, 0]])
    cross = np.arctan2(d[:, 1], d[:, 0]) + np.pi / 2  # d · u(θ) = 0
    cross = lo + np.mod(cross - lo, np.pi)
    inside = cross <= hi
    theta = np.concatenate([lo, cross[inside]])
    best = np.inf
    step = max(1, 2_000_000 // len(v))
    for j in range(0, theta.size, step):
        u, up = _directions(theta[j : j + step])
        pu, pp = v @ u.T, v @ up.T
        g = np.maximum(pu.max(axis=0) - pu.min(axis=0), pp.max(axis=0) - pp.min(axis=0))
        best = min(best, float(g.min()))
    return best


def _directions(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors u(θ) and u(θ + π/2), each (t, 2)."""
    c, s = np.cos(theta), np.sin(theta)
    return np.column_stack([c, s]), np.column_stack([-s, c])


def _diameter(points: np.ndarray, fallback: float) -> float:
    """Largest distance between two of points (m, 3), over their convex hull's vertices."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        v = points[ConvexHull(points).vertices]
    except (QhullError, ValueError):
        return fallback
    best = 0.0
    step = max(1, 2_000_000 // len(v))
    for j in range(0, len(v), step):
        d = np.linalg.norm(v[j : j + step, None, :] - v[None, :, :], axis=2)
        best = max(best, float(d.max()))
    return best


@dataclass(frozen=True)
class ProfileSource:
    """Where a profile's pressure distribution comes from and the readings it holds for.

    name : the source, e.g. ``"fem_pad"``.
    force : the jaw's reading [N] (normal force along its approach) the source made the
        distribution at.
    force_range : ``(lo, hi)`` [N], the readings the source can produce for this contact
        (the FEM pad: ``(0, what the layer reaches before the object meets its rigid back)``);
        a reading outside it is refused when the profile is scaled to it.
    linear : whether the distribution is the same at every reading (pressures proportional to
        the force, as REACH's Winkler pad at a fixed closing); False (the FEM pad: the contact
        grows with force) warns when the profile is scaled far from ``force``
        (``config.TOL.profile_force_ratio_warn``).
    """

    name: str
    force: float
    force_range: tuple[float, float] = (0.0, float("inf"))
    linear: bool = False

    def __post_init__(self) -> None:
        lo, hi = (float(v) for v in self.force_range)
        if not (np.isfinite(self.force) and self.force > 0 and 0 <= lo <= self.force <= hi):
            raise ValueError(
                f"ProfileSource {self.name!r}: force must be a reading > 0 [N] within force_range "
                f"(lo, hi) with 0 <= lo <= hi; got force {self.force!r}, force_range {self.force_range!r}"
            )
        object.__setattr__(self, "force", float(self.force))
        object.__setattr__(self, "force_range", (lo, hi))


def _as_float_array(name: str, value: Any, shape_tail: tuple[int, ...]) -> np.ndarray:
    if np.asarray(value).dtype == np.bool_:  # True is not 1 Pa or 1 m: a mask passed by mistake
        raise ValueError(f"{name} must be a numeric array; got booleans (a mask?) — pass the values")
    try:
        arr = np.array(value, dtype=np.float64, order="C")  # copy: profiles own their data
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a numeric array; got {type(value).__name__} ({exc})") from None
    expected_ndim = 1 + len(shape_tail)
    if arr.ndim != expected_ndim or arr.shape[1:] != shape_tail:
        want = "(n" + "".join(f", {d}" for d in shape_tail) + ")"
        raise ValueError(f"{name} must have shape {want}; got {arr.shape}")
    bad = ~np.isfinite(arr)
    if bad.any():
        idx = int(np.argwhere(bad)[0][0])
        raise ValueError(
            f"{name} must be finite; got {int(bad.sum())} NaN/inf values (first at element {idx}) "
            "— fix or drop those elements before building the profile"
        )
    return arr


def _check_lengths(
    centers: np.ndarray, normals: np.ndarray, areas: np.ndarray, pressures: np.ndarray
) -> None:
    """ValueError unless the profile has elements and every per-element array one per centre."""
    n = centers.shape[0]
    if n == 0:
        raise ValueError(
            "profile is empty: centers has 0 elements — a contact needs at least one element "
            "(check that the obstacle touches the pad)"
        )
    for name, arr in (("normals", normals), ("areas", areas), ("pressures", pressures)):
        if arr.shape[0] != n:
            raise ValueError(
                f"{name} has {arr.shape[0]} elements but centers has {n}; "
                "every per-element array must have the same length"
            )


def _check_areas(areas: np.ndarray) -> None:
    """ValueError unless the element areas (n,) are > 0 and none degenerate against their median."""
    if (areas <= 0).any():
        i = int(np.argmin(areas))
        raise ValueError(
            f"areas must be > 0; got {areas[i]:.3g} at element {i} "
            f"({int((areas <= 0).sum())} non-positive) — drop degenerate elements "
            "(from_mesh(..., drop_degenerate=True))"
        )
    rtol = config.TOL.degenerate_area_rtol
    # every area above rtol x the largest is above rtol x the median (at most the largest):
    # then no partition is needed to find the median
    if areas.min() > rtol * areas.max():
        return
    median_area = float(np.median(areas))
    tiny = areas <= rtol * median_area
    if tiny.any():
        i = int(np.argmax(tiny))
        raise ValueError(
            f"areas: element {i} is degenerate (area {areas[i]:.3g} <= "
            f"{rtol:g} x median {median_area:.3g}) — drop it "
            "(from_mesh(..., drop_degenerate=True))"
        )


def _check_pressures(pressures: np.ndarray) -> None:
    """ValueError unless the pressures (n,) are >= 0 and not all zero."""
    if (pressures < 0).any():
        i = int(np.argmin(pressures))
        raise ValueError(
            f"pressures must be >= 0; got min {pressures[i]:.6g} at element {i} — clip or fix the FEM export"
        )
    if not (pressures > 0).any():
        raise ValueError(
            "pressures are all zero: the profile transmits no force and has no pressure center "
            "— pass the contact pressures (or a uniform pressure, e.g. np.ones(n))"
        )


def _unit_normals(normals: np.ndarray, normalize_normals: bool) -> np.ndarray:
    """The normals (n, 3) divided by their lengths: ValueError for a zero one, or one off unit
    length by more than ``config.TOL.normal_unit_atol`` unless ``normalize_normals``."""
    lengths = _row_norms(normals)  # np.linalg.norm(normals, axis=1) to the last bit
    if (lengths == 0).any():
        i = int(np.argmin(lengths))
        raise ValueError(f"normals must be non-zero unit vectors; element {i} has a zero normal")
    off = np.abs(lengths - 1.0) > config.TOL.normal_unit_atol
    if off.any() and not normalize_normals:
        i = int(np.argmax(np.abs(lengths - 1.0)))
        raise ValueError(
            f"normals must be unit vectors; element {i} has length {lengths[i]:.6g} "
            f"({int(off.sum())} off by > {config.TOL.normal_unit_atol:g}) "
            "— pass normalize_normals=True to rescale them"
        )
    return _rows_over(normals, lengths)


#: what a profile's geometry is: its arrays and what is derived from them alone
_GEOMETRY = ("centers", "normals", "areas", "vertices", "faces", "allow_scale", "length_scale")


class ContactProfile:
    """Contact surface elements with pressures (thesis §3.2.4).

    Parameters
    ----------
    centers : (n, 3) float
        Element centers ``c_i`` [m].
    normals : (n, 3) float
        Unit normals ``n_i``, outward from the object (into the jaw).
    areas : (n,) float
        Element areas ``a_i`` [m²], all > 0.
    pressures : (n,) float
        Pressures ``p_i`` [Pa], all >= 0 and not all zero.
    vertices : (m, 3) float, optional
        Mesh vertices (for plotting/export); ``faces`` : (n, k) int, optional.
    source : ProfileSource, optional
        Provenance of the pressures (the reading they were made at and the readings the
        source holds for); None: unknown, nothing is checked.
    normalize_normals : bool
        Rescale non-unit normals instead of rejecting them.
    allow_scale : bool
        Accept a profile longer than ``config.TOL.max_object_extent_m`` (2 m).  Without
        it such a profile raises ``ValueError``: it is almost surely in
        millimetres (build it with ``from_mesh(..., units="mm")``).  Only this
        upper bound is checked: real contacts can be tiny (an FEM contact at
        δ = 0.1 mm on a 20 mm sphere is ~2 mm wide, a Hertz patch less, one
        element has zero extent), so no lower bound tells a unit mistake from a
        small patch.  A millimetre profile smaller than 2 mm is not caught either.

    Areas: a total area beyond ``config.TOL.profile_area_box_ratio`` times the surface of the
    box the centres span is refused (areas in mm² beside centres in m); a single element or a
    single row of centres is not judged.

    Normals: elements carrying more than ``config.TOL.flipped_normal_force_fraction``
    of ``F`` with normals pointing away from the force-weighted mean normal
    (``n_i · n̄ < 0``), or normal forces that cancel, warn (``ImplausibleWarning``) — the
    mark of a mesh with part of its faces wound the other way.  What cannot be seen here:
    a profile whose normals are *all* flipped (into the object) is a consistent surface that only the object
    could contradict, indistinguishable from a contact on the other side of a
    thin shell; the grasp layer checks that each jaw pushes rather than pulls.
    A contact genuinely wrapping more than about ±100° around the object also
    triggers the warning.
    """

    def __init__(  # noqa: PLR0913 - the four element arrays, then keyword-only metadata
        self,
        centers: Any,
        normals: Any,
        areas: Any,
        pressures: Any,
        *,
        vertices: Any = None,
        faces: Any = None,
        normalize_normals: bool = False,
        allow_scale: bool = False,
        source: ProfileSource | None = None,
    ) -> None:
        if source is not None and not isinstance(source, ProfileSource):
            raise ValueError(f"source must be a ProfileSource or None; got {type(source).__name__}")
        centers = _as_float_array("centers", centers, (3,))
        normals = _as_float_array("normals", normals, (3,))
        areas = _as_float_array("areas", areas, ())
        pressures = _as_float_array("pressures", pressures, ())
        _check_lengths(centers, normals, areas, pressures)
        _check_areas(areas)
        _check_pressures(pressures)
        normals = _unit_normals(normals, normalize_normals)

        self.centers = centers
        self.normals = normals
        self.areas = areas
        self.pressures = pressures
        self.vertices = None if vertices is None else _as_float_array("vertices", vertices, (3,))
        self.faces = None if faces is None else np.asarray(faces, dtype=np.int64)
        for arr in (self.centers, self.normals, self.areas, self.pressures):
            arr.flags.writeable = False  # cached properties depend on them
        self.allow_scale = bool(allow_scale)
        self.source = source
        box = _pca_box(centers)  # l_s and the area check share it
        if self.vertices is None:
            self.__dict__["length_scale"] = self._length_scale(box)
        check_extent(
            self.length_scale,
            "ContactProfile (l_s, the longest side of its PCA box)",
            allow_scale=self.allow_scale,
            check_lower=False,
            fix="build it with ContactProfile.from_mesh(..., units={units!r}), or scale centers and "
            "vertices by {factor:g} and areas by {area_factor:g}",
        )
        self._check_area_fits_extent(box[3])
        self._warn_flipped_normals()

    def _check_area_fits_extent(self, pca_sides: np.ndarray) -> None:
        """Refuse a total area far beyond what the centres' extent allows (areas in mm² beside
        centres in m): ``Σ a_i`` above ``config.TOL.profile_area_box_ratio`` times the surface
        area of the box the centres span.

        The box is the centres' PCA box, each side grown by their mean spacing ``h`` (an element
        reaches past its centre), where ``h`` is the cell of ``n`` centres tiling the two longest
        sides ``s1 >= s2``: ``(s1 + h)(s2 + h) = n h²`` (exact for a grid, ``s1/(n-1)`` for a
        strip) — from the centres alone, as the areas are what is judged.  A patch of a convex
        surface is part of the boundary of its convex hull, which lies in the box: its area is at
        most the box's surface (a flat patch about half of it).  One element, centres at one point
        and centres in one row (less than a spacing across: how wide its elements reach across
        the row the centres do not say) have no extent to judge by.  ``pca_sides`` (k,): the
        sides of the centres' PCA box (:func:`_pca_box`)."""
        n = len(self)
        sides = np.sort(pca_sides)[::-1]
        sides = np.concatenate([sides, np.zeros(3 - sides.size)])
        if n < 2 or not sides[0] > 0:
            return
        s1, s2 = float(sides[0]), float(sides[1])
        h = ((s1 + s2) + np.sqrt((s1 + s2) ** 2 + 4 * (n - 1) * s1 * s2)) / (2 * (n - 1))
        if s2 < h:
            return
        a, b, d = sides + h
        box = 2 * (a * b + b * d + a * d)
        total = float(self.areas.sum())
        ratio = config.TOL.profile_area_box_ratio
        if total <= ratio * box:
            return
        # the area unit that puts the patch nearest a tiling (half the box's surface)
        units = (("mm²", 1e-6), ("cm²", 1e-4))
        name, k = min(units, key=lambda u: abs(np.log(total * u[1] / (0.5 * box))))
        hint = (
            f"areas in {name} beside centres in metres? pass areas x {k:g} (a 1 {name} element is "
            f"{k:g} m²), or build it with ContactProfile.from_mesh(vertices, faces, pressures, units=...)"
            if total * k <= ratio * box
            else "check how the areas were computed (one element's area, in m², each)"
        )
        raise ValueError(
            f"areas: the {n} elements' total area {total:.4g} m² is {total / box:.3g} x the surface "
            f"area {box:.4g} m² of the box their centres span ({s1 * 1e3:.4g} x {s2 * 1e3:.4g} x "
            f"{sides[2] * 1e3:.4g} mm, each side grown by their spacing {h * 1e3:.3g} mm), more than "
            f"config.TOL.profile_area_box_ratio = {ratio:g}: a contact patch has at most about its "
            f"box's surface area (a patch of a convex surface at most exactly that) — {hint}"
        )

    def _warn_flipped_normals(self) -> None:
        """Warn (:class:`~workbench.plausible.ImplausibleWarning`) if normals disagreeing with
        the force-weighted mean normal carry more than ``config.TOL.flipped_normal_force_fraction``
        of ``F``, or if the normal forces cancel (``|Σ f_i n_i|`` at round-off of ``F``: equal
        faces wound both ways, so no direction is "the" mean normal)."""
        import warnings

        from .plausible import ImplausibleWarning

        mean = _weighted_column_sums(self.forces, self.normals)
        norm = float(np.linalg.norm(mean))
        fix = "fix the winding (trimesh.repair.fix_normals) or pass the normals outward from the object"
        if norm <= 64 * np.finfo(float).eps * self.F:  # zero up to summation round-off
            warnings.warn(
                f"ContactProfile: the normal forces cancel (|Σ p_i a_i n_i| = {norm:.3g} N for "
                f"F = Σ p_i a_i = {self.F:.4g} N): the faces are wound both ways, or the contact wraps "
                f"all round the object — {fix}",
                ImplausibleWarning,
                stacklevel=3,
            )
            return
        against = self.normals @ (mean / norm) < 0
        fraction = float(self.forces[against].sum()) / self.F
        if fraction > config.TOL.flipped_normal_force_fraction:
            warnings.warn(
                f"ContactProfile: {int(against.sum())} of {len(self)} elements, carrying "
                f"{100 * fraction:.0f}% of the force, have normals pointing away from the force-weighted "
                "mean normal (n_i . n_mean < 0): part of the mesh is probably wound the other way — "
                f"{fix}; ignore this only if the contact wraps more than ~±100° around it",
                ImplausibleWarning,
                stacklevel=3,
            )

    # ------------------------------------------------------------------ basics
    def __len__(self) -> int:
        return self.centers.shape[0]

    def __repr__(self) -> str:
        return (
            f"ContactProfile(n={len(self)}, F={self.F:.6g} N, "
            f"o={np.array2string(self.pressure_center, precision=4)})"
        )

    @cached_property
    def forces(self) -> np.ndarray:
        """(n,) float: local normal force magnitudes ``p_i a_i`` [N]."""
        return self.pressures * self.areas

    @cached_property
    def F(self) -> float:  # noqa: N802 (thesis symbol)
        """Sum magnitude of local normal forces ``F = Σ p_i a_i`` [N] (§3.2.2)."""
        return float(self.forces.sum())

    @cached_property
    def pressure_center(self) -> np.ndarray:
        """(3,) float: pressure center ``o``, Eq. 3.7."""
        o = _weighted_column_sums(self.forces, self.centers) / self.F  # (f[:, None] * c).sum(0) / F
        o.flags.writeable = False
        return o

    @cached_property
    def normalized_pressures(self) -> np.ndarray:
        """(n,) float: ``p̂ = p / F`` so that ``Σ p̂ a = 1`` [1/m²] (§3.2.2)."""
        return self.pressures / self.F

    @cached_property
    def normal_wrench(self) -> np.ndarray:
        """(6,) float: normal wrench ``w⊥`` about ``o``, Eq. 3.2 (the kernel of
        :func:`workbench.wrench.normal_wrench`, called here so that this module, which the
        wrench module builds on, does not import it)."""
        from . import _kernels

        out = np.empty(6)
        _kernels._normal_wrench(*self._soa, out)
        return out

    @cached_property
    def length_scale(self) -> float:
        """Longest side ``l_s`` of the PCA-aligned bounding box [m] (§3.3.2).

        The box is aligned with the principal axes of the vertices (centers
        if no mesh), so ``l_s`` is invariant under rigid motions.
        """
        return self._length_scale(_pca_box(self.vertices if self.vertices is not None else self.centers))

    def _length_scale(self, box: tuple) -> float:
        """:attr:`length_scale` from the PCA box (:func:`_pca_box`) of the vertices, or centres."""
        side = _longest_side(*box) if box[0].shape[0] >= 2 else 0.0
        return side if side > 0 else float(np.sqrt(self.areas.sum()))

    @cached_property
    def _soa(self) -> tuple[np.ndarray, ...]:
        """Kernel layout: contiguous ``rx, ry, rz, nx, ny, nz, wgt`` (r = c - o)."""
        r = _rows_minus(self.centers, self.pressure_center)
        cols = [np.ascontiguousarray(r[:, j]) for j in range(3)]
        cols += [np.ascontiguousarray(self.normals[:, j]) for j in range(3)]
        cols.append(np.ascontiguousarray(self.forces))
        return tuple(cols)

    # ------------------------------------------------------------- derivations
    def with_pressures(self, pressures: Any, *, source: ProfileSource | None = None) -> ContactProfile:
        """Same geometry with new per-element pressures (n,): a new distribution, so the
        ``source`` of this one does not carry over (pass the new one's, or use :meth:`scaled`
        for the same distribution at another force)."""
        if source is not None and not isinstance(source, ProfileSource):
            raise ValueError(f"source must be a ProfileSource or None; got {type(source).__name__}")
        pressures = _as_float_array("pressures", pressures, ())
        _check_lengths(self.centers, self.normals, self.areas, pressures)
        _check_pressures(pressures)
        # the geometry's checks (__init__) passed on these very arrays, read-only since, and
        # none of them reads the pressures: only those are checked anew
        new = object.__new__(type(self))
        new.__dict__.update({k: self.__dict__[k] for k in _GEOMETRY if k in self.__dict__})
        # the normals divided by their lengths once more, as every new profile's are (the last
        # bits of a third of unit vectors move): the same numbers as a profile made afresh
        new.normals = _unit_normals(self.normals, False)
        new.normals.flags.writeable = False
        pressures.flags.writeable = False
        new.pressures = pressures
        new.source = source
        new._warn_flipped_normals()
        return new

    def scaled(self, factor: float) -> ContactProfile:
        """The same distribution at ``factor`` (> 0) times the force: every pressure times
        ``factor``, the ``source`` kept (it says which readings the distribution holds for)."""
        factor = float(factor)
        if not (np.isfinite(factor) and factor > 0):
            raise ValueError(f"factor must be a finite number > 0; got {factor}")
        return self.with_pressures(self.pressures * factor, source=self.source)

    def with_source(self, source: ProfileSource | None) -> ContactProfile:
        """The same profile with provenance ``source`` (a profile source attaches it)."""
        return self.with_pressures(self.pressures, source=source)

    def normalized(self) -> ContactProfile:
        """Same geometry with ``p̂`` so that ``F = 1`` (a limit-surface "profile pair")."""
        return self.with_pressures(self.normalized_pressures, source=self.source)

    def transformed(self, rotation: Any = None, translation: Any = None) -> ContactProfile:
        """Rigidly moved copy: ``x' = R x + t``, ``n' = R n``.

        rotation : (3, 3) float, proper orthogonal; translation : (3,) float [m], at most
        ``config.TOL.max_object_extent_m`` long unless the profile allows any scale.
        """
        R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=np.float64)
        t = np.zeros(3) if translation is None else np.asarray(translation, dtype=np.float64)
        if R.shape != (3, 3):
            raise ValueError(f"rotation must be a (3, 3) orthogonal matrix; got shape {R.shape}")
        if not np.isfinite(R).all():
            raise ValueError(
                f"rotation must be a (3, 3) orthogonal matrix of finite numbers; got {R.tolist()}"
            )
        gram = R @ R.T
        # a float64 rotation is orthogonal to ~1e-15; 1e-9 admits one composed or read from text
        if not np.allclose(gram, np.eye(3), atol=1e-9):
            # say what is wrong: a rotation times a factor s (R Rᵀ = s² I) has a fix, others not
            head = (
                "rotation must be orthogonal (R Rᵀ = I); got R Rᵀ differing from I by up to "
                f"{np.abs(gram - np.eye(3)).max():.3g}"
            )
            s2 = float(np.trace(gram)) / 3.0
            if s2 > 0 and np.allclose(gram / s2, np.eye(3), atol=1e-9):
                raise ValueError(
                    f"{head}: a rotation scaled by {np.sqrt(s2):.6g}? pass rotation / {np.sqrt(s2):.6g} "
                    "(a profile moves rigidly)"
                )
            raise ValueError(
                f"{head}: not a rotation — build it with scipy.spatial.transform.Rotation (e.g. "
                "Rotation.from_euler('z', 30, degrees=True).as_matrix()) or orthonormalise it"
            )
        if np.linalg.det(R) < 0:
            raise ValueError("rotation must be proper (det = +1); a reflection flips the normals' side")
        if t.shape != (3,) or not np.isfinite(t).all():
            raise ValueError(f"translation must be (3,) finite numbers [m]; got {translation!r}")
        limit = config.TOL.max_object_extent_m
        if not self.allow_scale and np.linalg.norm(t) > limit:
            # a move farther than any object is large: a translation in millimetres
            raise ValueError(
                f"translation {t.tolist()} moves the profile {np.linalg.norm(t):.4g} m, more than "
                f"TOL.max_object_extent_m = {limit:g} m: it is probably in millimetres — pass "
                f"{(t * 1e-3).tolist()} [m] (or build the profile with allow_scale=True)"
            )
        verts = None if self.vertices is None else self.vertices @ R.T + t
        return ContactProfile(
            self.centers @ R.T + t,
            self.normals @ R.T,
            self.areas,
            self.pressures,
            vertices=verts,
            faces=self.faces,
            normalize_normals=True,
            allow_scale=self.allow_scale,
            source=self.source,
        )

    def in_contact_frame(self, rotation: Any = None) -> ContactProfile:
        """The profile in the contact frame C: origin at ``o``, axes ``R`` (§3.2.1).

        ``x_C = R (x_O - o)``; with ``rotation=None`` the axes stay parallel to O.
        """
        R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=np.float64)
        return self.transformed(R, -R @ self.pressure_center)

    # ------------------------------------------------------------ constructors
    @classmethod
    def from_mesh(
        cls,
        vertices: Any,
        faces: Any,
        pressures: Any,
        *,
        units: str | float = "m",
        flip_normals: bool = False,
        drop_degenerate: bool = False,
        allow_scale: bool = False,
    ) -> ContactProfile:
        """Profile from a triangle ``(m, 3)`` or quad ``(m, 4)`` mesh.

        Normals follow the face winding (right-hand rule) and must point out of
        the object; pass ``flip_normals=True`` if the mesh is wound the other way.
        Quads may be warped: their normal and area come from the vector area
        ``½ d1 × d2`` of the diagonals, their center is the vertex mean.

        vertices : (v, 3) float in ``units``; faces : (m, 3|4) int;
        pressures : (m,) float [Pa], or a scalar for uniform pressure;
        allow_scale : accept a profile longer than 2 m (see the class docstring).
        """
        scale = length_factor(units)
        verts = _as_float_array("vertices", vertices, (3,)) * scale
        f = np.asarray(faces)
        if f.ndim != 2 or f.shape[1] not in (3, 4) or not np.issubdtype(f.dtype, np.integer):
            raise ValueError(
                f"faces must be an integer array of shape (m, 3) or (m, 4); got {f.shape} {f.dtype}"
            )
        if f.size and (f.min() < 0 or f.max() >= verts.shape[0]):
            raise ValueError(
                f"faces index vertices 0..{verts.shape[0] - 1}; got indices {f.min()}..{f.max()}"
            )
        corners = verts[f]
        if f.shape[1] == 3:
            vec = 0.5 * np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
            centers = corners.mean(axis=1)
        else:
            vec = 0.5 * np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1])
            centers = corners.mean(axis=1)
        areas = np.linalg.norm(vec, axis=1)
        p = np.asarray(pressures, dtype=np.float64)
        if p.shape not in ((), (f.shape[0],)):
            raise ValueError(
                f"pressures must be one value per face, shape ({f.shape[0]},) for the {f.shape[0]} faces, or "
                f"a scalar for uniform pressure [Pa]; got shape {p.shape}. Per-vertex values: average them "
                "over each face's corners, e.g. p_vertex[faces].mean(axis=1)"
            )
        p = np.broadcast_to(p, (f.shape[0],)).copy()
        if drop_degenerate and areas.size:
            keep = areas > config.TOL.degenerate_area_rtol * np.median(areas)
            f, vec, areas, centers, p = f[keep], vec[keep], areas[keep], centers[keep], p[keep]
        safe = np.where(areas > 0, areas, 1.0)
        normals = vec / safe[:, None]
        if flip_normals:
            normals = -normals
            f = f[:, ::-1]
        return cls(centers, normals, areas, p, vertices=verts, faces=f, allow_scale=allow_scale)

    @classmethod
    def from_meshio(cls, mesh: Any, pressure: str | Any = "pressure", **kwargs: Any) -> ContactProfile:
        """Profile from a ``meshio.Mesh`` with triangle/quad cells.

        ``pressure`` names a cell-data field (one array per cell block) or is an
        array over all triangle/quad cells in block order.  ``kwargs`` go to
        :meth:`from_mesh` (``units``, ``flip_normals``, ``drop_degenerate``).  Cell data
        ``normals`` and ``areas`` (as :meth:`to_meshio` writes them) replace the ones
        derived from the cells, so a written profile reads back with its own ``F``.
        """
        blocks = [(i, c) for i, c in enumerate(mesh.cells) if c.type in ("triangle", "quad")]
        if not blocks:
            types = sorted({c.type for c in mesh.cells})
            raise ValueError(f"mesh has no triangle or quad cells (found {types}); extract the surface first")
        types = {c.type for _, c in blocks}
        if len(types) > 1:
            raise ValueError("mixed triangle and quad blocks: split them, or triangulate the quads first")
        faces = np.concatenate([c.data for _, c in blocks])
        if isinstance(pressure, str):
            if pressure not in mesh.cell_data:
                raise ValueError(
                    f"cell data {pressure!r} not in mesh (has {sorted(mesh.cell_data)}); "
                    "pass pressure=<field name> or an array"
                )
            p = np.concatenate([np.asarray(mesh.cell_data[pressure][i]).reshape(-1) for i, _ in blocks])
        else:
            p = pressure
        prof = cls.from_mesh(mesh.points[:, :3], faces, p, **kwargs)
        # the element normals and areas written by to_meshio are the profile's own (an FEM
        # profile's areas are not the quads' geometric ones): use them when every cell survived
        if all(k in mesh.cell_data for k in ("normals", "areas")) and len(prof) == len(faces):
            nrm = np.concatenate([np.asarray(mesh.cell_data["normals"][i]).reshape(-1, 3) for i, _ in blocks])
            area = np.concatenate([np.asarray(mesh.cell_data["areas"][i]).reshape(-1) for i, _ in blocks])
            scale = length_factor(kwargs.get("units", "m"))
            sign = -1.0 if kwargs.get("flip_normals", False) else 1.0
            prof = cls(
                prof.centers,
                sign * nrm,
                area * scale**2,
                prof.pressures,
                vertices=prof.vertices,
                faces=prof.faces,
                allow_scale=kwargs.get("allow_scale", False),
            )
        return prof

    @classmethod
    def from_trimesh(cls, mesh: Any, pressures: Any, **kwargs: Any) -> ContactProfile:
        """Profile from a ``trimesh.Trimesh`` (face winding gives the normals)."""
        return cls.from_mesh(np.asarray(mesh.vertices), np.asarray(mesh.faces), pressures, **kwargs)

    def to_meshio(self) -> Any:
        """``meshio.Mesh`` (needs vertices/faces) with cell data ``"pressure"`` (n,) [Pa],
        ``"normals"`` (n, 3) (the profile's unit normals, outward from the object) and
        ``"areas"`` (n,) [m²] — the element values themselves, which for FEM profiles
        differ slightly from what the exported faces' winding and size would give."""
        import meshio

        if self.vertices is None or self.faces is None:
            raise ValueError(
                "profile has no mesh (vertices/faces) to export; build it with from_mesh / "
                "from_meshio, or pass vertices= and faces= to ContactProfile"
            )
        kind = "triangle" if self.faces.shape[1] == 3 else "quad"
        cell_data = {
            "pressure": [np.array(self.pressures)],
            "normals": [np.array(self.normals)],
            "areas": [np.array(self.areas)],
        }
        return meshio.Mesh(self.vertices, [(kind, self.faces)], cell_data=cell_data)

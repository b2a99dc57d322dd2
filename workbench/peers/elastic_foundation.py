"""Elastic-foundation (Winkler) soft finger, as in GraspIt! (Ciocarlie, Lackner & Allen, "Soft finger
model with adaptive contact geometry for grasping and manipulation tasks", World Haptics 2007).

The pad is a bed of independent springs: a layer of thickness ``h`` over a rigid back, whose
pressure is proportional to the local penetration ``u`` (Johnson, *Contact Mechanics*, 1985, §4.3):
``p = k u`` with the foundation modulus ``k`` [Pa/m] of :func:`foundation_modulus`:

- ``kind="simple"`` (default, GraspIt!'s and Johnson's plain Winkler layer): ``k = E / h`` — the
  layer compressed uniaxially with free lateral expansion;
- ``kind="confined"``: ``k = (1 - ν) E / ((1 + ν)(1 - 2ν) h)`` — the oedometric modulus, lateral
  strain suppressed (Johnson §4.3's thin bonded layer).  It diverges as ``ν → 0.5``, which is the
  Winkler model's known failure for nearly incompressible thin layers: the confined value is an
  upper bound, the simple one a lower bound for a bonded pad.

Sphere of radius ``R`` at depth ``δ`` (a rigid sphere, pad face flat), penetration along the pad
normal ``u(r) = δ - R + √(R² - r²)`` for ``r <= r0 = √(2Rδ - δ²)``:

- area = the geometric overlap ``π r0² = π (2Rδ - δ²)`` (no sink-in, unlike Hertz);
- force ``F = k ∫ u dA = k V``, ``V = π δ² (3R - δ) / 3`` the cap volume;
- torsion/normal-force ratio ``τ_max / (μ F) = ∫ u r dA / ∫ u dA``: for an elliptic patch of a
  paraboloid indentation Ciocarlie et al. give ``8 √(ab) / 15``; for a circle (``a = b``) it is
  exactly ``8a/15`` (``u = δ(1 - r²/a²)``: ``∫ u r dA = 4π δ a³ / 15``, ``∫ u dA = π δ a² / 2``).  For
  an ellipse the exact paraboloid value is ``(16 / 15π) a E(1 - b²/a²)`` (``E`` the complete
  elliptic integral of the second kind), of which ``√(ab)`` approximates the mean radius
  (:func:`torsion_ratio_ellipse`); for the sphere cap itself :func:`sphere_torsion_ratio`.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import peers as _checks
from ..profile import ContactProfile

__all__ = [
    "PadGrid",
    "foundation_force",
    "foundation_modulus",
    "foundation_profile",
    "overlap_area",
    "sphere_torsion_ratio",
    "torsion_ratio_ellipse",
    "vertical_depth",
]

log = logging.getLogger(__name__)

KINDS = ("simple", "confined")


def foundation_modulus(E: float, h: float, nu: float | None = None, kind: str = "simple") -> float:
    """Foundation modulus ``k`` [Pa/m] of a layer of Young's modulus ``E`` [Pa] and thickness
    ``h`` [m]: ``E/h`` (``kind="simple"``) or ``(1-ν)E/((1+ν)(1-2ν)h)`` (``"confined"``, needs ``nu``)."""
    e = _checks.modulus("E (Young's modulus)", E)
    t = _checks.length("h (layer thickness)", h, "pad_thickness")
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}; got {kind!r}")
    if kind == "simple":
        return e / t
    if nu is None:
        raise ValueError("kind='confined' needs the Poisson ratio: pass nu=... (e.g. 0.45)")
    n = _checks.poisson("nu (Poisson ratio)", nu)
    return (1.0 - n) * e / ((1.0 + n) * (1.0 - 2.0 * n) * t)


def _sphere_case(R: float, delta: float) -> tuple[float, float]:
    return _checks.sphere(R, delta, "delta (penetration)")


def overlap_area(R: float, delta: float) -> float:
    """Geometric overlap area ``π (2Rδ - δ²)`` [m²] of a sphere ``R`` [m] at depth ``δ`` [m]."""
    r, d = _sphere_case(R, delta)
    return np.pi * (2.0 * r * d - d * d)


def foundation_force(
    R: float, delta: float, E: float, h: float, nu: float | None = None, kind: str = "simple"
) -> float:
    """Winkler force ``k V`` [N], ``V = π δ² (3R - δ) / 3`` the overlapped cap's volume [m³].
    ``delta`` must stay within the layer (``< h``, as :func:`foundation_profile` requires)."""
    _checks.length("R (sphere radius)", R)
    t = _checks.length("h (layer thickness)", h, "pad_thickness")
    d = _checks.real("delta (penetration)", delta, "m")
    if d >= t:  # before the depth's own checks: through the layer is refused, not warned as deep
        raise ValueError(
            f"delta = {d!r} m reaches through the layer of h = {t!r} m: a Winkler layer holds only "
            "depths below its thickness (delta < h; depths are in metres, 1 mm = 1e-3)"
        )
    r, d = _sphere_case(R, delta)
    k = foundation_modulus(E, h, nu, kind)
    return k * np.pi * d * d * (3.0 * r - d) / 3.0


def sphere_torsion_ratio(R: float, delta: float) -> float:
    """Exact ``τ_max / (μ F) = ∫ u r dA / ∫ u dA`` [m] of a sphere cap on a Winkler foundation.

    With ``s = r0/R``: ``∫ u r² dr = (δ - R) r0³/3 + R⁴ G(s)``, ``G(s) = (asin s - s√(1-s²)(1-2s²))/8``
    (``∫ t²√(1-t²) dt``), and ``∫ u r dr = δ² (3R - δ) / 6``.  Tends to ``8 r0 / 15`` as ``δ/R → 0``.
    """
    r, d = _sphere_case(R, delta)
    r0 = np.sqrt(2.0 * r * d - d * d)
    s = r0 / r
    c = np.sqrt(1.0 - s * s)
    g = (np.arcsin(s) - s * c * (1.0 - 2.0 * s * s)) / 8.0
    num = (d - r) * r0**3 / 3.0 + r**4 * g
    den = d * d * (3.0 * r - d) / 6.0
    return float(num / den)


def torsion_ratio_ellipse(a: float, b: float, exact: bool = False) -> float:
    """``τ_max / (μ F)`` [m] of an elliptic patch (semi-axes ``a``, ``b`` [m]) under a paraboloid
    Winkler pressure: Ciocarlie et al.'s ``8 √(ab) / 15``, or with ``exact=True`` the exact
    ``(16 / 15π) a' E(1 - b'²/a'²)`` (``a' >= b'``), equal for ``a = b``."""
    x = _checks.length("a (semi-axis)", a)
    y = _checks.length("b (semi-axis)", b)
    if not exact:
        return 8.0 * np.sqrt(x * y) / 15.0
    from scipy.special import ellipe

    hi, lo = max(x, y), min(x, y)
    return float(16.0 * hi * ellipe(1.0 - (lo / hi) ** 2) / (15.0 * np.pi))


def vertical_depth(
    obstacle: Any, points: np.ndarray, *, tol: float = 1e-12, max_iter: int = 200
) -> np.ndarray:
    """Depth [m] of ``points`` (m, 3) inside ``obstacle`` measured along ``-z`` (the distance down
    to the obstacle's surface), zero outside; returns (m,).

    Sphere tracing from inside: a ball of radius ``|d|`` around an inside point lies inside, so
    stepping down by ``|d|`` never crosses the surface and converges on it.  ``tol`` [m]: stop once
    ``|d| <= tol``; points still deeper after ``max_iter`` steps (a surface nearly parallel to z) are
    logged.  ``obstacle``: anything with ``signed_distance(x) -> (d (m,), n (m, 3))``, positive
    outside (:mod:`workbench.fem.obstacles`).
    """
    x = np.asarray(points, dtype=np.float64)
    if x.ndim != 2 or x.shape[1] != 3:
        raise ValueError(f"points must have shape (m, 3); got {x.shape}")
    d, _ = obstacle.signed_distance(x)
    t = np.zeros(len(x))
    active = np.flatnonzero(d < -tol)
    step = -d[active]
    for _ in range(max_iter):
        if active.size == 0:
            break
        t[active] += step
        q = x[active].copy()
        q[:, 2] -= t[active]
        da, _ = obstacle.signed_distance(q)
        keep = da < -tol
        active, step = active[keep], -da[keep]
    if active.size:
        log.warning(
            "vertical_depth: %d of %d points not converged after %d steps (surface nearly vertical there)",
            active.size,
            len(x),
            max_iter,
        )
    return t


def _check_delta(delta: float, t: float) -> float:
    """The jaw displacement [m]: a plausible compression in ``[0, t)``, ``t`` the layer thickness."""
    dlt = _checks.real("delta (jaw displacement)", delta, "m")
    if dlt < 0:
        raise ValueError(f"delta must be a jaw displacement >= 0 [m]; got {dlt} — negative is a gap")
    if dlt >= t:
        raise ValueError(
            f"delta = {dlt!r} m is not below the layer thickness h = {t!r} m: displacements are in "
            "metres (1 mm = 1e-3)"
        )
    _checks.compression("delta (jaw displacement)", dlt)
    return dlt


def _cell_depths(obstacle: Any, X: np.ndarray, d: np.ndarray, depth: str, tol: float) -> tuple:
    """``(u (m,), surf (m, 3))``: how deep the cell centres ``X`` (m, 3) [m] (signed distances
    ``d`` (m,)) lie inside the obstacle — along ``-z`` (``depth="vertical"``, to ``tol`` [m]) or
    along its normal (``"normal"``) — and the surface points below them."""
    if depth == "vertical":
        u = vertical_depth(obstacle, X, tol=tol)
        return u, X - u[:, None] * np.array([0.0, 0.0, 1.0])
    u = -d
    _, n_in = obstacle.signed_distance(X)
    return u, X - u[:, None] * n_in


def _warn_at_edge(inside: np.ndarray, cx: int, cy: int, w: float, ln: float) -> None:
    """Log a warning if a touching cell (flat ``inside`` indices of the ``cx`` × ``cy`` grid of a
    ``w`` × ``ln`` [m] pad) lies on the pad's border: the patch is truncated."""
    i, j = np.unravel_index(inside, (cx, cy))
    at_edge = (i == 0).any() or (i == cx - 1).any() or (j == 0).any() or (j == cy - 1).any()
    if at_edge:
        log.warning(
            "foundation_profile: the contact reaches the pad's border (%g x %g m): the patch is truncated "
            "— enlarge width/length",
            w,
            ln,
        )


@dataclass(frozen=True)
class PadGrid:
    """The Winkler pad's face as :func:`foundation_profile` samples it: ``width`` × ``length``
    [m] in x × y, centred on the z axis, an ``nx`` × ``ny`` grid of cells, and what a contact
    reaching its border means — ``edge="warn"`` (log that the grid truncates the patch: enlarge
    the pad) or ``"cut"`` (the pad's end cuts the contact on purpose, e.g. a cylinder spanning
    it).  Checked on construction; the sizes are kept as floats, the counts as ints."""

    width: float = 0.04
    length: float = 0.04
    nx: int = 160
    ny: int = 160
    edge: str = "warn"

    def __post_init__(self) -> None:
        if self.edge not in ("warn", "cut"):
            raise ValueError(
                "edge must be 'warn' or 'cut' (the pad's border cuts the contact on purpose); "
                f"got {self.edge!r}"
            )
        object.__setattr__(self, "width", _checks.length("width", self.width, "pad_size"))
        object.__setattr__(self, "length", _checks.length("length", self.length, "pad_size"))
        object.__setattr__(self, "nx", _checks.count("nx", self.nx, 1))
        object.__setattr__(self, "ny", _checks.count("ny", self.ny, 1))


def foundation_profile(
    obstacle: Any,
    delta: float,
    E: float,
    h: float,
    *,
    nu: float | None = None,
    kind: str = "simple",
    grid: PadGrid | None = None,
    depth: str = "vertical",
) -> ContactProfile | None:
    """Winkler pad pressed into ``obstacle`` by ``delta`` [m]: a :class:`ContactProfile`, or ``None``
    when nothing touches.

    Geometry as in :func:`workbench.fem.press`: the pad's face is the plane ``z = h`` (the layer fills
    ``0 <= z <= h``, centred on the z axis, ``width`` × ``length`` [m] in x × y), the obstacle touches
    it at ``delta = 0`` and the jaw moves by ``+delta`` along z; so the same obstacle (e.g.
    ``Sphere((0, 0, h + R), R)``) gives both models' profiles in the same frame.  ``width``,
    ``length``, ``nx``, ``ny`` and ``edge`` are those of ``grid`` (:class:`PadGrid`; None:
    ``PadGrid()``, a 0.04 m square pad of 160 × 160 cells).

    The face is an ``nx`` × ``ny`` grid of cells; a cell whose centre ``X = (x, y, h + δ)`` lies
    inside the obstacle by ``u`` (``depth="vertical"``: along the pad normal, the springs' axis;
    ``"normal"``: the signed distance) becomes one element: centre = the obstacle's surface point
    below ``X``, normal = the obstacle's outward normal there (into the jaw), area = the cell's area,
    pressure ``k u`` (:func:`foundation_modulus`).  So ``profile.F = k Σ u A_cell``, which converges
    to ``k V`` (:func:`foundation_force` for a sphere) as the grid is refined; the net force along
    the pad normal, ``Σ p a |n_z|``, is smaller by the patch's tilt (``1 - O(δ/R)``).  Friction: the
    Winkler springs carry no shear, so each element is a frictionless spring with Coulomb friction
    on the object's surface, as the FEM profile is.

    Raises ``ValueError`` if the obstacle reaches deeper than the layer (``u >= h``) and logs a
    warning if the patch touches the pad's border (the grid truncates it: enlarge the pad) — unless
    ``edge="cut"``: the pad's end is meant to cut the contact (a cylinder spanning the pad).
    """
    k = foundation_modulus(E, h, nu, kind)
    t = float(h)
    dlt = _check_delta(delta, t)
    g = PadGrid() if grid is None else grid
    w, ln, cx, cy = g.width, g.length, g.nx, g.ny
    if not hasattr(obstacle, "signed_distance"):
        raise ValueError(
            f"obstacle must have signed_distance(points) -> (d, n); got {type(obstacle).__name__} "
            "— use workbench.fem.obstacles.Sphere / Cylinder / Plane / MeshObstacle"
        )
    if depth not in ("vertical", "normal"):
        raise ValueError(f"depth must be 'vertical' or 'normal'; got {depth!r}")
    xs = (np.arange(cx) + 0.5) * (w / cx) - w / 2
    ys = (np.arange(cy) + 0.5) * (ln / cy) - ln / 2
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    X = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, t + dlt)])
    d, _ = obstacle.signed_distance(X)
    inside = np.flatnonzero(d < 0)
    if inside.size == 0:
        return None
    u, surf = _cell_depths(obstacle, X[inside], d[inside], depth, 1e-12 * max(w, ln))
    keep = u > 0
    inside, u, surf = inside[keep], u[keep], surf[keep]
    if inside.size == 0:
        return None
    if u.max() >= t:
        raise ValueError(
            f"the obstacle penetrates {u.max():.4g} m, not less than the layer thickness h = {t:.4g} m: "
            "the jaw would hit the object — reduce delta"
        )
    if g.edge == "warn":
        _warn_at_edge(inside, cx, cy, w, ln)
    _, normals = obstacle.signed_distance(surf)
    area = np.full(inside.size, (w / cx) * (ln / cy))
    log.debug("foundation_profile: delta=%g m, k=%g Pa/m, %d elements", dlt, k, inside.size)
    return ContactProfile(surf, normals, area, k * u)

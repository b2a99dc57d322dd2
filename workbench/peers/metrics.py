"""The measures by which the peers' contacts are compared with a reference contact:
the pressure field on a common grid, the torsion length, the 6DFW set's support along the six
axis twists, the 6DLS fitted to a peer's contact scored against the reference's exact 6DFW set,
and the two-jaw grasp in which resistance margins are compared.

Every function takes contacts in the pad frame of :func:`workbench.fem.press` (pad face ``z = h``,
the jaw pushing the object along ``+z``), so one grid and one grasp serve every peer.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import config
from ..limit_surface.base import LimitSurfaceModel
from ..profile import ContactProfile
from ..seeds import check_seed
from ..twists import sample_twists_thesis
from ..wrench import frictional_wrenches, w_max
from . import count, friction, length
from .mujoco_cone import check_coefficients, contact_basis

__all__ = [
    "PAD_TO_GRASP",
    "FittedLSError",
    "cone_supports",
    "face_grid_points",
    "field_from_elements",
    "field_from_nodes",
    "fitted_ls_error",
    "group_max",
    "jaw_force",
    "min_twists",
    "opposed_jaws",
    "rel_l2",
    "supports",
    "torsion_length",
]

#: rotation taking the pad frame to the grasp frame of :func:`workbench.grasp.tasks.lever_disturbances`
#: (grasp axis x, object axis z): the jaw's push ``+z`` becomes ``+x`` (the jaw sits at ``-x``) and the
#: pad's length axis ``y`` (a cylinder's axis) becomes the object axis ``z``.
PAD_TO_GRASP = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def _profile(p: Any) -> ContactProfile:
    if not isinstance(p, ContactProfile):
        raise ValueError(f"expected a ContactProfile; got {type(p).__name__}")
    return p


def jaw_force(profile: ContactProfile) -> float:
    """The force [N] the jaw's sensor reads: the net normal force on the object along the pad
    normal ``+z`` (``normal_wrench[2]``; ``<= profile.F`` on a curved contact)."""
    return float(_profile(profile).normal_wrench[2])


#: an axis of a peer's 6DFW set below this fraction of its group's (forces, torques) largest
#: reference support counts as absent (fitted_ls_error)
_THIN = 1e-3


def group_max(w: Any) -> np.ndarray:
    """(6,) each axis's group largest of a (6,) support or ``w_max``: the forces' (N) for the first
    three, the torques' (N m) for the last three — what "small along an axis" is measured against
    (one threshold across the two units would drop the rolling torques)."""
    v = np.asarray(w, dtype=np.float64)
    return np.repeat([v[:3].max(), v[3:].max()], 3)


def min_twists(model: str) -> int:
    """The fewest twists of :func:`fitted_ls_error` for ``model``: its ``2 n_twists`` wrenches (the
    thesis's sampling appends the translations) must reach the model's unknowns."""
    from ..limit_surface.fit_score import check_model, min_wrenches

    return -(-min_wrenches(check_model(model)) // 2)


def _pushing(profile: Any) -> tuple[ContactProfile, float]:
    """The profile and its jaw force, refused when the jaw force is not positive (a profile in
    another frame than the pad's: flipped normals, a rotated contact)."""
    p = _profile(profile)
    f = jaw_force(p)
    # a contact of the pad frame pushes mostly along +z: F cos(tilt), above half of F = Σ p a even on
    # a patch tilted 60° (a sign test let a profile turned by 90°, jaw force 3.5e-16 N, through)
    if not f > 0.5 * p.F:
        raise ValueError(
            f"the profile's jaw force (net normal force along the pad normal +z) is {f:.3g} N of its "
            f"total normal force {p.F:.3g} N: it is not a contact of the pad frame (face z = h, the jaw "
            "pushing the object along +z; normals out of the object, i.e. -z) - flipped normals or a "
            "rotated profile?"
        )
    return p, f


def face_grid_points(width: float, length_: float, spacing: float) -> tuple[np.ndarray, float]:
    """Cell centres (m, 2) [m] of a regular grid of spacing ~``spacing`` [m] over the pad face
    ``|x| <= width/2``, ``|y| <= length_/2``, and the cell area [m²]."""
    w, ln = length("width", width, "pad_size"), length("length", length_, "pad_size")
    s = length("spacing", spacing, "element_size")
    if s >= min(w, ln):
        raise ValueError(
            f"spacing {s!r} m is not below the face's sides ({w!r} x {ln!r} m): lengths are in metres "
            "(0.2 mm = 2e-4)"
        )
    nx, ny = max(1, int(round(w / s))), max(1, int(round(ln / s)))
    x = (np.arange(nx) + 0.5) * (w / nx) - w / 2
    y = (np.arange(ny) + 0.5) * (ln / ny) - ln / 2
    X, Y = np.meshgrid(x, y, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel()]), (w / nx) * (ln / ny)


def field_from_elements(profile: ContactProfile | None, grid: np.ndarray) -> np.ndarray:
    """A profile's pressure [Pa] at grid points (m, 2) in the pad face plane: linear
    interpolation over the element centres projected along ``z`` (a Delaunay triangulation), zero
    outside their convex hull (and everywhere for ``None``, no contact).  Returns (m,)."""
    g = np.asarray(grid, dtype=np.float64)
    if profile is None:
        return np.zeros(len(g))
    from scipy.interpolate import LinearNDInterpolator

    prof = _profile(profile)
    if g.ndim != 2 or g.shape[1] != 2:
        raise ValueError(f"grid must be (m, 2) points of the pad face [m]; got shape {g.shape}")
    xy = prof.centers[:, :2]
    if len(xy) < 3:
        raise ValueError(f"a pressure field needs >= 3 elements to interpolate; got {len(xy)}")
    f = LinearNDInterpolator(xy, prof.pressures, fill_value=0.0)
    return np.clip(f(g), 0.0, None)


def field_from_nodes(face_xy: np.ndarray, p_node: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Nodal pressures (n,) on a FEM pad's regular face grid (``face_xy`` (n, 2), the
    :class:`~workbench.fem.pad.CondensedPad`'s node order) at grid points (m, 2): bilinear, zero
    outside the face.  Returns (m,)."""
    from scipy.interpolate import RegularGridInterpolator

    xy = np.asarray(face_xy, dtype=np.float64)
    p = np.asarray(p_node, dtype=np.float64)
    if xy.ndim != 2 or xy.shape[1] != 2 or p.shape != (len(xy),):
        raise ValueError(f"face_xy must be (n, 2) and p_node (n,); got {xy.shape} and {p.shape}")
    xs, ys = np.unique(xy[:, 0]), np.unique(xy[:, 1])
    if xs.size * ys.size != len(xy):
        raise ValueError("face_xy is not a full regular grid of nodes (a graded or patched pad?)")
    ix, iy = np.searchsorted(xs, xy[:, 0]), np.searchsorted(ys, xy[:, 1])
    table = np.zeros((xs.size, ys.size))
    table[ix, iy] = p
    f = RegularGridInterpolator((xs, ys), table, bounds_error=False, fill_value=0.0)
    return f(np.asarray(grid, dtype=np.float64))


def rel_l2(p: np.ndarray, p_ref: np.ndarray) -> float:
    """``‖p − p_ref‖ / ‖p_ref‖`` over one grid (a grid of equal cells: the L2 norm's ratio)."""
    a, b = np.asarray(p, float), np.asarray(p_ref, float)
    if a.shape != b.shape:
        raise ValueError(f"fields must share the grid; got {a.shape} and {b.shape}")
    nb = float(np.linalg.norm(b))
    if nb == 0:
        raise ValueError("the reference field is zero: no contact to compare against")
    return float(np.linalg.norm(a - b) / nb)


def torsion_length(profile: ContactProfile, mu: float) -> float:
    """``τ_max / (μ f_n)`` [m]: the profile's 6DFW torsional capacity about the ``z`` axis through
    its pressure centre (:func:`workbench.wrench.w_max`) per unit friction and unit *jaw* force
    (:func:`jaw_force`, the net normal force along ``z``).  On a flat patch that is ``3πa/16`` for
    Hertz's pressure and ``8a/15`` for a Winkler paraboloid; on a curved one the jaw force is below
    ``F = Σ p a`` by the elements' tilt, so the length is above those by ``F / f_n = 1 + O(a²/R²)``
    (MuJoCo's coefficient is per unit normal force too).  Times ``μ f_n``: the torque capacity."""
    m = friction(mu, "torsion length")
    p, f = _pushing(profile)
    return float(w_max(p, m)[5] / (m * f))


def supports(profile: ContactProfile, mu: float) -> np.ndarray:
    """(6,) the 6DFW set's support along the six axis twists about the pressure centre (the exact
    ``w_max``, Eq. 3.10's normaliser) per unit jaw force: [N/N] for translations, [N m/N] for
    rotations."""
    m = friction(mu, "6DFW support")
    p, f = _pushing(profile)
    return w_max(p, m) / f


def cone_supports(coefficients: Any, normal: Any = (0.0, 0.0, -1.0)) -> np.ndarray:
    """(6,) the same six supports for MuJoCo's elliptic cone (:mod:`.mujoco_cone`) of friction
    ``coefficients`` (5,) at unit normal force, contact normal ``normal`` (3,) (outward from the
    object; the pad's ``-z``): for axis twist ``e_i``, ``√(Σ_j μ_j² d_j²)`` with ``d = Eᵀ e_i``
    the twist in contact coordinates (maximum dissipation on the cone's slice)."""
    mu = check_coefficients(coefficients)
    E = contact_basis(normal)
    d = E.T  # row i: e_i in contact coordinates
    return np.sqrt(((mu * d[:, 1:]) ** 2).sum(axis=1))


def opposed_jaws(profile: ContactProfile, center: Any) -> list[ContactProfile]:
    """The two-jaw grasp of one contact: the profile (pad frame, the jaw below the object) moved to
    the grasp frame of :data:`PAD_TO_GRASP` with the object's centre ``center`` (3,) [m] at the
    origin, and its mirror image turned by π about the object axis ``z`` (the jaw at ``+x``), as
    :func:`workbench.sources.scenes.elliptic_cylinder_grasp` pairs its jaws.  Returns two profiles."""
    c = np.asarray(center, dtype=np.float64)
    if c.shape != (3,) or not np.isfinite(c).all():
        raise ValueError(f"center must be a finite (3,) point [m]; got {center!r}")
    p = _profile(profile)
    reach = float(np.linalg.norm(p.pressure_center - c))
    if reach > 0.5 * config.TOL.max_object_extent_m:
        raise ValueError(
            f"center {c.tolist()} is {reach:.3g} m from the contact: the object's centre must be in "
            "metres like the profile (15 mm = 0.015)"
        )
    jaw = p.transformed(PAD_TO_GRASP, -PAD_TO_GRASP @ c)
    return [jaw, jaw.transformed(np.diag([-1.0, -1.0, 1.0]), np.zeros(3))]


@dataclass(frozen=True)
class FittedLSError:
    """A 6DLS fitted to a peer's contact and how far it lies from the reference's exact 6DFW set.

    At each exact surface point ``x`` of the reference (uniform normals), ``g = f(x)^(1/deg)`` is
    the ratio of the truth's radius to the peer's fitted surface's along that ray."""

    model: LimitSurfaceModel  # the fit (normalised by the peer's exact w_max)
    # exp(mean |ln g|) - 1: the number to quote; a set uniformly 2x too small or too large reads +100 %
    rel_err: float
    # exp(median(-ln g)) - 1, signed: > 0 the peer's surface lies outside the truth's (optimistic)
    bias: float
    radial_mean: float  # mean |g - 1|, support_error's radial error (penalises an under-sized set more)
    fit_s: float  # wall time of the fit [s]

    def as_dict(self) -> dict:
        """The numbers (JSON), without the model."""
        return {
            "rel_err": self.rel_err,
            "bias": self.bias,
            "radial_mean": self.radial_mean,
            "fit_s": self.fit_s,
        }


def fitted_ls_error(
    profile: ContactProfile,
    reference: ContactProfile,
    mu: float,
    *,
    model: str = "ellipsoid_sdp",
    n_twists: int = 500,
    n_directions: int = 2000,
    seed: int = 0,
) -> FittedLSError:
    """What a 6DLS fitted to a peer's contact gets wrong about the reference contact.

    The peer's ``profile`` is scaled to the reference's jaw force (:func:`jaw_force`; the sensor
    reads it, as in the margins), its 6DFWs at the thesis's motion sampling of its own contact
    (§3.3.2, ``sample_twists_thesis(n_twists, profile.length_scale, seed)``: ``2 n_twists`` twists
    with the translations) are fitted with ``model`` (:data:`workbench.limit_surface.fit_score.MODELS`)
    normalised by its exact ``w_max`` (Eq. 3.10), as a user fitting it would, and the fit is compared
    with the reference's exact 6DFW surface at ``n_directions`` points whose normals are uniform in
    the *reference's* normalised coordinates (the same points for every peer; the sampling of
    :func:`workbench.limit_surface.support_error.support_error`).  The ratio ``g`` of the truth's
    radius to the fit's along each ray is summarised symmetrically in ``g``
    (:class:`FittedLSError`): a ray where the fit is twice too short and one where it is twice too
    long count alike. Each contact's wrenches are about its own pressure centre (Eq. 3.7). With
    ``profile = reference`` it is the model's own error on the reference (a peer can land slightly
    below it: errors of shape and model partly cancel). Sampling matters: the fit's twists are
    random; at the defaults a Hertz peer of the peers' sphere case read 43.7-47.3 % over seeds 0-4
    (the reference's own fit 3.3-4.5 %). Peers that differ by shape are not mirror images even
    though each ray counts symmetrically: a copy of a Hertz contact scaled about its centre by 0.5
    reads 87 %, by 2 21 % (torques halved or doubled; the truth's surface points see a convex set's
    axes differently), Hertz at 2δ against Hertz at δ 22 % and the reverse 87 %.

    profile, reference : ContactProfile — peer and truth in the pad frame (:func:`jaw_force` above
        half the total normal force ``F``).
    A peer without capacity along an axis the reference has (below 1e-3 of the largest reference
    support of its group, forces or torques: a planar or nearly planar patch against a curved truth,
    a point contact) or whose set spans fewer dimensions has no 6DLS to compare: ``ValueError``.
    ``seed`` : int >= 0, for the twists and the truth's surface points.
    """
    from ..limit_surface.fit_score import fit_model, min_wrenches
    from ..limit_surface.normalize import prepare

    m = friction(mu, "fitted 6DLS to score")
    ref, f_ref = _pushing(reference)
    p, f_p = _pushing(profile)
    need = min_twists(model)
    if isinstance(n_twists, bool) or not (isinstance(n_twists, int | np.integer) and n_twists >= need):
        raise ValueError(
            f"n_twists must be an integer >= {need} for {model!r} (2 n_twists wrenches, with the "
            f"translations, against its {min_wrenches(model)} unknowns); got {n_twists!r}"
        )
    # an int, not a Generator: the truth's points must be the same for every peer compared
    seed = check_seed(seed, generator=False)
    p = p.with_pressures(p.pressures * (f_ref / f_p))
    # a peer without capacity along an axis the truth has (a flat or nearly flat patch: no rolling
    # torque; a few elements) has no 6DLS of the truth to compare: its fit's scale there is round-off
    wp, wr = w_max(p, m), w_max(ref, m)
    gm = group_max(wr)
    for grp, name in ((slice(0, 3), "force"), (slice(3, 6), "torque")):
        thin = (wp[grp] <= _THIN * gm[grp]) & (wr[grp] > _THIN * gm[grp])
        if thin.any():
            axes = [int(i) + grp.start for i in np.flatnonzero(thin)]
            raise ValueError(
                f"the peer's 6DFW set has (almost) no {name} capacity along axes {axes} where the "
                f"reference's has (w_max {wp[axes].tolist()} vs {wr[axes].tolist()}): a flat patch or a "
                "point contact has no 6DLS of the curved contact to compare - compare their supports "
                "(supports, cone_supports) instead"
            )
    xi = sample_twists_thesis(int(n_twists), p.length_scale, seed)
    t0 = time.perf_counter()
    fitted = fit_model(model, frictional_wrenches(p, xi, m), w_max=wp, twists=xi)
    fit_s = time.perf_counter() - t0
    _, _, scale, _, sub = prepare(frictional_wrenches(ref, xi, m), wr)
    ref_dim = sub.dim
    if fitted.dim < ref_dim:
        raise ValueError(
            f"the peer's 6DFW set spans {fitted.dim} of 6 dimensions, the reference's {ref_dim}: a flat "
            "patch (or a point contact) has no 6DLS of the curved contact to compare - compare their "
            "supports (supports, cone_supports) instead"
        )
    # the same truth points for every peer: normals uniform in the reference's normalised
    # coordinates (its subspace), twists -d ⊘ scale (maximum dissipation, support_error's map)
    u = np.random.default_rng(seed).standard_normal((count("n_directions", n_directions, 1), ref_dim))
    d = u if ref_dim == 6 else u @ sub.basis.T  # 6D: B = I, as support_error (seeded points reproducible)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    f = fitted.value(frictional_wrenches(ref, -d / scale, m))
    g = np.maximum(f, 0.0) ** (1.0 / fitted.degree)
    with np.errstate(divide="ignore"):
        lg = np.log(g)
    return FittedLSError(
        fitted,
        rel_err=float(np.expm1(np.mean(np.abs(lg)))),
        bias=float(np.expm1(np.median(-lg))),
        radial_mean=float(np.mean(np.abs(g - 1.0))),
        fit_s=fit_s,
    )

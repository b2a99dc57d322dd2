"""Every contact model of a contact profile, by name (thesis §4.1.3.3, §4.1.4.3; 6DFC §V).

``contact_sets(profile, name, params)`` returns the :class:`~.contacts.ContactSet` list
one jaw contributes under model ``name`` (its settings a :class:`ModelParameters`):

==================  =====================================================================
``point``           hard point contact (Eqs. 2.44, 2.47) at the pressure centre along the
                    net normal force, ``f⊥ <= F``
``soft_point``      soft point contact (Eq. 2.50; the thesis's "Point" baseline of
                    §4.1.4.3), ``f⊥ <= F``, torsion ``γ = μ Σ p a |r_t| / F``
``planar``          3DLS-planar: the profile projected onto its PCA plane (§4.1.4.3), a
                    3D ellipsoid fitted to its (f_t1, f_t2, τ_n) wrenches, in the plane's
                    frame (:func:`plane_frame_profile`)
``3dls_nonplanar``  3DLS fitted to the three major components of the 6DFWs — tangential
                    forces and torsion about the net normal — the other three set to
                    zero (§4.1.3.3: f_y, f_z, τ_x for a grasp axis x)
``6dfw``            the sampled 6DFWs themselves (no model): the "dense" reference
``reach``           REACH-style contact model (:func:`~.contacts.reach_contacts`): each
                    element of *any* profile a soft point contact with its own force,
                    clustered to ``reach_triangles`` (thesis §2.3.1.3); not to be confused
                    with :func:`~workbench.sources.reach.reach_profile`, a profile source from meshes
``6dls``            6D ellipsoid (or quartic) limit surface, force known (Eqs. 3.27, 3.28)
``6dls_quartic``    ``6dls`` with the SOS-convex quartic (Eq. 3.17, fitted with the
                    twist normals); the QP refines its linearisation by cutting planes
``6dfc``            6D friction cone, ``f_C <= F`` (Eqs. 3.29, 3.30)
==================  =====================================================================

All are built at μ = 1 and unit force semantics of :class:`ContactSet`, so one
build serves every μ and every grasp force (rescale with ``with_force``).
Limit surfaces go through a :class:`~workbench.limit_surface.LimitSurfaceCache`
(same profile ⇒ no resampling, no refit).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..groups import checked_group
from ..limit_surface import LimitSurfaceCache, fit_ellipsoid, fit_quartic
from ..limit_surface.cache import ModelSpec, SamplerSpec
from ..limit_surface.contact_wrench import ContactWrenchModel
from ..profile import ContactProfile
from ..wrench import frictional_wrenches
from .contacts import (
    ContactSet,
    limit_surface_contact,
    normal_frame,
    point_contact,
    reach_contacts,
    soft_point_contact,
    wrench_hull_contact,
)

log = logging.getLogger(__name__)

MODELS = ("point", "soft_point", "planar", "3dls_nonplanar", "6dfw", "reach", "6dls", "6dls_quartic", "6dfc")


def torsion_length(profile: ContactProfile, normal: np.ndarray) -> float:
    """``Σ p a |r_t| / F``: mean in-plane distance from the pressure centre [m]."""
    r = profile.centers - profile.pressure_center
    r_t = r - np.outer(r @ normal, normal)
    return float((profile.forces * np.linalg.norm(r_t, axis=1)).sum() / profile.F)


def net_normal(profile: ContactProfile) -> np.ndarray:
    """Unit outward normal of the contact: minus the net normal force direction."""
    f = profile.normal_wrench[:3]
    return -f / np.linalg.norm(f)


def planar_profile(profile: ContactProfile) -> ContactProfile:
    """The profile projected onto the plane through its pressure centre normal to the
    least-variance PCA axis of its element centres (oriented like the net normal);
    element forces are kept (so F is), areas shrink by ``|n·n_p|``.

    Centres on one line (a strip one element wide) or at one point leave the PCA plane
    undetermined: the plane is then the one through that line closest to normal to the net
    normal (``config.TOL.planar_collinear_rtol``)."""
    from .. import config

    c = profile.centers - profile.pressure_center
    nn = net_normal(profile)
    # the right singular vectors only: full U would be (n, n) (29 GiB at 62,000 elements); with
    # fewer than 3 elements the reduced Vt lacks the rows completing the basis, so ask for them
    _, s, Vt = np.linalg.svd(c * np.sqrt(profile.areas)[:, None], full_matrices=len(c) < 3)
    s = np.r_[s, np.zeros(3 - len(s))]
    if s[1] <= config.TOL.planar_collinear_rtol * s[0] or s[0] == 0:
        line = Vt[0] if s[0] > 0 else np.zeros(3)
        n_p = nn - (nn @ line) * line
        n_p /= np.linalg.norm(n_p)
    else:
        n_p = Vt[-1] * (1.0 if Vt[-1] @ nn >= 0 else -1.0)
    proj = profile.centers - np.outer(c @ n_p, n_p)
    cos = np.clip(np.abs(profile.normals @ n_p), 1e-3, None)
    areas = profile.areas * cos
    return ContactProfile(
        proj, np.tile(n_p, (len(proj), 1)), areas, profile.forces / areas, allow_scale=profile.allow_scale
    )


def _turn(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(3, 3) the smallest rotation taking unit ``a`` to unit ``b`` (Rodrigues; ``a · b > 0``)."""
    v, c = np.cross(a, b), float(a @ b)
    K = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + K + K @ K / (1.0 + c)


def plane_frame_profile(flat: ContactProfile) -> tuple[ContactProfile, np.ndarray]:
    """A flat profile (:func:`planar_profile`: one normal ``n_p`` (3,), centres on one plane)
    in its plane's frame: ``(local, R)`` with ``object = R @ local + flat.pressure_center``;
    ``R`` (3, 3) is the smallest rotation taking the object axis nearest ``n_p``, ``±e_k``, to
    ``n_p``, so the frame keeps the object's axes as far as the plane allows (``R = I`` for a
    plane normal to an axis).  ``local`` has normals exactly ``±e_k`` and centres exactly on
    ``x_k = 0``: its normal force and tilting torques are exactly 0.  In the object frame a
    plane a round-off off an axis (an SVD normal 1e-8 from it) leaves them at round-off size,
    and the wrench kernel resolves such slips (``|v_t|`` ~ 1e-12 ``|v|``) in directions turned
    by up to ~2e-4: they came out below the exact ``w_max`` (a negative one crashed the
    fit) or as spurious dimensions of the normalised wrenches."""
    n_p = flat.normals[0]
    k = int(np.argmax(np.abs(n_p)))
    axis = np.zeros(3)
    axis[k] = np.sign(n_p[k])
    R = _turn(axis, n_p)
    local = (flat.centers - flat.pressure_center) @ R  # rows R.T (c − o)
    local[:, k] = 0.0
    prof = ContactProfile(
        local, np.tile(axis, (len(local), 1)), flat.areas, flat.pressures, allow_scale=flat.allow_scale
    )
    return prof, R


def check_model(name: str) -> str:
    """``name`` if it is one of :data:`MODELS`, else a ``ValueError`` listing them (also used
    by the experiments' ``check_config`` to refuse a model before any work)."""
    if name not in MODELS:
        import difflib

        key = str(name).lower().replace("-", "_").replace(" ", "_")
        close = difflib.get_close_matches(key, MODELS, n=1, cutoff=0.6)
        hint = f" — did you mean {close[0]!r}?" if close else ""
        raise ValueError(f"model must be one of {MODELS}; got {name!r}{hint}")
    return name


def _check_n_wrenches(n_wrenches) -> int:
    """``n_wrenches`` of the 6DFW sample: an even integer >= 2, since the thesis sampler
    (§3.3.2, :func:`~workbench.twists.sample_twists_thesis`) draws ``n`` screw motions about
    Fibonacci axes and the ``n`` translations along the same axes, ``2n`` wrenches."""
    import numbers

    if (
        isinstance(n_wrenches, bool)
        or not isinstance(n_wrenches, numbers.Integral)
        or n_wrenches < 2
        or n_wrenches % 2
    ):
        odd = isinstance(n_wrenches, numbers.Integral) and not isinstance(n_wrenches, bool) and n_wrenches > 2
        even = f" — pass {n_wrenches - 1} or {n_wrenches + 1}" if odd else " — pass e.g. the default 600"
        raise ValueError(
            "n_wrenches must be an even integer >= 2 (the number of 6DFW samples: the thesis sampler "
            "draws n screw motions and the n translations along the same axes, 2n wrenches, so an odd "
            f"count cannot be met); got {n_wrenches!r}{even}"
        )
    return int(n_wrenches)


def _check_profile(profile: Any) -> None:
    """ValueError unless ``profile`` is a :class:`ContactProfile`, saying how to build one."""
    if not isinstance(profile, ContactProfile):
        fix = (
            "ContactProfile(**profile)"
            if isinstance(profile, dict) and {"centers", "normals", "areas", "pressures"} <= set(profile)
            else "ContactProfile(centers, normals, areas, pressures) or a source in workbench.sources"
        )
        raise ValueError(
            f"profile must be a ContactProfile (one jaw's contact: element centres, normals, areas and "
            f"pressures); got {type(profile).__name__} — build one with {fix}"
        )


@dataclass(frozen=True)
class ModelParameters:
    """How :func:`contact_sets` builds a contact model; each setting applies to the models named.

    M : linearisation directions of 6DLS/6DFC/3DLS (their ``representation="inner"|"outer"``).
    n_edges : the friction-cone polygon's edges of point-like contacts (point, soft point, REACH).
    n_wrenches : 6DFW samples of ``6dfw``/``3dls_nonplanar``, an even number >= 2 (n screw motions
        + n translations); checked when made, whatever the model (a bad value is never right).
    reach_triangles : REACH element clusters.
    quartic : the quartic limit surface for ``6dls``/``planar``/``3dls_nonplanar``.
    sampler : the training wrenches of the limit surfaces (6DLS, 6DFC, planar; None:
        ``SamplerSpec()``, see its kinds).
    """

    M: int = 200
    n_edges: int = 8
    n_wrenches: int = 600
    reach_triangles: int = 16
    quartic: bool = False
    sampler: SamplerSpec | None = None

    def __post_init__(self) -> None:
        _check_n_wrenches(self.n_wrenches)
        for name, least, what in (
            ("M", 1, "linearisation directions"),
            ("n_edges", 3, "friction-cone polygon edges"),
            ("reach_triangles", 1, "REACH element clusters"),
        ):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
                raise ValueError(f"{name} must be an integer >= {least} ({what}); got {value!r}")
        if not isinstance(self.quartic, (bool, np.bool_)):
            raise ValueError(f"quartic must be True or False; got {self.quartic!r}")
        if self.sampler is not None and not isinstance(self.sampler, SamplerSpec):
            raise ValueError(
                f"sampler must be a SamplerSpec or None (its defaults); got {type(self.sampler).__name__} "
                "— pass SamplerSpec(kind=...)"
            )


def contact_sets(
    profile: ContactProfile,
    name: str,
    params: ModelParameters | None = None,
    *,
    cache: LimitSurfaceCache | None = None,
    seed: int = 0,
) -> list[ContactSet]:
    """The contact sets of one jaw's ``profile`` under model ``name``: one of
    ``point``, ``soft_point``, ``planar``, ``3dls_nonplanar``, ``6dfw``, ``reach``,
    ``6dls``, ``6dls_quartic``, ``6dfc`` (the module docstring says what each is).

    Only what the model needs is computed: no limit surface for point/soft point/REACH,
    no 6DFW sampling except for ``6dfw``/``3dls_nonplanar``, no quartic unless asked.
    params : the model settings (:class:`ModelParameters`: M, n_edges, n_wrenches,
        reach_triangles, quartic, sampler; None: its defaults).
    cache : limit surfaces of the same normalised profile are reused (and scaled by F).
    seed : the samplers' seed, an integer >= 0.
    """
    params = checked_group(params, ModelParameters, "params")
    M, n_edges, n_wrenches = params.M, params.n_edges, params.n_wrenches
    reach_triangles, quartic, sampler = params.reach_triangles, params.quartic, params.sampler
    check_model(name)
    _check_profile(profile)
    cache = LimitSurfaceCache.check(cache)
    from ..seeds import check_seed

    seed = check_seed(seed, "seed", generator=False)  # every model, not only those that sample
    if name not in ("6dfw", "3dls_nonplanar") and n_wrenches != 600:
        # one set of keyword arguments for every model is a common loop, so no warning; the log
        # says where the setting does not apply
        log.info(
            "n_wrenches=%d has no effect on %r: it sets the 6DFW samples of '6dfw' and "
            "'3dls_nonplanar' only; a limit surface's training wrenches are sampler=SamplerSpec(n=...)",
            n_wrenches,
            name,
        )
    if name == "6dls_quartic":
        quartic = True
    spec = ModelSpec(model="quartic") if quartic else ModelSpec(method="sdp")
    F, o = profile.F, profile.pressure_center
    if name in ("point", "soft_point"):
        n = net_normal(profile)
        if name == "point":
            return [point_contact(o, n, F, n_edges=n_edges, name=name)]
        return [soft_point_contact(o, n, F, torsion_length(profile, n), n_edges=n_edges, name=name)]
    if name == "reach":
        return reach_contacts(profile, max_triangles=reach_triangles, n_edges=n_edges)
    if name != "6dfw" and np.ptp(profile.centers, axis=0).max() == 0.0:
        # one element (or coincident centres: a pad catching an edge or a corner): its exact 6DFW
        # set is the friction disc at the pressure centre, no torsion and no tilting torque — the
        # hard point contact every limit-surface model of it reduces to; a fit needs extent
        log.info("%s contact of one point (%d element(s)): its friction cone", name, len(profile.areas))
        return [point_contact(o, net_normal(profile), F, n_edges=n_edges, name=name)]
    if name in ("6dls", "6dls_quartic", "6dfc"):
        model = cache.contact_model(profile, 1.0, spec=spec, sampler=sampler)
        return [limit_surface_contact(model, o, F, M=M, cone=name == "6dfc", name=name, seed=seed)]
    if name == "planar":
        flat = planar_profile(profile)
        local, R = plane_frame_profile(flat)  # fitted in the plane's frame: exactly planar wrenches
        model = cache.contact_model(local, 1.0, spec=spec, sampler=sampler)
        return [limit_surface_contact(model, flat.pressure_center, F, M=M, name=name, seed=seed, R=R)]
    fw_sampler = SamplerSpec(kind="thesis", n=n_wrenches // 2, seed=seed)  # n rotations + n translations
    unit = profile.normalized()
    W = frictional_wrenches(unit, fw_sampler.twists(unit), 1.0)
    if name == "6dfw":
        return [wrench_hull_contact(profile, W * F)]
    # 3dls_nonplanar (§4.1.3.3): keep the three "major" components — the two tangential
    # forces and the torque about the contact normal, in the contact frame — and set the
    # other three (normal force, tilting torques) to zero
    R = normal_frame(net_normal(profile))  # columns: t1, t2, inward normal
    Wl = np.hstack([W[:, :3] @ R, W[:, 3:] @ R])  # wrenches in the contact frame
    Wl[:, [2, 3, 4]] = 0.0
    W3 = np.hstack([Wl[:, :3] @ R.T, Wl[:, 3:] @ R.T])
    ls = fit_quartic(W3) if quartic else fit_ellipsoid(W3, "sdp")
    model = ContactWrenchModel(ls, profile.normal_wrench / F)
    return [replace(limit_surface_contact(model, o, F, M=M, seed=seed), name=name)]

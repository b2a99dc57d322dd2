"""MuJoCo's ``condim=6`` elliptic friction cone: a point-contact model of a patch's wrench set.

MuJoCo contacts are points with a frame whose first axis is the normal; a ``condim=6`` contact
force is ``f = (f_n, f_t1, f_t2, τ_n, τ_r1, τ_r2)`` (normal force, two tangential forces, torsion,
two rolling torques) with friction coefficients ``μ = (μ_slide, μ_slide, μ_torsion, μ_roll,
μ_roll)``; the torsional and rolling coefficients have units of length.  The elliptic cone is
(MuJoCo documentation, Computation → Contact → Friction cones,
https://mujoco.readthedocs.io/en/stable/computation/index.html#friction-cones)::

    K = { f ∈ R^6 : f_1 >= 0,  f_1² >= Σ_{i=2..6} f_i² / μ_{i-1}² }

This module holds that cone as analytic formulas (no ``mujoco`` import): membership
(:func:`in_cone`), its support function at a given normal force (:func:`cone_support`), the
maximum-dissipation friction wrench for a twist (:func:`cone_friction_wrenches`, comparable to
:func:`workbench.frictional_wrenches`), the map between contact coordinates and workbench wrenches
(:func:`contact_basis`), the parameters that make the cone reproduce a profile's exact
friction capacities (:func:`mujoco_coefficients_from_profile`), and those a user would estimate
for a patch that is not simulated (:func:`patch_coefficients`).  With ``mujoco`` installed (extra
``peers``), :func:`mujoco_torsion_response` runs MuJoCo itself on a sphere-on-plane pair with these
coefficients, which the tests use to check the formula against the simulator on the torsional axis.

The cone slice at ``f_n`` is an ellipsoid with semi-axes ``μ_i f_n``: matched as below, it has the
6DFW set's extent along the five friction axes but not its shape (a curved patch's 6DFW couples
sliding with a rolling torque, which the cone's diagonal ellipsoid has no term for).

Wrench convention (CONVENTIONS.md): the wrench on the **object** about the contact point, the
profile's normal ``n`` outward from the object, so the normal force on the object is ``-f_n n``.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import peers as _checks
from ..profile import ContactProfile
from ..wrench import check_mu, check_twists, frictional_wrenches, normal_wrench

__all__ = [
    "MujocoCoefficients",
    "check_coefficients",
    "cone_friction_wrenches",
    "cone_support",
    "contact_basis",
    "in_cone",
    "MUJOCO_MIN_MU",
    "mujoco_coefficients_from_profile",
    "mujoco_torsion_response",
    "patch_coefficients",
    "torsion_coefficient",
]

log = logging.getLogger(__name__)

#: τ_max / (μ F a) of a circular patch of radius a under the named pressure distribution:
#: Hertz 3π/16 (Johnson §4.2), paraboloid on a Winkler foundation 8/15, uniform 2/3.
TORSION_FACTORS = {"hertz": 3.0 * np.pi / 16.0, "foundation": 8.0 / 15.0, "uniform": 2.0 / 3.0}


def check_coefficients(mu: Any) -> np.ndarray:
    """Friction coefficients as a (5,) float array ``(μ_slide, μ_slide, μ_torsion [m], μ_roll [m],
    μ_roll [m])``, all finite and >= 0; a (3,) ``(slide, torsion, roll)`` (MJCF's geom ``friction``)
    is expanded as MuJoCo does.  The sliding coefficients are judged by
    :func:`workbench.wrench.check_mu` (μ = 50 refused as a percentage, above 1.5 warned), the
    torsional and rolling ones, lengths, refused above 1 m (millimetres)."""
    try:
        m = np.asarray(mu, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"mu must be 5 (or 3) friction coefficients; got {mu!r}") from None
    if m.size == 3:
        m = np.array([m[0], m[0], m[1], m[2], m[2]])
    if m.size != 5:
        raise ValueError(
            f"mu must have 5 coefficients (slide, slide, torsion, roll, roll) or MJCF's 3 (slide, torsion, "
            f"roll); got {m.size}"
        )
    if not np.isfinite(m).all() or (m < 0).any():
        raise ValueError(f"mu must be finite coefficients >= 0; got {m.tolist()}")
    for i in (0,) if m[1] == m[0] else (0, 1):
        try:  # the sliding ones are Coulomb coefficients: the one rule of μ (50 is per cent)
            check_mu(float(m[i]))
        except ValueError as exc:
            raise ValueError(f"mu[{i}] (a sliding coefficient, Coulomb's μ): {exc}") from None
    if (m[2:] > 1.0).any():
        raise ValueError(
            f"the torsional and rolling coefficients are lengths in metres; got {m[2:].tolist()} — "
            "a patch-scale value is ~1e-3 (pass metres, not millimetres)"
        )
    return m


def _forces(f: Any, name: str = "f") -> tuple[np.ndarray, bool]:
    try:
        x = np.asarray(f, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a numeric (K, 6) array; got {type(f).__name__}") from None
    single = x.ndim == 1
    x = x[None, :] if single else x
    if x.ndim != 2 or x.shape[1] != 6:
        raise ValueError(
            f"{name} must have shape (K, 6) or (6,) (f_n, f_t1, f_t2, τ_n, τ_r1, τ_r2); got {np.shape(f)}"
        )
    if not np.isfinite(x).all():
        raise ValueError(f"{name} must be finite; got NaN/inf")
    return x, single


def in_cone(f: Any, mu: Any, rtol: float = 1e-12) -> np.ndarray | bool:
    """Whether contact forces ``f`` (K, 6) (or (6,)) in contact coordinates lie in the elliptic
    cone of coefficients ``mu`` (see :func:`check_coefficients`), up to ``rtol`` × ``f_n²``.
    A component whose coefficient is 0 must be 0.  Returns (K,) bool (or a bool)."""
    x, single = _forces(f)
    m = check_coefficients(mu)
    fn = x[:, 0]
    fr = x[:, 1:]
    pos = m > 0
    q = ((fr[:, pos] / m[pos]) ** 2).sum(axis=1)
    zero_ok = (np.abs(fr[:, ~pos]) <= np.sqrt(rtol) * np.abs(fn)[:, None]).all(axis=1)
    ok = (fn >= 0) & (q <= fn * fn * (1.0 + rtol)) & zero_ok
    return bool(ok[0]) if single else ok


def cone_support(d: Any, mu: Any, f_n: float = 1.0) -> np.ndarray | float:
    """Support function of the cone's slice at normal force ``f_n`` [N]: ``max d·f`` over
    ``f_1 = f_n``, ``Σ (f_i/μ_i)² <= f_n²``, i.e. ``f_n (d_1 + √(Σ μ_i² d_i²))``, for directions
    ``d`` (K, 6) (or (6,)) in contact coordinates.  Returns (K,) (or a float)."""
    x, single = _forces(d, "d")
    m = check_coefficients(mu)
    fn = _checks.real("f_n (normal force)", f_n, "N")
    if fn < 0:
        raise ValueError(f"f_n must be a normal force >= 0 [N]; got {fn}")
    h = fn * (x[:, 0] + np.sqrt(((m * x[:, 1:]) ** 2).sum(axis=1)))
    return float(h[0]) if single else h


def contact_basis(normal: Any) -> np.ndarray:
    """(6, 6) matrix ``E`` mapping contact coordinates to a workbench wrench on the object,
    ``w = E f``, ``f = E.T w`` (orthogonal): block-diagonal ``[B, B]`` with the columns of ``B``
    ``-n`` (the normal force on the object), ``t1``, ``t2`` (a right-handed tangent pair of the
    unit ``normal`` (3,), outward from the object).  The torque block maps ``(τ_n, τ_r1, τ_r2)``
    the same way; the cone is symmetric in every friction component, so these signs do not matter."""
    try:
        n = np.asarray(normal, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"normal must be a (3,) vector; got {normal!r}") from None
    if n.size != 3 or not np.isfinite(n).all() or np.linalg.norm(n) == 0:
        raise ValueError(f"normal must be a finite non-zero (3,) vector; got {normal!r}")
    n = n / np.linalg.norm(n)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    B = np.column_stack([-n, t1, t2])
    E = np.zeros((6, 6))
    E[:3, :3] = B
    E[3:, 3:] = B
    return E


def cone_friction_wrenches(twists: Any, normal: Any, mu: Any, f_n: float = 1.0) -> np.ndarray:
    """Maximum-dissipation friction wrenches (K, 6) of the cone slice at ``f_n`` [N] for twists
    (K, 6) (or (6,)) about the contact point: ``argmin ξ·w`` over the friction part, i.e. in
    contact coordinates ``f_i = -f_n μ_i² d_i / √(Σ μ_j² d_j²)`` with ``d = E.T ξ``; zero for a twist
    with no frictional component (never NaN).  The point-contact counterpart of
    :func:`workbench.frictional_wrenches` (which excludes the normal force likewise)."""
    xi, single = check_twists(twists)
    m = check_coefficients(mu)
    fn = _checks.real("f_n (normal force)", f_n, "N")
    if fn < 0:
        raise ValueError(f"f_n must be a normal force >= 0 [N]; got {fn}")
    E = contact_basis(normal)
    d = xi @ E  # rows: E.T ξ
    md = m * d[:, 1:]
    norm = np.sqrt((md**2).sum(axis=1))
    safe = np.where(norm > 0, norm, 1.0)
    f = np.zeros_like(d)
    f[:, 1:] = np.where((norm > 0)[:, None], -fn * m * md / safe[:, None], 0.0)
    w = f @ E.T
    return w[0] if single else w


def torsion_coefficient(a: float, mu: float, pressure: str = "hertz") -> float:
    """MuJoCo's torsional coefficient [m] of a circular patch of radius ``a`` [m] under Coulomb
    friction ``mu``: ``τ_max / f_n = c μ a`` with ``c`` = 3π/16 (``"hertz"``), 8/15
    (``"foundation"``) or 2/3 (``"uniform"``).  (MuJoCo's documentation reads the coefficient as
    "the diameter of the contact patch", ``2a``: that is the scale, not the Coulomb value.)"""
    r = _checks.length("a (patch radius)", a)
    m = _checks.friction(mu, "torsional coefficient")
    if pressure not in TORSION_FACTORS:
        raise ValueError(f"pressure must be one of {sorted(TORSION_FACTORS)}; got {pressure!r}")
    return TORSION_FACTORS[pressure] * m * r


#: the torsional coefficients a user may give an unsimulated patch of radius a: Hertz's 3π μ a / 16
#: (:func:`torsion_coefficient`) or μ·2a, MuJoCo's documentation's "diameter of the contact patch"
PATCH_TORSIONS = ("hertz", "diameter")


def patch_coefficients(mu: float, rho: float, delta: float, torsion: str = "hertz") -> np.ndarray:
    """A user's ``condim=6`` coefficients (5,) ``(μ, μ, μ_torsion [m], 0, 0)`` for a contact whose
    patch is not simulated but estimated: radius ``a = √(ρ δ)`` from the surface's curvature radius
    ``rho`` [m] at the contact and the depth ``delta`` [m] (Hertz's contact radius), torsion
    ``3π μ a / 16`` (``torsion="hertz"``, :func:`torsion_coefficient`'s Hertz value) or ``μ · 2a``
    (``"diameter"``), no rolling resistance.  ``mu``: Coulomb friction (> 0)."""
    m = _checks.friction(mu, "set of MuJoCo coefficients")
    r = _checks.length("rho (curvature radius)", rho)
    d = _checks.depth("delta (depth)", delta, below=r, below_name="the curvature radius rho")
    if torsion not in PATCH_TORSIONS:
        raise ValueError(f"torsion must be one of {PATCH_TORSIONS}; got {torsion!r}")
    a = np.sqrt(r * d)
    tors = 3.0 * np.pi * m * a / 16.0 if torsion == "hertz" else m * 2.0 * a
    return np.array([m, m, tors, 0.0, 0.0])


@dataclass(frozen=True)
class MujocoCoefficients:
    """A ``condim=6`` contact matched to a profile (:func:`mujoco_coefficients_from_profile`).

    friction : (5,) ``(μ_t1, μ_t2, μ_torsion [m], μ_roll1 [m], μ_roll2 [m])`` along ``basis``.
    normal : (3,) unit normal, outward from the object (the force-weighted mean).
    f_n : the net normal force ``|Σ p a n|`` [N] (MuJoCo's ``f_1``; ``<= profile.F``).
    basis : (6, 6) :func:`contact_basis` of ``normal`` with the tangents used.
    capacities : (5,) the profile's friction capacities along the five axes [N, N, N m, N m, N m].
    """

    friction: np.ndarray
    normal: np.ndarray
    f_n: float
    basis: np.ndarray
    capacities: np.ndarray

    @property
    def mjcf_pair_friction(self) -> str:
        """The five coefficients as MJCF's ``<pair friction="...">`` attribute."""
        return " ".join(f"{v:.9g}" for v in self.friction)


def mujoco_coefficients_from_profile(
    profile: ContactProfile, mu: float, rolling: str = "zero"
) -> MujocoCoefficients:
    """Coefficients for which MuJoCo's cone has the profile's exact friction capacities.

    With ``n`` the direction of the net normal force and ``f_n`` its magnitude, each coefficient is
    the profile's 6DFW support along one friction axis divided by ``f_n`` (maximum dissipation:
    the capacity along axis ``e`` is ``-frictional_wrenches(profile, e)·e``, twists about the
    pressure centre):

    - slide: translation along ``t1``, ``t2`` (``μ`` for a flat patch; per unit *net* normal force
      more for a curved one, whose tilted elements press harder than their ``z`` share);
    - torsion: rotation about ``n`` — ``τ_max / f_n``, e.g. ``3π μ a / 16`` for a Hertz patch;
    - rolling: ``rolling="zero"`` (default): 0.  Coulomb friction of a flat patch resists no
      rolling (the slip of a rotation about an in-plane axis is normal to the patch), so rolling
      resistance is a deformation effect outside the 6DFW; ``rolling="profile"`` takes the 6DFW's
      capacity about ``t1``, ``t2`` (non-zero only for a curved profile).

    profile : ContactProfile.  mu : Coulomb friction coefficient (> 0).
    """
    if not isinstance(profile, ContactProfile):
        raise ValueError(f"profile must be a ContactProfile; got {type(profile).__name__}")
    m = _checks.friction(mu, "set of MuJoCo coefficients")
    if rolling not in ("zero", "profile"):
        raise ValueError(f"rolling must be 'zero' or 'profile'; got {rolling!r}")
    wn = normal_wrench(profile)[:3]  # = -Σ p a n, on the object
    f_n = float(np.linalg.norm(wn))
    if f_n <= 1e-12 * profile.F:
        raise ValueError(
            "the profile's normal forces cancel (|Σ p a n| ~ 0, e.g. a closed surface): no net normal "
            "direction for a point contact — pass a one-sided contact patch"
        )
    n = -wn / f_n
    E = contact_basis(n)
    axes = E[:, 1:].T  # (5, 6): t1, t2 translations; n, t1, t2 rotations (sign-free)
    twists = np.zeros((5, 6))
    twists[0, :3], twists[1, :3] = axes[0, :3], axes[1, :3]
    twists[2, 3:], twists[3, 3:], twists[4, 3:] = axes[2, 3:], axes[3, 3:], axes[4, 3:]
    w = frictional_wrenches(profile, twists, m)
    cap = -np.einsum("ij,ij->i", w, twists) + 0.0
    coef = cap / f_n
    if rolling == "zero":
        coef[3:] = 0.0
    log.debug("mujoco_coefficients_from_profile: f_n=%g N, F=%g N, friction=%s", f_n, profile.F, coef)
    return MujocoCoefficients(coef, n, f_n, E, cap)


#: MuJoCo's floor on every friction coefficient (``mjMINMU``): a 0 in ``<pair friction>`` runs as 1e-5
MUJOCO_MIN_MU = 1e-5


def mujoco_torsion_response(
    mu: Any,
    torque_ratio: float,
    *,
    f_n: float = 1.0,
    radius: float = 0.02,
    timestep: float = 5e-4,
    settle_steps: int = 1000,
    steps: int = 400,
) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's own ``condim=6`` elliptic-cone contact under a torsional load (needs ``mujoco``).

    A free sphere of radius ``radius`` [m] and weight ``f_n`` [N] rests on a plane (contact pair
    with coefficients ``mu``, see :func:`check_coefficients`; ``cone="elliptic"``); after
    ``settle_steps`` it is loaded about the contact normal by ``torque_ratio × μ_torsion × f_n``
    [N m] for ``steps`` steps.  Returns ``(f, friction)``: the contact force (6,) of
    ``mj_contactForce`` in the contact frame ``(f_n, f_t1, f_t2, τ_n, τ_r1, τ_r2)`` and the five
    coefficients MuJoCo used (``mjData.contact.friction``, 0s raised to :data:`MUJOCO_MIN_MU`).

    Checks of :func:`in_cone` against MuJoCo itself: below capacity (``torque_ratio < 1``) the
    sphere sticks and ``|τ_n|`` equals the load; above it, it spins and MuJoCo's torsion sits on
    the cone's boundary, ``|τ_n| = μ_torsion f_n`` (with MuJoCo's instantaneous ``f_n``).  Only the
    torsional axis is probed: a sphere pushed sideways rolls (rolling friction ~0) rather than
    slides, so sliding and rolling are not a clean probe of the cone here.
    """
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - exercised only without mujoco
        raise ImportError("mujoco_torsion_response needs MuJoCo: pip install 'mujoco>=3'") from exc
    m = check_coefficients(mu)
    ratio = _checks.real("torque_ratio", torque_ratio, "-")
    fn = _checks.real("f_n (normal force)", f_n, "N")
    if fn <= 0:
        raise ValueError(f"f_n must be a weight > 0 [N]; got {fn}")
    r = _checks.length("radius", radius)
    dt = _checks.real("timestep", timestep, "s")
    n_settle = _checks.count("settle_steps", settle_steps, 0)
    n_steps = _checks.count("steps", steps, 1)
    g = 9.81
    friction = " ".join(repr(float(v)) for v in m)  # round-trips exactly
    xml = f"""
<mujoco>
  <option timestep="{dt:.12g}" cone="elliptic" gravity="0 0 -{g}" integrator="implicitfast"/>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1" condim="6"/>
    <body name="ball" pos="0 0 {r:.12g}">
      <freejoint/>
      <geom name="ball" type="sphere" size="{r:.12g}" mass="{fn / g:.12g}" condim="6"/>
    </body>
  </worldbody>
  <contact><pair geom1="floor" geom2="ball" condim="6" friction="{friction}"/></contact>
</mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    for _ in range(n_settle):
        mujoco.mj_step(model, data)
    data.xfrc_applied[1, 5] = ratio * m[2] * fn  # torque about the contact normal (+z), at the centre
    for _ in range(n_steps):
        mujoco.mj_step(model, data)
    if data.ncon != 1:
        raise RuntimeError(f"expected one sphere-plane contact, MuJoCo has {data.ncon}")
    f = np.zeros(6)
    mujoco.mj_contactForce(model, data, 0, f)
    used = np.array(data.contact.friction[0], dtype=np.float64)
    log.debug("mujoco_torsion_response: load ratio %g, contact force %s, friction %s", ratio, f, used)
    return f, used

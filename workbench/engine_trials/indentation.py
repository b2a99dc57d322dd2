"""Validation item (a) of the engines: a pad indented by a flat or a sphere, the
engine's force against our own neo-Hookean pad FEM, for δ ≤ 1 mm.

:func:`indent_pad` presses a rigid indenter into a 20 × 40 × 5 mm silicone pad (the trials' pad:
``PadGeometry()``, ``Material()``; back face bonded, the indenter frictionless as in our FEM) by
a sequence of depths and returns, per depth, the force the engine measures on the indenter along
the pressing axis (a load cell's reading) and the reference force, the same resultant of
:func:`workbench.fem.press` with ``fidelity="nonlinear"`` (the neo-Hookean layer).

Protocol (:class:`IndentProtocol`): the indenter is driven (MuJoCo: a mocap body; Drake: a stiff
PD-driven prismatic joint) from first touch through the depths at a constant speed, held at each;
the force is the mean over the last quarter of the hold.

MuJoCo (:class:`~.settings.EngineSettings`)
    The pad is the trials' flex pad: :func:`.pad.flexcomp_xml` on ``settings.pad_grid`` (5 × 9 × 3
    points: 5 × 5 × 2.5 mm) with its contacts carried by :func:`.pad.add_tips`.  ``mesh`` (a
    :class:`~workbench.fem.pad.PadGeometry`, graded or not) gives a finer pad on that geometry's
    nodes, each hex cut into the 6 tets of MuJoCo's own grid (on a uniform geometry it *is* the
    grid pad: the same forces), tips and settings unchanged.  A finer pad is needed because the
    trials' grid is coarser than a sphere's contact (radius √(Rδ) = 1.6 mm for R = 10 mm at
    δ = 0.25 mm: one vertex or none inside it): the trials' pad measures its grid (+190 % on
    R = 10 mm at 0.25 mm, −39 % at 1 mm), and on the flat −23 / −34 / −58 % at 0.25 / 0.5 / 1 mm.
    With the trials' contact impedance the tips also sink 0.055–0.08 mm into the indenter (MuJoCo's
    soft contact, whose stiffness scales with the vertex mass), a fifth of δ = 0.25 mm:
    :data:`STIFF_CONTACT` is the trials' settings with that sinking below 1.5 µm.
    MuJoCo 4's 3D flex is St Venant–Kirchhoff (SVK) on linear tets, softer than neo-Hookean in
    compression: on the flat it is below our pad by more than 10 % at every depth (−19 / −37 / −62 %
    on 11 × 21 × 6 vertices, the same on 21 × 41 × 6), and within 3 % of our own FEM run with the
    SVK law: the gap is the law, not the contact.  On spheres it is within 10 % at 0.25 mm only
    (R = 10 / 25 mm: +5 / −1 %, then −10 / −12 % at 0.5 mm, −32 % at 1 mm): there the linear tets'
    excess stiffness (+22 / +12 % over its own law in our FEM, as Drake on the same tets) offsets
    SVK's softness (−14 / −11 % in our FEM), so the pass is a cancellation, not agreement.
Drake (:class:`DrakeSettings`, needs ``pydrake``: the ``peers`` extra)
    A deformable FEM body (Drake's stable neo-Hookean on linear tets, SAP contact) on the same
    tets, the back vertices held by a wall boundary condition, the indenter a rigid hydroelastic
    geometry whose pressure field sets the contact's stiffness (:attr:`DrakeSettings.pressure_gradient`).
    On spheres it is within 10 % of our pad at every depth once the mesh resolves the contact
    (R = 25 mm on 1,710 vertices: +8 / +4 / −1 %; R = 10 mm on 4,725: +7 / +2 / −1 %, from +20 % at
    0.25 mm on 1,710).  On the flat it is within 10 % to 0.5 mm (−6 / −9 % on 1,386 vertices,
    −7 / −10 % on 3,366) and not at 1 mm (−14 / −15 %; −10 / −12 % against our pad on a 40 × 80 × 10
    mesh): Drake's stable neo-Hookean law is itself 14 % softer than ours there (our FEM run with
    Drake's law), and the contact sinks 46 µm.  A steeper pressure field (2e10 Pa/m) does not
    settle (SAP's near-rigid regime).
"""

from __future__ import annotations

import logging
import numbers
import time
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .settings import EngineSettings, import_mujoco

if TYPE_CHECKING:
    from ..fem.material import Material
    from ..fem.pad import PadGeometry

log = logging.getLogger(__name__)

__all__ = [
    "ENGINES",
    "INDENTERS",
    "STIFF_CONTACT",
    "DrakeSettings",
    "Indentation",
    "IndentProtocol",
    "indent_pad",
    "indenter_pad_mesh",
    "pad_tets",
]

INDENTERS = ("flat", "sphere")
ENGINES = ("mujoco", "drake")

#: The trials' engine settings with contacts that do not sink into the indenter: MuJoCo's contact
#: force is ``k r d / ((1 − d) A)`` for a penetration r, impedance d and the constraint's inverse
#: inertia A (∝ 1 / vertex mass), so a heavier pad (its weight does not act: gravity-compensated
#: and off here) and d → 1 stiffen it; the tips' penetration then stays below 1 % of δ = 0.25 mm
#: on the probe's meshes, and the force is the pad's, not the contact's.
STIFF_CONTACT = EngineSettings(contact_solimp=(0.9999, 0.9999, 1e-4, 0.5, 2.0), pad_mass=1.0)

# Freudenthal's 6 tets of a hex around its (0,0,0)-(1,1,1) diagonal (conforming between hexes):
# the split of MuJoCo's grid flexcomp, so a uniform PadGeometry gives the grid pad itself
_TETS = np.array(
    [
        [(0, 0, 0), (1, 0, 0), (1, 1, 0), (1, 1, 1)],
        [(0, 0, 0), (1, 0, 0), (1, 0, 1), (1, 1, 1)],
        [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 1, 1)],
        [(0, 0, 0), (0, 1, 0), (0, 1, 1), (1, 1, 1)],
        [(0, 0, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1)],
        [(0, 0, 0), (0, 0, 1), (0, 1, 1), (1, 1, 1)],
    ]
)


@dataclass(frozen=True)
class IndentProtocol:
    """How the indenter is driven (both engines)."""

    # indenter speed [m/s] between depths: slow against the pad's dynamics (a quasi-static press)
    speed: float = 0.01
    # hold [s] at each depth: the pad settles, then the force is averaged
    hold: float = 0.03
    # fraction of each hold, at its end, over which the force is averaged
    window: float = 0.25

    def __post_init__(self) -> None:
        for name, lo, hi, unit in (
            ("speed", 1e-4, 1.0, "m/s"),
            ("hold", 1e-3, 10.0, "s"),
            ("window", 0.01, 1.0, ""),
        ):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not lo <= v <= hi:
                raise ValueError(
                    f"IndentProtocol.{name} must be a number in [{lo:g}, {hi:g}] {unit}; got {v!r}"
                    + (" (a speed in mm/s? 10 mm/s = 0.01)" if name == "speed" else "")
                )


#: DrakeSettings.material -> pydrake's MaterialModel
_DRAKE_LAWS = {
    "neohookean": "kNeoHookean",
    "corotated": "kCorotated",
    "linear": "kLinear",
    "linearcorotated": "kLinearCorotated",
}


@dataclass(frozen=True)
class DrakeSettings:
    """Drake's options of the indentation (pydrake 1.51: deformable FEM, SAP contact)."""

    # discrete time step [s] of the plant (SAP); at 5 ms the flat's force is lost by 1 mm
    time_step: float = 1e-3
    # Drake's material law of the deformable pad: its stable neo-Hookean ("corotated", "linear" exist)
    material: str = "neohookean"
    # stiffness-proportional (Rayleigh) damping [s] of the pad: damps the press's transient
    stiffness_damping: float = 1e-3
    # the pad's density [kg/m³] (silicone)
    mass_density: float = 1100.0
    # contact stiffness [Pa/m]: the pressure per penetration of the indenter's hydroelastic field,
    # its modulus = gradient × the field's depth (R for a sphere, half the box's smallest side)
    pressure_gradient: float = 1e10
    # depth error [m] of the rigid sphere's inscribed tessellation (its resolution hint √(8 R sag):
    # 0.28 mm for R = 10 mm), 0.4 % of δ = 0.25 mm
    sphere_sag: float = 1e-6
    # PD stiffness [N/m] of the indenter's drive (critically damped), stiff against the pad
    drive_stiffness: float = 1e9
    # indenter mass [kg]
    indenter_mass: float = 0.1

    def __post_init__(self) -> None:
        if self.material not in _DRAKE_LAWS:
            raise ValueError(
                f"DrakeSettings.material must be one of {tuple(_DRAKE_LAWS)}; got {self.material!r}"
            )
        names = ("time_step", "stiffness_damping", "mass_density", "pressure_gradient", "sphere_sag")
        for name in (*names, "drive_stiffness", "indenter_mass"):
            v = getattr(self, name)
            zero = name == "stiffness_damping"  # undamped is a choice; the others must be > 0
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (v >= 0 if zero else v > 0):
                raise ValueError(
                    f"DrakeSettings.{name} must be a number {'>=' if zero else '>'} 0; got {v!r}"
                )
            if not v < float("inf"):
                raise ValueError(f"DrakeSettings.{name} must be finite; got {v!r}")
        if self.time_step > 2e-3:
            # validated at 1e-3 s; at 5e-3 s the press loses its force (the contact is not resolved)
            raise ValueError(
                f"DrakeSettings.time_step must be in (0, 2e-3] s; got {self.time_step!r} (1 ms = 1e-3)"
            )


@dataclass(frozen=True)
class Indentation:
    """One engine's indentation against our pad.

    depths : (n,) prescribed indenter travel past first touch [m], increasing.
    force : (n,) the engine's force on the indenter along the pressing axis [N] (mean over the
        hold's window); reference : (n,) our nonlinear pad FEM's, the same resultant [N];
    error : (n,) ``force / reference − 1``.
    travel : (n,) the indenter's actual travel [m] (MuJoCo's mocap: ``depths``; Drake's drive lags).
    penetration : (n,) the deepest contact penetration into the indenter [m] (the engine's
        contact compliance: the pad itself is compressed by about ``travel − penetration``).
    spread : (n,) the force's standard deviation over the window / its mean (settled: ≪ 1).
    vertices, elements : the engine's pad mesh (vertices include the pinned back layer).
    settings : the engine's settings, the protocol, the meshes (JSON-ready).
    seconds : wall time of the engine's run [s]; reference_seconds : of the FEM reference.
    engine_warnings : the engine's warnings {name: count} (empty when none).
    """

    engine: str
    indenter: str
    radius: float | None
    depths: np.ndarray
    force: np.ndarray
    reference: np.ndarray
    error: np.ndarray
    travel: np.ndarray
    penetration: np.ndarray
    spread: np.ndarray
    vertices: int
    elements: int
    settings: dict = field(repr=False)
    seconds: float = 0.0
    reference_seconds: float = 0.0
    engine_warnings: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """JSON-ready: the headline per depth (``depth`` [m], ``force`` and ``reference`` [N],
        ``error``, ``travel`` and ``penetration`` [m], ``spread``) and the run's record."""
        rows = [
            {
                "depth": float(d),
                "force": float(f),
                "reference": float(r),
                "error": float(e),
                "travel": float(t),
                "penetration": float(p),
                "spread": float(s),
            }
            for d, f, r, e, t, p, s in zip(
                self.depths,
                self.force,
                self.reference,
                self.error,
                self.travel,
                self.penetration,
                self.spread,
                strict=True,
            )
        ]
        return {
            "engine": self.engine,
            "indenter": self.indenter,
            "radius": self.radius,
            "depths": rows,
            "vertices": self.vertices,
            "elements": self.elements,
            "seconds": self.seconds,
            "reference_seconds": self.reference_seconds,
            "engine_warnings": dict(self.engine_warnings),
            "settings": self.settings,
        }


def indenter_pad_mesh(radius: float | None) -> PadGeometry:
    """The engine's pad nodes under an indenter of ``radius`` [m] (None: the flat), on the trials'
    20 × 40 × 5 mm pad (``PadGeometry()``'s size, as :func:`indent_pad`'s reference): under a
    sphere a graded mesh, 1 mm within 4 mm of the face's centre and within 4 mm below the face
    (the contact radius √(Rδ) is 1.6 mm at R = 10 mm, δ = 0.25 mm), growing by 1.5 outside
    (1,710 nodes); under the flat a uniform 10 × 20 × 5 hex mesh (2 × 2 × 1 mm).  Pass it as
    :func:`indent_pad`'s ``mesh``."""
    from ..fem.pad import PadGeometry

    return PadGeometry(nx=10, ny=20, nz=5) if radius is None else PadGeometry(grading=(0.004, 0.001, 1.5))


def pad_tets(geometry) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The tet mesh of a :class:`~workbench.fem.pad.PadGeometry`'s nodes: ``points`` (N, 3) [m]
    (x fastest last: index ``(i ny + j) nz + k``), ``tets`` (6 × hexes, 4) int, positively
    oriented, and ``back`` (K,) the indices of the bonded face ``z = 0``."""
    x, y, z = geometry.axes()
    nx, ny, nz = len(x), len(y), len(z)
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    points = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    i, j, k = (
        a.ravel() for a in np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), np.arange(nz - 1), indexing="ij")
    )
    tets = np.concatenate(
        [np.stack([((i + a) * ny + j + b) * nz + k + c for a, b, c in t], axis=1) for t in _TETS]
    )
    v = points[tets]
    vol = np.einsum("ij,ij->i", np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), v[:, 3] - v[:, 0])
    flip = vol < 0
    tets[flip, 1], tets[flip, 2] = tets[flip, 2].copy(), tets[flip, 1].copy()
    return points, tets, np.flatnonzero(np.isclose(points[:, 2], 0.0))


def _schedule(depths: np.ndarray, protocol: IndentProtocol) -> tuple[np.ndarray, np.ndarray, list]:
    """Breakpoints ``(times (m,), travel (m,))`` of the piecewise-linear drive from first touch
    through ``depths`` (ramp, hold, ...) and each depth's averaging window ``[(t0, t1), ...]``."""
    times, travel, windows = [0.0], [0.0], []
    for d in depths:
        t_ramp = times[-1] + (d - travel[-1]) / protocol.speed
        t_end = t_ramp + protocol.hold
        times += [t_ramp, t_end]
        travel += [d, d]
        windows.append((t_end - protocol.window * protocol.hold, t_end))
    return np.array(times), np.array(travel), windows


def _check_parts(indenter, engine, reference, material, settings, drake, protocol) -> tuple:
    """The indenter and engine names checked and ``(reference, material, settings, drake,
    protocol)`` with the defaults filled in, each checked to be of its type and the pad's rules
    of the trials (simulate_grasp) and of our FEM (condense_pad)."""
    from ..fem.material import Material
    from ..fem.pad import PadGeometry
    from ..plausible import check

    if indenter not in INDENTERS:
        raise ValueError(f"indenter must be one of {INDENTERS}; got {indenter!r}")
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}; got {engine!r}")
    reference = PadGeometry() if reference is None else reference
    material = Material() if material is None else material
    protocol = IndentProtocol() if protocol is None else protocol
    settings = EngineSettings() if settings is None else settings
    drake = DrakeSettings() if drake is None else drake
    for name, v, cls in (
        ("reference", reference, PadGeometry),
        ("material", material, Material),
        ("protocol", protocol, IndentProtocol),
        ("settings", settings, EngineSettings),
        ("drake", drake, DrakeSettings),
    ):
        if not isinstance(v, cls):
            article = "an" if cls.__name__[0] in "AEIOU" else "a"
            raise ValueError(f"{name} must be {article} {cls.__name__}; got {type(v).__name__}")
    # the pad's rules of the trials (simulate_grasp) and of our FEM (condense_pad)
    check("pad_modulus", material.E, "material.E (the pad's Young's modulus [Pa])")
    check("pad_size", reference.width, "reference.width [m]", warn=False)
    check("pad_size", reference.length, "reference.length [m]", warn=False)
    check("pad_thickness", reference.thickness, "reference.thickness [m]", warn=False)
    return reference, material, settings, drake, protocol


def _check_mesh(mesh, engine: str, reference, settings: EngineSettings):
    """The engine's pad nodes: ``mesh`` checked to be a PadGeometry of the reference's size, or
    for Drake the trials' grid when None (None for MuJoCo's own grid flexcomp)."""
    from ..fem.pad import PadGeometry

    size = (reference.width, reference.length, reference.thickness)
    if mesh is not None:
        if not isinstance(mesh, PadGeometry):
            raise ValueError(
                f"mesh must be a PadGeometry (or None: the trials' pad); got {type(mesh).__name__}"
            )
        if not np.allclose((mesh.width, mesh.length, mesh.thickness), size, rtol=1e-9, atol=0.0):
            raise ValueError(
                f"mesh is a {(mesh.width, mesh.length, mesh.thickness)} m pad and the reference a {size} m "
                "one: the engine's pad and ours must be the same pad — give the mesh the reference's "
                "width, length and thickness"
            )
    elif engine == "drake":  # the trials' pad's nodes (MuJoCo builds its own grid of them)
        nx, ny, nz = settings.pad_grid
        mesh = PadGeometry(*size, nx=nx - 1, ny=ny - 1, nz=nz - 1)
    return mesh


def _obstacle(indenter: str, radius, h: float):
    """The indenter as our FEM's obstacle touching the pad's face z = ``h`` [m]: a Plane, or a
    Sphere of ``radius`` [m] (which judges the radius)."""
    from ..fem.obstacles import Plane, Sphere

    if indenter == "flat":
        if radius is not None:
            raise ValueError(f"a flat indenter takes no radius; got radius={radius!r} (indenter='sphere'?)")
        return Plane(point=(0.0, 0.0, h), normal=(0.0, 0.0, -1.0))
    if radius is None:
        raise ValueError("a sphere indenter needs its radius [m], e.g. radius=0.01 for 10 mm")
    # the Sphere judges the radius (a number > 0, a plausible object size) before its centre
    lift = float(radius) if isinstance(radius, numbers.Real) and not isinstance(radius, bool) else 0.0
    return Sphere(center=(0.0, 0.0, h + lift), radius=radius)


def _check_depths(depths) -> np.ndarray:
    """(n,) the indentations [m], sorted: plausible compressions, distinct and > 0."""
    from ..plausible import check_each

    if np.ndim(depths) > 1:
        raise ValueError(f"depths must be a sequence of indentations [m]; got shape {np.shape(depths)}")
    given = list(np.atleast_1d(np.asarray(depths, dtype=object)))
    d = check_each("compression", given, "depths (indentations [m])")
    if d.size == 0 or not (d > 0).all() or np.unique(d).size != d.size:
        raise ValueError(f"depths must be distinct indentations > 0 [m]; got {given}")
    return np.sort(d)


def indent_pad(  # noqa: PLR0913 - four scalars of the test, then keyword-only objects already grouped
    indenter: str = "flat",
    radius: float | None = None,
    depths=(0.25e-3, 0.5e-3, 1e-3),
    engine: str = "mujoco",
    *,
    mesh: PadGeometry | None = None,
    reference: PadGeometry | None = None,
    material: Material | None = None,
    settings: EngineSettings | None = None,
    drake: DrakeSettings | None = None,
    protocol: IndentProtocol | None = None,
) -> Indentation:
    """Indent the pad by a ``"flat"`` (a rigid plate wider than the face) or a ``"sphere"`` of
    ``radius`` [m] by each of ``depths`` (n,) [m] in ``engine`` ("mujoco" or "drake"), and
    compare with our nonlinear pad FEM (module docstring).

    mesh : the engine's pad nodes, a :class:`~workbench.fem.pad.PadGeometry` of the reference's
        size (graded or not); ``None``: the trials' pad grid (``settings.pad_grid``).
    reference : our FEM's pad (size and mesh), default ``PadGeometry()`` (20 × 40 × 5 mm);
        material : default ``Material()`` (E = 1 MPa, ν = 0.45), the trials' silicone.
    settings : MuJoCo's (:class:`~.settings.EngineSettings`, default the trials'; see
        :data:`STIFF_CONTACT`); drake : Drake's (:class:`DrakeSettings`); protocol : the drive.

    Returns an :class:`Indentation`.  Depths are refused unless they are plausible pad
    compressions in metres (:func:`workbench.plausible.check`), > 0 and below the pad's thickness
    (:func:`workbench.fem.press`); a radius unless it is a plausible object size
    (:class:`workbench.fem.obstacles.Sphere`).  Without the engine, ImportError naming the extra.
    """
    from ..fem import press

    # the inputs, checked (module docstring), the defaults filled in (``mesh``: a PadGeometry
    # either way, or None for MuJoCo's own grid flexcomp of the trials' pad)
    reference, material, settings, drake, protocol = _check_parts(
        indenter, engine, reference, material, settings, drake, protocol
    )
    mesh = _check_mesh(mesh, engine, reference, settings)
    obstacle = _obstacle(indenter, radius, reference.thickness)
    depths = _check_depths(depths)
    if engine == "mujoco":
        import_mujoco()
    else:
        _import_pydrake()
    t0 = time.perf_counter()
    pressed = press(reference, material, obstacle, depths, fidelity="nonlinear")  # refuses δ >= h
    ref = np.array([float(pressed[float(d)].force_vector[2]) for d in depths])
    ref_seconds = time.perf_counter() - t0
    R = None if radius is None else float(radius)
    run = _run_mujoco if engine == "mujoco" else _run_drake
    t0 = time.perf_counter()
    out = run(
        indenter, R, depths, mesh, reference, material, settings if engine == "mujoco" else drake, protocol
    )
    seconds = time.perf_counter() - t0
    error = out["force"] / ref - 1.0
    record = {
        "engine": asdict(settings) if engine == "mujoco" else asdict(drake),
        "protocol": asdict(protocol),
        "mesh": f"the trials' grid flexcomp, {settings.pad_grid} points" if mesh is None else asdict(mesh),
        "reference": {"geometry": asdict(reference), "material": asdict(material), "fidelity": "nonlinear"},
        "drive": out["drive"],
        "contact": out["contact"],
    }
    if out["warnings"]:
        log.warning(
            "indentation (%s): the engine warned %s; its forces may not be reliable", engine, out["warnings"]
        )
    log.info(
        "indentation %s %s%s: force %s N against %s N (%s) on %d vertices in %.1f s",
        engine,
        indenter,
        "" if R is None else f" R {R * 1e3:g} mm",
        np.round(out["force"], 4).tolist(),
        np.round(ref, 4).tolist(),
        ", ".join(f"{100 * e:+.1f} %" for e in error),
        out["vertices"],
        seconds,
    )
    return Indentation(
        engine, indenter, R, depths, out["force"], ref, error, out["travel"], out["penetration"],
        out["spread"], out["vertices"], out["elements"], record, seconds, ref_seconds, out["warnings"],
    )  # fmt: skip


# ------------------------------------------------------------------------------------------ MuJoCo


def _flex_xml(mesh, reference, material, settings: EngineSettings) -> str:
    """The pad's ``<flexcomp>`` in the world frame (back face z = 0 pinned, face z = h): the trials'
    grid (``mesh`` None) or the tets of ``mesh``'s nodes."""
    from .pad import flexcomp_xml

    size = (reference.width, reference.length, reference.thickness)
    if mesh is None:
        return flexcomp_xml(
            "pad", size, material.E, material.nu, np.array([0.0, 0.0, size[2]]), np.array([0.0, 0.0, 1.0]),
            np.array([0.0, 1.0, 0.0]), settings,
        )  # fmt: skip
    points, tets, back = pad_tets(mesh)
    return (
        f'<flexcomp name="pad" type="direct" dim="3" point="{" ".join(f"{v:.9g}" for v in points.ravel())}" '
        f'element="{" ".join(map(str, tets.ravel()))}" radius="0" mass="{settings.pad_mass:g}">'
        f'<elasticity young="{material.E:g}" poisson="{material.nu:g}"/>'
        '<contact selfcollide="none" contype="0" conaffinity="0"/>'
        f'<pin id="{" ".join(map(str, back))}"/></flexcomp>'
    )


def _run_mujoco(indenter, R, depths, mesh, reference, material, settings: EngineSettings, protocol) -> dict:
    mujoco = import_mujoco()
    from .pad import add_tips, compile_spec, pad_spec

    w, ln, h = reference.width, reference.length, reference.thickness
    if indenter == "flat":  # a plate 5 mm wider than the face all round, its lower face at z = h
        geom = f'type="box" size="{w / 2 + 5e-3:g} {ln / 2 + 5e-3:g} 2.5e-3" pos="0 0 2.5e-3"'
    else:
        geom = f'type="sphere" size="{R:.9g}" pos="0 0 {R:.9g}"'
    # frictionless like our FEM: condim 1, and priority over the tips' contact parameters
    contact = f'contype="0" conaffinity="2" condim="1" priority="1" {settings.contact_attrs(0.0)}'
    xml = (
        f"<mujoco>{settings.option_xml()}<size memory='300M'/><worldbody>"
        f"{_flex_xml(mesh, reference, material, settings)}"
        f'<body name="indenter" mocap="true" pos="0 0 {h:.9g}">'
        f'<geom name="indenter" {geom} {contact}/></body>'
        "</worldbody></mujoco>"
    )
    spec = pad_spec(xml)
    add_tips(spec, "pad", np.array([0.0, 0.0, 1.0]), 0.0, settings)
    model = compile_spec(spec)
    data = mujoco.MjData(model)
    gid = model.geom("indenter").id
    times, travel, windows = _schedule(depths, protocol)
    dt = model.opt.timestep
    n = int(np.ceil(times[-1] / dt - 1e-9))
    f6 = np.zeros(6)
    samples: list[list[tuple[float, float]]] = [[] for _ in depths]
    for i in range(n):
        t = (i + 1) * dt
        data.mocap_pos[0] = (0.0, 0.0, h - np.interp(t, times, travel))
        mujoco.mj_step(model, data)
        k = next((k for k, (a, b) in enumerate(windows) if a <= t <= b + 1e-12), None)
        if k is None:
            continue
        fz, pen = 0.0, 0.0
        for j in range(data.ncon):
            c = data.contact[j]
            if gid not in (c.geom[0], c.geom[1]):
                continue
            mujoco.mj_contactForce(model, data, j, f6)
            # the normal (frame[0:3]) points from geom[0] to geom[1]; f6[0] pushes geom[1] along it
            sign = 1.0 if c.geom[1] == gid else -1.0
            fz += sign * f6[0] * c.frame[2]
            pen = max(pen, -c.dist)
        samples[k].append((fz, pen))
    warnings = {mujoco.mjtWarning(k).name: int(w.number) for k, w in enumerate(data.warning) if w.number > 0}
    drive, contact = {"indenter": "mocap body"}, {"tips": "add_tips", "condim": 1, "friction": 0.0}
    return _summarise(samples, depths.copy(), model.nflexvert, model.nflexelem, warnings, drive, contact)


def _summarise(samples, travel, vertices, elements, warnings, drive, contact) -> dict:
    """Means over each depth's window of ``samples`` [[(force, penetration[, travel]), ...], ...]."""
    force, pen, spread, trav = [], [], [], []
    for k, s in enumerate(samples):
        a = np.array(s, dtype=float)
        if a.size == 0:
            raise RuntimeError(f"no engine step fell in the averaging window of depth {k}: lengthen the hold")
        force.append(a[:, 0].mean())
        pen.append(a[:, 1].mean())
        spread.append(a[:, 0].std() / max(abs(a[:, 0].mean()), 1e-300))
        trav.append(a[:, 2].mean() if a.shape[1] > 2 else travel[k])
    return {
        "force": np.array(force),
        "penetration": np.array(pen),
        "spread": np.array(spread),
        "travel": np.array(trav),
        "vertices": int(vertices),
        "elements": int(elements),
        "warnings": warnings,
        "drive": drive,
        "contact": contact,
    }


# ------------------------------------------------------------------------------------------- Drake


def _import_pydrake() -> Any:
    try:
        import pydrake.all as drake
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(
            "the Drake indentation needs Drake's Python bindings: pip install -e '.[peers]' "
            "(or pip install 'drake>=1.51')"
        ) from exc
    return drake


def _vtk(points: np.ndarray, tets: np.ndarray) -> str:
    """Legacy-VTK text of a tet mesh (Drake's deformable mesh format)."""
    lines = [
        "# vtk DataFile Version 3.0",
        "pad",
        "ASCII",
        "DATASET UNSTRUCTURED_GRID",
        f"POINTS {len(points)} double",
    ]
    lines += [f"{x:.12g} {y:.12g} {z:.12g}" for x, y, z in points]
    lines.append(f"CELLS {len(tets)} {5 * len(tets)}")
    lines += [f"4 {a} {b} {c} {d}" for a, b, c, d in tets]
    lines.append(f"CELL_TYPES {len(tets)}")
    lines += ["10"] * len(tets)
    return "\n".join(lines) + "\n"


def _drake_indenter(pd, builder, indenter: str, R, h: float, w: float, ln: float, ds: DrakeSettings) -> tuple:
    """A plant (gravity off) of ``builder`` with the rigid, frictionless indenter on a PD-driven
    prismatic joint whose zero is first touch on the face z = ``h`` [m] (a plate ``w`` × ``ln``
    wide, or a sphere of radius ``R`` [m]): ``(plant, instance, joint, offset, contact)``,
    ``offset`` the indenter's centre above its lowest point [m], ``contact`` its record."""
    config = pd.MultibodyPlantConfig()
    config.time_step = ds.time_step
    config.discrete_contact_approximation = "sap"
    plant, _scene = pd.AddMultibodyPlant(config, builder)
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
    inst = plant.AddModelInstance("indenter")
    body = plant.AddRigidBody("indenter", inst, pd.SpatialInertia.SolidSphereWithMass(ds.indenter_mass, 0.01))
    rigid = pd.ProximityProperties()
    pd.AddContactMaterial(None, None, pd.CoulombFriction(0.0, 0.0), rigid)  # frictionless, as our FEM
    if indenter == "flat":  # a plate 5 mm wider than the face all round, 5 mm thick
        shape, offset, depth, resolution = pd.Box(w + 0.01, ln + 0.01, 5e-3), 2.5e-3, 2.5e-3, None
    else:
        shape, offset, depth = pd.Sphere(R), R, R
        resolution = float(np.sqrt(8.0 * R * ds.sphere_sag))
        rigid.AddProperty("hydroelastic", "resolution_hint", resolution)
    rigid.AddProperty("hydroelastic", "hydroelastic_modulus", ds.pressure_gradient * depth)
    plant.RegisterCollisionGeometry(body, pd.RigidTransform(), shape, "indenter", rigid)
    # the joint's zero is first touch: the indenter's lowest point on the face z = h; q = travel
    top = plant.AddFrame(
        pd.FixedOffsetFrame("touch", plant.world_frame(), pd.RigidTransform([0.0, 0.0, h + offset]))
    )
    joint = plant.AddJoint(pd.PrismaticJoint("press", top, body.body_frame(), [0.0, 0.0, -1.0]))
    actuator = plant.AddJointActuator("press", joint)
    kd = 2.0 * np.sqrt(ds.drive_stiffness * ds.indenter_mass)
    actuator.set_controller_gains(pd.PdControllerGains(p=ds.drive_stiffness, d=kd))
    contact = {
        "rigid_hydroelastic_modulus": ds.pressure_gradient * depth,
        "resolution_hint": resolution,
        "friction": 0.0,
    }
    return plant, inst, joint, offset, contact


def _drake_pad(
    pd, plant, points: np.ndarray, tets: np.ndarray, material, ds: DrakeSettings, h: float
) -> tuple:
    """Register the pad's tet mesh (``points`` (n, 3) [m], ``tets`` (m, 4)) as a deformable
    body of ``material``, its back z = 0 bonded: ``(deformable model, pad body id)``."""
    import tempfile
    from pathlib import Path

    cfg = pd.DeformableBodyConfig()
    cfg.set_youngs_modulus(material.E)
    cfg.set_poissons_ratio(material.nu)
    cfg.set_mass_density(ds.mass_density)
    cfg.set_stiffness_damping_coefficient(ds.stiffness_damping)
    cfg.set_material_model(getattr(pd.MaterialModel, _DRAKE_LAWS[ds.material]))
    soft = pd.ProximityProperties()
    pd.AddContactMaterial(None, None, pd.CoulombFriction(0.0, 0.0), soft)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "pad.vtk"
        path.write_text(_vtk(points, tets))
        geometry = pd.GeometryInstance(pd.RigidTransform(), pd.Mesh(str(path)), "pad")
        geometry.set_proximity_properties(soft)
        model = plant.mutable_deformable_model()
        pad_id = model.RegisterDeformableBody(geometry, cfg, 1.0)
    # the bonded back: zero displacement of the vertices at z = 0
    model.SetWallBoundaryCondition(pad_id, [0.0, 0.0, 1e-9 * h], [0.0, 0.0, 1.0])
    return model, pad_id


def _penetration(x: np.ndarray, indenter: str, R, zc: float, offset: float) -> float:
    """The indenter's deepest penetration [m] into the pad's vertices ``x`` (n, 3), its centre at
    height ``zc`` [m] (negative when apart)."""
    if indenter == "flat":
        return float(np.max(x[:, 2] - (zc - offset)))
    return float(np.max(R - np.linalg.norm(x - [0.0, 0.0, zc], axis=1)))


def _run_drake(indenter, R, depths, mesh, reference, material, ds: DrakeSettings, protocol) -> dict:
    pd = _import_pydrake()
    w, ln, h = reference.width, reference.length, reference.thickness
    points, tets, _ = pad_tets(mesh)
    builder = pd.DiagramBuilder()
    plant, inst, joint, offset, contact = _drake_indenter(pd, builder, indenter, R, h, w, ln, ds)
    model, pad_id = _drake_pad(pd, plant, points, tets, material, ds, h)
    plant.Finalize()
    times, travel, windows = _schedule(depths, protocol)
    traj = pd.PiecewisePolynomial.FirstOrderHold(times, travel.reshape(1, -1))
    source = builder.AddSystem(pd.TrajectorySource(traj, output_derivative_order=1))
    builder.Connect(source.get_output_port(), plant.get_desired_state_input_port(inst))
    diagram = builder.Build()
    sim = pd.Simulator(diagram)
    root = sim.get_mutable_context()
    ctx = plant.GetMyMutableContextFromRoot(root)
    sim.Initialize()
    port = plant.get_generalized_contact_forces_output_port(inst)
    n = int(np.ceil(times[-1] / ds.time_step - 1e-9))
    samples: list[list[tuple[float, float, float]]] = [[] for _ in depths]
    for i in range(n):
        t = (i + 1) * ds.time_step
        sim.AdvanceTo(t)
        k = next((k for k, (a, b) in enumerate(windows) if a <= t <= b + 1e-12), None)
        if k is None:
            continue
        q = float(joint.get_translation(ctx))
        fz = -float(port.Eval(ctx)[0])  # the generalized force along -z: the pad pushes the indenter up
        x = np.asarray(model.GetPositions(ctx, pad_id))
        x = x.T if x.ndim == 2 and x.shape[0] == 3 else x.reshape(-1, 3)
        pen = _penetration(x, indenter, R, h + offset - q, offset)  # h + offset - q: the indenter's centre
        samples[k].append((fz, max(pen, 0.0), q))
    return _summarise(
        samples, depths.copy(), len(points), len(tets), {}, {"indenter": "prismatic joint, PD drive"}, contact
    )

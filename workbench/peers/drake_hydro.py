"""Drake's hydroelastic contact between a compliant pad and a rigid sphere, cylinder or triangle
mesh, as a ContactProfile.

Needs ``pydrake`` (the optional extra ``peers``: ``pip install -e .[peers]``); importing this
module without it works, building a :class:`DrakeHydroPad` raises ``ImportError`` naming the fix.

Model (Elandt et al., IROS 2019; Drake's "Estimation of Hydroelastic Parameters",
https://drake.mit.edu/doxygen_cxx/group__hydro__params.html): a compliant body carries a pressure
field ``p = E_hydro · e``, ``e ∈ [0, 1]`` the *extent*; for a box, ``e`` = distance to the box's
boundary / half its smallest side (``geometry/proximity/make_box_field.cc``), so near a face the
box is an elastic (Winkler) foundation of depth ``H`` = half its smallest side: ``p = E_hydro u / H``.
Against a rigid body the contact surface is the rigid surface inside the box, each triangle
carrying the field's pressure, and ``f_n = (E_hydro / H) V`` at small depth (``V`` the overlap).

The box field is the distance to the *nearest* face: within ``u`` of a lateral face (``x = ±width/2``,
``y = ±length/2``) the pressure is ``E_hydro · (distance to that face) / H < E_hydro u / H``, falling
to 0 at the pad's edge, where the contact surface ends (the rigid surface is cut by the box).

Pad geometry (the frame of :func:`workbench.fem.press`): the pad face is the plane ``z = h``, the
pad is ``width`` × ``length`` in x × y, centred on the z axis, the obstacle (fixed, given in this
frame) lies above the face, touching it at ``delta = 0``, and the jaw moves by ``+delta`` along z.
``box="doubled"`` (default) registers a Box of height ``2h`` whose top face is the pad face (its
lower half stands in for the jaw): its foundation depth is then the layer thickness, ``H = h``, so
``p = E_hydro u / h`` — the Winkler layer of :mod:`workbench.peers.elastic_foundation` with
``k = E_hydro / h``.  ``box="layer"`` registers the layer itself, Box(width, length, h): ``H = h/2``,
twice as stiff for the same ``E_hydro``.

Modulus mapping (:func:`hydroelastic_modulus`): ``E_hydro = k H`` with ``k`` the foundation modulus
of the layer (:func:`workbench.peers.elastic_foundation.foundation_modulus`): with the default
``box="doubled"`` and ``kind="simple"`` that is ``E_hydro = E`` — Drake's own advice to start from
Young's modulus, and exactly the plain Winkler layer ``k = E/h``.  Both are a foundation model: no
Poisson coupling, no spreading of the load through the layer (Hertz's sink-in), so on a sphere
the contact is wider (radius ``√(2Rδ)`` against Hertz's ``√(Rδ)``) and its pressure a paraboloid
``∝ u`` instead of Hertz's elliptic dome.

Profile (:meth:`DrakeHydroPad.profile`): one element per contact-surface polygon (default,
``representation="polygon"``: ~3x fewer elements and conversion than triangles, same forces) or
triangle (``"triangle"``, which also keeps the mesh for export): centre = its centroid, normal =
Drake's face normal oriented out of the obstacle (into the pad), area = its area, pressure = the
field at the centroid (exact for the linear field: the mean of its vertices' values); the elements
lie on Drake's rigid surface: the obstacle's own triangles for a mesh, an inscribed tessellation for
a sphere or cylinder.
``profile.F = Σ p a`` is the pressure's integral over the curved surface, ``π R δ² E_hydro / H``
for a sphere (``∫ u dA`` over the cap, ``dA = 2π R dz``); the net normal force on the sphere,
``normal_wrench(profile)[2]`` (+z, pushed up by the pad below), is ``E_hydro V / H``.  Both
converge as the sphere's tessellation (``resolution``, default ``R/80``) is refined: the inscribed
polyhedron loses ``~resolution²/(8R)`` of depth, so the force is low by ``~resolution²/(4Rδ)``.

Cylinder (radius ``R``, axis in the face plane, here along y spanning the pad's length ``L``, the
contact ``|x| < √(2Rδ - δ²)`` clear of the x faces): ``p = (E_hydro / H) min(u, L/2 - |y|)``,
``u = δ - R + √(R² - x²)``.  The net normal force is ``(E_hydro / H) (L A - ∫ u² dx)``: ``A =
R² acos((R-δ)/R) - (R-δ) √(2Rδ - δ²)`` the circular segment of height ``δ``, less the taper at the
edges ``y = ±L/2`` (relatively ``~0.8 δ / L``: 4 % at δ = 1 mm on a 20 mm pad); ``profile.F``, over
the curved surface (``dA = R dθ dy``), is ``(E_hydro / H) R (L ∫ u dθ - ∫ u² dθ)``.  The inscribed
polygon (chords <= ``resolution``) loses ``ε ≈ resolution²/(8R)`` of depth, so both are low by
``~1.5 ε / δ`` (``A ∝ δ^1.5``).  A mesh is used as it is: an inscribed icosphere is low as a sphere
tessellated alike.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import peers as _checks
from ..profile import ContactProfile
from .elastic_foundation import foundation_modulus

__all__ = [
    "AXIS_TILT_TOL",
    "DrakeHydroPad",
    "Meshing",
    "foundation_depth",
    "hydroelastic_modulus",
    "sphere_force_law",
]

log = logging.getLogger(__name__)

BOXES = ("doubled", "layer")


def _import_pydrake() -> Any:
    try:
        import pydrake.geometry as geometry
    except ImportError as exc:  # pragma: no cover - exercised only without drake
        raise ImportError(
            "workbench.peers.drake_hydro needs Drake's Python bindings: pip install 'drake>=1.51' "
            "(or pip install -e '.[peers]')"
        ) from exc
    return geometry


def foundation_depth(h: float, width: float, length: float, box: str = "doubled") -> float:
    """Drake's foundation depth ``H`` [m] of the pad box: half its smallest side, which is ``h``
    for ``box="doubled"`` (height 2h) and ``h/2`` for ``box="layer"``; ValueError if a lateral side
    is the smallest (then the field's medial axis is not under the face)."""
    t = _checks.length("h (layer thickness)", h, "pad_thickness")
    w = _checks.length("width", width, "pad_size")
    ln = _checks.length("length", length, "pad_size")
    if box not in BOXES:
        raise ValueError(f"box must be one of {BOXES}; got {box!r}")
    height = 2.0 * t if box == "doubled" else t
    if height > min(w, ln):
        raise ValueError(
            f"the pad box's height {height:g} m exceeds its width/length ({w:g} x {ln:g} m): its pressure "
            "field would be set by the sides, not the face — use box='layer' or a wider pad"
        )
    return height / 2.0


def hydroelastic_modulus(
    E: float,
    h: float,
    width: float,
    length: float,
    *,
    nu: float | None = None,
    kind: str = "simple",
    box: str = "doubled",
) -> float:
    """``E_hydro = k H`` [Pa]: the hydroelastic modulus for which the pad box is the Winkler layer of
    foundation modulus ``k = foundation_modulus(E, h, nu, kind)``; ``E`` for the defaults."""
    k = foundation_modulus(E, h, nu, kind)
    return k * foundation_depth(h, width, length, box)


def sphere_force_law(R: float, delta: float, E_hydro: float, H: float) -> tuple[float, float]:
    """Drake's elastic-foundation law for a rigid sphere ``R`` at depth ``δ`` in a pad of
    foundation depth ``H`` [m]: ``(net normal force E V / H, pressure integral π R δ² E / H)`` [N],
    ``V = π δ² (3R - δ) / 3``."""
    r = _checks.length("R (sphere radius)", R)
    d = _checks.depth("delta", delta, below=r, below_name="the sphere radius R")
    e = _checks.modulus("E_hydro", E_hydro)
    fd = _checks.length("H (foundation depth)", H, "pad_thickness")
    V = np.pi * d * d * (3.0 * r - d) / 3.0
    return e * V / fd, np.pi * r * d * d * e / fd


#: largest ``|axis_z|`` (unit axis) of a cylinder taken as parallel to the pad face
AXIS_TILT_TOL = 1e-6


def _obstacle_kind(obstacle: Any) -> str:
    """The obstacle's kind, "sphere", "cylinder" or "mesh", for the obstacles of
    :mod:`workbench.fem.obstacles` (told apart by their attributes, so that this module does not
    import the FEM), else ValueError."""
    if hasattr(obstacle, "mesh") and hasattr(obstacle.mesh, "faces"):
        return "mesh"
    if all(hasattr(obstacle, a) for a in ("point", "axis", "radius")):
        return "cylinder"
    if hasattr(obstacle, "center") and hasattr(obstacle, "radius") and not hasattr(obstacle, "axis"):
        return "sphere"
    raise ValueError(
        "obstacle must be one of workbench.fem.obstacles' Sphere, Cylinder or MeshObstacle; got "
        f"{type(obstacle).__name__} — wrap any other closed shape as a MeshObstacle (a watertight "
        "trimesh in metres)"
    )


def _point(name: str, value: Any) -> np.ndarray:
    """A finite (3,) point [m], or ValueError."""
    c = np.asarray(value, dtype=np.float64)
    if c.shape != (3,) or not np.isfinite(c).all():
        raise ValueError(f"{name} must be a finite (3,) point [m]; got {value!r}")
    return c


def _cylinder_axis(axis: Any) -> np.ndarray:
    """The cylinder's unit axis (3,), parallel to the pad face ``z = h`` (``|a_z| <=``
    :data:`AXIS_TILT_TOL`), else ValueError."""
    a = np.asarray(axis, dtype=np.float64)
    n = float(np.linalg.norm(a)) if a.shape == (3,) else 0.0
    if not (np.isfinite(n) and n > 0):
        raise ValueError(f"cylinder axis must be a finite non-zero (3,) vector; got {axis!r}")
    a = a / n
    if abs(a[2]) > AXIS_TILT_TOL:
        raise ValueError(
            f"the cylinder's axis must be parallel to the pad face z = h (axis_z = 0); got axis "
            f"{tuple(np.round(a, 6))}, |axis_z| = {abs(a[2]):.3g} > {AXIS_TILT_TOL:g} — lay it in "
            "the x-y plane, e.g. axis=(0, 1, 0); a tilted or upright one meets the pad with Drake's "
            "finite cylinder's end, so model it as a capped MeshObstacle instead"
        )
    return a


def _obj_text(obstacle: Any) -> tuple[str, int]:
    """The MeshObstacle's triangles as Wavefront .obj text in metres (17 significant digits),
    wound outward, only its kept faces if it is one-sided (``facing``), and their number."""
    mesh = obstacle.mesh
    if not mesh.is_winding_consistent:
        raise ValueError(
            "the MeshObstacle's faces are not wound consistently, so Drake cannot tell its outside "
            "— repair the mesh first (trimesh.repair.fix_winding, fix_normals)"
        )
    faces = np.asarray(mesh.faces, dtype=np.int64)
    normals = np.asarray(mesh.face_normals, dtype=np.float64)
    if mesh.volume < 0:  # wound inward: Drake would find no contact at all
        faces, normals = faces[:, ::-1], -normals
    facing = getattr(obstacle, "facing", None)
    if facing is not None:
        faces = faces[normals @ np.asarray(facing, dtype=np.float64) > 0]
        if len(faces) == 0:
            raise ValueError(
                f"the one-sided MeshObstacle keeps no face (none has a normal along facing = {facing!r}) "
                "— pass facing=None or the direction the pad approaches from, e.g. (0, 0, -1)"
            )
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(mesh.vertices, dtype=np.float64).tolist()]
    lines += [f"f {i} {j} {k}" for i, j, k in (faces + 1).tolist()]
    return "\n".join(lines) + "\n", len(faces)


@dataclass(frozen=True)
class Meshing:
    """How Drake discretises a :class:`DrakeHydroPad`'s contact.

    resolution : the rigid sphere's or cylinder's tessellation hint [m], about its edge length
        (None: ``R/80``); a mesh obstacle takes none (its own triangles are used).
    cylinder_length : length [m] of Drake's finite cylinder standing in for an infinite one
        (None: 4x the pad's larger side); Cylinder obstacles only.
    representation : "polygon" (default) or "triangle" contact surfaces.

    Checked on construction (a positive length each, the representation's name; the lengths
    kept as floats); what depends on the obstacle (its kind, the pad's extent along a
    cylinder's axis) the pad checks.
    """

    resolution: float | None = None
    cylinder_length: float | None = None
    representation: str = "polygon"

    def __post_init__(self) -> None:
        if self.resolution is not None:
            object.__setattr__(
                self, "resolution", _checks.length("resolution", self.resolution, "element_size")
            )
        if self.cylinder_length is not None:
            object.__setattr__(
                self, "cylinder_length", _checks.length("cylinder_length", self.cylinder_length)
            )
        if self.representation not in ("triangle", "polygon"):
            raise ValueError(f"representation must be 'triangle' or 'polygon'; got {self.representation!r}")


class DrakeHydroPad:
    """A compliant hydroelastic pad and a rigid obstacle in a Drake SceneGraph, queried per ``delta``.

    obstacle : in the pad frame [m], one of (:mod:`workbench.fem.obstacles`)

        - ``Sphere`` (``.center``, ``.radius``): Drake's Sphere, tessellated at ``resolution``;
        - ``Cylinder`` (``.point``, ``.axis``, ``.radius``), infinite, its axis parallel to the pad
          face (``|axis_z| <= AXIS_TILT_TOL`` once normalised, else ValueError): Drake's finite
          Cylinder of length ``cylinder_length``, centred at the projection of the pad centre
          ``(0, 0, h/2)`` onto the axis, tessellated at ``resolution``;
        - ``MeshObstacle`` (``.mesh``, a watertight trimesh in metres, already transformed):
          Drake's rigid Mesh made of exactly these triangles (non-convex allowed), given to Drake
          as an in-memory .obj (no file is written); an inward-wound mesh is turned outward first
          (Drake finds no contact with inward triangles), and with ``.facing`` set only the faces
          the obstacle keeps (normal · facing > 0) are registered, as its signed distance does.

    h : layer thickness [m]; the pad face is ``z = h``.  width, length : pad size [m] along x, y.
    E_hydro : hydroelastic modulus [Pa] (see :func:`hydroelastic_modulus`).
    box : "doubled" (``H = h``) or "layer" (``H = h/2``), see the module docstring.
    meshing : Drake's ``resolution``, ``cylinder_length`` and ``representation``
        (:class:`Meshing`; None: ``Meshing()``).  A mesh is used as given, so a resolution with
        a MeshObstacle raises ValueError (coarsen or refine the mesh itself).
    edge : what a contact reaching the pad box's sides means — Drake cuts it there silently:
        "warn" (log that the patch is truncated: enlarge the pad) or "cut" (on purpose, e.g. a
        cylinder or an elongated mesh spanning the pad); default "cut" for a Cylinder, else "warn".
    The cylinder's length (``meshing.cylinder_length``) must be at least the pad's extent along
    the axis, ``|a_x| width + |a_y| length``, so that its flat caps lie beyond the pad; it is
    for Cylinders only (ValueError otherwise).

    Attributes: ``kind`` ("sphere", "cylinder" or "mesh"), ``R`` (radius [m]; None for a mesh),
    ``center`` (the sphere's centre or the Drake cylinder's centre (3,) [m]; None for a mesh),
    ``axis`` (the cylinder's unit axis (3,); None otherwise), ``resolution`` (None for a mesh),
    ``cylinder_length`` (None unless a cylinder), ``H`` (foundation depth [m]).

    The scene is built once (Drake tessellates here); each :meth:`profile` call moves the pad and
    runs ``QueryObject.ComputeContactSurfaces``; its wall time is appended to ``query_seconds``
    (the query) and ``convert_seconds`` (the conversion to a profile).
    """

    def __init__(
        self,
        obstacle: Any,
        h: float,
        E_hydro: float,
        *,
        width: float = 0.04,
        length: float = 0.04,
        box: str = "doubled",
        meshing: Meshing | None = None,
        edge: str | None = None,
    ) -> None:
        m = Meshing() if meshing is None else meshing
        self._set_geometry(obstacle, h, width, length, box)
        self.E_hydro = _checks.modulus("E_hydro (hydroelastic modulus)", E_hydro)
        self._set_resolution(m.resolution)
        self._set_cylinder_length(m.cylinder_length)
        self.representation = m.representation
        edge = ("cut" if self.kind == "cylinder" else "warn") if edge is None else edge
        if edge not in ("warn", "cut"):
            raise ValueError(
                f"edge must be 'warn' or 'cut' (the pad's sides cut the contact on purpose); got {edge!r}"
            )
        self.edge = edge
        mesh_obj = _obj_text(obstacle) if self.kind == "mesh" else None
        g = _import_pydrake()  # after the checks: careless input is reported with or without Drake
        self._build(g, mesh_obj)
        self.query_seconds: list[float] = []
        self.convert_seconds: list[float] = []

    def _set_geometry(self, obstacle: Any, h: float, width: float, length: float, box: str) -> None:
        """The obstacle's kind, radius, centre and axis, and the pad's size and foundation depth,
        checked (the attributes of the class docstring)."""
        self.kind = _obstacle_kind(obstacle)
        self.obstacle = obstacle
        self.R: float | None = None
        self.center: np.ndarray | None = None
        self.axis: np.ndarray | None = None
        if self.kind == "sphere":
            self.R = _checks.length("obstacle radius", obstacle.radius)
            self.center = _point("obstacle center", obstacle.center)
        elif self.kind == "cylinder":
            self.R = _checks.length("obstacle radius", obstacle.radius)
            self.axis = _cylinder_axis(obstacle.axis)
            foot = _point("cylinder point", obstacle.point)
        self.H = foundation_depth(h, width, length, box)
        self.h = float(h)
        if self.kind == "cylinder":  # the projection of the pad centre (0, 0, h/2) onto the axis
            self.center = foot + float((np.array([0.0, 0.0, 0.5 * self.h]) - foot) @ self.axis) * self.axis
        self.width, self.length, self.box = float(width), float(length), box

    def _set_resolution(self, resolution: float | None) -> None:
        """The tessellation hint of a sphere or cylinder (default ``R/80``); None for a mesh."""
        if self.kind == "mesh":
            if resolution is not None:
                raise ValueError(
                    f"resolution applies to a sphere or cylinder, which Drake tessellates; got "
                    f"resolution={resolution!r} with a MeshObstacle, whose own triangles are used — drop "
                    "it, or refine/coarsen the mesh itself (e.g. trimesh's subdivide)"
                )
            self.resolution: float | None = None
        else:
            self.resolution = self.R / 80.0 if resolution is None else resolution

    def _set_cylinder_length(self, cylinder_length: float | None) -> None:
        """The length of Drake's finite cylinder (default 4x the pad's larger side), at least the
        pad's extent along its axis; None unless the obstacle is a cylinder."""
        self.cylinder_length: float | None = None
        if self.kind == "cylinder":
            span = abs(self.axis[0]) * self.width + abs(self.axis[1]) * self.length
            if cylinder_length is None:
                self.cylinder_length = 4.0 * max(self.width, self.length)
            else:
                self.cylinder_length = cylinder_length
                if self.cylinder_length < span:
                    raise ValueError(
                        f"cylinder_length must be at least the pad's extent along the cylinder's axis, "
                        f"{span:g} m; got {self.cylinder_length:g} m — Drake's finite cylinder would end "
                        "over the pad and its flat caps cut the contact: pass a longer one or leave the "
                        "default (4x the pad's larger side)"
                    )
        elif cylinder_length is not None:
            raise ValueError(
                f"cylinder_length applies to a Cylinder obstacle only; got cylinder_length="
                f"{cylinder_length!r} with a {self.kind} — drop it"
            )

    def _build(self, g: Any, mesh_obj: tuple[str, int] | None) -> None:
        """The SceneGraph (Drake's ``pydrake.geometry`` module ``g``): the compliant pad box and
        the rigid obstacle (``mesh_obj``: a mesh's .obj text and face count), and its context."""
        from pydrake.math import RigidTransform

        self._rep = (
            g.HydroelasticContactRepresentation.kTriangle
            if self.representation == "triangle"
            else g.HydroelasticContactRepresentation.kPolygon
        )
        self._RigidTransform = RigidTransform
        self._g = g
        sg = g.SceneGraph()
        src = sg.RegisterSource("workbench.peers")
        self._f_pad = sg.RegisterFrame(src, g.GeometryFrame("pad"))
        self._f_obj = sg.RegisterFrame(src, g.GeometryFrame("object"))
        height = 2.0 * self.H
        self._pad_id = sg.RegisterGeometry(
            src,
            self._f_pad,
            g.GeometryInstance(RigidTransform(), g.Box(self.width, self.length, height), "pad"),
        )
        props = g.ProximityProperties()
        # the hint is ignored for boxes (Drake meshes them along their medial axis), needed by the API
        g.AddCompliantHydroelasticProperties(min(self.width, self.length, height), self.E_hydro, props)
        sg.AssignRole(src, self._pad_id, props)
        rigid = g.ProximityProperties()
        shape = self._rigid_shape(g, mesh_obj)
        if self.resolution is None:
            g.AddRigidHydroelasticProperties(rigid)  # a mesh is not tessellated: no hint
        else:
            g.AddRigidHydroelasticProperties(self.resolution, rigid)
        self._obj_id = sg.RegisterGeometry(
            src, self._f_obj, g.GeometryInstance(RigidTransform(), shape, "object")
        )
        sg.AssignRole(src, self._obj_id, rigid)
        self._sg, self._src = sg, src
        self._ctx = sg.CreateDefaultContext()

    def _rigid_shape(self, g: Any, mesh_obj: tuple[str, int] | None) -> Any:
        """Drake's shape of the obstacle; sets its pose ``_X_obj`` in the pad frame."""
        from pydrake.math import RigidTransform, RotationMatrix

        if self.kind == "sphere":
            shape = g.Sphere(self.R)
            self._X_obj = RigidTransform(self.center)
        elif self.kind == "cylinder":
            # Drake's cylinder runs along its local z: rotate z onto the axis
            shape = g.Cylinder(self.R, self.cylinder_length)
            self._X_obj = RigidTransform(RotationMatrix.MakeFromOneVector(self.axis, 2), self.center)
        else:
            from pydrake.common import MemoryFile

            text, n_faces = mesh_obj
            shape = g.Mesh(g.InMemoryMesh(mesh_file=MemoryFile(text, ".obj", "MeshObstacle")), 1.0)
            self._X_obj = RigidTransform()
            log.debug("DrakeHydroPad: rigid mesh of %d triangles", n_faces)
        return shape

    def _pose(self, delta: float) -> None:
        poses = self._g.FramePoseVector()
        # the box's top face at z = h + delta
        poses.set_value(self._f_pad, self._RigidTransform([0.0, 0.0, self.h + delta - self.H]))
        poses.set_value(self._f_obj, self._X_obj)
        self._sg.get_source_pose_port(self._src).FixValue(self._ctx, poses)

    def profile(self, delta: float) -> ContactProfile | None:
        """The contact profile at jaw displacement ``delta`` [m] (0 <= delta < h), or ``None`` if the
        obstacle does not touch the pad.  Its elements lie on Drake's rigid surface (the tessellated
        sphere or cylinder, or the mesh) inside the pad box, normals out of the obstacle (into the
        pad), in the pad frame [m]."""
        d = _checks.real("delta (jaw displacement)", delta, "m")
        if d < 0 or d >= self.h:
            raise ValueError(
                f"delta must be a jaw displacement in [0, h = {self.h:g}) m; got {d!r} — displacements are "
                "in metres (1 mm = 1e-3)"
            )
        _checks.compression("delta (jaw displacement)", d)
        self._pose(d)
        t0 = time.perf_counter()
        query = self._sg.get_query_output_port().Eval(self._ctx)
        surfaces = query.ComputeContactSurfaces(self._rep)
        t1 = time.perf_counter()
        self.query_seconds.append(t1 - t0)
        if not surfaces:
            return None
        if len(surfaces) != 1:  # pragma: no cover - one pad, one obstacle
            raise RuntimeError(f"expected one contact surface, got {len(surfaces)}")
        prof, extent = self._convert(surfaces[0])
        self.convert_seconds.append(time.perf_counter() - t1)
        if prof is not None and self.edge == "warn":
            # Drake cuts the contact at the box's sides without a word: a patch whose vertices reach
            # them is truncated (unless meant: edge="cut"); the elements' centroids stay up to a
            # third of an element inside, so they cannot tell
            reach = extent / np.array([self.width, self.length]) * 2.0
            if (reach > 1.0 - 1e-6).any():
                log.warning(
                    "DrakeHydroPad.profile(delta=%g): the contact reaches the pad's sides (%g x %g m): the "
                    "patch is truncated — enlarge width/length",
                    d,
                    self.width,
                    self.length,
                )
        log.debug(
            "DrakeHydroPad.profile(delta=%g): %s in %.3g ms (+ %.3g ms conversion)",
            d,
            prof,
            1e3 * self.query_seconds[-1],
            1e3 * self.convert_seconds[-1],
        )
        return prof

    def _convert(self, s: Any) -> tuple[ContactProfile | None, np.ndarray]:
        """The profile of Drake's contact surface ``s`` and the (2,) largest |x|, |y| of its vertices."""
        # Drake: face normals point out of N and into M; the profile's point out of the obstacle
        sign = 1.0 if s.id_N() == self._obj_id else -1.0
        if s.is_triangle():
            mesh, field = s.tri_mesh_W(), s.tri_e_MN()
            verts = np.array(mesh.vertices(), dtype=np.float64).reshape(-1, 3)
            tris = np.array(
                [[t.vertex(0), t.vertex(1), t.vertex(2)] for t in mesh.triangles()], dtype=np.int64
            )
            pv = np.array([field.EvaluateAtVertex(i) for i in range(len(verts))])
            corners = verts[tris]
            cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
            area = 0.5 * np.linalg.norm(cross, axis=1)
            ok = area > 0
            normals = sign * cross[ok] / (2.0 * area[ok, None])
            # Drake winds the triangles along its face normal: check the first one
            if np.dot(normals[0], sign * np.asarray(mesh.face_normal(int(np.argmax(ok))))) < 0:
                normals = -normals
            centers = corners[ok].mean(axis=1)
            pressure = pv[tris[ok]].mean(axis=1)
            area = area[ok]
            faces = tris[ok]
        else:
            mesh, field = s.poly_mesh_W(), s.poly_e_MN()
            n = mesh.num_elements()
            centers = np.array([mesh.element_centroid(i) for i in range(n)], dtype=np.float64).reshape(-1, 3)
            normals = sign * np.array([mesh.face_normal(i) for i in range(n)], dtype=np.float64).reshape(
                -1, 3
            )
            area = np.array([mesh.area(i) for i in range(n)])
            pressure = np.array([field.EvaluateCartesian(i, centers[i]) for i in range(n)])
            # the vertices only to tell a cut patch (edge="warn"): a Python loop, ~1 % of a query
            n_v = mesh.num_vertices() if self.edge == "warn" else 0
            corners = np.array([mesh.vertex(i) for i in range(n_v)], dtype=np.float64).reshape(-1, 3)
            verts, faces = None, None
        pressure = np.clip(pressure, 0.0, None)  # round-off at the rim (field 0 on the box surface)
        keep = (area > 1e-9 * np.median(area)) & np.isfinite(pressure)
        extent = np.abs(corners.reshape(-1, 3)[:, :2]).max(axis=0, initial=0.0)
        if not (pressure[keep] > 0).any():
            return None, extent
        prof = ContactProfile(
            centers[keep],
            normals[keep],
            area[keep],
            pressure[keep],
            vertices=verts,
            faces=None if faces is None else faces[keep],
        )
        return prof, extent

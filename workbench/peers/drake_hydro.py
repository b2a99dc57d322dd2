"""Drake's hydroelastic contact between a compliant pad and a rigid sphere, as a ContactProfile.

Needs ``pydrake`` (the optional extra ``peers``: ``pip install -e .[peers]``); importing this
module without it works, building a :class:`DrakeHydroPad` raises ``ImportError`` naming the fix.

Model (Elandt et al., IROS 2019; Drake's "Estimation of Hydroelastic Parameters",
https://drake.mit.edu/doxygen_cxx/group__hydro__params.html): a compliant body carries a pressure
field ``p = E_hydro · e``, ``e ∈ [0, 1]`` the *extent*; for a box, ``e`` = distance to the box's
boundary / half its smallest side (``geometry/proximity/make_box_field.cc``), so near a face the
box is an elastic (Winkler) foundation of depth ``H`` = half its smallest side: ``p = E_hydro u / H``.
Against a rigid body the contact surface is the rigid surface inside the box, each triangle
carrying the field's pressure, and ``f_n = (E_hydro / H) V`` at small depth (``V`` the overlap).

Pad geometry (the frame of :func:`workbench.fem.press`): the pad face is the plane ``z = h``, the
pad is ``width`` × ``length`` in x × y, the sphere touches at ``delta = 0`` and the jaw moves by
``+delta`` along z.  ``box="doubled"`` (default) registers a Box of height ``2h`` whose top face is
the pad face (its lower half stands in for the jaw): its foundation depth is then the layer
thickness, ``H = h``, so ``p = E_hydro u / h`` — the Winkler layer of
:mod:`workbench.peers.elastic_foundation` with ``k = E_hydro / h``.  ``box="layer"`` registers the
layer itself, Box(width, length, h): ``H = h/2``, twice as stiff for the same ``E_hydro``.

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
Drake's face normal oriented out of the sphere (into the pad), area = its area, pressure = the
field at the centroid (exact for the linear field: the mean of its vertices' values).
``profile.F = Σ p a`` is the pressure's integral over the curved surface, ``π R δ² E_hydro / H``
for a sphere (``∫ u dA`` over the cap, ``dA = 2π R dz``); the net normal force on the sphere,
``normal_wrench(profile)[2]`` (+z, pushed up by the pad below), is ``E_hydro V / H``.  Both
converge as the sphere's tessellation (``resolution``, default ``R/80``) is refined: the inscribed
polyhedron loses ``~resolution²/(8R)`` of depth, so the force is low by ``~resolution²/(4Rδ)``.
"""

from __future__ import annotations

import logging
import time
from typing import Any

import numpy as np

from .. import peers as _checks
from ..profile import ContactProfile
from .elastic_foundation import foundation_modulus

__all__ = ["DrakeHydroPad", "foundation_depth", "hydroelastic_modulus", "sphere_force_law"]

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
    t = _checks.length("h (layer thickness)", h)
    w = _checks.length("width", width)
    ln = _checks.length("length", length)
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
    fd = _checks.length("H (foundation depth)", H)
    V = np.pi * d * d * (3.0 * r - d) / 3.0
    return e * V / fd, np.pi * r * d * d * e / fd


class DrakeHydroPad:
    """A compliant hydroelastic pad and a rigid sphere in a Drake SceneGraph, queried per ``delta``.

    obstacle : the sphere, a :class:`workbench.fem.obstacles.Sphere` (centre [m], radius [m]).
    h : layer thickness [m]; the pad face is ``z = h``.  width, length : pad size [m].
    E_hydro : hydroelastic modulus [Pa] (see :func:`hydroelastic_modulus`).
    box : "doubled" (``H = h``) or "layer" (``H = h/2``), see the module docstring.
    resolution : the rigid sphere's tessellation hint [m] (default ``R/80``).
    representation : "polygon" (default) or "triangle" contact surfaces.

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
        resolution: float | None = None,
        representation: str = "polygon",
    ) -> None:
        radius = getattr(obstacle, "radius", None)
        center = getattr(obstacle, "center", None)
        if radius is None or center is None or hasattr(obstacle, "axis"):
            raise ValueError(
                f"obstacle must be a sphere with .center and .radius (workbench.fem.obstacles.Sphere); "
                f"got {type(obstacle).__name__} — other shapes are not wired to Drake yet"
            )
        self.R = _checks.length("obstacle radius", radius)
        c = np.asarray(center, dtype=np.float64)
        if c.shape != (3,) or not np.isfinite(c).all():
            raise ValueError(f"obstacle center must be a finite (3,) point [m]; got {center!r}")
        self.center = c
        self.H = foundation_depth(h, width, length, box)
        self.h = float(h)
        self.width, self.length, self.box = float(width), float(length), box
        self.E_hydro = _checks.modulus("E_hydro (hydroelastic modulus)", E_hydro)
        self.resolution = self.R / 80.0 if resolution is None else _checks.length("resolution", resolution)
        if representation not in ("triangle", "polygon"):
            raise ValueError(f"representation must be 'triangle' or 'polygon'; got {representation!r}")
        self.representation = representation
        g = _import_pydrake()  # after the checks: careless input is reported with or without Drake
        from pydrake.math import RigidTransform

        self._rep = (
            g.HydroelasticContactRepresentation.kTriangle
            if representation == "triangle"
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
        self._obj_id = sg.RegisterGeometry(
            src, self._f_obj, g.GeometryInstance(RigidTransform(), g.Sphere(self.R), "object")
        )
        rigid = g.ProximityProperties()
        g.AddRigidHydroelasticProperties(self.resolution, rigid)
        sg.AssignRole(src, self._obj_id, rigid)
        self._sg, self._src = sg, src
        self._ctx = sg.CreateDefaultContext()
        self.query_seconds: list[float] = []
        self.convert_seconds: list[float] = []

    def _pose(self, delta: float) -> None:
        poses = self._g.FramePoseVector()
        # the box's top face at z = h + delta
        poses.set_value(self._f_pad, self._RigidTransform([0.0, 0.0, self.h + delta - self.H]))
        poses.set_value(self._f_obj, self._RigidTransform(self.center))
        self._sg.get_source_pose_port(self._src).FixValue(self._ctx, poses)

    def profile(self, delta: float) -> ContactProfile | None:
        """The contact profile at jaw displacement ``delta`` [m] (0 <= delta < h), or ``None`` if the
        sphere does not touch the pad."""
        d = _checks.real("delta (jaw displacement)", delta, "m")
        if d < 0 or d >= self.h:
            raise ValueError(
                f"delta must be a jaw displacement in [0, h = {self.h:g}) m; got {d!r} — displacements are "
                "in metres (1 mm = 1e-3)"
            )
        self._pose(d)
        t0 = time.perf_counter()
        query = self._sg.get_query_output_port().Eval(self._ctx)
        surfaces = query.ComputeContactSurfaces(self._rep)
        t1 = time.perf_counter()
        self.query_seconds.append(t1 - t0)
        if not surfaces:
            return None
        if len(surfaces) != 1:  # pragma: no cover - one pad, one sphere
            raise RuntimeError(f"expected one contact surface, got {len(surfaces)}")
        prof = self._convert(surfaces[0])
        self.convert_seconds.append(time.perf_counter() - t1)
        log.debug(
            "DrakeHydroPad.profile(delta=%g): %s in %.3g ms (+ %.3g ms conversion)",
            d,
            prof,
            1e3 * self.query_seconds[-1],
            1e3 * self.convert_seconds[-1],
        )
        return prof

    def _convert(self, s: Any) -> ContactProfile | None:
        # Drake: face normals point out of N and into M; the profile's point out of the sphere
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
            verts, faces = None, None
        pressure = np.clip(pressure, 0.0, None)  # round-off at the rim (field 0 on the box surface)
        keep = (area > 1e-9 * np.median(area)) & np.isfinite(pressure)
        if not (pressure[keep] > 0).any():
            return None
        return ContactProfile(
            centers[keep],
            normals[keep],
            area[keep],
            pressure[keep],
            vertices=verts,
            faces=None if faces is None else faces[keep],
        )

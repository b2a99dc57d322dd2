"""Validation (d) of the engine judge, thin walls: why it is blocked on MuJoCo, on a small mesh.

MuJoCo 4's 2D flex (``elastic2d="both"``) bends by hinges between triangles, and how stiff a
hinge is depends on the triangles' shape.  A cantilever strip (PET, E 2.5 GPa, t 0.5 mm, ν 0,
50 × 10 mm, clamped by its first two columns of vertices) under a tip line load is checked
against beam theory, δ = F L³ / (3 E I) with I = b t³ / 12 and L the span from the clamp's
last column: cells twice as tall (across the strip) as long bend far too easily, cells half as
tall come within 15 %.  On a curved wall the cells are as tall as the mesh makes them, which is why a
squeezed PET cylinder missed our wall FEM by −19 to −30 % at every mesh we could run (README,
"Thin-walled objects"); Drake has no shells at all.  If a MuJoCo release fixes the hinge, the
first assertion fails and item (d) should be tried again.
"""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

E, T = 2.5e9, 5e-4  # PET [Pa], wall thickness [m]
LENGTH, WIDTH = 0.05, 0.01  # strip [m]
LOAD = 1e-3  # tip line load [N]: small, so the deflection stays linear (δ/t ~ 0.3)


def _strip_tip_deflection(nx: int, ny: int) -> tuple[float, float]:
    """(MuJoCo's tip deflection, beam theory's) [m] of the strip on an nx × ny vertex grid."""
    xs, ys = np.linspace(0.0, LENGTH, nx), np.linspace(0.0, WIDTH, ny)
    points = np.array([[x, y, 0.0] for y in ys for x in xs])

    def vid(i: int, j: int) -> int:
        return j * nx + i

    tris = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            a0, a1, b0, b1 = vid(i, j), vid(i + 1, j), vid(i, j + 1), vid(i + 1, j + 1)
            # alternating diagonals: no preferred direction for the hinges
            tris += [(a0, a1, b1), (a0, b1, b0)] if (i + j) % 2 == 0 else [(a0, a1, b0), (a1, b1, b0)]
    pins = [vid(i, j) for j in range(ny) for i in (0, 1)]
    xml = f"""<mujoco>
  <option integrator="discrete" gravity="0 0 0" timestep="1e-3" solver="Newton" tolerance="1e-10"
          iterations="100"/>
  <worldbody>
    <flexcomp name="strip" type="direct" dim="2" radius="1e-4" mass="0.01"
              point="{" ".join(f"{v:.12g}" for v in points.ravel())}"
              element="{" ".join(str(v) for v in np.ravel(tris))}">
      <elasticity young="{E:g}" poisson="0" thickness="{T:g}" elastic2d="both" damping="1e-3"/>
      <contact contype="0" conaffinity="0"/>
      <pin id="{" ".join(map(str, pins))}"/>
    </flexcomp>
  </worldbody>
</mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    tip = [vid(nx - 1, j) for j in range(ny)]
    share = np.ones(ny)
    share[[0, -1]] = 0.5  # a uniform line load lumped on the tip's vertices
    share *= LOAD / share.sum()
    bodies = [model.flex_vertbodyid[v] for v in tip]
    for k in range(1500):  # ramped over 0.7 s, then damped to rest
        data.xfrc_applied[bodies, 2] = share * min(1.0, (k + 1) / 700)
        mujoco.mj_step(model, data)
    assert np.abs(data.qvel).max() < 1e-4  # at rest: a static deflection
    got = data.flexvert_xpos.reshape(-1, 3)[tip, 2].mean()
    span = LENGTH - LENGTH / (nx - 1)  # from the clamp's last column
    beam = LOAD * span**3 / (3 * E * WIDTH * T**3 / 12)
    return float(got), float(beam)


def test_mujocos_shell_bending_depends_on_the_triangles_shape():
    # the same 21 columns along the strip, cells 2, 1 and 0.5 times as tall as long
    excess = []
    for ny in (3, 5, 9):
        got, beam = _strip_tip_deflection(21, ny)
        excess.append(got / beam - 1)
    assert excess[0] > 0.5  # twice as tall: more than 1.5 x beam theory's deflection
    assert excess[0] > excess[1] > excess[2] > 0  # stiffer as the cells flatten, never too stiff
    assert excess[2] < 0.15  # half as tall: within the 15 % item (d) asks of a cylinder

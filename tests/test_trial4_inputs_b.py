"""Careless inputs a new user fed the grasp layer, each of which was accepted silently or
refused with the wrong advice: a millimetre mesh with a mass, an inside-out mesh, a task
torque in N·mm, a torsion length in mm, a zero normal, a stiffness in N/mm, one model name
as a string, and the minimal-force scale of a grasp that cannot hold.  Each is now refused
(the message names the fix) or accepted with the right number, checked against the closed
form of a box held by two flat jaws."""

import warnings

import numpy as np
import pytest
import trimesh

from workbench.fem.material import Material
from workbench.fem.obstacles import MeshObstacle
from workbench.fem.pad import PadGeometry
from workbench.grasp import Jaws, ModelOptions, Task, evaluate_grasp
from workbench.grasp.contacts import point_contact, soft_point_contact
from workbench.grasp.work import work

MU, FORCE, MASS = 0.5, 10.0, 0.3
G = {"p1": [0.0, -0.02, 0.0], "p2": [0.0, 0.02, 0.0], "axis": [0.0, 1.0, 0.0]}


@pytest.fixture(scope="module")
def box():
    # 40 mm between the jaws, 60 mm tall: two flat 20 x 40 mm pads fit on its faces
    return trimesh.creation.box(extents=(0.05, 0.04, 0.06))


def _mm(grasp):
    return {k: np.asarray(v, float) for k, v in grasp.items()}


def test_a_millimetre_mesh_with_a_mass_is_evaluated_in_metres(box):
    # the mass check read the unconverted mesh (a 1.2e5 cm³ box: "a mesh in millimetres?") and
    # refused the very call units="mm" exists for; now the mesh is converted by the one gate of
    # every mesh input first, and the answer is the metre mesh's
    from workbench.units import mesh_in_metres

    mm = box.copy()
    mm.apply_scale(1e3)
    task = Task(mass=MASS, com=[0, 0, 0])
    kw = {"jaws": Jaws(force=FORCE), "options": ModelOptions("soft_point", MU)}
    in_m = evaluate_grasp(box, _mm(G), task, **kw)
    in_mm = evaluate_grasp(mesh_in_metres(mm, "object", units="mm"), _mm(G), task, **kw)
    # a millimetre mesh as it is: named, with the call to make
    with pytest.raises(ValueError, match=r"spans 60 m .*millimetres: convert it first: .*mesh_in_metres"):
        evaluate_grasp(mm, _mm(G), task, **kw)
    # two flat jaws on a box, gravity across the axis: friction holds m g with 2 μ F s
    assert in_m.min_force.scale == pytest.approx(MASS * 9.81 / (2 * MU * FORCE), rel=2e-3)
    assert in_mm.min_force.scale == pytest.approx(in_m.min_force.scale, rel=1e-9)


def test_an_inside_out_mesh_is_refused_by_name(box):
    # watertight, but every face wound inwards: REACH found no face towards the jaw (and blamed
    # the approach) and a pad pressed on it read 0 N
    inside_out = box.copy()
    inside_out.invert()
    assert inside_out.is_watertight and inside_out.volume < 0
    with pytest.raises(ValueError, match=r"inside out.*mesh.invert\(\)"):
        task = Task(mass=MASS, com=[0, 0, 0])
        evaluate_grasp(inside_out, _mm(G), task, options=ModelOptions(model="soft_point", mu=MU))
    with pytest.raises(ValueError, match=r"MeshObstacle is inside out"):
        MeshObstacle(inside_out)
    # the right way out presses with a force (the check refuses only the inverted one)
    from workbench.fem.fidelity import press

    ok = press(
        PadGeometry(nx=4, ny=8, nz=2), Material(), MeshObstacle(box.copy(), transform=_above(box)), [5e-4]
    )
    assert ok.profile(5e-4).F > 1.0


def _above(box):
    # the box's top face (z = 0.03) just touching the pad's face (z = 0.005), pad at the origin
    T = np.eye(4)
    T[2, 3] = 0.005 + 0.03
    return T


def test_a_task_torque_in_newton_millimetres_is_refused(box):
    # [0, 0, -2.9 N, 0, 0, 29 "N·m"]: a 2.9 N load 10 m from the origin; the torque was meant in N·mm
    kw = {"jaws": Jaws(force=FORCE), "options": ModelOptions(model="soft_point", mu=MU)}
    with pytest.raises(ValueError, match=r"at least 10 m from the object origin.*probably in N·mm"):
        evaluate_grasp(box, _mm(G), Task(w_ext=[0, 0, -2.9, 0, 0, 29.0]), **kw)
    # the same task in N·m is evaluated, and its answer is the closed form's: μF·2 resists 2.9 N
    ok = evaluate_grasp(box, _mm(G), Task(w_ext=[0, 0, -2.9, 0, 0, 0.029]), **kw)
    assert ok.resisted
    # a pure torque far beyond any gripper's is refused, an ordinary one passes
    with pytest.raises(ValueError, match=r"torque .*in \[0, 200\] N·m; got 2900.*N·mm"):
        evaluate_grasp(box, _mm(G), Task(w_ext=[0, 0, 0, 0, 2900.0, 0]), **kw)


def test_a_torsion_length_in_millimetres_is_refused():
    # 13.3 (mm) held 124 N·m of torsion from a 10 N grip
    with pytest.raises(ValueError, match=r"torsion_length .*got 13.3: probably in millimetres — pass 0.0133"):
        soft_point_contact([0, 0, 0], [0, 0, 1], 10.0, 13.3)
    c = soft_point_contact([0, 0, 0], [0, 0, 1], 10.0, 0.0133)
    # the torsion bound is the length (at μ = 1, unit force): |τ_z| <= 0.0133
    assert np.abs(c.friction[:, 5]).max() == pytest.approx(0.0133)
    assert soft_point_contact([0, 0, 0], [0, 0, 1], 10.0, 0.0).friction[:, 5].max() == 0.0


def test_a_zero_normal_is_refused():
    # it built a contact of NaNs, with only numpy's "invalid value in divide" as a hint
    with pytest.raises(ValueError, match=r"normal_out .*nonzero.*got \[0, 0, 0\]"):
        point_contact([0, 0, 0], [0, 0, 0], 10.0)
    with pytest.raises(ValueError, match=r"point must be the contact point \[m\], \(3,\) finite"):
        point_contact([0, np.nan, 0], [0, 0, 1], 10.0)
    with pytest.raises(ValueError, match=r"f_max must be a finite normal force >= 0"):
        point_contact([0, 0, 0], [0, 0, 1], -1.0)


def test_a_stiffness_in_newtons_per_millimetre_is_named():
    # 15 "N/m" (15 N/mm) gave 13.3 J silently: each 10 N jaw closing 0.67 m.  Below the softest
    # measured grasp (~140 N/m) it now warns with the N/mm reading; below
    # TOL.min_plausible_stiffness it is refused.  (A large closing is not refused: the minimal
    # forces of a heavy task on a soft map legitimately imply one — that is a low q_work.)
    from workbench import config
    from workbench.plausible import ImplausibleWarning

    with pytest.warns(
        ImplausibleWarning, match=r"15 N/m is below the usual 100 N/m.*probably in N/mm — pass 15000"
    ):
        assert work([10.0, 10.0], [15.0, 15.0], eps=0.0) == pytest.approx(2 * 10.0**2 / 15.0, rel=1e-12)
    lo = config.TOL.min_plausible_stiffness
    with pytest.raises(ValueError, match=r"stiffness at contact 1 .*probably in N/mm"):
        work([10.0, 10.0], [15e3, 0.5 * lo])
    # in N/m: W = Σ f (f / s + ε) with ε = 0, no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        assert work([10.0, 10.0], [15e3, np.inf], eps=0.0) == pytest.approx(10.0**2 / 15e3, rel=1e-12)


@pytest.mark.jit_only("the 6DLS fit is over 15 s as pure Python")
def test_one_model_name_is_one_model(box):
    from workbench.grasp.gripper_eval import evaluate_models
    from workbench.grasp.inputs import Task
    from workbench.sources.gripper import yumi

    T = np.eye(4)
    T[:3, :3] = [[1, 0, 0], [0, -1, 0], [0, 0, -1]]  # approach along −z, jaws closing along x
    T[2, 3] = 0.03 - 0.01 + yumi().tooltips[0][2, 3]
    small = trimesh.creation.box(extents=(0.03, 0.03, 0.06))
    one = evaluate_models(small, yumi(), T, Task(mass=0.05), models="soft_point")
    assert list(one) == ["soft_point"]
    both = evaluate_models(small, yumi(), T, Task(mass=0.05), models=("soft_point",))
    assert one["soft_point"].verdict.scale == both["soft_point"].verdict.scale
    with pytest.raises(ValueError, match="at least one contact model"):
        evaluate_models(small, yumi(), T, Task(mass=0.05), models=())


def test_the_minimal_force_scale_of_a_grasp_that_cannot_hold_is_inf(box):
    # μ = 0 holds nothing: the total was inf but the scale NaN; both say "no force" now
    task, opts = Task(mass=MASS, com=[0, 0, 0]), ModelOptions(model="soft_point", mu=0.0)
    ev = evaluate_grasp(box, _mm(G), task, jaws=Jaws(force=FORCE), options=opts)
    assert not ev.resisted
    assert ev.min_force.total == np.inf and ev.min_force.scale == np.inf

"""Careless inputs of a new-user trial ("no silent nonsense") to the mesh gate, the FEM
pad and wall, the trial reader, the gripper check and the experiments' configs: each was accepted
silently, crashed with an AttributeError / UnicodeDecodeError, or was refused naming the wrong
cause.  Each is refused now naming what was expected, what came and the fix; where the right
call is cheap it is checked against an independent number."""

import json

import numpy as np
import pytest
import trimesh

BOX = (0.06, 0.04, 0.08)  # an 80 mm tall box, faces at x = ±0.03
P1, AXIS = np.array([-0.03, 0.0, 0.0]), np.array([1.0, 0.0, 0.0])
GRASP = {"p1": P1, "p2": -P1, "axis": AXIS}


def _box() -> trimesh.Trimesh:
    return trimesh.creation.box(extents=BOX)


def _evaluate(mesh, grasp=GRASP, com=(0.0, 0.0, 0.0)):
    from workbench.grasp import Jaws, ModelOptions, Task, evaluate_grasp

    task, opts = Task(mass=0.3, com=com), ModelOptions(model="soft_point", mu=0.5)
    return evaluate_grasp(mesh, grasp, task, jaws=Jaws(force=10.0), options=opts)


def test_d33_nan_vertices_are_named_not_called_inside_out():
    """evaluate_grasp(box with 3 NaN vertices, g): the NaN volume read as "inside out … signed
    volume nan … mesh.invert()", a fix that cannot work."""
    from workbench.units import closed_mesh

    box = _box()
    v = box.vertices.copy()
    v[:3] = np.nan
    bad = trimesh.Trimesh(v, box.faces, process=False)
    with pytest.raises(ValueError, match=r"must have finite vertex coordinates; got 3 of 8 vertices") as exc:
        _evaluate(bad)
    assert "invert" not in str(exc.value) and "inside out" not in str(exc.value)
    assert closed_mesh(box, "box") is box  # the finite mesh passes the same gate unchanged


def test_e12_antipodal_grasps_refuse_an_inside_out_mesh_by_name():
    """antipodal_grasps(cup.invert(), 5, mu=0.5): logged "0 of 5 grasps … 100 no_far_side" instead
    of naming the inside-out mesh, which every other mesh input refuses."""
    from workbench.grasp import antipodal_grasps

    inverted = _box()
    inverted.invert()
    with pytest.raises(ValueError, match=r"mesh passed to antipodal_grasps is inside out.*mesh\.invert\(\)"):
        antipodal_grasps(inverted, 5, mu=0.5)
    # the same box the right way out: an antipodal pair of a box lies on opposite faces, one of
    # its sides apart along their normal
    grasps = antipodal_grasps(_box(), 3, mu=0.5, jaws=None, seed=0)
    assert len(grasps) == 3
    for g in grasps:
        n1, n2 = np.asarray(g["n1"]), np.asarray(g["n2"])
        assert np.allclose(n1, -n2, atol=1e-12)
        assert min(abs(abs((np.asarray(g["p2"]) - g["p1"]) @ n1) - side) for side in BOX) < 1e-9


def test_f12_a_plane_at_the_pads_back_names_its_point_not_delta(monkeypatch):
    """press(pad, Material(), Plane(), [1e-3]): the default Plane (point (0, 0, 0), the pad's back)
    was blamed on delta ("penetrates 0.006 m … reduce delta") after the pad was condensed."""
    import workbench.fem.fidelity as fidelity
    from workbench.fem.material import Material
    from workbench.fem.obstacles import Plane
    from workbench.fem.pad import PadGeometry

    geometry = PadGeometry(nx=6, ny=12, nz=2)  # 20 x 40 mm face, h = 5 mm

    def no_condensing(*args, **kwargs):
        raise AssertionError("the pad was condensed before the obstacle was checked")

    with monkeypatch.context() as m:
        m.setattr(fidelity, "condense_pad", no_condensing)
        with pytest.raises(
            ValueError,
            match=r"0\.005 m of it before the jaw moves \(delta = 0\): the obstacle is placed inside "
            r"the pad.*face at z = h = 0\.005 m.*e\.g\. Plane\(point=\(0, 0, 0\.005\)\)",
        ) as exc:
            fidelity.press(geometry, Material(), Plane(), [1e-3], cache_dir=False)
    assert "reduce delta" not in str(exc.value)
    # the call the message names presses the layer by 1 mm of its 5: between the unconfined
    # (E A δ/h) and the fully confined (M A δ/h, M = E(1-ν)/((1+ν)(1-2ν))) layer's force
    mat = Material()
    out = fidelity.press(geometry, mat, Plane(point=(0, 0, 0.005)), [1e-3], cache_dir=False)
    strain_area = geometry.width * geometry.length * 1e-3 / geometry.thickness
    confined = mat.E * (1 - mat.nu) / ((1 + mat.nu) * (1 - 2 * mat.nu))
    assert mat.E * strain_area < out[1e-3].force < confined * strain_area


def test_f16_an_approach_pointing_away_from_the_object_is_refused():
    """fem_jaw_profile(box, p1, -axis, 10): the jaw at p1 moving away from the box returned a 10 N
    profile on the opposite face, 60 mm from p1."""
    from workbench.fem.pad import PadGeometry
    from workbench.sources.fem_jaw import FemPad, fem_jaw_profile

    pad = FemPad(PadGeometry(nx=10, ny=20, nz=3), cache_dir=False)
    with pytest.raises(
        ValueError,
        match=r"approach \[-1\.0, 0\.0, 0\.0\] points away from the object at point \[-0\.03, 0\.0, 0\.0\].*"
        r"touches nothing on this side.*approach = -normal = \[1\.0, 0\.0, 0\.0\]",
    ):
        fem_jaw_profile(_box(), P1, -AXIS, 10.0, pad=pad)
    # the same rule names a point in millimetres (30 mm read as 30 m)
    with pytest.raises(
        ValueError, match=r"point .*probably in millimetres — pass metres .*\[-0\.03, 0\.0, 0\.0\]"
    ):
        fem_jaw_profile(_box(), P1 * 1000, AXIS, 10.0, pad=pad)
    # approaching into the object, the pad presses the face at p1: centred there by symmetry
    prof = fem_jaw_profile(_box(), P1, AXIS, 10.0, pad=pad)
    assert np.abs(prof.pressure_center - P1).max() < 1e-9
    assert prof.normal_wrench[:3] @ AXIS == pytest.approx(10.0, rel=1e-9)


def test_f27_squeeze_names_the_wall_to_pass_for_a_mesh():
    """squeeze(cup_trimesh, centre, axis): AttributeError 'Trimesh' object has no attribute
    'outer_xyz'."""
    from workbench.fem.wall import squeeze
    from workbench.fem.wall_grasps import stiffness_at
    from workbench.fem.wall_nonlinear import squeeze_nonlinear

    centre = np.array([0.0, 0.0, 0.04])
    with pytest.raises(
        ValueError,
        match=r"wall must be the Wall .*got Trimesh — a mesh is the object's surface, not its wall: "
        r"geo, wall = object_wall\(mesh\); squeeze\(wall, centre, axis\)",
    ):
        squeeze(_box(), centre, AXIS)
    with pytest.raises(ValueError, match=r"got tuple — object_wall returns the pair \(geometry, wall\)"):
        squeeze(("geometry", "wall"), centre, AXIS)
    # the functions that take a wall share the rule, each naming its own call
    with pytest.raises(ValueError, match=r"got Trimesh .*squeeze_nonlinear\(wall, centre\)"):
        squeeze_nonlinear(_box(), centre)
    with pytest.raises(ValueError, match=r"got Trimesh .*stiffness_at\(wall, geo, locations\)"):
        stiffness_at(_box(), None, np.zeros((2, 3)))


def test_i08_a_gripper_given_by_its_preset_name_is_refused_naming_the_call():
    """evaluate_gripper(box, 'yumi', pose): AttributeError 'str' object has no attribute 'mu'.
    check_gripper is the rule such calls apply (as simulate_gripper does: a Gripper, not a name)."""
    from workbench.sources.gripper import Gripper, check_gripper, yumi

    with pytest.raises(
        ValueError,
        match=r"gripper must be a workbench\.sources\.gripper\.Gripper \(e\.g\. yumi\(\)\); "
        r"got 'yumi' \(str\) — pass yumi\(\)",
    ):
        check_gripper("yumi")
    with pytest.raises(ValueError, match=r"got a dict — build one: yumi\(\), gripper_from_yaml\(path\)"):
        check_gripper({"force": 20.0})
    g = yumi()
    assert check_gripper(g) is g and isinstance(g, Gripper) and g.force == 20.0


def test_i10_read_trials_names_the_format_for_a_mesh_file(tmp_path):
    """read_trials('box.stl'): UnicodeDecodeError 'utf-8' codec can't decode byte 0xcc."""
    from workbench.sources.trials import default_trials_path, read_trials

    stl = tmp_path / "box.stl"
    _box().export(stl)
    with pytest.raises(
        ValueError,
        match=r"box\.stl is not a trial file: expected the REACH format, a JSON list of trials .*"
        r"got a binary file \(not UTF-8 text: a mesh or an archive\?\) — pass the trials' \.json file",
    ):
        read_trials(stl)
    cut = tmp_path / "cut.json"
    cut.write_text(default_trials_path().read_text()[:500])  # a truncated copy
    with pytest.raises(
        ValueError, match=r"cut\.json is not a trial file: .*got text that is not JSON .*truncated\?"
    ):
        read_trials(cut)
    assert len(json.loads(default_trials_path().read_text())) == len(
        read_trials(default_trials_path()).success
    )


def test_j06_a_zero_quadrature_tolerance_is_refused_by_its_key_before_the_run():
    """workbench run parametric-surfaces --quick --set quad_rtol=0: refused only once the run
    started, naming 'rtol' / config.TOL.quadrature_rtol rather than the key."""
    from workbench.runner.experiment_config import build_config
    from workbench.sources.surface_catalog import THESIS_SURFACES
    from workbench.sources.surfaces import surface_wrenches

    for name, key in (
        ("parametric-surfaces", "quad_rtol"),
        ("parametric-surfaces", "pca_rtol"),
        ("ls-fitting", "quad_rtol"),
    ):
        with pytest.raises(
            SystemExit, match=rf"^{name}: {key} must be a relative tolerance > 0, .*got 0\.0$"
        ):
            build_config(name, True, None, None, {key: 0.0})
    assert build_config("parametric-surfaces", True, None, None, {"quad_rtol": 1e-6})["quad_rtol"] == 1e-6
    # the library's argument keeps the same rule, naming the config default None stands for
    s1 = THESIS_SURFACES["S1"]
    with pytest.raises(
        ValueError, match=r"rtol must be a relative tolerance > 0 \(or None: config\.TOL\.quadrature_rtol\)"
    ):
        surface_wrenches(s1, [0, 0, 0, 0, 0, 1.0], 1.0, rtol=0)


def test_d27_a_grasp_in_millimetres_is_named_as_one():
    """evaluate_grasp(box_mm in metres, g_mm): "the pad footprint … around [-30, 0, 40] covers no
    part of the object … check center, approach and units", the point 30 m from an 80 mm box."""
    from workbench.units import far_from_object, mesh_in_metres

    box_mm = _box().apply_scale(1000.0)
    g_mm = {"p1": [-30.0, 0.0, 10.0], "p2": [30.0, 0.0, 10.0], "axis": AXIS}
    with pytest.raises(
        ValueError,
        match=r"covers no part of the object .*center \[-30\.0, 0\.0, 10\.0\] lies .* farther than the "
        r"object's own size \(0\.08 m\): it is probably in millimetres — pass metres "
        r"\(× 0\.001: \[-0\.03, 0\.0, 0\.01\]",
    ):
        _evaluate(mesh_in_metres(box_mm, "object", units="mm"), g_mm, com=[0.0, 0.0, 0.01])
    bounds = _box().bounds
    assert far_from_object([-0.03, 0.0, 0.01], bounds) is None  # on the face
    # the object's own size (its 80 mm side) outside its box is the limit: 70 mm off passes, 90 mm not
    assert far_from_object([-0.10, 0.0, 0.0], bounds) is None
    near = far_from_object([-0.12, 0.0, 0.0], bounds)
    assert "lies 0.09 m outside" in near and "probably" not in near  # no unit slip names 90 mm
    far = far_from_object([-300.0, 0.0, 0.0], bounds)  # neither mm nor cm brings it near the box
    assert "another unit than the mesh" in far and "probably" not in far

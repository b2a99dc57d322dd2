"""Careless inputs of the ninth new-user trial ("no silent nonsense"): two accepted
silently (an FEM obstacle the pad never reaches, pressed at 0 N; ``conform="no"`` read as True),
a thin mesh whose density refusal blamed the mass, and ranges quoted with another quantity's
examples.  Each is refused now, naming what was expected and the fix."""

import numpy as np
import pytest
import trimesh


def test_82_an_obstacle_the_pad_never_reaches_is_refused_not_pressed_at_zero_newtons():
    """press(PadGeometry(), Material(), Sphere((0, 0, 0.1), 0.02), [1e-3]): the sphere 75 mm
    beyond the face (z = h = 5 mm; 74 mm after the 1 mm move) returned force 0.0 without a word."""
    from workbench.fem.fidelity import press
    from workbench.fem.material import Material
    from workbench.fem.obstacles import Sphere
    from workbench.fem.pad import PadGeometry

    with pytest.raises(
        ValueError, match=r"the obstacle is 0.074 m beyond the pad's face even at the largest"
    ):
        press(PadGeometry(), Material(), Sphere((0.0, 0.0, 0.1), 0.02), [1e-3])
    # touching the face (bottom of the sphere at z = h): a positive force, growing with delta
    h = PadGeometry().thickness
    r = press(PadGeometry(nx=8, ny=16, nz=2), Material(), Sphere((0.0, 0.0, h + 0.02), 0.02), [2e-4, 4e-4])
    f = [r.profile(d).F for d in (2e-4, 4e-4)]
    assert 0 < f[0] < f[1]


def test_166_conform_must_be_a_bool():
    """simulate_disturbance(..., conform="no"): the string read as True and moulded the pads (the
    flag is now the pad's, EnginePad.conform)."""
    from workbench.engine_trials import EnginePad

    with pytest.raises(ValueError, match=r"conform must be True or False .*got 'no'"):
        EnginePad(conform="no")


def test_16_a_thin_mesh_is_named_as_the_cause_of_an_absurd_density():
    """evaluate_grasp(egg flattened to 7 µm, mass=0.06): refused as "a mass in grams? pass 6e-05";
    the mass was right, the mesh holds no volume."""
    from workbench.grasp.robust import check_object_mass

    egg = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    egg.apply_scale([0.025, 0.025, 3.5e-6])  # 7 µm thick, 50 mm wide: aspect 1.4e-4
    with pytest.raises(
        ValueError, match=r"the mesh is nearly flat \(its thinnest side 0.00014 of its longest"
    ):
        check_object_mass(0.06, egg)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        ("ring_wall", r"must be a ring radius .*real values: bottles and cups"),
        ("lift_height", r"must be a lift height .*real values: a robot lifts"),
        ("max_drift", r"must be a drift limit .*real values: the thesis labels a grasp failed beyond 9 mm"),
        ("semi_axis", r"must be a semi-axis .*semi-axis 5-50 mm"),
        ("torsion_length", r"must be a torsion length"),
    ],
)
def test_ranges_are_quoted_with_the_inputs_own_examples(call, match):
    """ring_wall(35.0, ...), TrialPhases(lift_height=50.0), TrialPhases(max_drift=5.0),
    elliptic_cylinder_grasp(a=30), soft_point_contact(torsion_length=5.0): each was refused in the
    right unit but described as "a lever arm ... a centre of mass 1-100 mm off the grasp axis" or
    "a jaw closing ... a pad pressed 0.1-5 mm into an object"."""
    from workbench.engine_trials.trial import TrialPhases
    from workbench.fem.wall import ring_wall
    from workbench.grasp.contacts import soft_point_contact
    from workbench.sources.scenes import elliptic_cylinder_grasp

    calls = {
        "ring_wall": lambda: ring_wall(35.0, 0.5e-3),
        "lift_height": lambda: TrialPhases(lift_height=50.0),
        "max_drift": lambda: TrialPhases(max_drift=5.0),
        "semi_axis": lambda: elliptic_cylinder_grasp(a=30, b=20),
        "torsion_length": lambda: soft_point_contact(np.zeros(3), [0.0, 0.0, 1.0], 5.0, torsion_length=5.0),
    }
    with pytest.raises(ValueError, match=match) as exc:
        calls[call]()
    assert "centre of mass 1-100 mm" not in str(exc.value) and "pad pressed 0.1-5 mm" not in str(exc.value)


def test_trial10_save_png_seed_and_wrench_name():
    """Trial 10: save_png(path, "not bytes") was a bare TypeError from atomic_write_bytes;
    evaluate_grasp(model="soft_point", seed=-3) was accepted where model="6dls" refused it;
    simulate_disturbance's torque check named the argument w_ext, not wrench."""
    from workbench.grasp.models import contact_sets
    from workbench.runner.results import save_png
    from workbench.sources.scenes import elliptic_cylinder_grasp

    with pytest.raises(ValueError, match=r"data must be the PNG's bytes; got str"):
        save_png("/tmp/never_written.png", "not bytes")
    with pytest.raises(ValueError, match=r"data must be a PNG image"):
        save_png("/tmp/never_written.png", b"GIF89a")
    prof = elliptic_cylinder_grasp(n_elements=60)[0]
    for model in ("soft_point", "6dls"):
        with pytest.raises(ValueError, match=r"seed must be an integer >= 0"):
            contact_sets(prof, model, seed=-3)
    pytest.importorskip("mujoco")
    from workbench.engine_trials import EngineObject, simulate_disturbance

    box = trimesh.creation.box(extents=(0.05, 0.04, 0.06))
    g = {"p1": [0.0, -0.02, 0.0], "p2": [0.0, 0.02, 0.0], "axis": [0.0, 1.0, 0.0]}
    with pytest.raises(ValueError, match=r"^wrench's "):
        obj = EngineObject(mass=0.1, mu=0.5)
        simulate_disturbance(box, g, [0.0, 0.0, -0.1, 0.0, 0.0, 500.0], force=5.0, obj=obj)

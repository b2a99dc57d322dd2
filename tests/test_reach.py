"""workbench.sources.reach: REACH profiles (Winkler on a sphere; the pipeline on a thesis object)."""

import numpy as np
import pytest

from workbench.grasp import gravity_wrench, resists


def test_reach_profile_of_a_sphere_is_winkler():
    """Flat pad closing δ on a sphere: F = π R k δ² (Winkler, δ ≪ R), contact on the axis."""
    import trimesh

    from workbench.sources.reach import reach_profile

    R, k, d = 0.03, 2e8, 1e-3
    s = trimesh.creation.icosphere(subdivisions=5, radius=R)
    p = reach_profile(s, [0, R, 0], [0, -1, 0], [0, 0, 1], closing=d, stiffness=k, max_edge=0.5e-3)
    assert p.F == pytest.approx(np.pi * R * k * d**2, rel=0.01)
    np.testing.assert_allclose(p.pressure_center[[0, 2]], 0.0, atol=1e-4)
    assert np.sqrt(np.hypot(p.centers[:, 0], p.centers[:, 2]).max() ** 2) == pytest.approx(
        np.sqrt(2 * R * d), rel=0.05
    )
    open_mesh = trimesh.Trimesh(s.vertices, s.faces[:-10])
    with pytest.raises(ValueError, match="watertight"):
        reach_profile(open_mesh, [0, R, 0], [0, -1, 0])
    with pytest.raises(ValueError, match="covers no part"):
        reach_profile(s, [0.5, R, 0], [0, -1, 0])


@pytest.mark.jit_only("over 15 s as pure Python")
def test_grasp_pipeline_on_a_thesis_object_if_available():
    """Antipodal sampling -> REACH profiles -> 6DLS -> resistance of the bottle's own weight."""
    from pathlib import Path

    import trimesh

    from workbench.grasp.models import contact_sets
    from workbench.grasp.sampling import antipodal_grasps
    from workbench.sources.jaws import with_axis_force
    from workbench.sources.reach import reach_profile

    path = (
        Path(__file__).resolve().parents[2]
        / "shared/data/thesis_objects/0006_bottle-gen_smoothie_150x040x040-04.obj"
    )
    if not path.exists():
        pytest.skip("thesis objects not available")
    mesh = trimesh.load(path, force="mesh")
    grasps = antipodal_grasps(mesh, 3, 0.5, seed=0, table_z=0.0, clearance=0.03, max_width=0.1)
    assert grasps
    g = grasps[0]
    # both jaws press with the same grasp-axis force (a force-sensor reading, §4.1.3.2)
    F = 10.0
    profiles = [
        with_axis_force(reach_profile(mesh, g["p1"], g["axis"], closing=1e-3, max_edge=1e-3), g["axis"], F),
        with_axis_force(reach_profile(mesh, g["p2"], -g["axis"], closing=1e-3, max_edge=1e-3), g["axis"], F),
    ]
    assert all(len(p) > 10 for p in profiles)
    sets = [c for p in profiles for c in contact_sets(p, "6dls", M=100, n_wrenches=400)]
    light = gravity_wrench(0.2 * 0.5 * F / 9.81, mesh.center_mass)
    heavy = gravity_wrench(5 * 0.5 * F / 9.81, mesh.center_mass)
    assert resists(sets, light, 0.5) and not resists(sets, heavy, 0.5)

"""workbench.grasp.sampling: antipodal grasps within the friction cone, seeded."""

import numpy as np


def test_antipodal_grasps_on_a_sphere_and_a_standing_cylinder():
    import trimesh

    from workbench.grasp.sampling import GraspSampling, antipodal_grasps

    R, mu = 0.03, 0.3
    g = antipodal_grasps(trimesh.creation.icosphere(subdivisions=4, radius=R), 30, mu, jaws=None, seed=0)
    assert len(g) == 30
    half = np.arctan(mu)
    for x in g:
        assert np.arccos(-x["n1"] @ x["axis"]) <= half + 1e-9
        assert np.arccos(x["n2"] @ x["axis"]) <= half + 1e-9
        # a chord within the friction cone passes within R sin(atan μ) of the centre
        assert np.linalg.norm(x["center"]) <= R * np.sin(half) + 1e-3
    cyl = trimesh.creation.cylinder(radius=R, height=0.1)  # z from -0.05 to 0.05
    sampling = GraspSampling(table_z=-0.05, clearance=0.02, max_width=0.07)
    g = antipodal_grasps(cyl, 20, mu, sampling, jaws=None, seed=1)
    assert len(g) == 20
    assert all(min(x["p1"][2], x["p2"][2]) >= -0.03 and x["width"] <= 0.07 for x in g)
    again = antipodal_grasps(cyl, 20, mu, sampling, jaws=None, seed=1)
    assert all(np.array_equal(a["p1"], b["p1"]) for a, b in zip(g, again, strict=True))  # seeded

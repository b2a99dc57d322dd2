"""workbench.grasp.models: every contact model of a profile by name."""

import numpy as np
import pytest

from workbench.grasp import resists


@pytest.mark.jit_only("over 15 s as pure Python")
def test_every_model_on_the_elliptic_cylinder_grasp():
    from workbench.grasp.models import MODELS, contact_sets, planar_profile
    from workbench.limit_surface import LimitSurfaceCache
    from workbench.sources.scenes import elliptic_cylinder_grasp

    profiles = elliptic_cylinder_grasp(force=25.0, n_elements=200)
    # the force-sensor convention: the grasp-axis normal force of each jaw is F
    assert -profiles[0].normal_wrench[0] == pytest.approx(25.0, rel=1e-12)
    flat = planar_profile(profiles[0])
    assert flat.F == pytest.approx(profiles[0].F, rel=1e-12)
    assert np.allclose(np.abs(flat.normals[:, 0]), 1.0)  # projected onto the yz-plane
    cache = LimitSurfaceCache()
    mu = 0.3
    lift = np.array([0, -0.9 * 2 * mu * 25.0, 0, 0, 0, 0])  # a weight along -y
    twist = np.array([0, 0, 0, 0.02, 0, 0])  # torque about the grasp axis
    for name in MODELS:
        sets = [c for p in profiles for c in contact_sets(p, name, cache=cache, M=100, n_wrenches=400)]
        # outer QP where the model has half-spaces (the thesis's QP), else the exact LP
        assert resists(sets, lift, mu), name  # friction force ~2μF > 0.9·2μF
        assert resists(sets, np.zeros(6), mu), name
        if name == "point":
            assert not resists(sets, twist, mu)  # no torsional friction
        else:
            assert resists(sets, twist, mu), name
    with pytest.raises(ValueError, match="model must be one of"):
        contact_sets(profiles[0], "ellipsoid")

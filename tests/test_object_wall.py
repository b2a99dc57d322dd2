"""workbench.fem.object_wall: the top edge of a hollow object's wall off its mesh (lip, shoulder, free)."""

from pathlib import Path

import numpy as np
import pytest
import trimesh

from workbench.fem.mesh_wall import radial_surface
from workbench.fem.object_wall import find_lip, is_closed_top, object_wall
from workbench.fem.wall import squeeze

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "deformable_objects" / "meshes"


def _cup(lip: bool) -> trimesh.Trimesh:
    """An open cup, a solid of revolution of its wall section [m]: 0.5 mm wall, 80 mm tall,
    radius 30 mm, with (or without) a 3 mm × 3 mm lip on top."""
    r, t, h = 0.030, 0.5e-3, 0.080
    top = [(r, h), (r + 3e-3, h), (r + 3e-3, h + 3e-3), (r - t, h + 3e-3)] if lip else [(r, h), (r - t, h)]
    section = np.array([(0.0, 0.0), (r, 0.0), *top, (r - t, t), (0.0, t)])
    m = trimesh.creation.revolve(section, sections=96)  # this order winds it outward
    assert m.is_watertight
    return m


def test_lip_is_found_with_its_size():
    m = _cup(lip=True)
    s = radial_surface(m)
    lip = find_lip(m, s)
    assert lip is not None and not is_closed_top(m, s)
    assert lip.width == pytest.approx(3.5e-3, abs=0.2e-3)  # 3 mm out + 0.5 mm wall
    assert lip.bulge == pytest.approx(3.0e-3, abs=0.2e-3)
    assert lip.z1 == pytest.approx(0.083, abs=1e-6) and 0.080 <= lip.z0 <= 0.0815


@pytest.mark.jit_only("over 15 s as pure Python")
def test_plain_open_edge_and_the_lip_stiffens_it():
    plain, lipped = _cup(lip=False), _cup(lip=True)
    s = radial_surface(plain)
    assert find_lip(plain, s) is None and not is_closed_top(plain, s)
    geo_p, wall_p = object_wall(plain, n_theta=32, n_z=16)
    geo_l, wall_l = object_wall(lipped, n_theta=32, n_z=16)
    assert geo_p.lip is None and not geo_p.clamp_top and geo_l.lip is not None
    z = 0.070  # a grasp near the top: the ring (lip) must stiffen it, a lot
    k = [squeeze(w, np.array([0.0, 0.0, z]), np.array([1.0, 0.0, 0.0])).stiffness for w in (wall_p, wall_l)]
    assert k[1] > 2 * k[0]
    with pytest.raises(ValueError, match="no lip"):
        object_wall(plain, top="lip")
    with pytest.raises(ValueError, match="top must be one of"):
        object_wall(plain, top="open")
    with pytest.raises(ValueError, match=r"wall thickness in \[1e-05, 0.05\] m"):
        object_wall(plain, thickness=0.0)


# the mustard bottle's star-shaped band runs over its shoulder up to the open nozzle
# (r ≈ 5 mm): its wall model includes the shoulder and keeps the nozzle's small edge free
@pytest.mark.parametrize(
    "name, closed, lip", [("plastic_cup", False, True), ("mustard", False, False), ("shampoo", True, False)]
)
def test_shared_objects_tops(name, closed, lip):
    path = DATA / f"{name}.obj"
    if not path.exists():
        pytest.skip("deformable_objects data not present")
    m = trimesh.load(path, force="mesh")
    s = radial_surface(m)
    assert is_closed_top(m, s) == closed
    assert (find_lip(m, s) is not None) == lip

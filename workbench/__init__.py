"""Nonplanar frictional contact workbench (J. Xu's thesis, 6DFC ICRA 2020).

Data flows one way: profile source (``workbench.sources``) -> profile -> wrenches ->
limit surface -> contact model -> grasp metric.  See README.md and ``workbench run --help``.
"""

from .limit_surface import fit_ellipsoid, fit_quartic
from .profile import ContactProfile
from .sources.surfaces import (
    ParametricSurface,
    mesh_profile,
    mesh_surface,
    project_to_plane,
    surface_moments,
    surface_w_max,
    surface_wrenches,
)
from .twists import (
    canonical_twists,
    plucker_from_twists,
    sample_twists_6dfc,
    sample_twists_thesis,
    translation_twists,
    twists_from_plucker,
)
from .wrench import frictional_wrenches, normal_wrench, w_max

__version__ = "0.1.0"

__all__ = [
    "ContactProfile",
    "ParametricSurface",
    "canonical_twists",
    "fit_ellipsoid",
    "fit_quartic",
    "frictional_wrenches",
    "mesh_profile",
    "mesh_surface",
    "normal_wrench",
    "plucker_from_twists",
    "project_to_plane",
    "sample_twists_6dfc",
    "sample_twists_thesis",
    "surface_moments",
    "surface_w_max",
    "surface_wrenches",
    "translation_twists",
    "twists_from_plucker",
    "w_max",
]

"""6D limit-surface models (thesis §3.3-3.4, 6DFC §IV)."""

from .base import LimitSurfaceModel
from .cache import LimitSurfaceCache, ModelSpec, SamplerSpec
from .contact_wrench import ContactWrenchModel
from .ellipsoid import EllipsoidLS, fit_ellipsoid
from .linearize import Linearization, linearize, sample_directions
from .normalize import pca_subspace, wrench_scale
from .quartic import QuarticLS, fit_quartic, is_sos_convex

__all__ = [
    "ContactWrenchModel",
    "EllipsoidLS",
    "LimitSurfaceCache",
    "Linearization",
    "ModelSpec",
    "SamplerSpec",
    "linearize",
    "sample_directions",
    "LimitSurfaceModel",
    "QuarticLS",
    "fit_ellipsoid",
    "fit_quartic",
    "is_sos_convex",
    "pca_subspace",
    "wrench_scale",
]

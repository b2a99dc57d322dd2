"""Isotropic linear-elastic material with validation."""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Material:
    """Young's modulus ``E`` [Pa] and Poisson ratio ``nu`` (silicone: nu up to 0.499)."""

    E: float = 1.0e6
    nu: float = 0.45

    def __post_init__(self) -> None:
        if isinstance(self.E, (bool, np.bool_)) or not isinstance(self.E, numbers.Real):
            raise ValueError(
                f"E must be a Young's modulus [Pa], a number; got {self.E!r} ({type(self.E).__name__})"
            )
        if not (np.isfinite(self.E) and self.E > 0):
            raise ValueError(f"E must be a positive Young's modulus [Pa]; got {self.E}")
        from workbench.plausible import check

        try:
            check("poisson", self.nu, "nu")
        except ValueError as exc:
            raise ValueError(f"{exc} — for incompressible silicone use e.g. 0.499") from None

    @property
    def mu(self) -> float:
        """Shear modulus G = E / (2 (1 + nu))."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def lam(self) -> float:
        """First Lamé parameter."""
        return self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))

    @property
    def bulk(self) -> float:
        """Bulk modulus K = lambda + 2 mu / 3."""
        return self.lam + 2.0 * self.mu / 3.0

    @property
    def p_wave(self) -> float:
        """Confined (oedometric) modulus (1 - nu) E / ((1 + nu)(1 - 2 nu))."""
        return self.lam + 2.0 * self.mu

"""Rigid obstacles as signed-distance functions (positive outside the obstacle).

``signed_distance(points)`` returns ``(d, n)``: the signed distance (N,) and
the obstacle's outward unit normal (N, 3) at the closest surface point — which
is the "outward from the object" normal of a contact profile.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v)
    if not np.isfinite(n) or n == 0:
        raise ValueError(f"direction must be a finite non-zero 3-vector; got {v}")
    return v / n


@dataclass(frozen=True)
class Plane:
    """Half-space ``(x - point)·normal <= 0``; ``normal`` points out of the obstacle."""

    point: tuple = (0.0, 0.0, 0.0)
    normal: tuple = (0.0, 0.0, -1.0)

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = _unit(self.normal)
        d = (x - np.asarray(self.point, float)) @ n
        return d, np.broadcast_to(n, x.shape).copy()


@dataclass(frozen=True)
class Sphere:
    center: tuple = (0.0, 0.0, 0.0)
    radius: float = 0.02

    def __post_init__(self) -> None:
        if not (np.isfinite(self.radius) and self.radius > 0):
            raise ValueError(f"radius must be > 0; got {self.radius}")

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r = x - np.asarray(self.center, float)
        dist = np.linalg.norm(r, axis=1)
        return dist - self.radius, r / np.where(dist > 0, dist, 1.0)[:, None]


@dataclass(frozen=True)
class Cylinder:
    """Infinite circular cylinder with axis through ``point`` along ``axis``."""

    point: tuple = (0.0, 0.0, 0.0)
    axis: tuple = (0.0, 1.0, 0.0)
    radius: float = 0.02
    _a: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not (np.isfinite(self.radius) and self.radius > 0):
            raise ValueError(f"radius must be > 0; got {self.radius}")
        object.__setattr__(self, "_a", _unit(self.axis))

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r = x - np.asarray(self.point, float)
        radial = r - (r @ self._a)[:, None] * self._a
        dist = np.linalg.norm(radial, axis=1)
        return dist - self.radius, radial / np.where(dist > 0, dist, 1.0)[:, None]

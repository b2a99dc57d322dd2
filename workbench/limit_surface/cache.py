"""Cache of limit surfaces for profile pairs ``(S, p̂)`` — the dataset D of
thesis §3.3.6.1.

The key is a SHA-256 of the geometry (centers, normals, areas), the normalised
pressure ``p̂``, μ, the twist-sampler settings and the model spec.  The stored
model is the one of the normalised profile (``F = 1``); :meth:`get` returns it
scaled by the profile's ``F`` (or a force reading).  A hit does no wrench
sampling and no solve (``stats`` counts both).  With ``directory`` set, models
persist as ``<key>.npz`` (written atomically).
"""

from __future__ import annotations

import hashlib
import io
import json
from collections import Counter
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from ..profile import ContactProfile
from ..results import atomic_write_bytes
from ..twists import sample_twists_6dfc, sample_twists_thesis
from ..wrench import frictional_wrenches, w_max
from .base import LimitSurfaceModel
from .contact_wrench import ContactWrenchModel
from .ellipsoid import EllipsoidLS, fit_ellipsoid
from .normalize import Subspace
from .quartic import QuarticLS, fit_quartic


@dataclass(frozen=True)
class SamplerSpec:
    """Twist sampler settings (part of the cache key)."""

    kind: str = "thesis"  # "thesis" (§3.3.2) or "6dfc" (paper §IV-C.1)
    n: int = 300  # thesis: n rotations + n translations; 6dfc: k1 = n, k2 = n // 2
    seed: int = 0
    radius_factor: float = 0.25

    def twists(self, profile: ContactProfile) -> np.ndarray:
        if self.kind == "thesis":
            return sample_twists_thesis(self.n, profile, self.seed, radius_factor=self.radius_factor)
        if self.kind == "6dfc":
            return sample_twists_6dfc(
                self.n, self.n // 2, profile, self.seed, radius_factor=self.radius_factor
            )
        raise ValueError(f"sampler kind must be 'thesis' or '6dfc'; got {self.kind!r}")


@dataclass(frozen=True)
class ModelSpec:
    """Which model to fit (part of the cache key)."""

    model: str = "ellipsoid"  # "ellipsoid" or "quartic"
    method: str = "lsq"  # ellipsoid: "lsq" | "sdp"
    solver: str = "CLARABEL"
    exact_w_max: bool = True  # normalise by the canonical-twist support values
    normals: bool = True  # quartic: also fit the twists as outward normals (fit_quartic(twists=...))


def _hash_arrays(*arrays: np.ndarray) -> hashlib._Hash:
    """SHA-256 of arrays quantised to 12 significant digits of their scale, so
    that e.g. ``p̂`` of a profile and of its 3x-pressure copy (equal up to the
    last bit) share a key."""
    h = hashlib.sha256()
    for a in arrays:
        a = np.asarray(a, dtype=np.float64)
        scale = float(np.abs(a).max()) if a.size else 1.0
        q = np.round(a / (scale if scale > 0 else 1.0) * 1e12).astype(np.int64)
        h.update(str(a.shape).encode())
        h.update(f"{scale:.11e}".encode())  # the scale itself to 12 significant digits
        h.update(np.ascontiguousarray(q).tobytes())
    return h


class LimitSurfaceCache:
    """In-memory (and optionally on-disk) cache of fitted limit surfaces."""

    def __init__(self, directory: str | Path | None = None) -> None:
        self._mem: dict[str, LimitSurfaceModel] = {}
        self.directory = None if directory is None else Path(directory)
        self.stats: Counter = Counter()

    @staticmethod
    def key(profile: ContactProfile, mu: float, sampler: SamplerSpec, spec: ModelSpec) -> str:
        h = _hash_arrays(profile.centers, profile.normals, profile.areas, profile.normalized_pressures)
        h.update(json.dumps({"mu": float(mu), "sampler": asdict(sampler), "model": asdict(spec)}).encode())
        return h.hexdigest()

    def get(
        self,
        profile: ContactProfile,
        mu: float = 1.0,
        *,
        sampler: SamplerSpec = SamplerSpec(),
        spec: ModelSpec = ModelSpec(),
        force: float | None = None,
    ) -> LimitSurfaceModel:
        """Limit surface of ``profile`` scaled by ``force`` (default ``profile.F``)."""
        k = self.key(profile, mu, sampler, spec)
        model = self._mem.get(k)
        if model is None and self.directory is not None and (self.directory / f"{k}.npz").exists():
            model = _load(self.directory / f"{k}.npz")
            self._mem[k] = model
            self.stats["disk_hits"] += 1
        if model is None:
            self.stats["misses"] += 1
            model = self._fit(profile.normalized(), mu, sampler, spec)
            self._mem[k] = model
            if self.directory is not None:
                _save(self.directory / f"{k}.npz", model)
        else:
            self.stats["hits"] += 1
        return model.scaled(profile.F if force is None else force)

    def contact_model(self, profile: ContactProfile, mu: float = 1.0, **kw) -> ContactWrenchModel:
        """Contact-wrench model of the normalised profile pair (scale by F at use)."""
        ls = self.get(profile, mu, force=1.0, **kw)
        return ContactWrenchModel(ls, profile.normal_wrench / profile.F)

    def _fit(
        self, prof: ContactProfile, mu: float, sampler: SamplerSpec, spec: ModelSpec
    ) -> LimitSurfaceModel:
        self.stats["sampling"] += 1
        xi = sampler.twists(prof)
        W = frictional_wrenches(prof, xi, mu)
        wm = w_max(prof, mu) if spec.exact_w_max else None
        self.stats["solves"] += 1
        if spec.model == "ellipsoid":
            return fit_ellipsoid(W, spec.method, w_max=wm, solver=spec.solver)
        if spec.model == "quartic":
            return fit_quartic(W, twists=xi if spec.normals else None, w_max=wm, solver=spec.solver)
        raise ValueError(f"model must be 'ellipsoid' or 'quartic'; got {spec.model!r}")


def _save(path: Path, model: LimitSurfaceModel) -> None:
    arrays = {
        "w_max": model.w_max,
        "scale": model.scale,
        "basis": model.subspace.basis,
        "complement": model.subspace.complement,
        "std": model.subspace.std,
        "info": np.array(json.dumps(model.info, default=str)),
    }
    if isinstance(model, EllipsoidLS):
        arrays.update(kind=np.array("ellipsoid"), A_e=model.A_e)
    else:
        arrays.update(kind=np.array("quartic"), A_q=model.A_q, gram=model.gram)
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    atomic_write_bytes(path, buf.getvalue())


def _load(path: Path) -> LimitSurfaceModel:
    with np.load(path) as d:
        sub = Subspace(d["basis"], d["complement"], d["std"])
        info = json.loads(str(d["info"]))
        if str(d["kind"]) == "ellipsoid":
            return EllipsoidLS(d["w_max"], d["scale"], sub, info, A_e=d["A_e"])
        return QuarticLS(d["w_max"], d["scale"], sub, info, A_q=d["A_q"], gram=d["gram"])

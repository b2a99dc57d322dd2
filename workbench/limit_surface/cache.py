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
import logging
import os
from collections import Counter
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from .. import config
from ..atomic_io import atomic_write_bytes
from ..coarsen import NoTangentPlane, _coarsen
from ..config import SAMPLER_KINDS
from ..profile import ContactProfile
from ..seeds import check_seed
from ..twists import sample_twists_6dfc, sample_twists_thesis
from ..twists_author import AUTHOR_LEVELS, box_sides
from ..wrench import check_mu, frictional_wrenches, w_max
from .base import LimitSurfaceModel
from .contact_wrench import ContactWrenchModel
from .ellipsoid import EllipsoidLS, fit_ellipsoid
from .normalize import Subspace
from .quartic import QuarticLS, fit_quartic
from .thesis_code import thesis_code_sample

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SamplerSpec:
    """Training-wrench sampler settings (part of the cache key).

    kind : "thesis" (§3.3.2: n rotations + n translations), "6dfc" (paper §IV-C.1:
        k1 = n, k2 = n // 2), "thesis-code" (the author's twist grid of ``fine_level``,
        one wrench per occupied cell of the downsampling grid,
        :mod:`.thesis_code`; ``n``, ``seed`` and ``radius_factor`` unused) or "mix"
        (the "thesis" sample and the "thesis-code" one together).
    cell_fraction : 0: the training wrenches are the contact's own 6DFWs.  In [0.001, 0.5]: they
        are those of the contact coarsened to square cells of side ``cell_fraction`` × its
        ``l_s`` (:func:`workbench.coarsen.coarsen_profile`, each cell at its centre of pressure,
        so the pressure centre o stays; the thesis's 3 mm FEM elements are ~0.15 l_s, §3.5.2),
        the twists still drawn on the contact itself (the author's grid on its own box).  A
        contact with no tangent plane to lay cells in (its normals cancel) or of one element is
        trained as given, logged and recorded in the model's ``info["training_cells"]`` (None).
        None: ``config.DEFAULTS.ls_training_cell_fraction`` (0), read when the spec is made.
    """

    kind: str | None = None  # None: config.DEFAULTS.ls_training_sampler, read when the spec is made
    n: int = 300
    seed: int = 0
    radius_factor: float = 0.25
    fine_level: int = 0  # thesis-code / mix only
    # the training contact's cell side [l_s]; 0: the contact as given; None: the config default
    cell_fraction: float | None = None

    def __post_init__(self) -> None:
        if self.kind is None:
            object.__setattr__(self, "kind", config.DEFAULTS.ls_training_sampler)
        if self.kind not in SAMPLER_KINDS:
            raise ValueError(f"sampler kind must be one of {SAMPLER_KINDS}; got {self.kind!r}")
        if self.fine_level not in AUTHOR_LEVELS:
            raise ValueError(f"fine_level must be one of {sorted(AUTHOR_LEVELS)}; got {self.fine_level!r}")
        check_seed(self.seed, generator=False)  # part of the cache key: the same draw every time
        cell = self.cell_fraction
        cell = config.DEFAULTS.ls_training_cell_fraction if cell is None else cell
        # the Defaults field's rule, as a float (0.1 and np.float64(0.1) share a cache key)
        what = "SamplerSpec cell_fraction (a fraction of the contact's l_s)"
        object.__setattr__(self, "cell_fraction", config.check_value("ls_training_cell_fraction", cell, what))

    def twists(self, profile: ContactProfile) -> np.ndarray:
        """(K, 6) twists of the "thesis" or "6dfc" sampler (the grid kinds choose
        their twists by their wrenches: use :meth:`training`)."""
        if self.kind == "thesis":
            return sample_twists_thesis(self.n, profile, self.seed, radius_factor=self.radius_factor)
        if self.kind == "6dfc":
            return sample_twists_6dfc(
                self.n, self.n // 2, profile, self.seed, radius_factor=self.radius_factor
            )
        raise ValueError(f"{self.kind!r} selects twists by their wrenches; call training(profile, mu)")

    def training(self, profile: ContactProfile, mu: float) -> tuple[np.ndarray, np.ndarray]:
        """Training twists (K, 6) and their raw friction wrenches (K, 6) on ``profile`` (on its
        coarsened copy when ``cell_fraction`` > 0)."""
        return self._training(profile, self.sliding_profile(profile), mu)

    def _training(
        self, profile: ContactProfile, sliding: ContactProfile, mu: float
    ) -> tuple[np.ndarray, np.ndarray]:
        parts = []
        if self.kind in ("thesis", "6dfc", "mix"):
            spec = self if self.kind != "mix" else replace(self, kind="thesis")
            xi = spec.twists(profile)
            parts.append((xi, frictional_wrenches(sliding, xi, mu)))
        if self.kind in ("thesis-code", "mix"):
            # the grid on the contact's own box: the twists do not depend on the coarsening
            sides = None if sliding is profile else box_sides(profile)
            code = thesis_code_sample(sliding, mu, self.fine_level, sides=sides)
            parts.append((code.train_twists, code.train_wrenches))
        return np.vstack([p[0] for p in parts]), np.vstack([p[1] for p in parts])

    def sliding_profile(self, profile: ContactProfile) -> ContactProfile:
        """The contact whose 6DFWs train the model: ``profile`` itself, or its ``cell_fraction``
        coarsening; a contact of one element, or with no tangent plane (coarsen's
        NoTangentPlane), is used as given, with a warning in the log for the latter (the model's
        ``info["training_cells"]`` is then None)."""
        if self.cell_fraction == 0 or len(profile.areas) < 2:
            return profile
        try:
            # cells at their centres of pressure: the twists' reference point o stays put
            return _coarsen(profile, self.cell_fraction * profile.length_scale, "pressure")
        except NoTangentPlane as err:
            n = len(profile.areas)
            log.warning("training wrenches on the contact as given (%d elements): %s", n, err)
            return profile


@dataclass(frozen=True)
class ModelSpec:
    """Which model to fit (part of the cache key)."""

    model: str = "ellipsoid"  # "ellipsoid" or "quartic"
    method: str = "lsq"  # ellipsoid: "lsq" | "sdp"
    # None: the model's default, read when the spec is made (part of the key):
    # config.DEFAULTS.ellipsoid_solver for the ellipsoid's SDP, .quartic_solver for the quartic
    solver: str | None = None
    exact_w_max: bool = True  # normalise by the canonical-twist support values
    normals: bool = True  # quartic: also fit the twists as outward normals (fit_quartic(twists=...))

    def __post_init__(self) -> None:
        if self.solver is None:
            d = config.DEFAULTS
            default = d.quartic_solver if self.model == "quartic" else d.ellipsoid_solver
            object.__setattr__(self, "solver", default)


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
    """In-memory (and optionally on-disk) cache of fitted limit surfaces.

    directory : where fitted surfaces are kept as ``<key>.npz`` (made when the first is
        written); None: in memory only.  A path that exists as a file is refused here.
    """

    def __init__(self, directory: str | Path | None = None) -> None:
        self._mem: dict[str, LimitSurfaceModel] = {}
        if directory is not None and not isinstance(directory, (str, os.PathLike)):
            raise ValueError(
                f"directory must be a path (str or pathlib.Path) or None; got {type(directory).__name__}"
            )
        self.directory = None if directory is None else Path(directory)
        if self.directory is not None:
            # the first fit would fail on writing (FileExistsError) after the work is done
            blocked = next((q for q in (self.directory, *self.directory.parents) if q.exists()), None)
            if blocked is not None and not blocked.is_dir():
                what = (
                    "is a file"
                    if blocked == self.directory
                    else f"cannot be made: {str(blocked)!r} is a file"
                )
                raise ValueError(
                    f"LimitSurfaceCache directory must be a directory path; got {str(self.directory)!r}, "
                    f"which {what}, not a directory — pass a directory (it is made when the first "
                    "surface is written), e.g. the file's folder"
                )
        self.stats: Counter = Counter()

    @staticmethod
    def check(cache: Any, name: str = "cache") -> LimitSurfaceCache:
        """``cache`` if it is a :class:`LimitSurfaceCache`, a fresh in-memory one for None, else a
        ValueError naming the class (a path is not a cache: ``LimitSurfaceCache(path)`` keeps the
        surfaces there) — the one rule of a ``cache=`` argument."""
        if cache is None:
            return LimitSurfaceCache()
        if isinstance(cache, LimitSurfaceCache):
            return cache
        fix = (
            f"pass LimitSurfaceCache({str(cache)!r}) to keep the limit surfaces in that directory"
            if isinstance(cache, (str, os.PathLike))
            else "pass a LimitSurfaceCache() (shared across calls) or None"
        )
        raise ValueError(
            f"{name} must be a LimitSurfaceCache or None; got {type(cache).__name__} {cache!r} — {fix}"
        )

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
        sampler: SamplerSpec | None = None,
        spec: ModelSpec = ModelSpec(),
        force: float | None = None,
    ) -> LimitSurfaceModel:
        """Limit surface of ``profile`` scaled by ``force`` (default ``profile.F``);
        ``sampler`` default ``SamplerSpec()`` (``config.DEFAULTS.ls_training_sampler``)."""
        check_mu(mu, what="limit surface")
        sampler = SamplerSpec() if sampler is None else sampler
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
        sliding = sampler.sliding_profile(prof)
        xi, W = sampler._training(prof, sliding, mu)
        # the training contact's own maxima: the coarse contact's wrenches may pass the fine one's
        wm = w_max(sliding, mu) if spec.exact_w_max else None
        self.stats["solves"] += 1
        if spec.model == "ellipsoid":
            model = fit_ellipsoid(W, spec.method, w_max=wm, solver=spec.solver)
        elif spec.model == "quartic":
            model = fit_quartic(W, twists=xi if spec.normals else None, w_max=wm, solver=spec.solver)
        else:
            raise ValueError(f"model must be 'ellipsoid' or 'quartic'; got {spec.model!r}")
        if sampler.cell_fraction > 0:
            model.info["training_cells"] = len(sliding.areas) if sliding is not prof else None
        return model


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

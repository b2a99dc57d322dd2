"""Table 3.3's fits of one contact profile under both protocols, and the protocol ablation.

Thesis §3.5.2: each FEM contact profile (normalised, a "profile pair") gets the models of
:data:`MODELS` fitted and scored under both protocols of :mod:`.protocols`:

* thesis-text — ``n_wrenches`` wrenches of the thesis sampler, Eq. 3.18 on ``n_heldout``
  held-out ones of the same sampler (seed ``+ 10**6``) and on the training ones;
* thesis-code — the author's twist grid in the frame ``code_frame`` (their grid is
  axis-aligned: the object frame is theirs), trained on the grid-downsampled wrenches,
  Eq. 3.18 on all of them;

and under both the sampler-independent support error.  :func:`profile_fit_row` gives
these as one flat row.  The protocol ablation (:func:`protocol_ablation`) repeats the
thesis-code protocol with one thing changed (:data:`ABLATION_VARIANTS`).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from ..coarsen import coarsen_profile
from ..profile import ContactProfile
from ..wrench import check_mu
from .author_objective import fit_author_objective
from .fit_score import fit_model, min_wrenches
from .protocols import ExactContact, fit_scores, thesis_code_sample_of, thesis_text_wrenches
from .thesis_code import ThesisCodeSample, check_protocol_config

#: the fits of every profile (:mod:`.fit_score`): Table 3.3's two and the unconstrained
#: least-squares ellipsoid
MODELS = ("ellipsoid_sdp", "ellipsoid_lsq", "quartic_values")
#: the models of Table 3.3 and of the protocol ablation, and the thesis's name of each
FAMILY = {"ellipsoid_sdp": "ellipsoid", "quartic_values": "quartic"}
TABLE_MODELS = tuple(FAMILY)
#: the protocol ablation's variants: what each changes against the thesis-code row
ABLATION_VARIANTS = {
    "jaw_frame": "the grid in the jaw frame (z = grasp axis) instead of the object frame",
    "origin_in_box": "box sides of the contact's nodes and the object origin (the code's zero-filled array)",
    "coarse_elements": "elements merged into ablation_cell_mm squares (the thesis's element size)",
    "author_objective": "the author's objective: L1 values (10) + twist directions (1) + ||A|| (1)",
}
#: frames the author's axis-aligned grid can be laid in
CODE_FRAMES = ("object", "jaw")


@dataclass(frozen=True)
class ProfileFitSettings:
    """What the fits of a profile depend on (fem-fitting's keys of the same names)."""

    mu: float = 1.0  # friction coefficient (normalised wrenches do not depend on it)
    n_wrenches: int = 600  # thesis-text training wrenches (thesis: 600)
    n_heldout: int = 2000  # thesis-text held-out wrenches of Eq. 3.18
    pitch_range: tuple[float, float] | None = (-1.0, 1.0)  # thesis-text pitch h / l_s
    support_directions: int = 2000  # normals of the support error
    thesis_code: bool = True  # also the thesis-code protocol
    fine_level: int = 0  # its twist grid (0: 48,483 twists)
    downsample_steps: float = 2.5  # its training grid: cell widths per wrench range
    code_frame: str = "object"  # frame of its axis-aligned grid: "object" or "jaw"
    ablation_cell_mm: float = 3.0  # element size of the coarse_elements ablation [mm]

    def __post_init__(self) -> None:
        check_mu(self.mu, what="limit surface")
        check_protocol_config(
            {k: getattr(self, k) for k in ("fine_level", "downsample_steps", "support_directions")}
        )
        if self.code_frame not in CODE_FRAMES:
            raise ValueError(f"code_frame must be one of {CODE_FRAMES}; got {self.code_frame!r}")
        n_quartic = min_wrenches("quartic_values")
        if self.n_wrenches < n_quartic or self.n_heldout < 1:
            raise ValueError(
                f"n_wrenches must be >= {n_quartic} (the quartic's coefficients; the thesis uses 600) and "
                f"n_heldout >= 1; got {self.n_wrenches} and {self.n_heldout}"
            )
        # below 0.1 mm a cell is finer than the pad's elements (1 mm) by 10x, above 100 mm larger than
        # any contact: neither is a coarsening (and a size in m given as mm lands below 0.1)
        if not 0.1 <= self.ablation_cell_mm <= 100:
            raise ValueError(
                "ablation_cell_mm must be a cell size in mm in [0.1, 100] (3: the thesis's); "
                f"got {self.ablation_cell_mm!r}"
            )

    @classmethod
    def from_config(cls, config: dict) -> ProfileFitSettings:
        """The settings among an experiment's ``config`` keys (absent ones: the defaults);
        ``pitch_range`` as a tuple."""
        given = {f.name: config[f.name] for f in fields(cls) if f.name in config}
        if given.get("pitch_range") is not None:
            given["pitch_range"] = tuple(given["pitch_range"])
        return cls(**given)


def _text_row(pn: ContactProfile, s: ProfileFitSettings, seed: int) -> dict:
    """The thesis-text protocol's keys of the row (:func:`profile_fit_row`)."""
    contact = ExactContact.of_profile(pn, s.mu, s.support_directions)
    W, _ = thesis_text_wrenches(contact, s.n_wrenches, seed, pitch_range=s.pitch_range)
    W_test, _ = thesis_text_wrenches(contact, s.n_heldout, seed + 10**6, pitch_range=s.pitch_range)
    row = {}
    for m, fs in fit_scores(contact, MODELS, W, test=W_test, support_seed=seed).items():
        row[f"{m}_fit_s"] = fs.fit_s
        row[f"{m}_error"] = fs.test_error
        row[f"{m}_train_error"] = fs.train_error
        row[f"{m}_support"] = fs.support.radial_mean
        row[f"{m}_fallback"] = fs.fallback
        row["dim"] = fs.model.dim
    return row


def _code_row(pc: ContactProfile, s: ProfileFitSettings, seed: int) -> tuple[dict, ThesisCodeSample]:
    """The thesis-code protocol's keys of the row on ``pc`` (the profile in the grid's
    frame) and its sample."""
    contact = ExactContact.of_profile(pc, s.mu, s.support_directions)
    code = thesis_code_sample_of(contact, s.fine_level, s.downsample_steps)
    row = {"code_n_train": len(code.train), "code_n_pool": len(code.wrenches)}
    fits = fit_scores(contact, MODELS, code.train_wrenches, test=code.wrenches, support_seed=seed)
    for m, fs in fits.items():
        row[f"{m}_code_fit_s"] = fs.fit_s
        row[f"{m}_code_error"] = fs.test_error
        row[f"{m}_code_support"] = fs.support.radial_mean
    return row, code


def profile_fit_row(
    profile: ContactProfile,
    settings: ProfileFitSettings,
    seed: int,
    *,
    to_object: tuple[np.ndarray, np.ndarray] | None = None,
    ablate: bool = False,
) -> dict:
    """Sample, fit the models of :data:`MODELS`, and measure their errors on the normalised
    ``profile`` under both protocols (module docstring); flat row of
    ``<model>_{fit_s,error,train_error,support,fallback}``, ``dim``, and with
    ``settings.thesis_code`` ``code_n_train``, ``code_n_pool``,
    ``<model>_code_{fit_s,error,support}`` (a model absent where underdetermined) and with
    ``ablate`` the :func:`protocol_ablation` keys.

    to_object : (R (3, 3), t (3,)) of the profile's (jaw) frame in the object frame
        (``x_object = R x + t``), the frame of the thesis-code protocol; ``None``: the same.
    seed : of the thesis-text sampler (held-out: ``seed + 10**6``) and the support errors.
    """
    pn = profile.normalized()
    row = _text_row(pn, settings, seed)
    if settings.thesis_code:
        p_obj = pn if to_object is None else pn.transformed(*to_object)
        pc = p_obj if settings.code_frame == "object" else pn
        code_row, code = _code_row(pc, settings, seed)
        row.update(code_row)
        if ablate:
            row.update(protocol_ablation(p_obj, pn, settings, code if pc is p_obj else None))
    return row


def code_errors(
    pc: ContactProfile,
    settings: ProfileFitSettings,
    *,
    sides: Any = None,
    coarse: bool = False,
    author: bool = False,
    code: ThesisCodeSample | None = None,
) -> dict:
    """Thesis-code Eq. 3.18 errors {model: error} of one ablation variant on profile ``pc``:
    the models of :data:`TABLE_MODELS` (left out where underdetermined), or with ``author``
    the author's objective in their place; and ``"n_train"``.

    sides : (3,) box sides [m] of the author's grid in place of the profile's.
    coarse : ``pc`` coarsened to ``settings.ablation_cell_mm`` cells first.
    code : the thesis-code sample of ``pc`` when the caller has it (the same wrenches).
    """
    if coarse:
        pc = coarsen_profile(pc, settings.ablation_cell_mm * 1e-3)
    if code is None:
        contact = ExactContact.of_profile(pc, settings.mu, settings.support_directions)
        code = thesis_code_sample_of(contact, settings.fine_level, settings.downsample_steps, sides=sides)
    W, wm = code.train_wrenches, code.w_max
    if author:
        fits = {m: fit_author_objective(W, code.train_twists, FAMILY[m], w_max=wm) for m in TABLE_MODELS}
    else:
        fits = {m: fit_model(m, W, w_max=wm) for m in TABLE_MODELS if len(W) >= min_wrenches(m)}
    out: dict = {m: model.fitting_error(code.wrenches) for m, model in fits.items()}
    out["n_train"] = len(code.train)
    return out


def protocol_ablation(
    p_obj: ContactProfile,
    p_jaw: ContactProfile,
    settings: ProfileFitSettings,
    code_obj: ThesisCodeSample | None = None,
) -> dict:
    """Row keys ``abl_<variant>_<model>``: each of :data:`ABLATION_VARIANTS`' Eq. 3.18 error in
    place of the thesis-code protocol's ``<model>``, and ``abl_<variant>_n_train``.
    p_obj, p_jaw : the normalised profile in the object and in the jaw frame.
    code_obj : the thesis-code sample of ``p_obj`` if the caller has one (reused, not redrawn)."""
    pts = p_obj.vertices if p_obj.vertices is not None else p_obj.centers
    box_with_origin = np.ptp(np.vstack([pts, np.zeros(3)]), axis=0)
    variants = {
        "jaw_frame": lambda: code_errors(p_jaw, settings),
        "origin_in_box": lambda: code_errors(p_obj, settings, sides=box_with_origin),
        "coarse_elements": lambda: code_errors(p_obj, settings, coarse=True),
        "author_objective": lambda: code_errors(p_obj, settings, author=True, code=code_obj),
    }
    row = {}
    for name, fn in variants.items():
        for key, v in fn().items():
            row[f"abl_{name}_{key}"] = v
    return row


def ablation_due(index: int, every: int) -> bool:
    """Whether the ``index``-th profile (0-based, in sweep order) gets the protocol ablation:
    every ``every``-th one, starting with the first (none when ``every`` is 0)."""
    return bool(every) and index % every == 0


__all__ = [
    "ABLATION_VARIANTS",
    "CODE_FRAMES",
    "FAMILY",
    "MODELS",
    "TABLE_MODELS",
    "ProfileFitSettings",
    "ablation_due",
    "code_errors",
    "profile_fit_row",
    "protocol_ablation",
]

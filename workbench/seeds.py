"""The one rule of a seed: every sampler's ``seed`` (or ``rng``) is an int >= 0 or a
``numpy.random.Generator`` (CONVENTIONS.md, "Randomness and reproducibility").

A low-level module of its own so that the core samplers (:mod:`workbench.twists`,
:mod:`workbench.limit_surface`) and the grasp layer (:mod:`workbench.grasp.robust` re-exports
it) share it without importing each other.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["check_seed"]


def check_seed(seed: Any, name: str = "seed", *, generator: bool = True) -> int | np.random.Generator:
    """``seed`` of a Monte-Carlo draw: an int >= 0 or a ``numpy.random.Generator`` (returned as
    given; an int as a Python int), else a ValueError naming ``name`` — numpy's own says
    "SeedSequence expects int or sequence of ints", and a Generator method called on an int
    says "'int' object has no attribute 'uniform'".

    generator : False where the caller needs the same draw on every call (an int only): a
        Generator is then refused too.
    """
    if generator and isinstance(seed, np.random.Generator):
        return seed
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) or seed < 0:
        if not generator and isinstance(seed, np.random.Generator):
            raise ValueError(
                f"{name} must be an integer >= 0 here (the same draw on every call); got a "
                f"numpy.random.Generator, whose draws differ per call — pass an integer, e.g. {name}=0"
            )
        accepted = "an integer >= 0 or a numpy.random.Generator" if generator else "an integer >= 0"
        integral = (
            isinstance(seed, (float, np.floating)) and np.isfinite(seed) and seed >= 0 and seed == int(seed)
        )
        fix = f"pass {name}={int(seed)}" if integral else f"pass an integer, e.g. {name}=0"
        raise ValueError(
            f"{name} must be {accepted}; got {seed!r} — {fix} (the same seed gives the same samples)"
        )
    return int(seed)

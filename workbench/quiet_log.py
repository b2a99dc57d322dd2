"""A logger quieted for a loop whose per-item messages the caller sums up itself."""

from __future__ import annotations

import logging
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["quieted"]


@contextmanager
def quieted(logger: logging.Logger, level: int = logging.ERROR) -> Iterator[None]:
    """``logger`` passes only records at ``level`` or above inside the block, and its own level
    again after it (also on an exception).  For a loop that records what each call would log
    (drops, fallbacks) and logs one summary line: the rule that nothing is silent still holds."""
    before = logger.level
    logger.setLevel(level)
    try:
        yield
    finally:
        logger.setLevel(before)

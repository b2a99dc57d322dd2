"""Settings groups given where a function takes one.

A settings group is a frozen dataclass that gathers one function's options and checks its own
fields when made (:class:`~workbench.grasp.inputs.Task`, :class:`~workbench.grasp.models.ModelParameters`,
:class:`~workbench.fem.wall.SqueezeControls`, ...).  A function taking one accepts the group
or None (the group's defaults) and nothing else: a dict of the old keyword arguments is refused
with the call that builds the group from it.  One check, here, so that every entry point gives
the same answer and the same message.
"""

from __future__ import annotations

import sys
from typing import Any, TypeVar

__all__ = ["checked_group", "public_name"]

G = TypeVar("G")


def public_name(kind: type) -> str:
    """The shortest dotted name ``kind`` can be imported by: its module's nearest enclosing
    package that exports it (``workbench.grasp.Task`` for ``workbench.grasp.inputs.Task``)."""
    parts = kind.__module__.split(".")
    for n in range(1, len(parts) + 1):
        module = sys.modules.get(".".join(parts[:n]))
        if module is not None and getattr(module, kind.__name__, None) is kind:
            return f"{module.__name__}.{kind.__qualname__}"
    return f"{kind.__module__}.{kind.__qualname__}"


def checked_group(value: Any, kind: type[G], name: str, *, hint: str = "", required: bool = False) -> G:
    """``value`` if it is a ``kind``, ``kind()`` (its defaults) for None, else a ValueError that
    names the group by its public name, what was given, and the fix: ``Kind(**name)`` for a dict,
    else ``hint`` (how to build one) or leaving ``name`` out.

    value : the argument as given; kind : the group's class; name : the argument's name;
    required : a group with no defaults to stand in (e.g. the task's load): None is refused too,
    and the message says it is required (``hint`` then says how to build one)."""
    if value is None and not required:
        return kind()
    if isinstance(value, kind):
        return value
    if isinstance(value, dict):
        fix = f"pass {kind.__name__}(**{name})"
    else:
        fix = hint or f"pass a {kind.__name__}(...) or leave {name} out for the defaults"
    what = "required" if required else "or None: its defaults"
    raise ValueError(f"{name} must be a {public_name(kind)} ({what}); got {type(value).__name__} — {fix}")

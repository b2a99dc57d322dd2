"""What an experiment's config key means: its unit, its physical quantity and its allowed values.

Each experiment module declares ``KEYS = {name: Key(...)}`` beside its ``DEFAULT_CONFIG``.
:func:`~workbench.runner.experiment_config.build_config` judges every ``--set`` and ``--grid``
value by it before any work — the physical numbers by the one rule of their quantity
(:mod:`workbench.plausible`: ``--set E=2500`` on a bottle wall is refused as "probably in
MPa"), the words by their allowed values — and ``workbench run NAME --help`` prints it.
The keys every experiment shares (``seed``, ``workers``, ``scheduler``) are :data:`COMMON`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from .. import plausible

__all__ = ["COMMON", "Key", "check_key", "describe"]


@dataclass(frozen=True)
class Key:
    """One config key.

    doc : what it is, in a few words ("wall Young's modulus", "pad (width, length)").
    unit : the unit its numbers are given in ("Pa", "m", "mm", "N", "kg"); "" if none.
    quantity : the :data:`workbench.plausible.RANGES` quantity every number of the value
        is (a list: each element; a dict without ``fields``, e.g. ``{object: kg}``: each
        value); ``None``: not a physical input judged there.
    scale : SI units per unit of the value (1e-3 for a key in mm), applied before the check.
    choices : the allowed values of a word (or of each word of a list), or a callable
        returning them (read at check time, so the library's own list is the one source).
    fields : ``{field: (quantity, scale)}`` of a dict value's physical fields, or of a list
        value's positions (int keys: a pad ``[w, l, h]`` in mm is two sizes and a thickness);
        stored read-only.
    unset : a value meaning "not given, use the data's own" (e.g. a mass of 0 read from the
        trial file): not judged.
    named, examples : what ``quantity`` is called in a refusal or warning, and the real values
        quoted there, instead of the range's own (:func:`workbench.plausible.check`'s): a drift
        limit judged by the "closing" range is not "a jaw closing ... a pad pressed 0.1-5 mm".
    """

    doc: str
    unit: str = ""
    quantity: str | None = None
    scale: float = 1.0
    choices: Sequence[Any] | Callable[[], Sequence[Any]] | None = None
    fields: Mapping[str | int, tuple[str, float]] = field(default_factory=dict)
    unset: Any = None
    named: str | None = None
    examples: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "fields", MappingProxyType(dict(self.fields)))
        for q in [self.quantity, *(q for q, _ in self.fields.values())]:
            if q is not None and q not in plausible.RANGES:
                raise ValueError(f"Key quantity {q!r} is not one of {sorted(plausible.RANGES)}")

    def allowed(self) -> tuple[Any, ...] | None:
        """The allowed values (``choices`` called if it is a callable)."""
        if self.choices is None:
            return None
        return tuple(self.choices() if callable(self.choices) else self.choices)


#: keys whose meaning is the same in every experiment
COMMON: dict[str, Key] = {
    "seed": Key("random seed (numpy), >= 0"),
    "workers": Key(
        "where rows run: 0 = a local Dask cluster of one worker per core when there are many rows, "
        "1 = serially in this process, N = N local workers (changes no number)"
    ),
    "scheduler": Key("address of an existing Dask scheduler (tcp://host:port); empty = a local cluster"),
}


def _numbers(value: Any, maps: bool = False) -> list[tuple[str, float]]:
    """The numbers of ``value`` (a number, or nested lists of them; with ``maps`` also a dict's
    values), in order, each with its place ("", "[1]", "['cup']")."""
    if isinstance(value, bool):
        return []
    if isinstance(value, (int, float)):
        return [("", value)]
    if isinstance(value, (list, tuple)):
        return [(f"[{i}]{p}", x) for i, v in enumerate(value) for p, x in _numbers(v, maps)]
    if maps and isinstance(value, dict):
        return [(f"[{k!r}]{p}", x) for k, v in value.items() for p, x in _numbers(v, maps)]
    return []


def _words(value: Any) -> list[str]:
    if isinstance(value, str):
        return [value]
    if isinstance(value, (list, tuple)):
        return [x for v in value for x in _words(v)]
    return []


def check_key(name: str, key: Key, value: Any) -> None:
    """``ValueError`` unless every number of ``value`` is a plausible ``key.quantity`` and every
    word one of ``key.choices`` (an :class:`~workbench.plausible.ImplausibleWarning` for an
    unusual number); the message names the key, its unit and the likely slip."""
    if key.unset is not None and value == key.unset:
        return
    if key.quantity is not None:
        for place, x in _numbers(value, maps=not key.fields):
            what = f"{name}{place} [{key.unit}]" if key.unit else f"{name}{place}"
            plausible.check(
                key.quantity,
                x,
                what,
                scale=key.scale,
                unit=key.unit or None,
                examples=key.examples,
                named=key.named,
            )
    for f, (q, scale) in key.fields.items():
        if isinstance(value, dict):
            v = value.get(f) if isinstance(f, str) else None
        else:
            v = (
                value[f]
                if isinstance(value, (list, tuple)) and isinstance(f, int) and f < len(value)
                else None
            )
        if v is not None and not isinstance(v, bool) and isinstance(v, (int, float)):
            what = f"{name}[{f!r}]" + (f" [{key.unit}]" if key.unit else "")
            plausible.check(q, v, what, scale=scale, unit=key.unit or None)
    allowed = key.allowed()
    if allowed is not None:
        bad = [w for w in _words(value) if w not in allowed]
        if not _words(value) and not isinstance(value, (list, tuple)) and value not in allowed:
            bad = [value]
        if bad:
            raise ValueError(
                f"{name} must be one of {list(allowed)}; got {value!r} ({', '.join(map(repr, bad))} not)"
                + _did_you_mean(bad, allowed)
            )


def _did_you_mean(bad: list, allowed) -> str:
    """The hint " — did you mean '6dls'?" for the words of ``bad`` that are an allowed word in another case
    or spelling ("6DLS", "soft-point"), else ""."""
    import difflib

    hints = []
    for w in bad:
        key = str(w).lower().replace("-", "_").replace(" ", "_")
        close = difflib.get_close_matches(key, [str(a) for a in allowed], n=1, cutoff=0.6)
        if close:
            hints.append(f"{close[0]!r} for {w!r}")
    return f" — did you mean {', '.join(hints)}?" if hints else ""


def describe(key: Key) -> str:
    """A one-line description for ``--help``: meaning, unit, plausible range, allowed values."""
    parts = [key.doc]
    if key.unit:
        parts[0] += f" [{key.unit}]"
    if key.quantity is not None:
        r = plausible.RANGES[key.quantity]
        lo, hi = (u / key.scale for u in r.usual)
        unit = f" {key.unit}" if key.unit else ""
        parts.append(f"plausible {r.interval(key.scale)}{unit}, usual [{lo:g}, {hi:g}]{unit}")
    for f, (q, scale) in key.fields.items():
        r = plausible.RANGES[q]
        unit = key.unit or r.unit  # a field is in its key's unit
        parts.append(f"[{f!r}] {r.name} {r.interval(scale)} {unit}".rstrip())
    if key.unset is not None:
        parts.append(f"{key.unset!r} = not given (taken from the data)")
    allowed = key.allowed()
    if allowed is not None:
        parts.append("one of " + ", ".join(map(str, allowed)))
    return "; ".join(parts)


def verdict_keys(judged: str) -> dict[str, Key]:
    """The keys ``max_drift`` [m] and ``max_turn_deg`` of an engine-judged experiment, ``judged``
    naming what passes (e.g. "resisted grasp", "completed task"): the drift judged by the trials'
    own rule for their drift limit (the "closing" range, in the trials' words)."""
    from ..engine_trials.trial import _DRIFT_EXAMPLES

    return {
        "max_drift": Key(
            f"engine verdict: a {judged}'s largest drift of the object relative to the gripper",
            "m",
            "closing",
            named="limit on the object's drift in the gripper",
            examples=_DRIFT_EXAMPLES,
        ),
        "max_turn_deg": Key(f"engine verdict: largest turn of a {judged} [deg]"),
    }

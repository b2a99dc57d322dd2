"""The experiments' registry and their configs: name -> module, and each run's config built
from the experiment's defaults, its quick overrides and the user's ``--set`` values, checked
before any work (used by the ``workbench`` command line and by :mod:`workbench.runner.sweep`)."""

from __future__ import annotations

import importlib
import json
import math
import shlex
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .experiment_keys import COMMON, Key, check_key, describe

#: experiment name -> module in the ``experiments`` package
EXPERIMENTS = {
    "parametric-surfaces": "workbench.experiments.parametric_surfaces",
    "discretization": "workbench.experiments.discretization",
    "ls-fitting": "workbench.experiments.ls_fitting",
    "fem-validation": "workbench.experiments.fem_validation",
    "fem-fitting": "workbench.experiments.fem_fitting",
    "power-law": "workbench.experiments.power_law",
    "wall-stiffness": "workbench.experiments.wall_stiffness",
    "sensitivity": "workbench.experiments.sensitivity",
    "sensitivity-engine": "workbench.experiments.sensitivity_engine",
    "sensitivity-engine-bottles": "workbench.experiments.sensitivity_engine_bottles",
    "engine-validation": "workbench.experiments.engine_validation",
    "minimal-work": "workbench.experiments.minimal_work",
    "minimal-work-engine": "workbench.experiments.minimal_work_engine",
    "wall-nonlinear": "workbench.experiments.wall_nonlinear",
    "peers": "workbench.experiments.peers",
    "physical-trials": "workbench.experiments.physical_trials",
    "grasp-dataset": "workbench.experiments.grasp_dataset",
}


class _CliText(str):
    """The raw text of a ``--set`` value, parsed once the key's type is known."""


def _parse_value(text: str) -> Any:
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def _parse_sets(items: list[str]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for item in items:
        if "=" not in item:
            raise SystemExit(f"--set expects key=value; got {item!r}")
        key, value = item.split("=", 1)
        key = key.strip()
        if key in out:  # the last one would win silently
            raise SystemExit(f"--set {key} is given twice ({out[key]} and {value}); give it once")
        out[key] = _CliText(value)
    return out


# ------------------------------------------------------------------ value types
# A schema is inferred from a default value: "bool", "int", "float", "str",
# "any" (None defaults, or lists mixing kinds), ("list", element schema or None
# for an empty default), ("map", value schema) for dicts whose values share one
# type (free keys, e.g. {"major": 0.0, "minor": 1.57}), ("record", {key: schema})
# for dicts of mixed types (fixed keys, e.g. a pad's width and nx).


def _schema(default: Any) -> Any:
    if default is None:
        return "any"
    if isinstance(default, bool):
        return "bool"
    if isinstance(default, int):
        return "int"
    if isinstance(default, float):
        return "float"
    if isinstance(default, str):
        return "str"
    if isinstance(default, (list, tuple)):
        return ("list", _merge([_schema(v) for v in default]) if default else None)
    if isinstance(default, dict):
        values = {str(k): _schema(v) for k, v in default.items()}
        kinds = set(map(repr, values.values()))
        if not values:
            return ("map", "any")
        if len(kinds) == 1:
            return ("map", next(iter(values.values())))
        return ("record", values)
    return "any"


def _merge(schemas: list[Any]) -> Any:
    """One schema for the elements of a list: int and float merge to float."""
    kinds = {repr(s) for s in schemas}
    if len(kinds) == 1:
        return schemas[0]
    if kinds == {"'int'", "'float'"}:
        return "float"
    return "any"


def _describe(schema: Any) -> str:
    if schema is None:
        return "any JSON value"
    if isinstance(schema, str):
        return {"any": "any JSON value"}.get(schema, schema)
    kind, inner = schema
    if kind == "list":
        return "list" if inner is None else f"list of {_describe(inner)}"
    if kind == "map":
        return f"object of {_describe(inner)}"
    return "object {" + ", ".join(f"{k}: {_describe(v)}" for k, v in inner.items()) + "}"


class _Mismatch(Exception):
    """A value does not fit its schema; ``args[0]`` says where and why."""


class ConfigValueError(SystemExit):
    """A config value that does not fit its key's default, raised before any work: its
    ``SystemExit`` message is the CLI's (``--set KEY=VALUE: ...``), and its parts — ``key``, the
    value as given (``text``), what the key ``expects``, its ``default`` (JSON) and the
    ``reason`` — let a caller that took the value from another option word it for that option
    (:meth:`message`; a sweep's ``--grid``) instead of rewriting the text."""

    def __init__(self, key: str, text: str, expects: str, default: str, reason: str, flag: str = "--set"):
        self.key, self.text, self.expects, self.default, self.reason = key, text, expects, default, reason
        self.flag = flag
        super().__init__(self.message())

    def example(self) -> str:
        """The default as the option that gave the value takes it: ``--set 'mu=0.5'``, ``--seed 0``."""
        if self.flag == "--set":
            return f"--set {shlex.quote(f'{self.key}={self.default}')}"
        return f"{self.flag} {self.default}"

    def message(self, given: str | None = None, fix: str | None = None) -> str:
        """``GIVEN: KEY expects ... (default ...); REASON — FIX``; ``given`` defaults to the option
        and value (``--set mu=-1``, ``--seed -1``), ``fix`` to an example with the default."""
        if given is None:
            given = f"--set {self.key}={self.text}" if self.flag == "--set" else f"{self.flag} {self.text}"
        fix = f"give e.g. {self.example()}" if fix is None else fix
        return f"{given}: {self.key} expects {self.expects} (default {self.default}); {self.reason} — {fix}"


def _check(value: Any, schema: Any, where: str) -> Any:
    """``value`` coerced to ``schema`` (int -> float); raises _Mismatch."""
    if schema is None or isinstance(schema, str):
        return _check_scalar(value, schema, where)
    kind, inner = schema
    if isinstance(value, str) and value.lstrip()[:1] in ("[", "{"):  # JSON that did not parse
        try:
            json.loads(value)
        except json.JSONDecodeError as exc:
            what = "list" if kind == "list" else "object"
            raise _Mismatch(f"{where}{value!r} is not a JSON {what} ({exc})") from None
    if kind == "list":
        if not isinstance(value, (list, tuple)):
            raise _Mismatch(f"{where}{value!r} is not a list")
        return [_check(v, inner, f"{where}element {i}: ") for i, v in enumerate(value)]
    if not isinstance(value, dict):
        raise _Mismatch(f"{where}{value!r} is not an object")
    if kind == "map":
        return {k: _check(v, inner, f"{where}[{k!r}]: ") for k, v in value.items()}
    extra = sorted(set(value) - set(inner))
    if extra:
        raise _Mismatch(f"{where}unknown key(s) {extra} (known: {sorted(inner)})")
    return {k: _check(v, inner[k], f"{where}[{k!r}]: ") for k, v in value.items()}


#: scalar schema -> (test of a value, what a value that fails it is not); "float" and "any"
#: have their own rules (finiteness, int -> float) in :func:`_check_scalar`
_SCALAR_TESTS: dict[str, tuple[Callable[[Any], bool], str]] = {
    "bool": (lambda v: isinstance(v, bool), "is not a bool (true or false)"),
    "int": (lambda v: isinstance(v, int) and not isinstance(v, bool), "is not an int"),
    "str": (lambda v: isinstance(v, str), "is not a string"),
}


def _check_scalar(value: Any, schema: str | None, where: str) -> Any:
    """``value`` checked against a scalar ``schema`` (:func:`_check`); raises _Mismatch."""
    if schema == "any" or schema is None:
        _check_finite(value, where)
        return value
    if schema == "float":
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            if not math.isfinite(value):
                raise _Mismatch(f"{where}{value!r} is not finite")
            return float(value)
        raise _Mismatch(f"{where}{value!r} is not a number")
    test, what = _SCALAR_TESTS[schema]
    if not test(value):
        raise _Mismatch(f"{where}{value!r} {what}")
    return str(value) if schema == "str" else value


def _check_finite(value: Any, where: str) -> None:
    if isinstance(value, float) and not math.isfinite(value):
        raise _Mismatch(f"{where}{value!r} is not finite")
    if isinstance(value, (list, tuple)):
        for v in value:
            _check_finite(v, where)
    elif isinstance(value, dict):
        for v in value.values():
            _check_finite(v, where)


def _coerce(key: str, value: Any, default: Any, flag: str = "--set") -> Any:
    """The ``--set`` value for ``key`` checked against its default's type, or
    :class:`ConfigValueError`; ``flag`` names an option that gives the key alone (``--seed``)
    in the message instead of ``--set key=``."""
    schema = _schema(default)
    if isinstance(value, _CliText):
        text = str(value)
        parsed = _parse_value(text)
        # a str key takes the text itself unless it is a JSON string ("S3" or "\"S3\"")
        value = parsed if schema != "str" or isinstance(parsed, str) else text
    else:
        text = _dumps(value)
    try:
        return _check_range(key, _check(value, schema, ""), default)
    except _Mismatch as exc:
        raise ConfigValueError(key, text, _describe(schema), _dumps(default), exc.args[0], flag) from None


def _number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _check_range(key: str, value: Any, default: Any) -> Any:
    """Generic ranges read off the defaults (no per-key tables): a number, or a list's
    numbers, whose default is non-negative must be non-negative (μ, counts, sizes,
    noise levels; offsets with negative defaults are free); a ``*_range`` key is
    ``[lo, hi]`` with ``lo <= hi``.  Maps (e.g. approach angles) are not judged."""
    if _number(default) and default >= 0 and _number(value) and value < 0:
        # a float key may be a size the experiment refuses at 0 too; an integer key (a seed, a
        # count) takes 0 unless its experiment says otherwise
        zero = "" if isinstance(default, int) else " (the experiment may refuse 0 as well, e.g. a thickness)"
        raise _Mismatch(
            f"{value!r} is negative; the default is not, and this key takes no negative values{zero}"
        )
    if isinstance(default, (list, tuple)) and default and all(_number(d) and d >= 0 for d in default):
        bad = [v for v in value if _number(v) and v < 0]
        if bad:
            raise _Mismatch(f"elements {bad} are negative; this key takes no negative values")
    if key.endswith("_range") and isinstance(default, (list, tuple)) and len(default) == 2:
        if len(value) != 2 or not value[0] <= value[1]:
            raise _Mismatch(f"{value!r} is not a range [lo, hi] with lo <= hi")
    return value


def _dumps(value: Any) -> str:
    return json.dumps(value, default=repr)


def build_config(name: str, quick: bool, out: str | None, seed: int | None, sets: dict[str, Any]) -> dict:
    """Experiment config: its defaults, then quick overrides, then CLI values.

    Every ``sets`` value must fit the type of the key's default (bool, int, float
    — an int is accepted and converted —, str, lists and dicts element by
    element, anything for a ``None`` default) and numbers must be finite;
    otherwise, or for an unknown key, ``SystemExit`` says which key, what it
    expects and what it got — before any work starts.  An experiment's optional
    ``check_config(config)`` then checks what the defaults cannot tell (a ``ValueError``
    naming the key becomes the ``SystemExit``).
    """
    if name not in EXPERIMENTS:
        raise SystemExit(f"unknown experiment {name!r}; known: {sorted(EXPERIMENTS)}")
    module = importlib.import_module(EXPERIMENTS[name])
    config = dict(module.DEFAULT_CONFIG)
    if quick:
        config.update(module.QUICK_CONFIG)
    config["quick"] = quick
    config["out"] = str(Path(out) if out else Path("results") / name)
    _apply_seed(name, module, config, seed, sets)
    _check_set_keys(name, config, sets)
    defaults = {**module.DEFAULT_CONFIG, "quick": False, "out": config["out"]}
    config.update({key: _coerce(key, value, defaults[key]) for key, value in sets.items()})
    _check_set_values(name, module, config, sets)
    return config


def _apply_seed(name: str, module: Any, config: dict, seed: int | None, sets: dict[str, Any]) -> None:
    """Put ``--seed`` into ``config`` (checked like ``--set seed=...``), or ``SystemExit`` for an
    experiment without a seed key or a seed also given by ``--set``."""
    refusal = None if seed is None else seed_refusal(name, seed)
    if refusal is not None:  # a seed the experiment does not read: the run would ignore it silently
        raise SystemExit(refusal)
    if seed is not None and "seed" in sets:  # one of them would be ignored silently
        raise SystemExit(f"seed is given by --seed ({seed}) and by --set seed={sets['seed']}: give it once")
    if seed is not None:  # checked like --set seed=... (a negative seed fails in numpy otherwise)
        config["seed"] = _coerce("seed", seed, module.DEFAULT_CONFIG["seed"], "--seed")


def _check_set_keys(name: str, config: dict, sets: dict[str, Any]) -> None:
    """``SystemExit`` for a ``--set`` of ``quick`` or ``out``, or of a key ``config`` does not have
    (with the closest known keys)."""
    reserved = sorted({"quick", "out"} & set(sets))
    if reserved:  # a grid over them would label quick runs "quick=False" or write outside the sweep
        raise SystemExit(f"{reserved} are set by --quick and --out, not as config values")
    unknown = set(sets) - set(config)
    if unknown:
        import difflib

        known = sorted(set(config) - {"quick", "out"})
        hints = {k: difflib.get_close_matches(k, known, n=1) for k in sorted(unknown)}
        close = [f"{h[0]!r} for {k!r}" for k, h in hints.items() if h]
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        raise SystemExit(f"unknown config keys for {name}: {sorted(unknown)}{hint}; known: {known}")


def _check_set_values(name: str, module: Any, config: dict, sets: dict[str, Any]) -> None:
    """``SystemExit`` for a ``--set`` value its key's rule refuses, or a config the experiment's
    own ``check_config`` refuses."""
    keys = key_specs(module)
    for key in sets:  # each physical number by its quantity's one rule, each word by its choices
        if key in keys:
            try:
                check_key(key, keys[key], config[key])
            except ValueError as exc:
                raise SystemExit(f"{name}: --set {key}={_dumps(config[key])}: {exc}") from None
    check = getattr(module, "check_config", None)  # what a key's default cannot tell (a level, a kind)
    if check is not None:
        try:
            check(config)
        except ValueError as exc:
            raise SystemExit(f"{name}: {exc}") from None


def seed_refusal(name: str, seed: Any, flag: str = "--seed") -> str | None:
    """Why ``flag SEED`` cannot seed experiment ``name``, or None if it can: an experiment with
    no ``seed`` key would run unchanged while its summary recorded the seed, so the option is
    refused, naming the experiment's own seed keys (``seeds``, a list) and how to set them."""
    if name not in EXPERIMENTS:  # build_config names the unknown experiment
        return None
    module = importlib.import_module(EXPERIMENTS[name])
    defaults = module.DEFAULT_CONFIG
    if "seed" in defaults:
        return None
    # a negative or non-integer seed is not suggested back (the key's own check would refuse it)
    good = isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0
    example = seed if good else 0
    keys = key_specs(module)
    own = []
    for k, default in defaults.items():
        if "seed" not in k:
            continue
        value = [example] if isinstance(default, list) else example
        what = "a list" if isinstance(default, list) else _describe(_schema(default))
        doc = f"{keys[k].doc}; " if k in keys else ""
        own.append(f"`{k}` ({doc}{what}): use --set {shlex.quote(f'{k}={_dumps(value)}')}")
    head = f"{flag} {seed}: {name} has no `seed` key: {flag} would change no number, yet be recorded"
    if not own:
        return f"{head}; it takes no seed — drop {flag}"
    return f"{head}; its draws are seeded by " + " and by ".join(own)


def key_specs(module: Any) -> dict[str, Key]:
    """The :class:`~workbench.runner.experiment_keys.Key` of each config key of an experiment module:
    its ``KEYS``, then the keys every experiment shares."""
    return {**COMMON, **getattr(module, "KEYS", {})}


def config_help(name: str) -> str:
    """The keys of experiment ``name`` with type, default, ``--quick`` value, and what each
    means: unit, plausible range, allowed values (:func:`~workbench.runner.experiment_keys.describe`)."""
    module = importlib.import_module(EXPERIMENTS[name])
    quick = module.QUICK_CONFIG
    keys = key_specs(module)
    lines = ["config keys (--set KEY=VALUE, JSON; a bare word is a string):"]
    for key, default in module.DEFAULT_CONFIG.items():
        line = f"  {key} ({_describe(_schema(default))}) = {_dumps(default)}"
        if key in quick:
            line += f"   [--quick: {_dumps(quick[key])}]"
        lines.append(line)
        if key in keys:
            lines.append(f"      {describe(keys[key])}")
    lines.append("  quick, out: set by --quick and --out")
    return "\n".join(lines)

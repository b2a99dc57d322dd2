"""``workbench`` console script: ``workbench run <experiment> [--quick] [--out DIR]
[--seed N] [--set key=value ...]``, ``workbench sweep <experiment> --grid KEY=JSON_LIST ...``
(:mod:`workbench.sweep`) and ``workbench list``.

``--set`` values are JSON (a bare word is a string) and are checked against the
type of the experiment's default before anything runs: ``workbench run NAME
--help`` lists every key with its type and default."""

from __future__ import annotations

import argparse
import importlib
import json
import logging
import math
import shlex
import sys
import time
from pathlib import Path
from typing import Any

#: experiment name -> module in the ``experiments`` package
EXPERIMENTS = {
    "parametric-surfaces": "experiments.parametric_surfaces",
    "discretization": "experiments.discretization",
    "ls-fitting": "experiments.ls_fitting",
    "fem-validation": "experiments.fem_validation",
    "fem-fitting": "experiments.fem_fitting",
    "wall-stiffness": "experiments.wall_stiffness",
    "sensitivity": "experiments.sensitivity",
    "minimal-work": "experiments.minimal_work",
    "wall-nonlinear": "experiments.wall_nonlinear",
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
        out[key.strip()] = _CliText(value)
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


def _check(value: Any, schema: Any, where: str) -> Any:
    """``value`` coerced to ``schema`` (int -> float); raises _Mismatch."""
    if schema == "any" or schema is None:
        _check_finite(value, where)
        return value
    if schema == "bool":
        if isinstance(value, bool):
            return value
        raise _Mismatch(f"{where}{value!r} is not a bool (true or false)")
    if schema == "int":
        if isinstance(value, int) and not isinstance(value, bool):
            return value
        raise _Mismatch(f"{where}{value!r} is not an int")
    if schema == "float":
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            if not math.isfinite(value):
                raise _Mismatch(f"{where}{value!r} is not finite")
            return float(value)
        raise _Mismatch(f"{where}{value!r} is not a number")
    if schema == "str":
        if isinstance(value, str):
            return str(value)
        raise _Mismatch(f"{where}{value!r} is not a string")
    kind, inner = schema
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


def _check_finite(value: Any, where: str) -> None:
    if isinstance(value, float) and not math.isfinite(value):
        raise _Mismatch(f"{where}{value!r} is not finite")
    if isinstance(value, (list, tuple)):
        for v in value:
            _check_finite(v, where)
    elif isinstance(value, dict):
        for v in value.values():
            _check_finite(v, where)


def _coerce(key: str, value: Any, default: Any) -> Any:
    """The ``--set`` value for ``key`` checked against its default's type."""
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
        shown = _dumps(default)
        raise SystemExit(
            f"--set {key}={text}: {key} expects {_describe(schema)} (default {shown}); "
            f"{exc.args[0]} — give e.g. --set {shlex.quote(f'{key}={shown}')}"
        ) from None


def _number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _check_range(key: str, value: Any, default: Any) -> Any:
    """Generic ranges read off the defaults (no per-key tables): a number, or a list's
    numbers, whose default is non-negative must be non-negative (μ, counts, sizes,
    noise levels; offsets with negative defaults are free); a ``*_range`` key is
    ``[lo, hi]`` with ``lo <= hi``.  Maps (e.g. approach angles) are not judged."""
    if _number(default) and default >= 0 and _number(value) and value < 0:
        raise _Mismatch(
            f"{value!r} is negative; the default is not, and this key takes no negative values "
            "(the experiment may refuse 0 as well, e.g. a thickness)"
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
    if seed is not None:
        config["seed"] = seed
    unknown = set(sets) - set(config)
    if unknown:
        raise SystemExit(f"unknown config keys for {name}: {sorted(unknown)}; known: {sorted(config)}")
    defaults = {**module.DEFAULT_CONFIG, "quick": False, "out": config["out"]}
    config.update({key: _coerce(key, value, defaults[key]) for key, value in sets.items()})
    check = getattr(module, "check_config", None)  # what a key's default cannot tell (a level, a kind)
    if check is not None:
        try:
            check(config)
        except ValueError as exc:
            raise SystemExit(f"{name}: {exc}") from None
    return config


def config_help(name: str) -> str:
    """The keys of experiment ``name`` with type, default and ``--quick`` value."""
    module = importlib.import_module(EXPERIMENTS[name])
    quick = module.QUICK_CONFIG
    lines = ["config keys (--set KEY=VALUE, JSON; a bare word is a string):"]
    for key, default in module.DEFAULT_CONFIG.items():
        line = f"  {key} ({_describe(_schema(default))}) = {_dumps(default)}"
        if key in quick:
            line += f"   [--quick: {_dumps(quick[key])}]"
        lines.append(line)
    lines.append("  quick, out: set by --quick and --out")
    return "\n".join(lines)


def _first_doc_line(name: str) -> str:
    """The experiment module docstring's first paragraph, on one line."""
    doc = (importlib.import_module(EXPERIMENTS[name]).__doc__ or "").strip()
    return " ".join(doc.split("\n\n")[0].split())


class _ExperimentParser(argparse.ArgumentParser):
    """``workbench run NAME``: its help lists the experiment's config keys
    (built on demand, so only ``--help`` imports the experiment)."""

    experiment = ""

    def format_help(self) -> str:
        self.epilog = config_help(self.experiment)
        self.description = _first_doc_line(self.experiment)
        return super().format_help()


class _CommandParser(argparse.ArgumentParser):
    """``workbench list`` / ``workbench run``: the latter's help lists every experiment."""

    lists_experiments = False

    def format_help(self) -> str:
        if self.lists_experiments:
            names = "\n".join(f"  {n:22s} {_first_doc_line(n)}" for n in EXPERIMENTS)
            self.epilog = f"experiments (workbench run NAME --help lists NAME's config keys):\n{names}"
        return super().format_help()


def _add_run_options(p: argparse.ArgumentParser, *, suppress: bool) -> None:
    """The run options, on ``run`` itself (so they may precede NAME) and on each
    experiment's parser with suppressed defaults (so they do not overwrite)."""

    def d(value: Any) -> Any:
        return argparse.SUPPRESS if suppress else value

    p.add_argument("--quick", action="store_true", default=d(False), help="small, fast configuration")
    p.add_argument("--out", default=d(None), help="output directory (default results/<experiment>)")
    p.add_argument("--seed", type=int, default=d(None))
    p.add_argument(
        "--set",
        dest="sets_after" if suppress else "sets",
        action="append",
        default=d([]),
        metavar="KEY=VALUE",
        help="override a config key (repeatable); the keys are listed below"
        if suppress
        else "override a config key (repeatable); workbench run NAME --help lists them",
    )
    p.add_argument("-v", "--verbose", action="store_true", default=d(False))


_SWEEP_EPILOG = """\
examples:
  workbench sweep sensitivity --quick --grid mu=[0.3,0.5,0.7]
  workbench sweep fem-fitting --quick --grid 'fine_level=[1,2]' --zip 'seed=[0,1]' --workers 2
  workbench sweep ls-fitting --quick --grid 'surfaces=[["S1"],["S3"]]' --scheduler tcp://10.0.0.5:8786
  workbench sweep sensitivity --quick --grid mu=[0.3,0.5,0.7] --plot mu precision

Every point's config is checked before any work.  Results: DIR/table.parquet (one row per
point), DIR/points/<key>/ (each run's outputs), DIR/sweep.json; a killed sweep resumes on
re-run.  workbench run NAME --help lists NAME's keys."""


def _add_sweep_parser(sub: Any, fmt: Any) -> None:
    sw = sub.add_parser(
        "sweep",
        help="run an experiment over a grid of settings on Dask, one Parquet table per sweep",
        description="Run EXPERIMENT at every point of a grid of config values, as Dask tasks "
        "(a local cluster of one single-threaded worker per core by default).",
        epilog=_SWEEP_EPILOG,
        formatter_class=fmt,
    )
    sw.add_argument(
        "experiment",
        choices=list(EXPERIMENTS),
        metavar="experiment",
        help="one of: " + ", ".join(EXPERIMENTS),
    )
    sw.add_argument(
        "--grid",
        action="append",
        default=[],
        metavar="KEY=JSON_LIST",
        help="a key and its values, e.g. mu=[0.3,0.5]; several --grid form the Cartesian product",
    )
    sw.add_argument(
        "--zip",
        action="append",
        default=[],
        metavar="KEY=JSON_LIST",
        help="lists paired element by element (all of one length), one more axis of the product",
    )
    sw.add_argument("--quick", action="store_true", help="start every point from the quick configuration")
    sw.add_argument(
        "--set",
        dest="sets",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="a fixed config value for every point",
    )
    sw.add_argument(
        "--seed", type=int, default=None, help="seed of every point (or sweep it with --grid seed=[...])"
    )
    sw.add_argument(
        "--out",
        default=None,
        help="sweep directory (default results/sweeps/<experiment>-<hash of the sweep>)",
    )
    where = sw.add_mutually_exclusive_group()
    where.add_argument(
        "--workers", type=int, default=None, help="local cluster: worker processes (default one per core)"
    )
    where.add_argument(
        "--scheduler", default=None, metavar="ADDRESS", help="an existing Dask cluster, e.g. tcp://host:8786"
    )
    sw.add_argument(
        "--threads", type=int, default=1, help="threads per worker and Numba threads per task (default 1)"
    )
    sw.add_argument("--retry-failed", action="store_true", help="run points recorded as failed again")
    sw.add_argument(
        "--plot",
        nargs=2,
        action="append",
        default=[],
        metavar=("KEY", "METRIC"),
        help="write DIR/plot_KEY_METRIC.png: a table column against a varied key (repeatable)",
    )
    sw.add_argument("-v", "--verbose", action="store_true")


def _parse_lists(items: list[str], flag: str) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for item in items:
        if "=" not in item:
            raise SystemExit(f"{flag} expects KEY=JSON_LIST, e.g. mu=[0.3,0.5]; got {item!r}")
        key, text = (x.strip() for x in item.split("=", 1))
        try:
            values = json.loads(text)
        except json.JSONDecodeError as exc:
            raise SystemExit(
                f'{flag} {key}={text}: not a JSON list ({exc}); e.g. {key}=[0.3,0.5] or {key}=\'["a","b"]\''
            ) from None
        if key in out:
            raise SystemExit(f"{flag} {key} is given twice; give one list per key")
        out[key] = values
    return out


def _sweep(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    from .sweep import SweepError, plot_sweep, run_sweep

    if not args.verbose:  # distributed sets INFO on import and logs every worker's start and stop
        import distributed  # noqa: F401

        logging.getLogger("distributed").setLevel(logging.WARNING)

    def fail(exc: BaseException) -> None:
        msg = exc.code if isinstance(exc, SystemExit) else str(exc)
        if not isinstance(msg, str):
            raise exc
        parser.exit(2, f"workbench sweep {args.experiment}: error: {msg}\n")

    try:
        grid, zipped = _parse_lists(args.grid, "--grid"), _parse_lists(args.zip, "--zip")
        summary = run_sweep(
            args.experiment,
            grid,
            zipped,
            quick=args.quick,
            sets=_parse_sets(args.sets),
            seed=args.seed,
            out=args.out,
            workers=args.workers,
            scheduler=args.scheduler,
            threads=args.threads,
            retry_failed=args.retry_failed,
        )
    except (SweepError, SystemExit) as exc:
        fail(exc)
    print(
        f"sweep {args.experiment}: {summary['n_points']} points ({summary['n_ok']} ok, "
        f"{summary['n_failed']} failed; {summary['n_resumed']} resumed, {summary['n_submitted']} run) "
        f"in {summary['seconds']:.1f} s"
    )
    print(f"  table: {summary['table']}")
    for key, metric in args.plot:
        try:
            print(f"  figure: {plot_sweep(summary['table'], key, metric)}")
        except SweepError as exc:
            fail(exc)
    return 0 if summary["n_failed"] == 0 else 1


def build_parser() -> argparse.ArgumentParser:
    """The ``workbench`` argument parser (``list``, ``run NAME`` with per-experiment help, ``sweep``)."""
    fmt = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(prog="workbench", description=__doc__, formatter_class=fmt)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_CommandParser)
    sub.add_parser("list", help="list experiments")
    run = sub.add_parser("run", help="run an experiment and write results/<name>/", formatter_class=fmt)
    run.lists_experiments = True
    _add_run_options(run, suppress=False)
    names = run.add_subparsers(
        dest="experiment",
        metavar="experiment",
        required=True,
        parser_class=_ExperimentParser,
        help="one of the experiments below",
    )
    for name in EXPERIMENTS:
        p = names.add_parser(name, formatter_class=fmt)
        p.experiment = name
        _add_run_options(p, suppress=True)
    _add_sweep_parser(sub, fmt)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)

    if args.command == "list":
        for name in EXPERIMENTS:
            print(f"{name:24s} {_first_doc_line(name)}")
        return 0

    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING, format="%(levelname)s %(name)s: %(message)s"
    )
    if args.command == "sweep":
        return _sweep(parser, args)
    sets = args.sets + getattr(args, "sets_after", [])
    try:
        config = build_config(args.experiment, args.quick, args.out, args.seed, _parse_sets(sets))
    except SystemExit as exc:
        if isinstance(exc.code, str):
            parser.exit(2, f"workbench run {args.experiment}: error: {exc.code}\n")
        raise
    module = importlib.import_module(EXPERIMENTS[args.experiment])
    t0 = time.perf_counter()
    try:
        summary = module.run(config)
    except ValueError as exc:  # careless input found during the run: one clean line, exit 2
        if args.verbose:
            raise
        parser.exit(2, f"workbench run {args.experiment}: error: {exc}\n(-v shows the traceback)\n")
    print(f"{args.experiment}: wrote {config['out']}/summary.json in {time.perf_counter() - t0:.1f} s")
    for line in summary.get("headline", []):
        print(f"  {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""``workbench`` console script: ``workbench run <experiment> [--quick] [--out DIR]
[--seed N] [--set key=value ...] [--config NAME=VALUE ...]``,
``workbench sweep <experiment> --grid KEY=JSON_LIST ...`` (:mod:`workbench.runner.sweep`),
``workbench report [--results DIR] [--out FILE]`` (:mod:`workbench.runner.report`) and
``workbench list``.

``--set`` values are JSON (a bare word is a string) and are checked against the
type of the experiment's default before anything runs: ``workbench run NAME
--help`` lists every key with its type and default."""

from __future__ import annotations

import argparse
import importlib
import json
import logging
import sys
import time
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from typing import Any

from .experiment_config import EXPERIMENTS, _parse_sets, build_config, config_help


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
    p.add_argument(
        "--seed",
        type=int,
        default=d(None),
        help="the experiment's `seed` key (refused for one without it: NAME --help lists its keys)",
    )
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
    dest = "configs_after" if suppress else "configs"
    _add_config_option(p, dest, d([]), "this run (summary.json records it)")
    p.add_argument("-v", "--verbose", action="store_true", default=d(False))


_SWEEP_EPILOG = """\
examples:
  workbench sweep sensitivity --quick --grid mu=[0.3,0.5,0.7]
  workbench sweep fem-fitting --quick --grid 'fine_level=[1,2]' --zip 'seed=[0,1]' --workers 2
  workbench sweep ls-fitting --quick --grid 'surfaces=[["S1"],["S3"]]' --scheduler tcp://10.0.0.5:8786
  workbench sweep sensitivity --quick --grid mu=[0.3,0.5,0.7] --plot mu truth_positive_fraction

Every point's config is checked before any work, and so is every point's memory where the
experiment estimates it (wall-stiffness: from its mesh): a point larger than a worker's
memory limit is refused (its row says how much it needs) and the others run.  Results:
DIR/table.parquet (one row per point), DIR/points/<key>/ (each run's outputs), DIR/sweep.json;
a killed sweep resumes on re-run, and a finished point is never computed again.
workbench run NAME --help lists NAME's keys."""


def _add_config_option(p: argparse.ArgumentParser, dest: str, default: Any, scope: str) -> None:
    """``--config NAME=VALUE`` (repeatable) of ``run`` and ``sweep``, into ``dest``."""
    p.add_argument(
        "--config",
        dest=dest,
        action="append",
        default=default,
        metavar="NAME=VALUE",
        help=f"set a tolerance or default of workbench.config for {scope}, e.g. "
        "ls_training_cell_fraction=0.1 (repeatable; JSON, a bare word is a string)",
    )


@contextmanager
def _configured(parser: argparse.ArgumentParser, command: str, items: list[str]) -> Iterator[None]:
    """The ``--config`` settings ``items`` in force inside the block (:func:`workbench.config.override`);
    one refused (not NAME=VALUE, given twice, unknown, or a value its field refuses) exits with
    status 2 before the block runs."""
    from workbench import config as wb_config

    with ExitStack() as stack:
        try:
            stack.enter_context(wb_config.override(**_parse_configs(items)))
        except (SystemExit, ValueError) as exc:
            msg = exc.code if isinstance(exc, SystemExit) else exc
            parser.exit(2, f"workbench {command}: error: --config: {msg}\n")
        yield


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
        "--seed",
        type=int,
        default=None,
        help="seed of every point (or sweep it with --grid seed=[...]); refused for an experiment "
        "without a `seed` key",
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
    _add_config_option(sw, "configs", [], "every point (part of each point's key)")
    sw.add_argument(
        "--plot",
        nargs=2,
        action="append",
        default=[],
        metavar=("KEY", "METRIC"),
        help="write DIR/plot_KEY_METRIC.png: a table column against a varied key (repeatable); log axes "
        "on a geometric grid, units from the names (stiffness_N_per_m: N/m)",
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
    from .sweep import SweepError

    if not args.verbose:  # distributed sets INFO on import and logs every worker's start and stop
        import distributed  # noqa: F401

        logging.getLogger("distributed").setLevel(logging.WARNING)
    try:
        grid, zipped = _parse_lists(args.grid, "--grid"), _parse_lists(args.zip, "--zip")
        _check_plot_keys(args.plot, grid, zipped)
    except (SweepError, SystemExit) as exc:
        _sweep_fail(parser, args, exc)
    with _configured(parser, f"sweep {args.experiment}", args.configs):
        return _sweep_configured(parser, args, grid, zipped)


def _sweep_configured(parser: argparse.ArgumentParser, args: argparse.Namespace, grid, zipped) -> int:
    from .sweep import SweepError, plot_sweep, run_sweep

    try:
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
            metrics=[metric for _, metric in args.plot],
        )
    except (SweepError, SystemExit) as exc:
        _sweep_fail(parser, args, exc)
    except KeyboardInterrupt:
        parser.exit(
            130,
            f"\nworkbench sweep {args.experiment}: interrupted; every finished point is kept — "
            "re-run the same command to resume\n",
        )
    _print_sweep(args.experiment, summary)
    for key, metric in args.plot:
        try:
            print(f"  figure: {plot_sweep(summary['table'], key, metric, zipped=list(zipped))}")
        except SweepError as exc:
            _sweep_fail(parser, args, exc)
    return 0 if summary["n_failed"] == 0 and not summary.get("n_refused", 0) else 1


def _sweep_fail(parser: argparse.ArgumentParser, args: argparse.Namespace, exc: BaseException) -> None:
    """Exit 2 with a sweep's error as one line (a ``SystemExit`` without a message is re-raised)."""
    msg = exc.code if isinstance(exc, SystemExit) else str(exc)
    if not isinstance(msg, str):
        raise exc
    parser.exit(2, f"workbench sweep {args.experiment}: error: {msg}\n")


def _check_plot_keys(plots: list[list[str]], grid: dict[str, Any], zipped: dict[str, Any]) -> None:
    """``SweepError`` for a ``--plot KEY METRIC`` whose key is not swept.  The key is checked now;
    the metric by run_sweep before any work (against this sweep's finished rows, the experiment's
    declared columns or its earlier tables) or, with none of those, on the first finished point."""
    from .sweep import SweepError

    for key, _ in plots:
        if key not in {**grid, **zipped}:
            raise SweepError(
                f"--plot {key} ...: {key!r} is not a swept key; plot against one of {[*grid, *zipped]}"
            )


def _print_sweep(experiment: str, summary: dict) -> None:
    """The sweep's summary (:func:`~workbench.runner.sweep.run_sweep`) as the command prints it."""
    n_refused = summary.get("n_refused", 0)
    print(
        f"sweep {experiment}: {summary['n_points']} points ({summary['n_ok']} ok, "
        f"{summary['n_failed']} failed"
        + (f", {n_refused} refused for memory" if n_refused else "")
        + f"; {summary['n_resumed']} resumed, {summary['n_submitted']} run) in {summary['seconds']:.1f} s"
    )
    if summary["n_other_code"]:
        print(
            f"  {summary['n_other_code']} points were computed by other code "
            f"(revisions {', '.join(summary['other_code_revisions'])}; the sources changed since): re-run "
            "(their old rows stay in points.jsonl)"
        )
    print(f"  table: {summary['table']}")
    for bad in summary["failed"]:
        print(f"  failed: {bad['point']}: {bad['error']}")
    if summary["n_failed"]:
        print("  (tracebacks in the table's error column; failed points run again with --retry-failed)")
    for bad in summary.get("refused", []):
        print(f"  {bad['point']}: {bad['error']}")


def build_parser() -> argparse.ArgumentParser:
    """The ``workbench`` argument parser (``list``, ``run NAME`` with per-experiment help, ``sweep``,
    ``report``)."""
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
    rep = sub.add_parser(
        "report",
        help="write results/REPORT.md: every reproduced thesis number beside ours, from the summaries",
        description="Compare the thesis's printed numbers with ours, read from the committed summaries "
        "(DIR/*/summary.json, DIR/benchmarks/*.json) only, and write them as Markdown. Runs nothing; "
        "a missing key gives its row 'missing: <file>:<key path>' and a warning; a DIR that does not "
        "exist or holds no summary is an error (make results with `make reproduce` or `workbench run NAME`).",
        formatter_class=fmt,
    )
    rep.add_argument(
        "--results", default="results", metavar="DIR", help="results directory to read (default results)"
    )
    rep.add_argument(
        "--out", default=None, metavar="FILE", help="Markdown file to write (default DIR/REPORT.md)"
    )
    rep.add_argument(
        "-v", "--verbose", action="store_true", help="log at INFO level (warnings are always shown)"
    )
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
    if args.command == "report":
        return _report(parser, args)
    return _run(parser, args)


def _report(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    """``workbench report``."""
    from .report import write_report

    try:
        written = write_report(args.results, args.out)
    except ValueError as exc:  # no results to report (a mistyped --results): one clean line, exit 2
        if args.verbose:
            raise
        parser.exit(2, f"workbench report: error: {exc}\n")
    print(f"report: wrote {written}")
    return 0


def _run(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    """``workbench run NAME``: its config built and checked, its memory checked, then run under
    the ``--config`` settings (:func:`workbench.config.override`)."""
    with _configured(parser, f"run {args.experiment}", args.configs + getattr(args, "configs_after", [])):
        return _run_configured(parser, args)


def _parse_configs(items: list[str]) -> dict[str, Any]:
    """``NAME=VALUE`` items as a dict, each value JSON (a bare word a string), each name once."""
    out: dict[str, Any] = {}
    for item in items:
        if "=" not in item:
            raise SystemExit(f"expects NAME=VALUE; got {item!r}")
        name, text = (part.strip() for part in item.split("=", 1))
        if name in out:  # the last one would win silently
            raise SystemExit(f"{name} is given twice ({out[name]!r} and {text}); give it once")
        try:
            out[name] = json.loads(text)
        except json.JSONDecodeError:
            out[name] = text
    return out


def _run_configured(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    sets = args.sets + getattr(args, "sets_after", [])
    try:
        config = build_config(args.experiment, args.quick, args.out, args.seed, _parse_sets(sets))
    except SystemExit as exc:
        if isinstance(exc.code, str):
            parser.exit(2, f"workbench run {args.experiment}: error: {exc.code}\n")
        raise
    module = importlib.import_module(EXPERIMENTS[args.experiment])
    need = _memory_check(args.experiment, config)
    if need is not None:
        parser.exit(2, f"workbench run {args.experiment}: error: {need}\n")
    t0 = time.perf_counter()
    try:
        summary = module.run(config)
    except ValueError as exc:  # careless input found during the run: one clean line, exit 2
        if args.verbose:
            raise
        parser.exit(2, f"workbench run {args.experiment}: error: {exc}\n(-v shows the traceback)\n")
    resumed = summary.get("n_resumed")
    # rows finished by an earlier run (same config and code) were read back, not recomputed:
    # their timings in the headline are that run's
    note = f" ({resumed} rows resumed from its checkpoint)" if isinstance(resumed, int) and resumed else ""
    print(f"{args.experiment}: wrote {config['out']}/summary.json in {time.perf_counter() - t0:.1f} s{note}")
    for line in summary.get("headline", []):
        print(f"  {line}")
    return 0


def _memory_check(experiment: str, config: dict) -> str | None:
    """Why a run cannot fit this machine's available memory (its experiment's estimate,
    :func:`workbench.runner.sweep.memory_estimate`), or None; more than half of it is warned."""
    import psutil

    from .sweep import memory_estimate

    est = memory_estimate(experiment, config)
    if est is None:
        return None
    free = psutil.virtual_memory().available
    gib = 2.0**30
    if est > free:
        return (
            f"this run needs ~{est / gib:.1f} GiB (the experiment's memory model), more than the "
            f"{free / gib:.1f} GiB available here — use a coarser mesh, or run it on a larger machine"
        )
    if est > free / 2:
        logging.getLogger(__name__).warning(
            "this run needs ~%.1f GiB of the %.1f GiB available here", est / gib, free / gib
        )
    return None


if __name__ == "__main__":
    sys.exit(main())

"""The sections of ``results/REPORT.md`` that are not thesis claims: our contact
against the peers (``peers/summary.json``) and the runtime-versus-error trade-off of our own
knobs (``benchmarks/pareto.json``), rendered from the committed summaries only.

Pure rendering: :func:`render_peers_sections` reads through a :class:`workbench.runner.report_rules.Summaries`
(passed in: this module imports nothing of the report) and returns Markdown; a missing file gives
a line saying which and the command that writes it.
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["METRICS", "render_peers_sections"]

#: the per-peer-and-case errors of the peers summary, in table order, with their headings
METRICS = (
    ("force_rel_err", "jaw force"),
    ("area_rel_err", "area"),
    ("pressure_rel_l2", "pressure L2"),
    ("torsion_rel_err", "torsion length"),
    ("torque_rel_err", "torque capacity"),
    ("margin_bias", "margin bias"),
    ("margin_rel_err", "margin abs. error"),
    ("ls_bias", "fitted 6DLS bias"),
    ("ls_rel_err", "fitted 6DLS error"),
)

_PEER_NAMES = {
    "neo-Hookean": "neo-Hookean FEM (reference)",
    "condensed": "condensed FEM (ours)",
    "linear": "linear full-mesh FEM (ours)",
    "hertz": "Hertz half-space",
    "foundation": "elastic foundation (GraspIt!)",
    "drake": "Drake hydroelastic",
    "mujoco_hertz": "MuJoCo cone, torsion 3πμa/16",
    "mujoco_diameter": "MuJoCo cone, torsion μ·2a",
}


def _pct(x: Any) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return f"{100 * x:+.1f} %"


def _err(key: str, x: Any, margin_resolution: float | None) -> str:
    """A signed error as ``+1.2 %``; a norm (pressure L2, the margins' median |s/s_true - 1|)
    unsigned, and a margin error below the bisection's resolution as ``< resolution``."""
    if x is None or key in (
        "force_rel_err",
        "area_rel_err",
        "torsion_rel_err",
        "torque_rel_err",
        "margin_bias",
        "ls_bias",
    ):
        return _pct(x)
    if key == "margin_rel_err" and margin_resolution is not None and x < margin_resolution:
        return f"< {100 * margin_resolution:.1f} %"
    return f"{100 * x:.1f} %"


def _res(x: Any) -> str:
    return "—" if x is None else f"{100 * x:.1f} %"


def _ms(x: Any) -> str:
    return "—" if x is None else f"{x:.3g}"


_PEERS = "peers/summary.json"


def _setup(cfg: dict) -> str:
    """The pad, its material, the jaw displacements and the fitted 6DLS of the peers run (``config``)."""
    if not cfg:
        return ""
    w, ln, h = cfg.get("pad_mm", ["?"] * 3)
    return (
        f"The pad: {w} × {ln} × {h} mm, E = {cfg.get('E', 0) / 1e6:g} MPa, ν = {cfg.get('nu')}, "
        f"μ = {cfg.get('mu')}; jaw displacements δ = {', '.join(map(str, cfg.get('deltas_mm', [])))} mm"
        f"{' (quick run)' if cfg.get('quick') else ''}; the fitted 6DLS: {cfg.get('ls_model')} on "
        f"{2 * cfg.get('ls_twists', 0)} wrenches, scored at {cfg.get('ls_directions')} points. "
    )


def _peers_intro(s: Any, cases: list, res: Any) -> list[str]:
    """What the peers table compares and how to read it, the definitions, and the table's head."""
    ref = _opt(s, _PEERS, "reference")
    dm = _opt(s, _PEERS, "margin_delta_mm")
    defs = _opt(s, _PEERS, "definitions") or {}
    setup = _setup(_opt(s, _PEERS, "config") or {})
    return [
        "What a researcher loses using the contact model of the simulator they already have: each peer on "
        f"the same contacts ({', '.join(cases)}, each pressed into one silicone pad) against the reference, "
        f"{ref or 'the neo-Hookean pad'}. {setup}"
        "Signed errors are peer/reference − 1, each the largest in magnitude over the jaw displacements; "
        "the pressure L2 and the margin's absolute error are unsigned. The margins are the two-jaw "
        "grasp's resistance margins against "
        f"lever disturbances (§4.1.3.1) at δ = {dm} mm and equal jaw force, the truth being the "
        "reference's exact 6DFW sets; the bias is the median s/s_true − 1 (> 0: the peer promises more "
        "than the contact holds); margins are bisected to "
        f"{_res(res)}, so smaller differences read `< {_res(res)}`. Regenerate: `workbench run peers`.",
        "",
        *[f"- *{k}*: {v}" for k, v in defs.items()],
        "",
        "| peer | case | " + " | ".join(h for _, h in METRICS) + " | ms per query |",
        "|---|---|" + "---|" * len(METRICS) + "---|",
    ]


def _peer_rows(peers: dict, res: Any) -> list[str]:
    """One table row per peer and case: its errors (:data:`METRICS`) and its runtime."""
    lines = []
    for peer, cases in peers.items():
        for case, m in cases.items():
            cells = [_PEER_NAMES.get(peer, peer), case]
            cells += [_err(k, m.get(k), res) for k, _ in METRICS]
            cells.append(_ms(m.get("ms_per_query")))
            lines.append("| " + " | ".join(cells) + " |")
    return lines


def _drake_row(case: str, metric: str, r: dict) -> str:
    """One case and error of the condensed-FEM-against-Drake table (a ratio read beyond the
    measured range carries its bound, >= or <=)."""
    be = r.get("error_ratio_bound") or ""
    bt = r.get("runtime_ratio_bound") or ""
    cells = [
        case,
        metric,
        f"{r['drake_ms']:.3g}",
        f"{r['drake_error']:.3g}",
        f"{r['condensed_error_at_drake_ms']:.3g}",
        f"{be}{r['error_ratio_drake_over_condensed']:.3g}",
        f"{r['condensed_ms_at_drake_error']:.3g}",
        f"{bt}{r['runtime_ratio_drake_over_condensed']:.3g}",
    ]
    return "| " + " | ".join(cells) + " |"


def _vs_drake(s: Any) -> list[str]:
    """The condensed FEM against Drake on each one's runtime-vs-error sweep (nothing if not run)."""
    vs = _opt(s, _PEERS, "vs_drake") or {}
    if not vs:
        return []
    ds = _opt(s, _PEERS, "sweep_delta_mm")
    return [
        "",
        f"Condensed FEM against Drake, read on each one's runtime-vs-error sweep at δ = {ds} mm "
        "(ratios Drake / condensed: above 1 the condensed FEM is more accurate, or faster):",
        "",
        "| case | error | Drake ms | Drake error | condensed error at Drake's ms | error ratio | "
        "condensed ms at Drake's error | runtime ratio |",
        "|---|---|---|---|---|---|---|---|",
        *(_drake_row(case, metric, r) for case, per in vs.items() for metric, r in per.items()),
        "",
        "A ratio marked >= or <= was read beyond the condensed sweep's measured range (the condensed FEM "
        "was not measured that fast, or that inaccurate): it is that bound, not an estimate.",
    ]


def _run_notes(s: Any) -> list[str]:
    """The peers run's parameter mapping, peer versions and skipped peers (each if recorded)."""
    lines = []
    mapping = _opt(s, _PEERS, "mapping") or {}
    if mapping:
        lines += [
            "",
            "Parameter mapping: " + "; ".join(f"{_PEER_NAMES.get(k, k)}: {v}" for k, v in mapping.items()),
        ]
    ver = _opt(s, _PEERS, "peer_versions") or {}
    if ver:
        lines.append("Peer versions: " + ", ".join(f"{k} {v}" for k, v in ver.items()) + ".")
    skipped = _opt(s, _PEERS, "skipped") or {}
    if skipped:
        lines.append("Skipped: " + "; ".join(f"{k} ({v})" for k, v in skipped.items()) + ".")
    return lines


def _hertz_notes(s: Any) -> list[str]:
    """Where Hertz applies: the peers run's thick blocks and fem-validation's (each if recorded)."""
    lines = []
    hb = _opt(s, _PEERS, "hertz_half_space")
    if hb:
        per = ", ".join(
            f"{_pct(e)} at a/H = {q:.3g}" for e, q in zip(hb["force_rel_err"], hb["a_over_H"], strict=True)
        )
        lines.append(
            f"Where Hertz applies: our condensed FEM's force at δ = {hb['delta_mm']:.4g} mm on thick blocks "
            "is "
            f"{per} from Hertz's; the layer's first-order stiffening in a/H removed (Richardson), the "
            f"half-space force is {_pct(hb['extrapolated_force_rel_err'])} from it."
        )
    hz = _opt(s, "fem-validation/summary.json", "hertz")
    if hz:
        lines.append(
            "Where Hertz applies (a thick block, `workbench run fem-validation`): our FEM's contact radius "
            f"{_pct(hz.get('a_rel_err'))} and peak pressure {_pct(hz.get('p0_rel_err'))} from Hertz's "
            "for the computed force, on the finest mesh."
        )
    return lines


def _peers(s: Any, link_prefix: str) -> list[str]:
    lines = ["", "## Against the peers", ""]
    try:
        peers = s.get(_PEERS, "peers")
    except LookupError as exc:  # workbench.runner.report_rules.MissingKey
        return lines + [f"missing: {exc.where} — run `workbench run peers`."]
    cases = list(dict.fromkeys(c for per in peers.values() for c in per))
    res = _opt(s, _PEERS, "margin_resolution")
    lines += _peers_intro(s, cases, res) + _peer_rows(peers, res) + _vs_drake(s) + _run_notes(s)
    lines += _hertz_notes(s)
    figs = _opt(s, _PEERS, "figures") or []
    if figs:
        rel = [_beside("peers", f) for f in figs]
        lines.append("Figure: " + ", ".join(f"[{r}]({link_prefix}{r})" for r in rel) + ".")
    return lines


def _beside(folder: str, path: str) -> str:
    """A figure written beside its summary, relative to the results directory: ``folder`` (the
    summary's, under results/) and the file's name — whatever directory the run wrote to first
    (``--out /tmp/x`` copied into results/ later links to results/, not to /tmp/x)."""
    return f"{folder}/{str(path).replace(chr(92), '/').rsplit('/', 1)[-1]}"


def _opt(s: Any, file: str, path: str) -> Any:
    try:
        return s.get(file, path)
    except LookupError:
        return None


def _pareto(s: Any, link_prefix: str) -> list[str]:
    lines = ["", "## Our knobs: runtime against error", ""]
    try:
        fams = s.get("benchmarks/pareto.json", "families")
    except LookupError as exc:  # workbench.runner.report_rules.MissingKey
        return lines + [f"missing: {exc.where} — run `python benchmarks/bench_pareto.py`."]
    lines += [
        "Each knob's settings as (runtime, error against that family's best reference); the default's "
        "place on the front (if off it, the setting that beats it, with its numbers: differences of a few "
        "per cent in runtime are within timing noise) and the cheapest setting whose error is within "
        "each budget (0.1, 0.01, 0.001 in the family's error metric). Each family measures its own "
        "error and runtime, stated per row. Regenerate: `python benchmarks/bench_pareto.py`.",
        "",
        "| knob | error metric | runtime metric | default | default error | default runtime [s] | "
        "on the front | cheapest within budget |",
        "|---|---|---|---|---|---|---|---|",
    ]
    items = fams.items() if isinstance(fams, dict) else ((f.get("name", "?"), f) for f in fams)
    for name, f in items:
        default = next((p for p in f.get("points", []) if p.get("is_default")), {})
        cheapest = f.get("cheapest_within") or {}
        budget = "; ".join(f"{k}: {v if v is not None else 'none'}" for k, v in cheapest.items()) or "—"
        err, rt = f.get("default_error"), f.get("default_runtime_s")
        front = f.get("default_on_front", "—")
        if front is False:
            by = {p.get("setting"): p for p in f.get("points", [])}
            beat = [by.get(b, {"setting": b}) for b in f.get("default_dominated_by") or []]
            nan = float("nan")
            front = "no — " + ", ".join(
                f"{b['setting']} ({b.get('error', nan):.3g}, {b.get('runtime_s', nan):.3g} s)" for b in beat
            )
        metric = f"{f.get('error_metric', '—')} (reference: {f.get('reference', '—')})"
        lines.append(
            f"| {name} | {metric} | {f.get('runtime_metric', '—')} | {default.get('setting', '—')} | "
            f"{'—' if err is None else f'{err:.3g}'} | {'—' if rt is None else f'{rt:.3g}'} | "
            f"{'yes' if front is True else front} | {budget} |"
        )
    fig = _opt(s, "benchmarks/pareto.json", "figure")
    if fig:
        lines.append("")
        r = _beside("benchmarks", fig)
        lines.append(f"Figure: [{r}]({link_prefix}{r}).")
    return lines


def render_peers_sections(s: Any, link_prefix: str = "") -> str:
    """The two sections as Markdown (each starting with a blank line and a ``##`` heading)."""
    return "\n".join(_peers(s, link_prefix) + _pareto(s, link_prefix)) + "\n"

"""Write docs/equations.md: every thesis (and 6DFC paper) equation the package cites, and where.

The index is built from the code, never by hand: :func:`definitions` walks each module of the
installed package (``workbench``, its subpackages included) with :mod:`ast` and
:mod:`tokenize`, giving every module, class and function its own docstring and comment lines;
:data:`CITATION` then finds the citations in those lines.  A comment block directly above a
``def`` or ``class`` (or its decorators) belongs to that definition, a comment inside one to the
innermost definition around it, the rest to the module.

Run ``python docs/generate_equations.py`` after citing, moving or renaming a cited definition:
``tests/test_docs.py`` fails while docs/equations.md differs from what this writes.

Citation format (one, so that ``grep 'Eq. 3.8'`` finds them all): ``Eq. 3.6`` for one thesis
equation, ``Eqs. 3.10–3.12`` (en dash) for a range and ``Eqs. 3.10, 3.12`` for a list; the 6DFC
paper's (ICRA 2020, numbered by section) as ``6DFC Eq. IV.2``.  :func:`old_format_citations`
finds the other spellings.
"""

from __future__ import annotations

import ast
import io
import re
import sys
import tokenize
from collections import defaultdict
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "equations.md"
COMMAND = "python docs/generate_equations.py"

#: source folder -> the dotted name it installs as (pyproject.toml's package-dir)
PACKAGES = {"workbench": "workbench"}

_THESIS = r"[1-6]\.\d{1,3}"
_PAPER = r"[IVX]+\.\d{1,2}"
_END = r"(?!\d)(?!\.\d)"  # a whole number: not 3.1 of 3.10, not 4.3 of §4.3.3
_ITEM = rf"(?:{_THESIS}|{_PAPER}){_END}"
#: one citation in the house format: ``Eq. 3.6``, ``Eqs. 3.10–3.12, 3.17``, ``6DFC Eq. IV.2``
CITATION = re.compile(rf"(?<![\w.])(?P<kw>Eqs?)\. (?P<items>{_ITEM}(?:(?:–|,\s+){_ITEM})*)")
#: spellings the house format replaced: parenthesised numbers, hyphen or slash ranges,
#: a list after the singular ``Eq.``, a single number after ``Eqs.``, a paper equation without "6DFC "
_OLD = [
    (re.compile(r"\bEqs?\.\s*\(\s*\d"), "parenthesised number"),
    (re.compile(rf"\bEqs?\.\s*\(?{_THESIS}\)?\s*[-/]\s*\(?\d"), "hyphen or slash between numbers"),
    (re.compile(rf"\bEq\.\s*{_THESIS}(?:–|,\s*){_THESIS}"), "several numbers after 'Eq.'"),
    (re.compile(rf"\bEqs\.\s*{_ITEM}(?!\s*(?:–|,\s*)\d)"), "one number after 'Eqs.'"),
    (re.compile(r"\bEqs?\.(?=\d)|\bEqs?(?= \d)"), "missing '. ' after Eq"),
    (re.compile(r"(?<!6DFC )\bEqs?\.\s*[IVX]+\."), "a 6DFC paper equation without '6DFC ' before 'Eq.'"),
]

#: one line per cited thesis equation, read from the thesis text (chapter.number -> meaning)
MEANINGS = {
    "2.14": "power-law pressure p(r) = p₀ [1 − (r/a)^k]^(1/k) on a circle (Xydas et al.; k = 2: Hertz)",
    "2.21": "Plücker moment vector m = q × e of the instantaneous screw axis, ‖e‖ = 1",
    "2.22": "Plücker constraint eᵀm = 0",
    "2.26": "velocity along the screw axis v∥ = h ω, h the scalar pitch",
    "2.27": "linear velocity at o: v = h ω + ‖ω‖ m",
    "2.28": "twist at o: ξ = [v; ω] = ‖ω‖ [h e + m; e]",
    "2.30": "unit twist: [h e + m; e] with a rotation (‖ω‖ = 1), [e; 0] for a pure translation",
    "2.44": "friction cone of the hard point contact: √(f_x² + f_y²) ≤ μ f⊥, f⊥ ≥ 0",
    "2.47": "outer N-sided polyhedral approximation of the friction cone",
    "2.50": "soft point contact wrench set: the friction cone and |τ_z| ≤ γ f⊥",
    "2.79": "contact map G_n = [R_n 0; t̂_n R_n R_n] B_n from contact frame C_n to object frame O",
    "2.80": "grasp wrench c^O = Σ_n G_n c^(C_n), the sum of the contact wrenches in O",
    "2.81": "grasp map G = [G_1 … G_N]",
    "2.88": "grasp wrench space W_L1 = Conv(∪_n contact wrenches): sum of normal forces bounded",
    "2.99": "GWS-based success: −w_ext inside W, i.e. on the inner side of every facet",
    "2.100": "wrench resistance QP: minimise ‖G c + w_ext‖² with each c_n in its contact wrench set",
    "2.101": "robust wrench resistance q_robust = (1/K) Σ R_i over K perturbed trials",
    "3.1": "pressure center o = ∫ p σ dS / ∫ p dS of a parametric surface",
    "3.2": "normal wrench w⊥ = −∫ p [n; r × n] dS about o",
    "3.3": "linear velocity of a surface point: h e + m − σ × e (rotation), e (translation)",
    "3.4": "direction of relative velocity: (I − n nᵀ) v, normalised",
    "3.5": "frictional wrench of a parametric surface: w = −μ ∫ p [v̂_r; r × v̂_r] dS",
    "3.6": "relative-velocity direction at element i: v_i projected on its tangent plane, normalised",
    "3.7": "pressure center of a discrete surface o = Σ c_i p_i a_i / Σ p_i a_i",
    "3.8": "discrete frictional wrench: f = −μ Σ p_i a_i v̂_ri, τ = −μ Σ p_i a_i (c_i − o) × v̂_ri",
    "3.9": "the 6D limit surface f(x) = 1 bounds every frictional wrench: f(w*) ≤ 1",
    "3.10": "normalised wrench ŵ_i = w_i ⊘ w_max (element-wise)",
    "3.11": "ellipsoid fit: minimise Σ (ŵ_iᵀ A_e ŵ_i − 1)² subject to A_e ≻ 0",
    "3.12": "the SDP ellipsoid: Eq. 3.11's objective − α log det A_e, A_e ⪰ 0, α > 0",
    "3.13": "least-squares ellipsoid A_e* = argmin Σ ‖ŵ_iᵀ A_e ŵ_i − 1‖² (no definiteness constraint)",
    "3.14": "auxiliary vector y(x, z) = [x_1 zᵀ, …, x_6 zᵀ]ᵀ ∈ ℝ³⁶",
    "3.15": "SOS convexity: zᵀ ∇²f₂(x) z = y(x, z)ᵀ M y(x, z) with M ≻ 0 (36 × 36)",
    "3.16": "Eq. 3.15 as sparse linear constraints V₁ vec(M) = V₂ A_q",
    "3.17": "SOS-convex quartic fit: minimise Σ (f₂(ŵ_i) − 1)² subject to V₁ vec(M) = V₂ A_q, M ≻ 0",
    "3.18": "wrench fitting error ε = (1/K) Σ |f(ŵ_i) − 1|",
    "3.19": "6DLS sampling: a hypercube point scaled onto f = 1 (Newton's method)",
    "3.20": "denormalised surface samples s_m = ŝ_m ∘ w_max",
    "3.21": "inner linearised frictional constraints F_inner = Conv(X)",
    "3.22": "denormalisation as a matrix: s_m = W_max ŝ_m, W_max = diag(w_max)",
    "3.23": "outward normal n_m of the denormalised ellipsoid at s_m",
    "3.24": "outer linearised frictional constraints: wᵀ n_m ≤ s_mᵀ n_m for every m",
    "3.25": "contact wrench c = w + w⊥ (frictional plus normal wrench)",
    "3.26": "contact wrench model: f(c − w⊥) ≤ 1, the 6DLS centred at w⊥",
    "3.27": "inner linearised contact wrench constraints Conv({s_m + w⊥})",
    "3.28": "outer linearised contact wrench constraints (c − w⊥)ᵀ n_m ≤ s_mᵀ n_m",
    "3.29": "6D friction cone: (c − f⊥ w⊥)ᵀ A_e (c − f⊥ w⊥) ≤ f⊥², 0 ≤ f⊥ ≤ f⊥,max",
    "3.30": "outer linearised 6DFC: (c − f⊥ w⊥)ᵀ n_m ≤ f⊥ s_mᵀ n_m, 0 ≤ f⊥ ≤ f⊥,max",
    "4.1": "contact n's linearised wrenches in O: c_n,m = [R_n 0; t̂_n R_n R_n] (s_n,m + w⊥n)",
    "4.2": "grasp wrench space W_L∞ = Conv(Minkowski sum of the contacts' wrench sets)",
    "4.3": "normalised power-law pressure p̂(r) = p₀ [1 − (r/r_max)^k]^(1/k), r along y from o_g",
    "4.4": "minimal grasp force: minimise Σ f⊥i subject to G c + w_ext = 0, c_i ∈ C_i^outer",
    "4.5": "work of the jaws W = Σ f⊥i d_i with d_i = f⊥i / s_i + ε (Hooke's law)",
    "4.6": "minimal-work quality q_work = 1 − W / W_max",
}
#: cited numbers that the thesis text does not hold (possibly wrong citations)
NOT_IN_THESIS: set[str] = set()
#: the 6DFC paper's equations (section.number -> meaning)
PAPER_MEANINGS = {
    "IV.2": "6D friction cone: (w − f_C f_N)ᵀ A (w − f_C f_N) ≤ f_C², 0 ≤ f_C ≤ f_C,max",
    "IV.3": "resistance QP: minimise ‖G z̃ + t‖² subject to F z̃ ≤ h (every contact's linearised cone)",
}


@dataclass(frozen=True)
class Definition:
    """A module, class or function with the text of its docstring and its own comments."""

    module: str  #: dotted module name as installed, e.g. ``workbench.fem.pad``
    qualname: str  #: ``Class.method``, ``outer.inner``; "" for the module itself
    text: str

    @property
    def name(self) -> str:
        return f"{self.module}:{self.qualname}" if self.qualname else self.module


def source_files(root: Path = ROOT) -> Iterator[tuple[str, Path]]:
    """(dotted module name, file) of every module of the package, sorted by name."""
    out = []
    for folder, dotted in PACKAGES.items():
        for path in (root / folder).rglob("*.py"):
            if "__pycache__" in path.parts:
                continue
            rel = path.relative_to(root / folder).with_suffix("").parts
            parts = rel[:-1] if rel[-1] == "__init__" else rel
            out.append((".".join((dotted, *parts)), path))
    yield from sorted(out)


def _scopes(tree: ast.AST) -> list[tuple[int, int, str, ast.AST]]:
    """(first line — decorators included —, last line, qualname, node) of every class and function."""
    scopes: list[tuple[int, int, str, ast.AST]] = []

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                qualname = f"{prefix}{child.name}"
                first = min([child.lineno] + [d.lineno for d in child.decorator_list])
                scopes.append((first, child.end_lineno or child.lineno, qualname, child))
                visit(child, qualname + ".")
            else:
                visit(child, prefix)

    visit(tree, "")
    return scopes


def _comment_owners(source: str, scopes: list) -> tuple[dict[int, str], dict[int, str]]:
    """``({line: comment text}, {line: qualname it belongs to})``: a comment inside a definition
    belongs to the innermost one, a comment block right above a definition to that definition,
    the rest to the module (``""``)."""
    lines = source.splitlines()
    comments: dict[int, str] = {}
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT:
            comments[tok.start[0]] = tok.string.lstrip("#:").strip()

    def comment_only(lineno: int) -> bool:
        return lineno in comments and lines[lineno - 1].lstrip().startswith("#")

    owner: dict[int, str] = {}
    for lineno in comments:
        inside = [(last - first, qualname) for first, last, qualname, _ in scopes if first <= lineno <= last]
        owner[lineno] = min(inside)[1] if inside else ""
    for first, _, qualname, _ in scopes:
        lineno = first - 1
        while comment_only(lineno):
            owner[lineno] = qualname
            lineno -= 1
    return comments, owner


def definitions(module: str, source: str) -> list[Definition]:
    """The module and each class and function in ``source``, each with its docstring and the
    comment lines that belong to it (see the module docstring for which do)."""
    tree = ast.parse(source)
    scopes = _scopes(tree)
    comments, owner = _comment_owners(source, scopes)
    texts: dict[str, list[str]] = defaultdict(list)
    texts[""].append(ast.get_docstring(tree, clean=True) or "")
    for _, _, qualname, node in scopes:
        texts[qualname].append(ast.get_docstring(node, clean=True) or "")
    for lineno in sorted(comments):
        texts[owner[lineno]].append(comments[lineno])
    order = [""] + [qualname for _, _, qualname, _ in sorted(scopes)]
    return [Definition(module, q, "\n".join(t for t in texts[q] if t)) for q in order]


def _key(number: str) -> tuple[int, int]:
    head, tail = number.split(".")
    roman = {"I": 1, "V": 5, "X": 10}
    if head.isdigit():
        return int(head), int(tail)
    values = [roman[c] for c in head]
    total = sum(-v if i + 1 < len(values) and v < values[i + 1] else v for i, v in enumerate(values))
    return 100 + total, int(tail)  # the paper's after the thesis's


def cited(text: str) -> list[str]:
    """The equations cited in ``text``: thesis numbers as ``"3.6"``, the 6DFC paper's (numbered
    by section in Roman numerals) as ``"6DFC IV.2"``; a range ``3.10–3.12`` gives every number
    in it."""
    out = []
    for m in CITATION.finditer(text):
        items = re.split(r",\s+", m.group("items"))
        for item in items:
            if "–" in item:
                lo, hi = item.split("–")
                (a, i), (b, j) = lo.split("."), hi.split(".")
                numbers = [f"{a}.{k}" for k in range(int(i), int(j) + 1)] if a == b else [lo, hi]
            else:
                numbers = [item]
            out += [f"6DFC {n}" if n[0] in "IVX" else n for n in numbers]
    return out


def old_format_citations(text: str) -> list[tuple[int, str, str]]:
    """(line, excerpt, what is wrong) of every citation in ``text`` not in the house format."""
    out = []
    for pattern, why in _OLD:
        for m in pattern.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            out.append((line, text[m.start() : m.start() + 30].split("\n")[0], why))
    return sorted(out)


def index(root: Path = ROOT) -> tuple[dict[str, set[str]], int]:
    """{equation: names of the definitions citing it} and the number of citing definitions."""
    found: dict[str, set[str]] = defaultdict(set)
    citing = set()
    for module, path in source_files(root):
        for d in definitions(module, path.read_text(encoding="utf-8")):
            for number in cited(d.text):
                found[number].add(d.name)
                citing.add(d.name)
    return found, len(citing)


def _meaning(number: str) -> str:
    if number.startswith("6DFC "):
        return PAPER_MEANINGS.get(number[5:], "(not found in the 6DFC paper text)")
    if number in NOT_IN_THESIS:
        return "(not found in the thesis text)"
    return MEANINGS.get(number, f"(no meaning written yet: add it to MEANINGS in {Path(__file__).name})")


def render(root: Path = ROOT) -> str:
    """The Markdown of docs/equations.md."""
    found, n_definitions = index(root)
    numbers = sorted(found, key=lambda n: _key(n.removeprefix("6DFC ")))
    missing = [n for n in numbers if n in NOT_IN_THESIS]
    out = [
        "# Equations → code",
        "",
        f"<!-- generated by `{COMMAND}`; do not edit: tests/test_docs.py checks it is current -->",
        "",
        "Every equation of J. Xu's thesis (and of the 6DFC paper, ICRA 2020) that the package's",
        "docstrings and comments cite, with the definitions that cite it (`module:function`,",
        "`module:Class.method`, or `module` for a module docstring or module-level comment;",
        "`workbench.fem.pad` is `workbench/fem/pad.py`). Tests and benchmarks are not indexed.",
        "Citations are written `Eq. 3.6`, `Eqs. 3.10–3.12`, `Eqs. 3.10, 3.12`, and",
        "`6DFC Eq. IV.2` for the paper, so `grep -rn 'Eq. 3.8'` finds them; a range cites every",
        "equation in it. The meanings are one line each, from the thesis text.",
        "",
        f"{len(numbers)} equations cited by {n_definitions} definitions.",
        "",
        "| equation | meaning | cited in |",
        "|---|---|---|",
    ]
    for n in numbers:
        label = f"6DFC Eq. {n[5:]}" if n.startswith("6DFC ") else f"Eq. {n}"
        names = ", ".join(f"`{name}`" for name in sorted(found[n]))
        out.append(f"| {label} | {_meaning(n).replace('|', chr(92) + '|')} | {names} |")
    if missing:
        out += [
            "",
            "## Cited but not in the thesis text",
            "",
            "These numbers are cited but the thesis has no such equation: the citations may be wrong.",
            "",
        ]
        out += [f"- Eq. {n}: " + ", ".join(f"`{name}`" for name in sorted(found[n])) for n in missing]
    return "\n".join(out) + "\n"


def main() -> int:
    text = render()
    OUT.write_text(text, encoding="utf-8")
    sys.stdout.write(f"wrote {OUT.relative_to(ROOT)} ({text.count(chr(10))} lines)\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

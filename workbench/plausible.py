"""Plausible ranges of the physical inputs: one rule per quantity.

Every physical number a user gives — a Young's modulus, a Poisson ratio, a friction
coefficient, a wall or pad thickness, a mass, a density, a jaw force, a pad size, a
closing — is judged here, whichever entry point takes it (a function argument, a
``--set`` or a ``--grid`` value), so the same number gets the same answer everywhere:

- outside the range of real materials and grippers (``Range.lo``/``Range.hi``) it is
  refused with a ``ValueError`` that names the likely unit slip and the value to pass
  (``E=2500`` for a bottle wall: "probably in MPa: pass 2.5e9");
- inside that range but outside the usual one (``Range.usual``) it passes with an
  :class:`ImplausibleWarning` that says why it is unusual.

The ranges are SI (m, kg, N, Pa).  They are deliberately wide: they exist to catch unit
slips (a factor 1,000 or 10⁶), not to judge a design.  A quantity whose upper limit is a
config tolerance (``Range.limit_field``, e.g. ``TOL.max_plausible_mass_kg``) reads it at
call time.  :func:`markdown_table` renders the table for ``docs/inputs.md``.
"""

from __future__ import annotations

import logging
import numbers
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

log = logging.getLogger(__name__)

__all__ = ["RANGES", "ImplausibleWarning", "Range", "check", "check_each", "markdown_table"]


class ImplausibleWarning(UserWarning):
    """A physical input inside the range of real things but outside the usual one."""


@dataclass(frozen=True)
class Range:
    """The plausible values of one physical quantity [SI].

    name : how a message names it ("wall Young's modulus").
    unit : its SI unit ("Pa"); "" for a dimensionless number.
    lo, hi : refused below ``lo`` / above ``hi`` (``lo_open``: ``lo`` itself refused too).
    usual : (lo, hi) — values outside it pass with an :class:`ImplausibleWarning`.
    slips : (unit name, SI value of one such unit) — the units a mistaken number was
        probably given in, tried in order: the first that makes it a usual value is named.
    examples : real values, quoted in every message (where the range comes from).
    limit_field : a ``config.TOL`` field that replaces ``hi`` (read at call time).
    lo_field : a ``config.TOL`` field that replaces ``lo`` (read at call time).
    hi_open : ``hi`` itself refused too (a Poisson ratio of 0.5 makes the stiffness singular).
    slip_margin : a slip is named only when it brings the value this factor inside the usual
        range at both ends (1: anywhere in it) — a μ of 5 is a typo more often than 5 %, whose
        0.05 sits at the usual range's edge.
    """

    name: str
    unit: str
    lo: float
    hi: float
    usual: tuple[float, float]
    slips: tuple[tuple[str, float], ...] = ()
    examples: str = ""
    lo_open: bool = True
    limit_field: str | None = None
    hi_open: bool = False
    lo_field: str | None = None
    slip_margin: float = 1.0

    def lower(self) -> float:
        """``lo``, or the config tolerance that sets it."""
        if self.lo_field is None:
            return self.lo
        from . import config

        return float(getattr(config.TOL, self.lo_field))

    def upper(self) -> float:
        """``hi``, or the config tolerance that sets it."""
        if self.limit_field is None:
            return self.hi
        from . import config

        return float(getattr(config.TOL, self.limit_field))

    def interval(self, scale: float = 1.0) -> str:
        """The accepted values as an interval, in units of ``scale`` SI ("(0, 500]")."""
        return _interval(self.lower() / scale, self.upper() / scale, self.lo_open, self.hi_open)


_MM, _CM = ("millimetres", 1e-3), ("centimetres", 1e-2)

#: quantity key -> its range.  Sources: polymer and metal moduli from Ashby's material
#: charts (M. F. Ashby, *Materials Selection in Mechanical Design*, 4th ed., ch. 4);
#: elastomer pads from Shore-A hardness (Gent 1958: 10-90 Shore A ≈ 0.3-30 MPa); friction
#: of rubber on plastic, metal and glass 0.2-1.5; grippers from vendor data sheets
#: (parallel-jaw grippers: 1-300 N a jaw, pads 5-60 mm, strokes up to ~0.2 m).
RANGES: dict[str, Range] = {
    "wall_modulus": Range(
        "wall Young's modulus",
        "Pa",
        1e5,
        1e12,
        (5e7, 4.5e11),
        (("MPa", 1e6), ("GPa", 1e9), ("kPa", 1e3)),
        "PET bottle 2-4 GPa, HDPE ~1 GPa, aluminium 70 GPa, steel 200 GPa",
    ),
    "pad_modulus": Range(
        "pad Young's modulus",
        "Pa",
        1e3,
        1e10,
        (1e4, 1e8),
        (("MPa", 1e6), ("kPa", 1e3), ("GPa", 1e9)),
        "silicone pads 0.1-10 MPa (Ecoflex 00-30 ~0.1 MPa, 30 Shore A ~1 MPa), polyurethane ~30 MPa",
    ),
    "poisson": Range(
        "Poisson ratio",
        "",
        -1.0,
        0.5,
        (0.0, 0.49999),
        (("per cent", 1e-2),),
        "plastics 0.35-0.42, metals ~0.3, silicone 0.45-0.4999",
        hi_open=True,
    ),
    "mu": Range(
        "friction coefficient",
        "",
        0.0,
        2.0,
        (0.05, 1.5),
        (("per cent", 1e-2),),
        "rubber on plastic or metal 0.3-1.2, silicone on glass up to ~1.5",
        lo_open=False,
        slip_margin=2.0,
    ),
    "wall_thickness": Range(
        "wall thickness",
        "m",
        1e-5,
        0.05,
        (1e-4, 1e-2),
        (_MM, ("micrometres", 1e-6), _CM),
        "PET bottle 0.2-0.5 mm, HDPE jug ~1 mm, glass jar 2-4 mm",
        lo_open=False,
    ),
    "pad_thickness": Range(
        "pad thickness",
        "m",
        1e-4,
        0.1,
        (5e-4, 3e-2),
        (_MM, _CM),
        "silicone gripper pads 1-10 mm",
        lo_open=False,
    ),
    "pad_size": Range(
        "pad size",
        "m",
        1e-4,
        0.2,
        (2e-3, 0.1),
        (_MM, _CM),
        "parallel-jaw pads 5-60 mm wide or long (YuMi's 20 x 8 mm, Robotiq 2F-85's 22 x 38 mm)",
    ),
    "jaw_force": Range(
        "jaw force",
        "N",
        0.0,
        500.0,
        (1.0, 300.0),
        (("millinewtons", 1e-3),),
        "parallel-jaw grippers 1-300 N a jaw (YuMi 20 N, Franka 70 N, Robotiq 2F-85 20-235 N)",
    ),
    "closing": Range(
        "jaw closing",
        "m",
        0.0,
        0.1,
        (1e-6, 0.04),
        (_MM, ("micrometres", 1e-6), _CM),
        "a pad pressed 0.1-5 mm into an object, a thin wall dented up to ~40 mm",
        lo_open=False,
    ),
    "compression": Range(
        "pad compression",
        "m",
        0.0,
        0.02,
        (1e-6, 0.005),
        (_MM, ("micrometres", 1e-6), _CM),
        "a silicone pad (1-10 mm thick) pressed 0.1-3 mm; no pad layer is 20 mm deep",
        lo_open=False,
    ),
    "pose_noise_trans": Range(
        "position noise (a standard deviation)",
        "m",
        0.0,
        0.05,
        (0.0, 0.01),
        (_MM, _CM),
        "grasp-pose errors of 1-5 mm (6DFC: 3 mm), a centre of mass known to a few mm",
        lo_open=False,
    ),
    "pose_noise_rot": Range(
        "rotation noise (a standard deviation)",
        "rad",
        0.0,
        0.5,
        (0.0, 0.2),
        (("degrees", 0.017453292519943295),),
        "grasp-pose errors of 0.003-0.1 rad (0.2-6 deg)",
        lo_open=False,
    ),
    "relative_noise": Range(
        "relative noise (a standard deviation of a factor 1 + N(0, s))",
        "",
        0.0,
        0.5,
        (0.0, 0.3),
        (("per cent", 1e-2),),
        "friction, mass or force known to 5-30 %; s >= 0.5 makes negative factors common",
        lo_open=False,
    ),
    "weight": Range(
        "weight (a load in newtons)",
        "N",
        0.0,
        200.0,
        (0.01, 100.0),
        (("grams-force", 9.80665e-3), ("millinewtons", 1e-3)),
        "a 10 g part 0.1 N, a full 0.5 L bottle 5 N, a power drill 15 N",
    ),
    "lever": Range(
        "lever arm (an offset on the object)",
        "m",
        0.0,
        1.0,
        (1e-3, 0.3),
        (_MM, _CM),
        "a centre of mass 1-100 mm off the grasp axis",
    ),
    "winkler_stiffness": Range(
        "pad stiffness (Winkler modulus = E / layer thickness)",
        "Pa/m",
        1e4,
        1e14,
        (3e5, 2e11),
        (("MPa/m", 1e6), ("kPa/m", 1e3), ("Pa/mm", 1e3)),
        "a 5 mm silicone layer of 1 MPa: 2e8 Pa/m; 1-10 mm pads of 0.1-10 MPa: 1e7-1e10 Pa/m",
    ),
    "element_size": Range(
        "element size (a mesh refinement length)",
        "m",
        1e-6,
        0.05,
        (5e-5, 0.01),
        (_MM, ("micrometres", 1e-6)),
        "contact patches resolved at 0.1-2 mm",
    ),
    "mass": Range(
        "object mass",
        "kg",
        0.0,
        20.0,
        (1e-3, 10.0),
        (("grams", 1e-3),),
        "a 3 cm plastic cube 0.01 kg, a full 0.5 L bottle 0.5 kg, a power drill 1.5 kg",
        limit_field="max_plausible_mass_kg",
    ),
    "density": Range(
        "mean density",
        "kg/m³",
        5.0,
        23000.0,
        (30.0, 20000.0),
        (("g/cm³", 1e3),),
        "an empty bottle ~30 kg/m³ (mass over enclosed volume), wood 500, water 1000, steel 7850",
    ),
    "stiffness": Range(
        "object stiffness (jaw force per closing)",
        "N/m",
        10.0,
        1e12,
        (100.0, 1e8),
        (("N/mm", 1e3), ("N/cm", 1e2)),
        "the softest measured grasp ~140 N/m (a mustard wall), thin PET bottles 1e3-3e4 N/m, "
        "a rigid part under a pad 1e5-1e7 N/m; np.inf for a rigid contact",
        lo_open=False,  # TOL.min_plausible_stiffness itself is accepted
        lo_field="min_plausible_stiffness",
    ),
    "torque": Range(
        "torque (a moment on the object)",
        "N·m",
        0.0,
        200.0,
        (0.0, 10.0),
        (("N·mm", 1e-3), ("N·cm", 1e-2)),
        "a 0.5 kg bottle held 50 mm off its centre of mass 0.25 N·m, a power drill 2-5 N·m",
        lo_open=False,
    ),
    "half_angle": Range(
        "half-angle of a wrapped contact",
        "rad",
        0.0,
        np.pi,
        (0.0, np.pi / 2),
        (("degrees", 0.017453292519943295),),
        "a pad wrapping a cylinder by 0.3-1.0 rad (17-57 deg); pi wraps it all round",
        lo_open=False,
    ),
    "opening": Range(
        "gripper opening",
        "m",
        0.0,
        0.5,
        (5e-3, 0.3),
        (_MM, _CM),
        "parallel-jaw strokes 20-200 mm (YuMi 50 mm, Robotiq 2F-85 85 mm)",
    ),
}


def _a(noun: str) -> str:
    return ("an " if noun[0] in "aeiou" else "a ") + noun


def _interval(lo: float | str, hi: float | str, lo_open: bool, hi_open: bool) -> str:
    lo_text = lo if isinstance(lo, str) else f"{lo:g}"
    hi_text = hi if isinstance(hi, str) else f"{hi:g}"
    return f"{'(' if lo_open else '['}{lo_text}, {hi_text}{')' if hi_open else ']'}"


def _fmt(x: float, unit: str) -> str:
    return f"{x:g} {unit}".rstrip()


_SI_NAMES = {"m": "metres", "kg": "kilograms", "N": "newtons", "Pa": "pascals"}

#: a unit slip is named only for a value this far (a ratio) outside the usual range: a Poisson
#: ratio of 0.5 is not 0.5 % and a 400 N jaw is not 400 mN, though both are unusual
_SLIP_MIN_RATIO = 2.0


def _likely(r: Range, v: float, scale: float, unit: str, plausible: bool = False) -> str:
    """The slip that makes ``v`` (given in ``unit``, ``scale`` SI each) a usual value, as the
    fix to name in ``unit`` ("" if none does).  ``plausible``: ``v`` is a real value (the warning
    band), so a smaller unit is named only for a number typed like one (>= 1: 30 for 30 mm, not
    0.03 for 0.03 mm)."""
    lo, hi = r.usual
    if not (v * scale > 0 and (v * scale < lo / _SLIP_MIN_RATIO or v * scale > hi * _SLIP_MIN_RATIO)):
        return ""  # near the usual range: unusual, but no sign of another unit
    # SI given to a key in mm
    si_unit = () if scale == 1.0 or not r.unit else ((_SI_NAMES.get(r.unit, r.unit), 1.0),)
    # a usual range from 0 (noise: none is usual): a slip must land within two decades of its
    # top, not merely above 0 — 0.03 m of noise is large, not 0.03 mm
    floor = r.usual[0] if r.usual[0] > 0 else r.usual[1] * 1e-2
    for slip, si in (*si_unit, *r.slips):
        if si == scale or (plausible and si < scale and abs(v) < 1):  # no slip, or none likely
            continue
        if floor * r.slip_margin <= v * si <= r.usual[1] / r.slip_margin:
            return f": probably in {slip} — pass {v * si / scale:.6g}" + (f" [{unit}]" if unit else "")
    return ""


def check(
    key: str,
    value: Any,
    what: str | None = None,
    *,
    scale: float = 1.0,
    unit: str | None = None,
    warn: bool = True,
    examples: str | None = None,
    named: str | None = None,
) -> float:
    """``value`` as a float if it is a plausible ``key`` quantity (see :data:`RANGES`), else
    ``ValueError`` naming the range, the likely unit slip and the value to pass; a value
    inside the range but unusual passes with an :class:`ImplausibleWarning` saying why.

    key : a quantity of :data:`RANGES` ("wall_modulus", "mu", "mass", ...).
    value : the number, in SI units unless ``scale`` says otherwise (a bool is refused:
        ``force=True`` is a slip, not 1 N).
    what : how to name the input in the message (an argument or a config key); default the
        quantity's name.
    scale, unit : ``value`` is in units of ``scale`` SI named ``unit`` (a config key in mm:
        1e-3, "mm"); messages then speak that unit.  Returns the value as given (not SI).
    warn : False: only the hard range (a generic solver that also takes validation blocks,
        e.g. an 80 mm deep elastic half-space, judges only what no real body is).
    examples, named : real values of this input to quote, and what it is, instead of the
        quantity's own (a ring's radius judged by the "lever" range is not "a lever arm ... a centre
        of mass off the grasp axis").
    """
    r = RANGES[key]
    if examples is not None or named is not None:
        from dataclasses import replace

        r = replace(r, examples=r.examples if examples is None else examples, name=named or r.name)
    name = what or r.name
    unit = r.unit if unit is None else unit
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a number [{unit or '-'}]; got {value!r} ({type(value).__name__})")
    given = float(value)
    x = given * scale
    lo, hi = r.lower(), r.upper()
    low = x <= lo if r.lo_open else x < lo
    high = x >= hi if r.hi_open else x > hi
    if not np.isfinite(x) or low or high:
        over = (
            f" (config.TOL.{r.limit_field}: raise it for an unusual case)"
            if r.limit_field and x > hi
            else f" (config.TOL.{r.lo_field} sets the limit)"
            if r.lo_field and x < lo
            else ""
        )
        hint = _likely(r, given, scale, unit) if np.isfinite(x) else ""
        if not hint and np.isfinite(x) and x > hi:
            hint = f": more than any real {r.name}"
        raise ValueError(
            f"{name} must be {_a(r.name)} in {r.interval(scale)} {unit}".rstrip()
            + f"{over}; got {value!r}{hint} (real values: {r.examples})"
        )
    # the closed lower limit itself is a deliberate idealisation (mu = 0: frictionless), not a slip
    if warn and not r.usual[0] <= x <= r.usual[1] and not (x == lo and not r.lo_open):
        hint = _likely(r, given, scale, unit, plausible=True)
        side = "below" if x < r.usual[0] else "above"
        bound = (r.usual[0] if x < r.usual[0] else r.usual[1]) / scale
        warnings.warn(
            f"{name} = {given:g} {unit}".rstrip()
            + f" is {side} the usual {_fmt(bound, unit)} of {_a(r.name)} ({r.examples}); "
            + (f"was it in another unit{hint}?" if hint else "results may not describe a real gripper"),
            ImplausibleWarning,
            stacklevel=2,
        )
    return given


def check_each(key: str, values: Any, what: str | None = None, *, warn: bool = True) -> np.ndarray:
    """Every number of ``values`` (a scalar, sequence or array) checked by :func:`check`;
    returns them as a float array of the same shape."""
    arr = np.asarray(values, dtype=object)
    out = np.empty(arr.shape, dtype=np.float64)
    for idx, v in np.ndenumerate(arr):
        if isinstance(v, (np.floating, np.integer)):
            v = v.item()
        out[idx] = check(key, v, what, warn=warn)
    return out


def markdown_table() -> str:
    """The ranges as a Markdown table (quantity, unit, refused outside, warned outside,
    unit slips named, real values) — the table of ``docs/inputs.md``."""
    lines = [
        "| quantity | unit | refused outside | warned outside | slips named | real values |",
        "|---|---|---|---|---|---|",
    ]
    for key, r in RANGES.items():
        hi = f"{r.hi:g}" if r.limit_field is None else f"TOL.{r.limit_field} ({r.hi:g})"
        lo = f"{r.lo:g}" if r.lo_field is None else f"TOL.{r.lo_field} ({r.lo:g})"
        slips = ", ".join(u for u, _ in r.slips) or "-"
        lines.append(
            f"| `{key}`: {r.name} | {r.unit or '-'} | {_interval(lo, hi, r.lo_open, r.hi_open)} "
            f"| [{r.usual[0]:g}, {r.usual[1]:g}] "
            f"| {slips} | {r.examples} |"
        )
    return "\n".join(lines)

"""The engine's settings: every field a measured choice (the probes of :mod:`.probes`)."""

from __future__ import annotations

from dataclasses import dataclass

#: MuJoCo's spellings of ``<option integrator=...>`` (its enum mjtIntegrator, MuJoCo 4): the XML
#: parser takes these exactly, case included, and reads any other word as an "invalid keyword"
INTEGRATORS = ("discrete", "Euler", "RK4", "implicit", "implicitfast")


def import_mujoco():
    """The ``mujoco`` module, or an ImportError naming the extra that installs it."""
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(
            "engine trials need MuJoCo: pip install -e '.[peers]' (make reproduce installs it)"
        ) from exc
    return mujoco


@dataclass(frozen=True)
class EngineSettings:
    """MuJoCo options of a trial and of the validation probes.

    The defaults are the settings under which the probes reproduce Coulomb friction (a pulled
    block and a tilted plane slip at μ within 1 %, a flat flex pad spins at μ∫p|r|dA within
    6 %) with a pre-slip creep below 0.1 mm/s at half the slip load.
    """

    # elliptic friction cones: pyramidal ones are anisotropic (a pull at 45° slips at μ/√2)
    cone: str = "elliptic"
    # ratio of frictional to normal constraint impedance: creep below the slip load falls as
    # 1/impratio (0.64 mm/s at 1, 0.0064 mm/s at 100 for a block at half its slip load)
    impratio: float = 100.0
    # time step [s]: a smaller one alone does not reduce creep, it only allows stiffer contacts
    timestep: float = 1e-3
    # Newton's method; CG does not converge on flex pads (creep 45x larger)
    solver: str = "Newton"
    # solver tolerance; below 1e-6 the flex's M+K solve runs out of iterations at every step
    tolerance: float = 1e-6
    # solver iterations per step
    iterations: int = 100
    # flex elasticity is integrated only by the discrete integrator in MuJoCo 4
    integrator: str = "discrete"
    # contact reference (time constant [s], damping ratio): stiff, at MuJoCo's 2-step floor
    contact_solref: tuple[float, float] = (0.002, 1.0)
    # contact impedance (d0, d_width, width [m], midpoint, power): near-hard contacts
    contact_solimp: tuple[float, float, float, float, float] = (0.99, 0.999, 1e-4, 0.5, 2.0)
    # radius [m] of the spheres on the pad face's vertices that carry its contacts: the flex's
    # own element contacts on a box jump by a grid spacing between steps and never settle
    tip_radius: float = 3e-4
    # pad mass [kg] (per pad) in the engine, gravity-compensated: 0.1 kg instead of silicone's
    # 4.4 g cuts creep 5x and penetration 6x (the pad's weight does not act)
    pad_mass: float = 0.1
    # pad grid points along its width, length, thickness (a 5 x 9 x 3 grid: 5 mm x 5 mm x 2.5 mm)
    pad_grid: tuple[int, int, int] = (5, 9, 3)
    # a non-convex object collides as convex slabs this thick [m] across gravity (MuJoCo collides
    # each mesh as its hull: a bottle's waist would be bridged); 0: as its hull (.collision)
    object_slab: float = 5e-3

    def __post_init__(self) -> None:
        # each rule a step, in this order: the first broken one is the error
        self._check_choices()
        self._check_numbers()
        self._check_contact()
        self._check_pad_and_object()

    def _check_choices(self) -> None:
        """The cone, solver and integrator: words MuJoCo's XML takes."""
        if self.cone not in ("elliptic", "pyramidal"):
            raise ValueError(f"cone must be 'elliptic' or 'pyramidal'; got {self.cone!r}")
        if self.solver not in ("Newton", "CG", "PGS"):
            raise ValueError(f"solver must be 'Newton', 'CG' or 'PGS'; got {self.solver!r}")
        if self.integrator not in INTEGRATORS:
            word = self.integrator.lower() if isinstance(self.integrator, str) else None
            case = [k for k in INTEGRATORS if k.lower() == word]
            raise ValueError(
                f"integrator must be one of MuJoCo's {INTEGRATORS}, spelled as its XML takes them (case "
                f"included); got {self.integrator!r}"
                + (f" — pass {case[0]!r}" if case else "")
                + " (the probes validated the default, 'discrete')"
            )

    def _check_numbers(self) -> None:
        """The positive numbers, the timestep and tip radius in metres, the iteration count."""
        for name in ("impratio", "timestep", "tolerance", "tip_radius", "pad_mass"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (v > 0 and v < float("inf")):
                raise ValueError(f"{name} must be a positive finite number; got {v!r}")
        if self.timestep > 2e-3:
            # the probes validated 1e-3; at 0.1 s the flex's stiffness is ill-conditioned (MuJoCo
            # warns) and the pads' contacts are no longer resolved
            raise ValueError(
                f"timestep {self.timestep!r} s is above 2e-3 s: the engine's settings are validated "
                "at 1e-3 s (a timestep in ms? 1 ms = 1e-3)"
            )
        if self.tip_radius > 2e-3:
            raise ValueError(
                f"tip_radius {self.tip_radius!r} m is larger than a pad's grid spacing: give it in "
                "metres (0.3 mm = 3e-4)"
            )
        if (
            isinstance(self.iterations, bool)
            or not isinstance(self.iterations, int)
            or not (1 <= self.iterations <= 100_000)
        ):
            # 0 iterations leave every constraint unsolved: the pads pass through the object and
            # a trial reads as a miss
            raise ValueError(f"iterations must be an integer in [1, 100000]; got {self.iterations!r}")

    def _check_contact(self) -> None:
        """The contact's solref (above MuJoCo's 2-step floor) and solimp."""
        sr = self.contact_solref
        if len(sr) != 2 or not all(isinstance(v, (int, float)) and 0 < v < float("inf") for v in sr):
            # MuJoCo reads mixed signs as an error and silently falls back to its own (0.02, 1);
            # negative pairs are its direct (stiffness, damping) form, which these probes never used
            raise ValueError(
                f"contact_solref must be (time constant [s] > 0, damping ratio > 0); got {sr!r} "
                "(the validated setting is (0.002, 1.0))"
            )
        if sr[0] < 2 * self.timestep:
            raise ValueError(
                f"contact_solref's time constant {sr[0]!r} s is below 2 time steps "
                f"({2 * self.timestep:g} s): MuJoCo would raise it to that floor unannounced; give "
                ">= 2 * timestep"
            )
        si = self.contact_solimp
        if len(si) != 5 or not (
            0 < si[0] < 1 and 0 < si[1] < 1 and si[2] > 0 and 0 < si[3] < 1 and si[4] >= 1
        ):
            raise ValueError(
                "contact_solimp must be (d0, d_width in (0, 1), width [m] > 0, midpoint in (0, 1), "
                f"power >= 1); got {si!r} (the validated setting is (0.99, 0.999, 1e-4, 0.5, 2.0))"
            )

    def _check_pad_and_object(self) -> None:
        """The object's slab thickness and the pad's grid."""
        sl = self.object_slab
        if isinstance(sl, bool) or not isinstance(sl, (int, float)) or not (0 <= sl <= 0.05):
            raise ValueError(
                f"object_slab must be a thickness in [0, 0.05] m (0: the object's convex hull); got {sl!r} "
                "(5 mm = 5e-3)"
            )
        if len(self.pad_grid) != 3 or any(int(n) != n or n < 2 for n in self.pad_grid):
            raise ValueError(
                f"pad_grid must be three integers >= 2 (points along x, y, z); got {self.pad_grid!r}"
            )

    def option_xml(self, gravity: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> str:
        """The MJCF ``<option>`` element of these settings."""
        g = " ".join(f"{x:g}" for x in gravity)
        return (
            f'<option timestep="{self.timestep:g}" cone="{self.cone}" impratio="{self.impratio:g}" '
            f'solver="{self.solver}" tolerance="{self.tolerance:g}" iterations="{self.iterations}" '
            f'integrator="{self.integrator}" gravity="{g}"/>'
        )

    def contact_attrs(self, mu: float) -> str:
        """MJCF attributes of a geom's contact: friction μ and these solref/solimp."""
        sr = " ".join(f"{x:g}" for x in self.contact_solref)
        si = " ".join(f"{x:g}" for x in self.contact_solimp)
        return f'friction="{mu:g} 0 0" solref="{sr}" solimp="{si}"'

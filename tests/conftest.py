import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))  # tests/naive.py

SHARED = Path(__file__).resolve().parents[2] / "shared"


@pytest.fixture(autouse=True, scope="session")
def _workbench_cache(tmp_path_factory):
    """Keep the tests' disk caches (condensed pads) out of the user's cache directory:
    under the repository's .pytest_cache, so local re-runs still reuse them."""
    import os

    root = Path(__file__).resolve().parents[1] / ".pytest_cache" / "workbench-cache"
    root.mkdir(parents=True, exist_ok=True)
    old = os.environ.get("WORKBENCH_CACHE_DIR")
    os.environ["WORKBENCH_CACHE_DIR"] = str(root)
    yield root
    if old is None:
        os.environ.pop("WORKBENCH_CACHE_DIR", None)
    else:
        os.environ["WORKBENCH_CACHE_DIR"] = old


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture(scope="session")
def s4_data():
    """S4 (thesis Table 3.1) at 800 elements, normalised: the profile, 300 training and 2,000
    test wrenches (tests/test_ellipsoid.py, test_quartic.py, test_base.py, test_linearize.py)."""
    from workbench import frictional_wrenches, mesh_profile, sample_twists_thesis
    from workbench.sources.surface_catalog import S4

    prof = mesh_profile(S4, 800).normalized()
    train = frictional_wrenches(prof, sample_twists_thesis(300, prof, seed=1))
    test = frictional_wrenches(prof, sample_twists_thesis(2000, prof, seed=2))
    return prof, train, test


@pytest.fixture(scope="session")
def s4_quartic(s4_data):
    from workbench import fit_quartic

    return fit_quartic(s4_data[1])


# ------------------------------------------------------------------ FEM pads shared by test files
# tests/test_fem_contact.py, test_fem_extract.py, test_fem_fidelity.py, test_fem_profile_force.py
@pytest.fixture(scope="session")
def thin_pad():
    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry, condense_pad

    # h = 1 mm, 0.5 mm face spacing: a/h = 3.2 for the indentation below
    geom = PadGeometry(width=0.012, length=0.012, thickness=0.001, nx=24, ny=24, nz=2)
    return condense_pad(geom, Material(E=1.0e6, nu=0.0), cache_dir=False)


@pytest.fixture(scope="session")
def pad_cache(request, tmp_path_factory):
    # the default 20 x 40 x 5 mm pad condenses in tens of seconds: keep it in pytest's cache
    # (.pytest_cache, per checkout) so only the first run pays for it
    cache = getattr(request.config, "cache", None)
    return cache.mkdir("fem-pads") if cache is not None else tmp_path_factory.mktemp("fem-pads")


#: jaw displacements [mm] of ``sphere_press`` (the test files that parametrize over them keep a copy)
SPHERE_PRESS_DELTAS_MM = [0.1, 0.25, 0.5, 1.0, 2.0, 3.0]


@pytest.fixture(scope="session")
def sphere_press(pad_cache):
    """The default pad (E = 1 MPa, nu = 0.45, as fem-fitting) pressed into a R 20 mm sphere by
    ``SPHERE_PRESS_DELTAS_MM``: a ``workbench.fem.Pressed``."""
    from workbench.fem import press
    from workbench.fem.material import Material
    from workbench.fem.obstacles import Sphere
    from workbench.fem.pad import PadGeometry

    h = PadGeometry().thickness
    sphere = Sphere((0.0, 0.0, h + 0.02), 0.02)
    return press(
        PadGeometry(),
        Material(E=1.0e6, nu=0.45),
        sphere,
        [d * 1e-3 for d in SPHERE_PRESS_DELTAS_MM],
        cache_dir=pad_cache,
    )


# ------------------------------------------------------------------ the no-JIT run
# `make test-nojit` runs the whole suite with NUMBA_DISABLE_JIT=1 except the tests marked
# ``@pytest.mark.jit_only("why")`` (registered in pyproject.toml, --strict-markers), with
# --check-kernels: the session then fails unless every Numba kernel of the library
# (tests/njit_kernels.py) ran as Python in some test.  tests/test_nojit.py keeps the
# Makefile to that rule.
def pytest_addoption(parser):
    parser.addoption(
        "--check-kernels",
        action="store_true",
        help="with NUMBA_DISABLE_JIT=1: fail the session unless every @njit function of the library ran",
    )


def pytest_collection_modifyitems(config, items):
    # the slow tests first (a stable sort): pytest-xdist hands each worker a contiguous share and
    # work stealing takes from the ends of the queues, so a long test left at the end runs alone
    # while the other worker idles; begun first, the run ends on short tests
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)
    for item in items:
        for mark in item.iter_markers("jit_only"):
            reason = mark.args[0] if mark.args else mark.kwargs.get("reason")
            if not (isinstance(reason, str) and reason.strip()):
                raise pytest.UsageError(
                    f"{item.nodeid}: pytest.mark.jit_only needs the reason the test cannot run with "
                    'NUMBA_DISABLE_JIT=1, e.g. @pytest.mark.jit_only("3 min as pure Python; its kernels '
                    'run in test_x.py")'
                )


class KernelReach:
    """Records the first test in which each kernel runs (as a plain Python function, JIT off).

    Each kernel is replaced, wherever a workbench module binds it, by a wrapper that notes the
    current test and puts the kernel back everywhere at its first call: no cost afterwards."""

    def __init__(self, kernels):
        import importlib

        self.first = {}  # "module.function" -> test node id
        self.pending = {}
        for module, name in kernels:
            func = getattr(importlib.import_module(module), name)
            self.pending[f"{module}.{name}"] = func
            self._rebind(func, self._wrapper(f"{module}.{name}", func))

    @staticmethod
    def _rebind(old, new):
        for mod_name, mod in list(sys.modules.items()):
            if mod_name.split(".")[0] == "workbench" and mod is not None:
                for attr, value in list(vars(mod).items()):
                    if value is old:
                        setattr(mod, attr, new)

    def _wrapper(self, key, func):
        import functools
        import os

        @functools.wraps(func)
        def first_call(*args, **kwargs):
            if key in self.pending:
                del self.pending[key]
                self.first[key] = os.environ.get("PYTEST_CURRENT_TEST", "?").rsplit(" ", 1)[0]
                self._rebind(first_call, func)
            return func(*args, **kwargs)

        return first_call


class KernelTally:
    """The pytest-xdist controller's view: the kernels each worker's :class:`KernelReach` saw
    run (sent back as ``workeroutput``), merged as the workers finish."""

    def __init__(self, kernels):
        self.first = {}
        self.pending = {f"{module}.{name}": None for module, name in kernels}

    def merge(self, first):
        for key, test in first.items():
            if key in self.pending:
                del self.pending[key]
                self.first[key] = test


def pytest_sessionstart(session):
    if not session.config.getoption("--check-kernels"):
        return
    import numba
    from njit_kernels import njit_functions

    if not numba.config.DISABLE_JIT:
        raise pytest.UsageError("--check-kernels needs NUMBA_DISABLE_JIT=1 (the kernels as Python)")
    controller = session.config.getoption("numprocesses", None) and not hasattr(session.config, "workerinput")
    # under pytest-xdist each worker records the kernels its share of the tests ran, and the
    # controller (which runs no test) judges their union
    cls = KernelTally if controller else KernelReach
    session.config._kernel_reach = cls(njit_functions())


@pytest.hookimpl(optionalhook=True)  # a pytest-xdist hook
def pytest_testnodedown(node, error):
    reach = getattr(node.config, "_kernel_reach", None)
    if isinstance(reach, KernelTally):
        reach.merge(getattr(node, "workeroutput", {}).get("kernels_first", {}))


def pytest_sessionfinish(session, exitstatus):
    reach = getattr(session.config, "_kernel_reach", None)
    if reach is None:
        return
    if hasattr(session.config, "workerinput"):  # a worker sees a share: the controller judges
        session.config.workeroutput["kernels_first"] = dict(reach.first)
        return
    if reach.pending and exitstatus == pytest.ExitCode.OK:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    reach = getattr(config, "_kernel_reach", None)
    if reach is None:
        return
    tr = terminalreporter
    tr.section("Numba kernels run as Python (--check-kernels)")
    for key, test in sorted(reach.first.items()):
        tr.write_line(f"{key}: first in {test}")
    for key in sorted(reach.pending):
        tr.write_line(
            f"{key}: NOT RUN by any test of this session - every test reaching it was left out of "
            "the no-JIT run (marked jit_only?): let one of them run without JIT",
            red=True,
        )
    if reach.pending:
        tr.write_line(f"--check-kernels: {len(reach.pending)} kernel(s) not run as Python: FAILED", red=True)

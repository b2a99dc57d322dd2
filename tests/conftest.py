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
    from workbench.surface_catalog import S4

    prof = mesh_profile(S4, 800).normalized()
    train = frictional_wrenches(prof, sample_twists_thesis(300, prof, seed=1))
    test = frictional_wrenches(prof, sample_twists_thesis(2000, prof, seed=2))
    return prof, train, test


@pytest.fixture(scope="session")
def s4_quartic(s4_data):
    from workbench import fit_quartic

    return fit_quartic(s4_data[1])

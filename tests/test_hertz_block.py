"""Our condensed FEM against Hertz on thick blocks (workbench.peers.hertz_block): Hertz's force in
closed form, the layer's stiffening halving with a/H, and the Richardson limit within 3 %."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.peers.hertz_block import hertz_half_space

BLOCK = {"R_mm": 20.0, "a_mm": 1.5, "nu": 0.3, "fine_mm": 0.6, "depths_mm": [20.0, 40.0]}


@pytest.mark.jit_only("two graded thick blocks condensed and solved: their kernels as Python")
def test_the_half_space_limit_is_hertz():
    hb = hertz_half_space(BLOCK, 1.0e6)
    R, a = 20e-3, 1.5e-3
    d = a * a / R
    assert hb["delta_mm"] == pytest.approx(d * 1e3, rel=1e-15)
    assert hb["hertz_force_N"] == pytest.approx(4 / 3 * 1e6 / (1 - 0.09) * np.sqrt(R) * d**1.5, rel=1e-12)
    assert hb["a_over_H"] == pytest.approx([a / 20e-3, a / 40e-3], rel=1e-15)
    e1, e2 = hb["force_rel_err"]
    # the layer stiffens at first order in a/H: positive, about halved at twice the depth
    assert 0 < e2 < e1
    assert hb["extrapolated_force_rel_err"] == pytest.approx(2 * e2 - e1, abs=1e-12)
    assert abs(hb["extrapolated_force_rel_err"]) < 0.03  # the requirement: within 3 %


def test_depths_must_be_h_and_2h():
    with pytest.raises(ValueError, match="two depths H, 2H"):
        hertz_half_space({**BLOCK, "depths_mm": [20.0, 30.0]}, 1.0e6)

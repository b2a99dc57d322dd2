"""workbench.quiet_log: a logger quieted inside the block, its own level back after it."""

import logging

import pytest

from workbench.quiet_log import quieted


def test_quieted_drops_warnings_inside_and_restores_the_level_even_on_an_error(caplog):
    log = logging.getLogger("workbench.test_quiet_log")
    log.setLevel(logging.INFO)
    with caplog.at_level(logging.INFO, logger=log.name):
        with quieted(log):
            log.warning("inside")
            log.error("kept")
        log.warning("after")
        with pytest.raises(RuntimeError), quieted(log):
            raise RuntimeError("x")
    assert [r.getMessage() for r in caplog.records] == ["kept", "after"]
    assert log.level == logging.INFO

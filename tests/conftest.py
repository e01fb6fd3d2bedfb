"""Shared fixtures: robots are parsed once per session."""

import pytest
from hypothesis import settings

from scalf_opt.robot import Robot

# the same examples on every run and machine: a failure reproduces, CI never flickers
settings.register_profile("deterministic", derandomize=True, deadline=None)
settings.load_profile("deterministic")


@pytest.fixture(scope="session")
def scalf():
    return Robot.from_preset("scalf")


@pytest.fixture(scope="session")
def hyq():
    return Robot.from_preset("hyq")


@pytest.fixture(scope="session")
def solo12():
    return Robot.from_preset("solo12")

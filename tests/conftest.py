"""Shared fixtures: robots are parsed once per session."""

import pytest

from scalf_opt.robot import Robot


@pytest.fixture(scope="session")
def scalf():
    return Robot.from_preset("scalf")


@pytest.fixture(scope="session")
def hyq():
    return Robot.from_preset("hyq")


@pytest.fixture(scope="session")
def solo12():
    return Robot.from_preset("solo12")

"""The swing-family registry: every kind builds the names it offers, and a new kind is one
registration that every command then takes, from the optimizer to a saved result read back."""

import re

import numpy as np
import pytest

import scalf_opt as so
import scalf_opt.locomotion.swing.registry as registry
from scalf_opt.cli import main
from scalf_opt.energy.margins import NO_LIFT_PROFILE
from scalf_opt.errors import ConfigError
from scalf_opt.io.saved import read_saved_swings
from scalf_opt.locomotion.swing.fourier import FourierFamily
from scalf_opt.locomotion.swing.registry import (
    FAMILY_KINDS,
    FamilyKind,
    make_family,
    register_family_kind,
)


@pytest.mark.parametrize("kind", FAMILY_KINDS, ids=lambda k: k.pattern.pattern)
def test_every_kind_builds_the_names_it_offers(kind):
    for name in kind.names:
        assert kind.pattern.fullmatch(name)
        family = make_family(name)
        assert family.name == name
        assert len(family.parameter_names) == family.n_params


def test_an_unknown_name_lists_every_kind_and_the_nearest_name():
    with pytest.raises(
        ConfigError, match=r"use reference, paper, fourier-N .*did you mean 'joint-6'"
    ):
        make_family("jiont-6")


COSINES = (("cos", 2), ("cos", 3))
"""A toy family's free terms, both joints: cosines only (4 parameters)."""


@pytest.fixture
def toy_kind(monkeypatch):
    monkeypatch.setattr(registry, "FAMILY_KINDS", list(registry.FAMILY_KINDS))
    kind = FamilyKind(
        re.compile("cosines"),
        lambda match: FourierFamily(match.group(0), "joint", (COSINES, COSINES)),
        "cosines (a toy)",
        ("cosines",),
    )
    register_family_kind(kind)
    return kind


def test_a_new_family_is_one_registration_end_to_end(toy_kind, tmp_path, capsys):
    # four cosines cannot shape the lift-off to the default lift profile (both legs infeasible)
    result = so.optimize_swing("scalf", family="cosines", loads="trunk", lift=NO_LIFT_PROFILE)
    assert result.converged
    for leg in ("RF", "LH"):
        swing = result.cycle.legs[leg].swing_energy_j
        assert swing < result.reference.legs[leg].swing_energy_j  # it optimized something
    result.write(tmp_path / "toy")
    saved = read_saved_swings(tmp_path / "toy")
    assert saved.families["RF"] == "cosines" and saved.parameters["RF"].size == 4
    np.testing.assert_array_equal(saved.parameters["RF"], result.run.legs["RF"].best.theta)
    # the command line takes the name, and reads the saved swings back
    assert main(["evaluate", "--swing", str(tmp_path / "toy"), "--json"]) == 0
    assert '"swing_family": "cosines"' in capsys.readouterr().out
    with pytest.raises(ConfigError, match="already a family name"):
        register_family_kind(toy_kind)

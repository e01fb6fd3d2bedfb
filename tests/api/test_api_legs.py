"""The API takes legs as the command line does: a name in any case, ``pair``, or several names;
anything else is a one-line :class:`ConfigError` that names ``legs`` before any work starts."""

import pytest

import scalf_opt as so
from scalf_opt.errors import ConfigError
from scalf_opt.types import leg_tuple


def test_legs_are_a_name_a_pair_or_names_in_any_case():
    assert leg_tuple("rf") == ("RF",)
    assert leg_tuple("Pair") == ("RF", "LH")
    assert leg_tuple(["lh", "RF"]) == ("LH", "RF")
    assert leg_tuple(("RF", "LH", "LF", "RH")) == ("RF", "LH", "LF", "RH")


@pytest.mark.parametrize(
    ("legs", "match"),
    [
        (("RX",), r"legs: unknown leg 'RX' \(legs: RF, LH, LF, RH, or pair\)"),
        ("R", "unknown leg 'R'"),
        (("RF", "rf"), "leg RF given twice"),
        ((), "no leg given"),
        ((1,), "unknown leg 1"),
    ],
)
def test_a_wrong_leg_is_named(legs, match):
    with pytest.raises(ConfigError, match=match) as info:
        leg_tuple(legs)
    assert info.value.field == "legs"


def test_optimize_swing_checks_its_legs_first():
    robot = so.load_robot("scalf")
    with pytest.raises(ConfigError, match="legs: unknown leg 'RX'"):
        so.optimize_swing(robot, legs=("RX",))

"""The API takes legs as the command line does (a name in any case, ``pair``, or names) and
names every other wrong argument: a one-line :class:`ConfigError` before any work starts."""

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
        (None, "give a leg name or names, got None"),
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


def test_other_wrong_arguments_are_named_too():
    robot = so.load_robot("scalf")
    with pytest.raises(ConfigError, match="did you mean 'joint-6'") as info:
        so.optimize_swing(robot, family="joint6")
    assert info.value.field == "family"
    with pytest.raises(ConfigError, match="the number of starts must be an integer >= 1, got 0"):
        so.optimize_swing(robot, starts=0)
    with pytest.raises(ConfigError, match=r"gait must be a Gait \(read_gait\(robot=") as info:
        so.evaluate(robot, {"period_s": 0.5})
    assert info.value.field == "gait"


def test_one_result_directory_or_format_is_not_read_letter_by_letter(tmp_path):
    # view(from_dirs="results/opt") looked for "r/summary.json"
    robot = so.load_robot("solo12")
    gait = so.read_gait(robot=robot, sample_rate_hz=150)
    so.optimize_swing(robot, gait, family="paper", loads="trunk").write(tmp_path / "opt")
    _, shown = so.view(tmp_path / "v.html", robot, from_dirs=str(tmp_path / "opt"))
    assert [t.label for t in shown] == ["reference (cubic spline)", "opt (paper, ipopt)"]
    files, _ = so.figures(
        tmp_path / "figs", robot, from_dirs=tmp_path / "opt", formats="png", grid_points=3
    )
    assert files and {f.suffix for f in files} == {".png"}


def test_a_catalog_name_is_a_robot_everywhere():
    # evaluate("go1") raised AttributeError: 'str' object has no attribute 'parent'
    named = so.evaluate("go1", so.read_gait(robot="go1"), loads="trunk")
    loaded = so.evaluate(so.load_robot("go1"), loads="trunk")
    assert named.energy_j == loaded.energy_j
    with pytest.raises(ConfigError, match="robot must be a catalog robot's name") as info:
        so.optimize_swing(3)
    assert info.value.field == "robot"

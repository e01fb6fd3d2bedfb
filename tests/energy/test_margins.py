"""The margins every optimizer keeps inside the joint range and the cylinder stroke."""

import json
import math

import pytest

from scalf_opt.cli import main
from scalf_opt.energy.limits import leg_bounds
from scalf_opt.energy.margins import DEFAULT_MARGINS, NO_MARGINS, LiftProfile, LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.problem import SwingProblem


@pytest.fixture(scope="module")
def pipeline(scalf):
    return EnergyPipeline(scalf, Gait())


def test_the_range_the_stroke_and_the_efforts_move_inwards_and_nothing_else(pipeline):
    bounds = leg_bounds(pipeline.physics("RF"))
    margins = LimitMargins(stop_rad=0.03, stroke_m=0.004, effort_share=0.1)
    moved = margins.apply(bounds)
    assert [b.name for b in moved] == [b.name for b in bounds]
    seen = set()
    for old, new in zip(bounds, moved, strict=True):
        if old.output == "q":
            low = high = 0.03
        elif old.quantity == "cyl_len":
            low = high = 0.004
        elif old.quantity in ("tau", "cyl_force"):  # 800 N m, 14 kN: a tenth of each end
            low, high = 0.1 * abs(old.lower), 0.1 * abs(old.upper)
        else:
            assert new == old  # rates and speeds: no margin
            continue
        seen.add(old.quantity)
        assert new.lower == old.lower + low and new.upper == old.upper - high
    assert seen == {"q", "cyl_len", "tau", "cyl_force"}  # SCalf has all four
    assert NO_MARGINS.apply(bounds) == bounds


def test_an_asymmetric_force_limit_keeps_its_share_at_each_end(hyq):
    """HyQ's hip cylinder pulls 1960 N and pushes 3217 N: 5 % of each, not of the larger."""
    bounds = leg_bounds(EnergyPipeline(hyq, Gait()).physics("RF"))
    force = next(b for b in bounds if b.name == "cyl_force_hip")
    moved = next(b for b in DEFAULT_MARGINS.apply(bounds) if b.name == "cyl_force_hip")
    assert moved.lower == pytest.approx(0.95 * force.lower, rel=1e-15)
    assert moved.upper == pytest.approx(0.95 * force.upper, rel=1e-15)
    assert moved.source.endswith(", less margin")


def test_the_loaded_stance_keeps_the_effort_margin_too(pipeline):
    """Under whole-body loads the swing moves the stance legs' torques: their rows in the NLP and
    the exact evaluation are bounded at 95 % of the limit (760 N m on SCalf)."""
    from scalf_opt.optimize.nlp import _stance_limits

    problem = SwingProblem(pipeline, "RF", make_family("joint-6"))
    (coupling,) = problem.couplings
    lower, upper = _stance_limits(problem, coupling)
    assert sorted(set(upper.tolist())) == pytest.approx([760.0, 13300.0], rel=1e-15)
    assert (lower == -upper).all()


def test_the_swing_problem_holds_its_margins(pipeline):
    family = make_family("joint-6")
    plain = SwingProblem(pipeline, "RF", family, margins=NO_MARGINS)
    default = SwingProblem(pipeline, "RF", family)
    assert default.margins == DEFAULT_MARGINS
    i = next(k for k, b in enumerate(plain.bounds) if b.name == "q_knee")
    lo_plain, hi_plain = plain.constraint_bounds
    lo, hi = default.constraint_bounds
    assert lo[i, 0] - lo_plain[i, 0] == pytest.approx(math.radians(2.0), rel=1e-12)
    assert hi_plain[i, 0] - hi[i, 0] == pytest.approx(math.radians(2.0), rel=1e-12)


@pytest.mark.parametrize(
    ("margins", "field"),
    [
        ({"stop_rad": -0.1}, "stop_rad"),
        ({"stroke_m": math.nan}, "stroke_m"),
        ({"effort_share": 0.6}, "effort_share"),
        ({"effort_share": True}, "effort_share"),
    ],
)
def test_a_bad_margin_names_itself(margins, field):
    with pytest.raises(ConfigError, match=field):
        LimitMargins(**margins)


@pytest.mark.parametrize(
    ("profile", "field"),
    [
        ({"height_m": -0.01}, "lift_height_m"),
        ({"height_m": math.inf}, "lift_height_m"),
        ({"fraction": 0.0}, "lift_fraction"),
        ({"fraction": 0.6}, "lift_fraction"),
        ({"touchdown_speed_m_s": 0.0}, "touchdown_speed_m_s"),
        ({"touchdown_speed_m_s": math.nan}, "touchdown_speed_m_s"),
    ],
)
def test_a_bad_lift_profile_names_its_field(profile, field):
    with pytest.raises(ConfigError, match=field):
        LiftProfile(**profile)


def test_the_saved_optimum_states_its_margins_and_keeps_them(optimum):
    summary = json.loads((optimum / "summary.json").read_text())
    assert summary["limit_margins"] == pytest.approx(
        {
            "stop_margin_deg": 2.0,
            "stroke_margin_mm": 2.0,
            "effort_margin_pct": 5.0,
            "lift_height_mm": 16.0,
            "lift_fraction": 0.15,
            "touchdown_speed_m_s": 0.832,
        },
        rel=1e-12,
    )


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--stop-margin", "-1"], "argument --stop-margin: -1 is out of range (0..30)"),
        (["--stroke-margin", "51"], "argument --stroke-margin: 51 is out of range (0..50)"),
        (["--effort-margin", "60"], "argument --effort-margin: 60 is out of range (0..50)"),
        (["--lift-fraction", "0.7"], "argument --lift-fraction: 0.7 is out of range"),
    ],
)
def test_optimize_refuses_a_margin_out_of_range(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["optimize", *argv])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err


def test_optimize_refuses_a_margin_that_leaves_no_range(capsys):
    assert main(["optimize", "--stop-margin", "29"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("scalf-opt: error: ") and err.count("\n") == 1
    assert "the stance of RF at this gait takes q_hip within 0.506145 rad of the end" in err


def test_a_margin_wider_than_the_range_is_refused(pipeline):
    with pytest.raises(ConfigError, match="stop_rad = 10 leaves no room in q_hip"):
        LimitMargins(stop_rad=10.0).apply(leg_bounds(pipeline.physics("RF")))


def test_a_range_of_a_full_turn_has_no_stop_to_keep_clear_of(solo12):
    """Solo12's +-10 rad is a URDF placeholder, not an end stop: no margin (and the same optima)."""
    bounds = leg_bounds(EnergyPipeline(solo12, Gait()).physics("RF"))
    moved = DEFAULT_MARGINS.apply(bounds)
    assert [m for b, m in zip(bounds, moved, strict=True) if b.output == "q"] == [
        b for b in bounds if b.output == "q"
    ]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--lift-fraction", "0"], "lift profile lift_fraction = 0.0 must be in (0, 0.5]"),
        (["--touchdown-speed", "-1"], "lift profile touchdown_speed_m_s = -1.0 must be > 0"),
        (["--touchdown-speed", "nan"], "touchdown_speed_m_s = nan must be > 0"),
    ],
)
def test_optimize_names_a_bad_lift_profile_in_one_line(argv, message, capsys):
    assert main(["optimize", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("scalf-opt: error: ") and err.count("\n") == 1 and message in err

"""The margins every optimizer keeps inside the joint range and the cylinder stroke."""

import json
import math

import pytest

from scalf_opt.cli import main
from scalf_opt.energy.limits import leg_bounds
from scalf_opt.energy.margins import DEFAULT_MARGINS, NO_MARGINS, LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.problem import SwingProblem


@pytest.fixture(scope="module")
def pipeline(scalf):
    return EnergyPipeline(scalf, Gait())


def test_the_range_and_the_stroke_move_inwards_and_nothing_else(pipeline):
    bounds = leg_bounds(pipeline.physics("RF"))
    margins = LimitMargins(stop_rad=0.03, stroke_m=0.004)
    moved = margins.apply(bounds)
    assert [b.name for b in moved] == [b.name for b in bounds]
    seen = set()
    for old, new in zip(bounds, moved, strict=True):
        if old.output == "q":
            step = 0.03
        elif old.quantity == "cyl_len":
            step = 0.004
        else:
            assert new == old  # rates, torques, forces, speeds: no margin
            continue
        seen.add(old.quantity)
        assert new.lower == old.lower + step and new.upper == old.upper - step
    assert seen == {"q", "cyl_len"}  # SCalf has both
    assert NO_MARGINS.apply(bounds) == bounds


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
    [({"stop_rad": -0.1}, "stop_rad"), ({"stroke_m": math.nan}, "stroke_m")],
)
def test_a_bad_margin_names_itself(margins, field):
    with pytest.raises(ConfigError, match=field):
        LimitMargins(**margins)


def test_the_saved_optimum_states_its_margins_and_keeps_them(optimum):
    summary = json.loads((optimum / "summary.json").read_text())
    assert summary["limit_margins"] == {"stop_margin_deg": 2.0, "stroke_margin_mm": 2.0}


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--stop-margin", "-1"], "argument --stop-margin: -1 is out of range (0..30)"),
        (["--stroke-margin", "51"], "argument --stroke-margin: 51 is out of range (0..50)"),
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
    assert DEFAULT_MARGINS.apply(bounds) == bounds

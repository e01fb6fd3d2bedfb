"""The 3-D model's trot schedule: who stands when, the flight, and the grid's edges."""

import numpy as np
import pytest

from scalf_opt.errors import GaitError
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.types import LEG_NAMES


def test_a_flying_trot_has_two_flights_and_diagonal_pairs():
    s = trot_schedule(0.3, 0.35, 100.0)
    assert s.intervals % 2 == 0 and s.duty_cycle * s.intervals == s.stance_nodes
    stance = {leg: s.stance[i] for i, leg in enumerate(LEG_NAMES)}
    np.testing.assert_array_equal(stance["RF"], stance["LH"])
    np.testing.assert_array_equal(stance["LF"], stance["RH"])
    assert not (stance["RF"] & stance["LF"]).any()  # the pairs never share the ground
    # each pair stands D N + 1 nodes (both edges), the rest is flight: two flights per cycle
    assert stance["RF"].sum() == s.stance_nodes + 1
    assert s.flight.sum() == s.intervals - 2 * (s.stance_nodes + 1)
    edges = np.flatnonzero(np.diff(s.flight.astype(int)) == 1)
    assert len(edges) == 2


def test_a_walking_trot_shares_the_ground_and_never_flies():
    s = trot_schedule(0.5, 0.6, 200.0)
    assert not s.flight.any()
    assert (s.stance.sum(axis=0) == 4).sum() > 0


def test_a_stance_that_wraps_stands_on_the_previous_foothold():
    s = trot_schedule(0.5, 0.6, 100.0)
    i = LEG_NAMES.index("LF")  # touches down at T/2 and stands past the period's end
    wrapped = np.flatnonzero(s.previous_stance[i])
    assert wrapped.size == s.stance_nodes - s.intervals // 2 + 1
    assert (wrapped < s.intervals // 2).all() and s.stance[i, wrapped].all()
    assert not s.previous_stance[LEG_NAMES.index("RF")].any()


def test_swing_phase_runs_from_lift_off_to_touch_down():
    s = trot_schedule(0.4, 0.5, 100.0)
    phase = s.swing_phase("RF")
    swing = ~np.isnan(phase)
    assert swing.sum() == s.intervals - s.stance_nodes - 1
    assert np.all(np.diff(phase[swing]) > 0)
    assert phase[swing].min() > 0 and phase[swing].max() < 1


@pytest.mark.parametrize("duty", [0.1, 0.9])
def test_a_duty_factor_out_of_range_is_named(duty):
    with pytest.raises(GaitError, match="duty_cycle") as info:
        trot_schedule(0.4, duty, 100.0)
    assert info.value.field == "duty_cycle"


def test_a_duty_factor_no_grid_resolves_is_named():
    with pytest.raises(GaitError, match="three decimals"):
        trot_schedule(0.4, 0.3333333, 100.0)


def test_stance_between_nodes_and_at_them_despite_rounding():
    s = trot_schedule(0.5, 0.4, 40.0)
    n = s.intervals
    nodes = np.arange(n, dtype=float)
    np.testing.assert_array_equal(s.stance_at(nodes), s.stance)
    # a time divided by the step lands a hair off the node: still the node
    np.testing.assert_array_equal(s.stance_at(nodes - 1e-12), s.stance)
    np.testing.assert_array_equal(s.stance_at(nodes + 1e-12), s.stance)
    inside = s.stance & np.roll(s.stance, -1, axis=1)
    np.testing.assert_array_equal(s.stance_at(nodes + 0.5), inside)
    np.testing.assert_array_equal(s.stance_at(nodes + n), s.stance)  # periodic


def test_swing_progress_runs_from_lift_off_to_touch_down():
    s = trot_schedule(0.5, 0.4, 40.0)
    for leg in ("RF", "LH", "LF", "RH"):
        phase = s.swing_phase(leg)
        swing = ~np.isnan(phase)
        progress = s.swing_progress(leg, np.arange(s.intervals))
        np.testing.assert_allclose(progress[swing], phase[swing], rtol=0, atol=1e-15)
        lift = s.touchdown_node(leg) + s.stance_nodes
        assert s.swing_progress(leg, lift) == 0.0
        assert s.swing_progress(leg, lift + s.intervals - s.stance_nodes - 1e-9) == pytest.approx(1)

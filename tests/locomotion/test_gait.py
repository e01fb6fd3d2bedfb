"""Gait validation, gait files, timing and the stance path of Table 3."""

import numpy as np
import pytest

from scalf_opt.errors import ConfigError, GaitError
from scalf_opt.locomotion.gait import EVENT_SIDE_S, Gait
from scalf_opt.locomotion.gait_file import read_gait
from scalf_opt.locomotion.stance import stance_path, trunk_acceleration_m_s2
from scalf_opt.locomotion.trot import support_groups, support_masks


def test_paper_defaults():
    g = Gait()
    assert (g.period_s, g.duty_cycle, g.step_length_m, g.clearance_m) == (0.5, 0.5, 0.25, 0.08)
    assert (g.stance_height_m, g.sample_rate_hz, g.cycles) == (0.75, 200.0, 10)
    assert g.speed_m_s == pytest.approx(1.0)  # Section 6.1: 1.0 m/s
    assert g.stance_duration_s == g.swing_duration_s == 0.25
    tau = g.phase_times_s("stance")
    assert tau.size == 51 and tau[1] == pytest.approx(0.005)


def test_stance_path_meets_table_3():
    g = Gait()
    p, pd, pdd = stance_path(g, np.array([0.0, g.stance_duration_s]), "RF")
    s, t, z0 = g.step_length_m, g.period_s, g.stance_height_m
    np.testing.assert_allclose(p[:, 0], [s / 2, -z0], rtol=1e-15)
    np.testing.assert_allclose(p[:, 1], [-s / 2, -z0], rtol=1e-15)
    np.testing.assert_allclose(pd[:, 0], [-2 * s / t, 0.0], rtol=1e-15)
    np.testing.assert_allclose(pd[:, 1], [-2 * s / t, 0.0], rtol=1e-15)
    assert np.all(pdd == 0.0)
    assert np.all(trunk_acceleration_m_s2(g, np.linspace(0, 0.25, 7)) == 0.0)


def test_stance_velocity_is_the_derivative_of_the_position():
    g = Gait(step_length_m=0.3, period_s=0.6, duty_cycle=0.6)
    tau = np.linspace(0.0, g.stance_duration_s, 11)
    h = 1e-6
    p_plus, p_minus = stance_path(g, tau + h, "RF")[0], stance_path(g, tau - h, "RF")[0]
    np.testing.assert_allclose(
        (p_plus - p_minus) / (2 * h), stance_path(g, tau, "RF")[1], atol=1e-8
    )


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("period_s", 0.0, "period_s"),
        ("period_s", -1.0, "period_s"),
        ("step_length_m", float("nan"), "step_length_m"),
        ("clearance_m", -0.1, "clearance_m"),
        ("stance_height_m", 0.0, "stance_height_m"),
        ("duty_cycle", 1.0, r"duty_cycle .* \[0.5, 1\)"),
        ("duty_cycle", 0.0, "duty_cycle"),
        ("duty_cycle", 0.4, "flight phase"),
        ("sample_rate_hz", 0.0, "sample_rate_hz"),
        ("sample_rate_hz", 10.0, "too low"),
        ("cycles", 0, "cycles"),
        # the command line's bounds hold for files and the API too (a period of 1e300 s was
        # blamed on the sample rate)
        ("period_s", 1e300, r"period_s = 1e\+300 must be at most 60 s"),
        ("clearance_m", 11.0, "clearance_m = 11.0 must be at most 10 m"),
    ],
)
def test_impossible_gaits_name_the_field(field, value, match):
    with pytest.raises(GaitError, match=match):
        Gait(**{field: value})


def test_gait_file_round_trip(tmp_path):
    path = tmp_path / "gait.toml"
    path.write_text("[gait]\nperiod_s = 0.6\nstep_length_m = 0.2\ncycles = 3\n")
    g = read_gait(path)
    assert (g.period_s, g.step_length_m, g.cycles, g.duty_cycle) == (0.6, 0.2, 3, 0.5)


@pytest.mark.parametrize(
    ("text", "error", "match"),
    [
        ("[gait]\nperiod = 0.5\n", ConfigError, "field 'period'; did you mean 'period_s'"),
        ("[gait]\nduty = 0.6\n", ConfigError, "field 'duty'; did you mean 'duty_cycle'"),
        ("[gait]\nperiod_s = 'fast'\n", ConfigError, "period_s must be a number"),
        ("[gait]\ncycles = 2.5\n", ConfigError, "cycles must be an integer"),
        ("[gait\nperiod_s = 1\n", ConfigError, "not valid TOML"),
        ("[gait]\nclearance_m = -0.08\n", GaitError, "clearance_m"),
    ],
)
def test_bad_gait_files_name_file_and_field(tmp_path, text, error, match):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(error, match=match) as info:
        read_gait(path)
    assert "bad.toml" in str(info.value)


def test_missing_gait_file(tmp_path):
    with pytest.raises(ConfigError, match=r"nope\.toml"):
        read_gait(tmp_path / "nope.toml")


def support_legs(gait, cycle_time_s, leg):
    """The legs on the ground at one cycle time, in support_masks' order."""
    masks = support_masks(gait, np.array([cycle_time_s]), leg)
    return [other for other, down in masks.items() if down[0]]


def test_trot_support_sets():
    g = Gait()
    assert sorted(support_legs(g, 0.1, "RF")) == ["LH", "RF"]
    assert sorted(support_legs(g, 0.25, "RF")) == ["LH", "RF"]  # LF touches down: carries 0
    g2 = Gait(duty_cycle=0.6)
    assert sorted(support_legs(g2, 0.28, "RF")) == ["LF", "LH", "RF", "RH"]


def test_support_groups_partition_the_times_by_the_legs_on_the_ground():
    g = Gait(duty_cycle=0.7)
    times = np.linspace(0.0, g.stance_duration_s, 101)  # RF's stance, both edges
    groups = support_groups(support_masks(g, times, "RF"))
    assert sorted(np.concatenate([at for at, _ in groups]).tolist()) == list(range(times.size))
    assert len(groups) == 2  # RF + LH alone; all four (LF + RH ending, then starting, stance)
    for at, legs in groups:
        for j in at:
            assert legs == support_legs(g, float(times[j]), "RF")
            assert legs[:2] == ["RF", "LH"]


def test_gait_files_that_are_not_gaits(tmp_path):
    path = tmp_path / "g.toml"
    path.write_text("[gait]\nperiod_s = 0.5\n[gaits]\nperiod_s = 0.4\n")
    with pytest.raises(ConfigError, match=r"g\.toml: unknown key or table 'gaits' beside \[gait\]"):
        read_gait(path)
    path.write_bytes(b"[gait]\nperiod_s = 0.5 # \xe9t\xe9\n")
    with pytest.raises(ConfigError, match=r"g\.toml: gait file is not UTF-8 text"):
        read_gait(path)


def test_resource_limits_are_named(tmp_path):
    with pytest.raises(GaitError, match=r"sample_rate_hz = 100000000.0 is too high.*20000 samples"):
        Gait(sample_rate_hz=1e8)
    with pytest.raises(GaitError, match=r"cycles = 10000 must be an integer in 1\.\.1000"):
        Gait(cycles=10000)


def test_a_stance_longer_than_half_a_cycle_is_sampled_on_each_side_of_the_other_pairs_events():
    """Duty 0.6, T = 0.5 s: LF and RH lift off 0.05 s and touch down 0.25 s into RF's stance."""
    g = Gait(duty_cycle=0.6, period_s=0.5)
    t = g.phase_times_s("stance")
    uniform = np.linspace(0.0, g.stance_duration_s, 61)  # round(0.3 s x 200 Hz) intervals
    sides = [0.05 - EVENT_SIDE_S, 0.05 + EVENT_SIDE_S, 0.25 - EVENT_SIDE_S, 0.25 + EVENT_SIDE_S]
    far = np.min(np.abs(uniform[:, None] - np.array([0.05, 0.25])), axis=1) > 2 * EVENT_SIDE_S
    # the events as the gait computes them (0.3 - 0.25 s): equal to 1e-16 s
    np.testing.assert_allclose(t, np.union1d(uniform[far], sides), rtol=0, atol=1e-15)
    assert t.size == 61 + 4 - 2  # 0.05 s and 0.25 s were samples of the uniform grid
    feet = [support_legs(g, float(x), "RF") for x in sides]
    assert [len(f) for f in feet] == [4, 2, 2, 4]  # each side of each event has its own support
    # at duty 0.5 the events are the stance's own ends: the grid stays uniform; so does a swing
    assert np.array_equal(Gait().phase_times_s("stance"), np.linspace(0.0, 0.25, 51))
    assert np.array_equal(g.phase_times_s("swing"), np.linspace(0.0, 0.2, 41))

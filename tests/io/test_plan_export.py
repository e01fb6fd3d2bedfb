"""``export``: the saved optimum at any rate, checked against independent physics and read back."""

import json
from pathlib import Path

import numpy as np
import pytest

from scalf_opt.api import analyze_log, export_plan
from scalf_opt.cli import main
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.io.plan_export import fitted_rate, planned_mechanical_energy_j, stream_columns
from scalf_opt.locomotion.gait import EVENT_SIDE_S, Gait
from scalf_opt.logs.analysis import leg_cylinders
from scalf_opt.types import LEG_NAMES


@pytest.fixture(scope="module")
def export(optimum, scalf):
    return export_plan(optimum, scalf, rate_hz=1000, cycles=3).export


def test_the_stream_is_uniform_periodic_and_starts_at_rf_touchdown(export):
    gait = export.saved.gait
    n = round(gait.period_s * 1000)
    assert export.t_s.size == 3 * n
    np.testing.assert_allclose(np.diff(export.t_s), 1e-3, rtol=1e-9)
    for leg in LEG_NAMES:
        v = export.values[leg]
        for name in ("q", "qd", "qdd", "tau", "foot", "cyl_len", "cyl_vel", "cyl_force"):
            # seamless: the next cycle repeats the first, sample for sample
            np.testing.assert_array_equal(v[name][:, :n], v[name][:, n : 2 * n])
        assert v["contact"].mean() == pytest.approx(gait.duty_cycle, abs=1e-9)
    rf, lf = export.values["RF"]["contact"], export.values["LF"]["contact"]
    assert rf[0] and not rf[n // 2] and not lf[0] and lf[n // 2]
    # at touch-down RF's foot is half a step ahead, on the ground
    np.testing.assert_allclose(
        export.values["RF"]["foot"][:, 0],
        [gait.step_length_m / 2 + gait.stance_x_offset_m("RF"), -gait.stance_height_m],
        atol=1e-9,
    )


def fourth_order_derivative(y, dt):
    """(-y[k+2] + 8 y[k+1] - 8 y[k-1] + y[k-2]) / (12 dt) at k = 2..n-3: error O(dt^4)."""
    return (-y[:, 4:] + 8 * y[:, 3:-1] - 8 * y[:, 1:-3] + y[:, :-4]) / (12 * dt)


def test_rates_and_accelerations_are_the_angles_derivatives(export):
    """Fourth-order central differences of the angles and rates at 1 kHz, inside each phase
    (the swing's 6th harmonic makes a second-order difference miss by 0.3 %)."""
    dt = 1e-3
    for leg in LEG_NAMES:
        v = export.values[leg]
        q, qd, qdd = v["q"], v["qd"], v["qdd"]
        contact = v["contact"]
        same = np.all(
            [contact[k : contact.size - 4 + k] == contact[2:-2] for k in range(5)], axis=0
        )
        for y, dy in ((q, qd), (qd, qdd)):
            np.testing.assert_allclose(
                fourth_order_derivative(y, dt)[:, same],
                dy[:, 2:-2][:, same],
                atol=1e-4 * np.abs(dy).max(),
            )
        # the loop closes: the step from the last sample to the first is an ordinary step
        # (Taylor: within dt^2 max|qdd|, where a seam would jump)
        np.testing.assert_allclose(
            q[:, 0] - q[:, -1], dt * qd[:, -1], atol=dt**2 * np.abs(qdd).max()
        )


def test_cylinders_follow_their_own_mapping(export, scalf):
    pipeline = EnergyPipeline(scalf, export.saved.gait)
    for leg in LEG_NAMES:
        v = export.values[leg]
        for j, cylinder in enumerate(leg_cylinders(pipeline, leg)):
            arm = np.array(cylinder.moment_arm_m(v["q"][j])).ravel()
            np.testing.assert_allclose(
                v["cyl_len"][j], np.array(cylinder.length_m(v["q"][j])).ravel(), rtol=1e-12
            )
            np.testing.assert_allclose(v["cyl_vel"][j], arm * v["qd"][j], rtol=1e-9, atol=1e-12)
            np.testing.assert_allclose(v["cyl_force"][j] * arm, v["tau"][j], rtol=1e-9, atol=1e-9)


def test_every_rate_is_an_evaluation_not_an_interpolation(optimum, scalf, export):
    """At 500 Hz each phase has an odd number of steps: the values still equal 1 kHz's."""
    slow = export_plan(optimum, scalf, rate_hz=500, cycles=1).export
    for leg in LEG_NAMES:
        for name in ("q", "qd", "qdd", "tau", "cyl_force"):
            fine = export.values[leg][name][:, : 2 * slow.t_s.size : 2]
            np.testing.assert_allclose(slow.values[leg][name], fine, rtol=1e-9, atol=1e-9)
    # 333 Hz puts no sample on the touch-downs: the nearest rate that does, 332 Hz
    odd = export_plan(optimum, scalf, rate_hz=333).export
    assert (odd.rate_hz, odd.requested_rate_hz, odd.t_s.size) == (332.0, 333.0, 166)
    np.testing.assert_array_equal(odd.values["RF"]["contact"][:83], True)
    assert not odd.values["RF"]["contact"][83:].any()
    with pytest.raises(ConfigError, match="too coarse"):
        export_plan(optimum, scalf, rate_hz=10)
    with pytest.raises(ConfigError, match="cycles"):
        export_plan(optimum, scalf, rate_hz=1000, cycles=0)
    # inside the 1000 cycles, but 500,000 instants: more than analyze-log reads back
    with pytest.raises(ConfigError, match=r"are 500,000 instants, more than the 150,000") as info:
        export_plan(optimum, scalf, rate_hz=1000, cycles=1000)
    assert info.value.field == "cycles" and "at most 300 at this rate" in str(info.value)


def test_a_rate_that_fits_is_kept_to_the_last_bit():
    # 350 / 0.7 s is 500.00000000000006 in floating point: the export said "500 Hz, not 500 Hz"
    gait = Gait(period_s=0.7, duty_cycle=0.6)
    assert fitted_rate(gait, 500.0) == (500.0, 350)
    assert fitted_rate(gait, 500.5) == (350 / 0.7, 350)  # one that does not fit: N / T
    assert fitted_rate(Gait(), 333.0) == (332.0, 166)


def test_the_csv_at_1000_hz_gives_back_the_plans_energy(optimum, tmp_path, capsys):
    path = tmp_path / "plan.csv"
    code = main(
        ["export", "--from", str(optimum), "--rate", "1000", "--cycles", "4", "--out", str(path)]
    )
    assert code == 0 and f"wrote {path}" in capsys.readouterr().out
    result = analyze_log(path, plan=optimum)
    comparison = result.to_dict()["plan_comparison"]
    assert result.measured.velocity_source == "measured"
    # measured -0.04 % for the robot (3e-5 % before the lift profile: the default optimum's
    # lift-off is sharper now, and the log's 1 kHz samples and the plan's 600 Hz ones integrate
    # it 0.2 W apart; at 2 and 4 kHz the log reads -0.06 %); per leg the one sample at
    # touch-down (the force's jump, larger under the whole-body loads) moves 0.7 % between
    # stance and the leg's neighbours
    assert abs(comparison["change_percent"]) < 0.1
    for leg in LEG_NAMES:
        assert abs(comparison["legs"][leg]["change_percent"]) < 1.0
    # docs/plan-to-robot.md quotes it
    page = (Path(__file__).parents[2] / "docs" / "plan-to-robot.md").read_text()
    watts = (comparison["measured_average_power_w"], comparison["planned_average_power_w"])
    assert "{:.2f} W measured, {:.2f} W planned".format(*watts) in page
    changes = [comparison["legs"][leg]["change_percent"] for leg in LEG_NAMES]
    assert f"per leg {min(changes):+.2f} % to {max(changes):+.2f} %" in page


@pytest.mark.parametrize("cycles", [2, 3])
def test_an_export_of_n_cycles_holds_n_minus_2_complete_cycles_of_rf(
    optimum, tmp_path, capsys, cycles
):
    """RF's touch-down at t = 0 is not seen in the log, and the last cycle's closing instant is
    the next cycle's first (docs/plan-to-robot.md): RF and LH hold N - 2 complete cycles, LF
    and RH N - 1; with none, the refusal names RF and where its first cycle would end."""
    path = tmp_path / "plan.csv"
    args = ["--rate", "1000", "--cycles", str(cycles), "--out", str(path), "-q"]
    assert main(["export", "--from", str(optimum), *args]) == 0
    if cycles == 2:
        assert main(["analyze-log", str(path), "--plan", str(optimum)]) == 2
        err = capsys.readouterr().err
        assert (
            "leg RF has no complete gait cycle: one period (0.5 s) from its first touch-down "
            "at t = 0.5 s ends at 1 s, after its last sample at 0.999 s"
        ) in err
        return
    legs = analyze_log(path, plan=optimum).analysis.legs
    assert {leg: len(legs[leg].windows_s) for leg in LEG_NAMES} == {
        "RF": 1,
        "LH": 1,
        "LF": 2,
        "RH": 2,
    }


def test_the_json_and_the_bag_carry_the_urdf_names(export, scalf, tmp_path):
    from rosbags.highlevel import AnyReader

    data = json.loads(export.write(tmp_path / "plan.json").read_text())
    assert data["legs"]["RF"]["joints"] == list(scalf.leg("RF").joint_names)
    assert len(data["legs"]["LH"]["angle_rad"][1]) == export.t_s.size
    urdf = [name for leg in LEG_NAMES for name in scalf.leg(leg).joint_names]
    seen = {}
    with AnyReader([export.write(tmp_path / "plan.mcap")]) as reader:
        for connection, _, raw in reader.messages():
            message = reader.deserialize(raw, connection.msgtype)
            seen.setdefault(connection.topic, []).append((connection.msgtype, message))
    assert {t: m[0][0] for t, m in seen.items()} == {
        "/plan/joint_states": "sensor_msgs/msg/JointState",
        "/plan/cylinder_states": "sensor_msgs/msg/JointState",
        "/plan/joint_trajectory": "trajectory_msgs/msg/JointTrajectory",
    }
    states = [m for _, m in seen["/plan/joint_states"]]
    assert len(states) == export.t_s.size and list(states[0].name) == urdf
    k = 123
    np.testing.assert_allclose(states[k].position[:2], export.values["RF"]["q"][:, k], rtol=1e-15)
    np.testing.assert_allclose(states[k].effort[2:4], export.values["LH"]["tau"][:, k], rtol=1e-15)
    (trajectory,) = [m for _, m in seen["/plan/joint_trajectory"]]
    assert list(trajectory.joint_names) == urdf and len(trajectory.points) == export.t_s.size
    point = trajectory.points[k]
    assert point.time_from_start.nanosec == k * 1_000_000
    np.testing.assert_allclose(point.accelerations[:2], export.values["RF"]["qdd"][:, k])


def test_the_plans_mechanical_energy_is_its_pipelines(export):
    """|tau qd| summed over the phases: the paper accounting's energy less the friction heat."""
    cycle = export.cycle
    for leg, energy in planned_mechanical_energy_j(cycle).items():
        leg_cycle = cycle.legs[leg]
        assert energy == pytest.approx(leg_cycle.energy_j - leg_cycle.loss_j, rel=1e-12)


def test_bad_exports_are_refused_in_one_line(optimum, tmp_path, capsys):
    for argv, message in (
        (["--rate", "10", "--out", str(tmp_path / "p.csv")], "--rate: a rate of 10 Hz is too"),
        (["--rate", "nan", "--out", str(tmp_path / "p.csv")], "--rate: the rate must be a finite"),
        (["--rate", "1e5", "--out", str(tmp_path / "p.csv")], "--rate: a rate of 100000 Hz is"),
        (["--rate", "100", "--out", str(tmp_path / "p.txt")], "unknown format '.txt'"),
        (["--rate", "100", "--out", str(tmp_path / "p.csv"), "--robot", "hyq"], "provenance"),
    ):
        code = main(["export", "--from", str(optimum), *argv])
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and message in err, err
    assert not list(tmp_path.iterdir())


def test_the_stream_takes_the_two_feet_side_of_a_stance_load_jump():
    """Duty 0.6: the stance grid has two samples at each jump, the stream one (its own grid)."""
    gait = Gait(duty_cycle=0.6, period_s=0.5, sample_rate_hz=200)
    t = gait.phase_times_s("stance")
    columns = stream_columns(t, 60, gait.stance_load_jumps_s()[1:])
    uniform = np.linspace(0.0, 0.3, 61)
    np.testing.assert_allclose(t[columns], uniform, rtol=0, atol=2 * EVENT_SIDE_S)
    lift_off, touch_down = gait.stance_load_jumps_s()
    assert t[columns[10]] > lift_off and t[columns[50]] < touch_down  # two feet on the ground


def test_a_plan_with_a_duty_above_a_half_exports_and_reads_back(tmp_path, capsys):
    saved = tmp_path / "opt"
    gait = ["--duty", "0.6", "--family", "joint-2", "--loads", "trunk"]
    assert main(["optimize", *gait, "-q", "--out", str(saved)]) == 0
    path = tmp_path / "plan.csv"
    args = ["--from", str(saved), "--rate", "1000", "--cycles", "3", "--out", str(path), "-q"]
    assert main(["export", *args]) == 0
    result = analyze_log(path, plan=saved)
    # the log holds one sample per instant, the plan both sides of each jump of the stance load
    assert abs(result.to_dict()["plan_comparison"]["change_percent"]) < 3.0
    capsys.readouterr()

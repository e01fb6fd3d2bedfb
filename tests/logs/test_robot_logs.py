"""A robot's own log, every joint: Unitree's LowState bag and SDK CSV, contacts, the model beside.

The logs are a known synthetic Go1 trot (``examples/unitree_log.py``): the model's reference
trot with an abduction motion added, written as Unitree's driver and SDK write them. The truth is
the dense integral of ``|tau dq|`` of the very samples written, so the reader, the contacts and
the cycle alignment are what is tested, not the model.
"""

import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from scalf_opt.api import analyze_robot_log, export_plan
from scalf_opt.cli import main
from scalf_opt.errors import ConfigError, LogError
from scalf_opt.logs.contacts import motion_stance
from scalf_opt.logs.mapping import BUILT_IN, mapping_from_dict

sys.path.insert(0, str(Path(__file__).parents[2] / "examples"))
from unitree_log import (
    ABDUCTION_NM,
    ABDUCTION_RAD,
    UNITREE_ORDER,
    exact_energy_j,
    synthetic_trot,
    write_lowstate_bag,
    write_sdk_csv,
)

MAPPINGS = Path(__file__).parents[2] / "examples" / "mappings"
PERIOD_S = 0.3
START_PHASE = 0.37  # the recording starts 37 % into RF's cycle: no touch-down at its first sample


def joint_state_bag(path, names, t, q, dq, tau, keep=None):
    """The joints as a ``sensor_msgs/JointState`` bag (``keep``: the rows written), stamped
    from 1 s on."""
    from scalf_opt.io.ros_bag import JointStateSeries, write_bag

    rows = list(range(len(names))) if keep is None else keep
    series = JointStateSeries(
        "/joint_states", tuple(names[k] for k in rows), t + 1.0, q[rows], dq[rows], tau[rows]
    )
    return write_bag(path, [series])


@pytest.fixture(scope="module")
def trot(tmp_path_factory):
    """Go1's reference trot at T 0.3 s, 500 Hz, 6 cycles: the export and the Unitree arrays."""
    folder = tmp_path_factory.mktemp("go1ref")
    assert (
        main(["evaluate", "--robot", "go1", "--period", str(PERIOD_S), "--out", str(folder), "-q"])
        == 0
    )
    export = export_plan(folder, "go1", rate_hz=500, cycles=6).export
    return export, synthetic_trot(export, cycles_skip=START_PHASE)


@pytest.fixture(scope="module")
def logs(trot, tmp_path_factory):
    folder = tmp_path_factory.mktemp("logs")
    _, arrays = trot
    return (
        write_lowstate_bag(folder / "lowstate.mcap", *arrays),
        write_sdk_csv(folder / "sdk.csv", *arrays),
    )


def test_a_lowstate_bag_and_an_sdk_csv_give_every_joints_energy(trot, logs):
    """Done-when: all 12 joints' mechanical energy per cycle within 1 % (here 1e-4: the samples
    are the truth's; float32 in the bag, 6 digits in the CSV)."""
    export, (t, _q, dq, tau, _force) = trot
    exact = exact_energy_j(t, dq, tau, export.saved.gait.period_s)
    bag, table = logs
    for result in (
        analyze_robot_log(bag, "go1"),  # the LowState topic is recognised: no mapping given
        analyze_robot_log(table, "go1", mapping=MAPPINGS / "unitree_sdk_csv.toml"),
    ):
        energies = {j.joint: j.cycle_j for j in result.analysis.joints}
        assert sorted(energies) == sorted(UNITREE_ORDER)
        for joint, energy in energies.items():
            truth = exact[UNITREE_ORDER.index(joint)]
            assert energy == pytest.approx(truth, rel=1e-4), joint
            if joint.endswith("_hip_joint"):  # the abduction's closed form, pi A B per cycle
                assert energy == pytest.approx(np.pi * ABDUCTION_RAD * ABDUCTION_NM, rel=1e-4)
        for leg in result.analysis.legs.values():
            assert leg.contact_method == "foot force"
            assert leg.period_s == pytest.approx(PERIOD_S, rel=1e-3)
            assert leg.duty_cycle == pytest.approx(0.5, abs=1e-3)
        # the abduction does work the sagittal model leaves out, and it is stated
        hips = sum(j.cycle_j for j in result.analysis.joints if not j.modelled)
        total = sum(j.cycle_j for j in result.analysis.joints)
        assert result.analysis.left_out_share == pytest.approx(hips / total, rel=1e-9)
        assert result.analysis.left_out_share > 0.05


def test_without_contacts_the_torques_find_the_same_phases(trot, logs):
    """Done-when: no contact information and an arbitrary start: per-leg stance and swing
    energies within 3 % of those with contacts."""
    bag, _table = logs
    with_sensors = analyze_robot_log(bag, "go1").analysis
    blind = replace(BUILT_IN["unitree_go"], foot_force=None, feet=())
    without = analyze_robot_log(bag, "go1", mapping=blind).analysis
    for leg in with_sensors.legs:
        assert without.legs[leg].contact_method == "joint torque"
        a, b = with_sensors.leg_energy_j(leg), without.leg_energy_j(leg)
        for phase in ("stance", "swing"):
            assert b[phase] == pytest.approx(a[phase], rel=0.03), (leg, phase)


def test_the_motion_finds_lift_off_and_touch_down():
    """A foot height with a flat stance and a bump: the stance is where the foot is down."""
    t = np.linspace(0.0, 3.0, 3001)
    phase = np.mod(t, 1.0)
    swing = phase >= 0.6
    s = (phase - 0.6) / 0.4
    height = np.where(swing, 0.05 * np.sin(np.pi * s) ** 2, 0.0) - 0.3
    height += 1e-4 * np.sin(2 * np.pi * 37 * t)  # 0.1 mm of sensor noise
    stance = motion_stance(height, "log", "RF")
    assert np.all(stance[~swing])  # never a swing while the foot is down
    # every sample more than 3 % of the lift (1.5 mm) off the ground, noise included, swings;
    # below that a slowly lifting foot cannot be told from a standing one by its height
    assert not np.any(stance[height > -0.3 + 0.0016])
    assert np.count_nonzero(stance[swing]) / np.count_nonzero(swing) < 0.12


def test_compare_at_the_logs_own_gait_agrees_with_the_model_on_its_own_trot(trot, logs):
    """The log of the model's own reference trot, compared at the gait measured from it: the
    hip pitch and knee energies are the model's within 2 %; the abduction is not modelled.

    2 %, not less: the plan's power jumps at each touch-down (the load passes from one pair to
    the other in an instant), which the model integrates from both sides and a sampled log
    across one step: 1.4 % on the hind knees at 500 Hz, 0.7 % at 1 kHz (first order in the
    step, measured)."""
    export, _ = trot
    gait = export.saved.gait
    speed = gait.step_length_m / (gait.duty_cycle * gait.period_s)
    result = analyze_robot_log(logs[0], "go1", speed_m_s=speed, compare=True)
    comparison = result.comparison
    assert comparison.gait.period_s == pytest.approx(gait.period_s, rel=1e-3)
    assert comparison.gait.stance_height_m == pytest.approx(gait.stance_height_m, rel=1e-3)
    assert comparison.gait.step_length_m == pytest.approx(gait.step_length_m, rel=1e-3)
    for joint in comparison.joints:
        if joint.joint.endswith("_hip_joint"):
            assert joint.planned_j == 0.0 and joint.ratio is None
        else:
            assert joint.ratio == pytest.approx(1.0, abs=0.02), joint.joint


def test_analyze_log_compare_on_a_go1_flying_trot(trot, tmp_path, capsys):
    """Done-when: a Go1 log at T 0.3 s, duty 0.35 gives the per-joint table and the figure; the
    sagittal model cannot fly and says where it was evaluated instead."""
    export, (t, q, dq, tau, force) = trot
    period = export.saved.gait.period_s
    dt = t[1] - t[0]
    flying = np.zeros_like(force)
    for k, column in enumerate(force):
        downs = np.flatnonzero((column[1:] > 0) & (column[:-1] == 0)) + 1
        for d in downs:
            flying[k, d : d + round(0.35 * period / dt)] = 120
    bag = write_lowstate_bag(tmp_path / "flying.mcap", t, q, dq, tau, flying)
    figure = tmp_path / "joints.png"
    code = main(
        [
            "analyze-log",
            str(bag),
            "--robot",
            "go1",
            "--speed",
            "0.4",
            "--compare",
            "--figure",
            str(figure),
        ]
    )
    out = capsys.readouterr().out
    assert code == 0
    assert all(f"{leg}        0.3000  0.347" in out for leg in ("RF", "LH", "LF", "RH")), out
    assert "flying trot" in out and "FR_hip_joint" in out and "not modelled" in out
    assert figure.stat().st_size > 10_000
    code = main(
        ["analyze-log", str(bag), "--robot", "go1", "--speed", "0.4", "--compare", "--json"]
    )
    data = json.loads(capsys.readouterr().out)
    assert code == 0
    assert data["duty_cycle"] == pytest.approx(0.35, abs=0.01)
    assert data["model_comparison"]["gait"]["duty_cycle"] == 0.5
    assert len(data["model_comparison"]["joints"]) == 12


def test_odometry_gives_the_speed_and_the_cost_of_transport(trot, tmp_path):
    _, arrays = trot
    bag = write_lowstate_bag(tmp_path / "odo.mcap", *arrays, odometry_speed_m_s=0.45)
    result = analyze_robot_log(bag, "go1", odometry_topic="/odom")
    a = result.analysis
    assert a.speed_source == "odometry" and a.speed_m_s == pytest.approx(0.45, rel=1e-6)
    assert a.cost_of_transport == pytest.approx(
        a.average_power_w / (a.mass_kg * 9.81 * a.speed_m_s), rel=1e-12
    )


def test_stale_samples_are_dropped_and_counted_and_a_slow_log_is_warned(trot, tmp_path):
    _, (t, q, dq, tau, force) = trot
    k = np.arange(t.size)
    repeat = np.where(k % 10 == 5, k - 1, k)  # every tenth sample re-publishes the one before
    bag = write_lowstate_bag(
        tmp_path / "stale.mcap", t, q[:, repeat], dq[:, repeat], tau[:, repeat], force[:, repeat]
    )
    notes = analyze_robot_log(bag, "go1").analysis.notes
    assert any(
        f"{np.count_nonzero(repeat != k)} repeated stale sample(s) dropped" in n for n in notes
    )
    slow = k % 20 == 0  # 25 Hz: 7.5 samples per cycle
    bag = write_lowstate_bag(
        tmp_path / "slow.mcap", t[slow], q[:, slow], dq[:, slow], tau[:, slow], force[:, slow]
    )
    notes = analyze_robot_log(bag, "go1").analysis.notes
    assert any("samples per cycle" in n and "fewer than 40" in n for n in notes), notes


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--robot", "scalf"], r"joint 'FR_hip_joint' of the mapping is not a joint of scalf"),
        (["--robot", "go1", "--mapping", "unitree_gp"], r"did you mean 'unitree_go'"),
        (["--robot", "go1", "--compare"], r"--compare: .* give --speed"),
        (["--robot", "go1", "--speed", "-1"], r"the speed must be in \(0, 100\)"),
        (["--robot", "go1", "--plan", "x"], r"--plan is for a log of the sagittal joints"),
        (["--robot", "go1", "--topic", "/nothing"], r"no topic '/nothing'"),
    ],
)
def test_bad_robot_log_input_is_one_line(logs, argv, message, capsys):
    import re

    code = main(["analyze-log", str(logs[0]), *argv])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert re.search(message, err), err


def test_bad_mapping_files_are_one_line(logs, tmp_path, capsys):
    cases = {
        'source = "csv"\ntime = "t"\njoints = ["a"]\npostion = "q_{i}"\neffort = "e"\n': (
            "unknown field 'postion'; did you mean 'position'?"
        ),
        'source = "csv"\ntime = "t"\njoints = ["a", "b"]\nposition = "q"\neffort = "e_{i}"\n': (
            "names one place for 2 indices"
        ),
        'source = "bag"\nmessage = "x/msg/Y"\njoints = ["a"]\nposition = "q-1"\neffort = "e"\n': (
            "is not a field path"
        ),
    }
    for text, message in cases.items():
        path = tmp_path / "m.toml"
        path.write_text(text)
        code = main(["analyze-log", str(logs[1]), "--robot", "go1", "--mapping", str(path)])
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and message in err, err
    wrong = tmp_path / "wrong.toml"
    wrong.write_text(
        (MAPPINGS / "unitree_sdk_csv.toml").read_text().replace("tau_est_{i}", "tau_{i}")
    )
    code = main(["analyze-log", str(logs[1]), "--robot", "go1", "--mapping", str(wrong)])
    err = capsys.readouterr().err
    assert code == 2 and "row 1, column tau_0: missing from the header" in err, err
    assert "did you mean 'tau_est_0'" in err


def test_a_joint_named_twice_in_a_joint_state_bag_is_refused(trot, tmp_path):

    _, (t, q, dq, tau, _) = trot
    names = list(UNITREE_ORDER)
    names[3] = names[0]
    bag = joint_state_bag(tmp_path / "twice.mcap", names, t, q, dq, tau)
    with pytest.raises(LogError, match="named twice"):
        analyze_robot_log(bag, "go1", mapping="joint_state")
    from scalf_opt.api import analyze_log

    with pytest.raises(LogError, match="message 0: joint 'FR_hip_joint' is named twice"):
        analyze_log(bag, "go1")  # the sagittal reader too


def test_mapping_tables_check_their_fields():
    table = {
        "source": "csv",
        "time": "t",
        "joints": ["a"],
        "position": "q",
        "effort": "e",
        "foot_force": "f_{i}",
    }
    with pytest.raises(ConfigError, match="fields foot_force and feet go together"):
        mapping_from_dict(table, "m")
    with pytest.raises(ConfigError, match="'XX' is not a leg"):
        mapping_from_dict({**table, "feet": ["XX"]}, "m")


def test_a_joint_state_bag_counts_every_joint_with_its_mapping(trot, tmp_path, capsys):
    """The same joints as JointState: the sagittal route says what it leaves out, the mapping
    ``joint_state`` counts every joint, and the two agree on the hip pitch and knee."""

    _, (t, q, dq, tau, _) = trot
    bag = joint_state_bag(tmp_path / "js.mcap", UNITREE_ORDER, t, q, dq, tau)
    assert main(["analyze-log", str(bag), "--robot", "go1"]) == 0
    out = capsys.readouterr().out
    assert "the joint angles' self-similarity" in out
    assert "average power of the hip pitch and knee joints (4 legs; every joint with " in out
    assert main(["analyze-log", str(bag), "--robot", "go1", "--json"]) == 0
    sagittal = json.loads(capsys.readouterr().out)
    assert sagittal["velocity_source"] == "measured" and sagittal["filter"] is None
    every = analyze_robot_log(bag, "go1", mapping="joint_state").analysis
    assert len(every.joints) == 12
    modelled = sum(j.cycle_j / every.legs[j.leg].period_s for j in every.joints if j.modelled)
    assert modelled == pytest.approx(sagittal["average_power_w"], rel=0.01)


def test_a_sqlite3_bag_and_the_older_unitree_messages(trot, tmp_path):
    """``unitree_legged_msgs/msg/LowState`` (camelCase fields) in an sqlite3 bag that stores its
    message definitions: recognised by its type, read through the built-in mapping."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    _, (t, q, dq, tau, force) = trot
    store = get_typestore(Stores.EMPTY)
    store.register(
        get_types_from_msg(
            "uint8 mode\nfloat32 q\nfloat32 dq\nfloat32 ddq\nfloat32 tauEst\n",
            "unitree_legged_msgs/msg/MotorState",
        )
    )
    store.register(
        get_types_from_msg(
            "uint8 levelFlag\nMotorState[20] motorState\nint16[4] footForce\nuint32 tick\n",
            "unitree_legged_msgs/msg/LowState",
        )
    )
    motor = store.types["unitree_legged_msgs/msg/MotorState"]
    low = store.types["unitree_legged_msgs/msg/LowState"]
    folder = tmp_path / "legacy"
    with Writer(folder, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        conn = writer.add_connection("/low_state", low.__msgtype__, typestore=store)
        for k, tk in enumerate(t):
            motors = [
                motor(
                    10,
                    *(float(a[j, k]) if j < 12 else 0.0 for a in (q, dq)),
                    0.0,
                    float(tau[j, k]) if j < 12 else 0.0,
                )
                for j in range(20)
            ]
            msg = low(0, motors, force[:, k].astype(np.int16), k)
            writer.write(conn, round((100.0 + tk) * 1e9), store.serialize_cdr(msg, low.__msgtype__))
    result = analyze_robot_log(folder, "go1")
    assert result.mapping == "unitree_legged_msgs"
    reference = analyze_robot_log(
        write_lowstate_bag(tmp_path / "new.mcap", t, q, dq, tau, force), "go1"
    )
    for new, old in zip(reference.analysis.joints, result.analysis.joints, strict=True):
        # 1e-6, not 1e-9: the MCAP writer above stamps 2026's epoch plus t in doubles, a grid of
        # a quarter microsecond (2e-8 here); the reader keeps integer nanoseconds
        assert old.cycle_j == pytest.approx(new.cycle_j, rel=1e-6)


def test_ranges_and_gaps_are_warned(trot, tmp_path):
    _, (t, q, dq, tau, force) = trot
    shifted = q.copy()
    shifted[2] -= 1.5  # FR_calf_joint 1.5 rad off: another zero, or another robot
    late = t.copy()
    late[300:] += 0.05  # 50 ms without a message
    bag = write_lowstate_bag(tmp_path / "odd.mcap", late, shifted, dq, tau, force)
    notes = analyze_robot_log(bag, "go1").analysis.notes
    assert any(
        n.startswith("warning: FR_calf_joint reaches") and "beyond its URDF range" in n
        for n in notes
    ), notes
    assert any(
        n.startswith("1 gap(s) in the time stamps") and "the longest 52 ms" in n for n in notes
    ), notes


def test_the_torques_hold_up_the_robots_weight(trot, logs, tmp_path):
    """The plan's torques, turned back into foot forces by the URDF's Jacobians, carry the
    robot's weight over a cycle (2 %: the legs' inertia is left out of the estimate); torques in
    other units (here twice) are warned."""
    from scalf_opt.logs.contacts import carried_mass_kg

    result = analyze_robot_log(logs[0], "go1")
    go1 = result.robot
    line = next(n for n in result.analysis.notes if "hold up" in n)
    assert not line.startswith("warning") and line.endswith(
        f"go1 weighs {go1.total_mass_kg:.3g} kg"
    )
    from scalf_opt.logs.contacts import log_contacts
    from scalf_opt.logs.mapping import BUILT_IN as MAPPINGS_BUILT_IN
    from scalf_opt.logs.robot_log import robot_log
    from scalf_opt.logs.robot_sources import bag_series

    log = robot_log(bag_series(logs[0], MAPPINGS_BUILT_IN["unitree_go"], None), go1)
    carried = carried_mass_kg(log, go1, log_contacts(log, go1).stance)
    assert carried == pytest.approx(go1.total_mass_kg, rel=0.02)
    _, (t, q, dq, tau, force) = trot
    bag = write_lowstate_bag(tmp_path / "double.mcap", t, q, dq, 2 * tau, force)
    notes = analyze_robot_log(bag, "go1").analysis.notes
    assert any(n.startswith("warning: the joint torques hold up 2") for n in notes), notes


def test_a_log_without_the_abduction_is_read_and_says_so(trot, tmp_path):
    """A plan's export holds the hip pitch and knee only: read, the missing joints named; a log
    without a knee is refused."""

    _, (t, q, dq, tau, _) = trot
    keep = [k for k, j in enumerate(UNITREE_ORDER) if not j.endswith("_hip_joint")]
    bag = joint_state_bag(tmp_path / "sagittal.mcap", UNITREE_ORDER, t, q, dq, tau, keep)
    analysis = analyze_robot_log(bag, "go1", mapping="joint_state").analysis
    assert len(analysis.joints) == 8 and analysis.left_out_share == 0.0
    assert any(
        n.startswith("warning: 4 leg joint(s) of go1 are not in the log") and "FR_hip_joint" in n
        for n in analysis.notes
    )
    keep = [k for k, j in enumerate(UNITREE_ORDER) if j != "RL_calf_joint"]
    bag = joint_state_bag(tmp_path / "kneeless.mcap", UNITREE_ORDER, t, q, dq, tau, keep)
    with pytest.raises(LogError, match="leg LH's joint 'RL_calf_joint' is not in the log"):
        analyze_robot_log(bag, "go1", mapping="joint_state")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda t: t.__setitem__(50, t[49] + 2e-6), r"row 52, column time_ms: .* closer than the"),
        (lambda t: t.__setitem__(50, t[49]), r"row 52, column time_ms: .* does not increase"),
        (lambda t: t.__setitem__(slice(60, None), t[60:] + 68 * 3.156e7), r"beyond the 1e\+07 s"),
    ],
)
def test_times_too_close_or_too_far_are_refused_in_every_reader(trot, tmp_path, change, message):
    """The 10 us step and the 116-day span of the cylinder CSV hold for a robot's CSV, its bags
    and the sagittal reader of a JointState bag."""
    from scalf_opt.api import analyze_log

    _, (t, q, dq, tau, force) = trot
    t = t.copy()
    change(t)
    table = write_sdk_csv(tmp_path / "sdk.csv", t, q, dq, tau, force)
    with pytest.raises(LogError, match=message):
        analyze_robot_log(table, "go1", mapping=MAPPINGS / "unitree_sdk_csv.toml")
    bag_message = message.replace("row 52, column time_ms", "message 50")
    bag = joint_state_bag(tmp_path / "js.mcap", UNITREE_ORDER, t, q, dq, tau)
    with pytest.raises(LogError, match=bag_message):
        analyze_robot_log(bag, "go1", mapping="joint_state")
    with pytest.raises(LogError, match=bag_message):
        analyze_log(bag, "go1")


def test_a_bag_whose_topic_has_no_name_is_refused(trot, tmp_path):
    """A bag folder whose metadata names a topic null: one line from every reader."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    from scalf_opt.api import analyze_log

    _, (_, q, dq, tau, _) = trot
    q, dq, tau = (np.ascontiguousarray(a.T) for a in (q, dq, tau))  # a row per instant
    store = get_typestore(Stores.ROS2_HUMBLE)
    state = store.types["sensor_msgs/msg/JointState"]
    header, stamp = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    folder = tmp_path / "nameless"
    with Writer(folder, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        conn = writer.add_connection("/joint_states", state.__msgtype__, typestore=store)
        for k in range(5):
            msg = state(header(stamp(1 + k, 0), "b"), list(UNITREE_ORDER), q[k], dq[k], tau[k])
            writer.write(conn, (1 + k) * 10**9, store.serialize_cdr(msg, state.__msgtype__))
    metadata = folder / "metadata.yaml"
    text = metadata.read_text()
    assert "name: /joint_states" in text
    metadata.write_text(text.replace("name: /joint_states", "name: null"))
    for call in (
        lambda: analyze_log(folder, "go1"),
        lambda: analyze_robot_log(folder, "go1", mapping="joint_state"),
    ):
        with pytest.raises(
            LogError, match="a topic of sensor_msgs/msg/JointState messages has no name"
        ):
            call()

"""``read_plan``: a saved 3-D cycle read back as the very plan it was written from.

The plan is Go1's kinematic start (no solve: the files hold data, not an optimum) with the trunk
rolled, pitched and yawed on smooth periodic sines, so the quaternion and angular-velocity
conversions are exercised away from zero. Its footholds are set where Pinocchio's own
``framesForwardKinematics`` puts each foot at its touch-down node (the trunk's orientation from
Pinocchio's ``rpyToMatrix``, not the package's), as the optimizer's stance rows make them.
"""

import csv
import json
import math
import shutil
from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.errors import ConfigError
from scalf_opt.io.whole_body_export import read_plan, write_cycle
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize.whole_body_nlp import CycleProblem, kinematic_start
from scalf_opt.robots.loading import load_robot
from scalf_opt.types import LEG_NAMES

RTOL = 1e-9
"""Relative tolerance of the round trip (the CSV holds ``repr`` floats: measured ~1e-15)."""

TILTS = {
    # (offset, amplitude, harmonic, phase) of roll, pitch, yaw [rad]
    "tilted": ((0.05, 0.25, 1, 0.3), (-0.1, 0.3, 2, 1.1), (0.2, 0.4, 1, 2.0)),
    # pitch up to 77 deg: E(rpy) is ill-conditioned (1 / cos(pitch) = 4.5) near the 80 deg limit
    "steep": ((-0.2, 0.3, 2, 0.0), (1.2, 0.15, 1, 0.7), (-0.3, 0.5, 1, 0.4)),
}


@pytest.fixture(scope="module")
def physics():
    return WholeBodyPhysics.of(load_robot("go1"))


def tilted_plan(physics, tilts):
    """The kinematic start of a flying trot with the trunk's roll, pitch and yaw on sines."""
    gait = default_gait_for(physics.robot)
    schedule = trot_schedule(gait.period_s, 0.4, 50.0)
    problem = CycleProblem(
        physics, schedule, gait.speed_m_s, gait.stance_height_m, gait.clearance_m
    )
    start = kinematic_start(problem)
    x, xd, xdd = start.x.copy(), start.xd.copy(), start.xdd.copy()
    omega = 2 * np.pi / schedule.period_s
    t = schedule.times_s
    for r, (offset, amplitude, harmonic, phase) in enumerate(tilts):
        w = harmonic * omega
        x[3 + r] += offset + amplitude * np.sin(w * t + phase)
        xd[3 + r] += amplitude * w * np.cos(w * t + phase)
        xdd[3 + r] -= amplitude * w**2 * np.sin(w * t + phase)
    # and a lateral sway
    x[1] += 0.01 * np.sin(omega * t)
    xd[1] += 0.01 * omega * np.cos(omega * t)
    xdd[1] -= 0.01 * omega**2 * np.sin(omega * t)
    plan = replace(start, x=x, xd=xd, xdd=xdd)
    return replace(plan, footholds_m=pinocchio_footholds(plan))


def pinocchio_footholds(plan):
    """Each foot's (x, y) at its touch-down node, by Pinocchio alone (2, 4) [m]."""
    model = plan.physics.model
    data = model.createData()
    holds = np.zeros((2, len(LEG_NAMES)))
    for i, leg in enumerate(LEG_NAMES):
        k = plan.schedule.touchdown_node(leg)
        rotation = pin.rpy.rpyToMatrix(*plan.x[3:6, k])
        quat = pin.Quaternion(rotation).coeffs()  # (x, y, z, w)
        q = np.concatenate([plan.x[:3, k], quat, plan.x[6:, k]])
        pin.framesForwardKinematics(model, data, q)
        holds[:, i] = data.oMf[model.getFrameId(plan.physics.feet[i])].translation[:2]
    return holds


def summary_of(plan):
    schedule = plan.schedule
    return {
        "model": "3d",
        "robot": plan.physics.robot.name,
        "period_s": schedule.period_s,
        "duty_cycle": schedule.duty_cycle,
        "speed_m_s": plan.speed_m_s,
        "nodes": schedule.intervals,
        "accounting": "paper",
    }


@pytest.fixture(scope="module", params=sorted(TILTS))
def written(request, physics, tmp_path_factory):
    plan = tilted_plan(physics, TILTS[request.param])
    out = tmp_path_factory.mktemp(f"cycle_{request.param}")
    write_cycle(out, summary_of(plan), plan, "paper")
    return out, plan


def assert_rows_close(got, want, name):
    """Each row within RTOL of its own largest magnitude (rows through zero are not relative)."""
    assert got.shape == want.shape, name
    scale = np.maximum(np.abs(want).max(axis=1, keepdims=True), 1e-300)
    error = float((np.abs(got - want) / scale).max())
    assert error <= RTOL, f"{name}: relative error {error:.3g}"


def test_the_saved_cycle_reads_back_as_the_plan_it_was_written_from(written, physics):
    out, plan = written
    # the trunk really turns: each angle sweeps 0.2 rad or more, each rate reaches 1 rad/s
    assert np.ptp(plan.x[3:6], axis=1).min() > 0.2 and np.abs(plan.xd[3:6]).max(axis=1).min() > 1
    got = read_plan(out, physics)
    assert got.physics is physics
    assert got.schedule == plan.schedule and got.speed_m_s == plan.speed_m_s
    for name in ("x", "xd", "xdd", "forces_n", "footholds_m"):
        assert_rows_close(getattr(got, name), getattr(plan, name), name)
    # the forces and the joints' and trunk position's columns are copied, bit for bit
    np.testing.assert_array_equal(got.forces_n, plan.forces_n)
    np.testing.assert_array_equal(got.x[6:], plan.x[6:])
    np.testing.assert_array_equal(got.xdd[:3], plan.xdd[:3])
    energy = plan.evaluate("paper").total_j
    assert got.evaluate("paper").total_j == pytest.approx(energy, rel=RTOL)
    slip, got_slip = plan.check("paper").stance_slip_m, got.check("paper").stance_slip_m
    assert got_slip == pytest.approx(slip, rel=RTOL, abs=1e-12)


def test_the_quaternions_sign_does_not_matter(written, physics, tmp_path):
    out, plan = written
    copy = copied(out, tmp_path)
    columns = read_columns(copy)
    for axis in "xyzw":
        columns[f"base_quat_{axis}"] = [-v for v in columns[f"base_quat_{axis}"]]
    write_columns(copy, columns)
    got = read_plan(copy, physics)
    for name in ("x", "xd", "xdd", "footholds_m"):
        assert_rows_close(getattr(got, name), getattr(plan, name), name)


def test_node_times_within_a_nanosecond_are_the_nodes(written, physics, tmp_path):
    out, plan = written
    copy = copied(out, tmp_path)
    columns = read_columns(copy)
    columns["t_s"][3] += 0.9e-9
    write_columns(copy, columns)
    assert read_plan(copy, physics).schedule == plan.schedule


def test_a_denser_reading_is_read_back_and_read_the_same(physics, tmp_path):
    """A cycle the driver read at eight points per interval keeps that reading (its energy is
    the one the optimizer saw); one saved without the field is read at the default four."""
    plan = tilted_plan(physics, TILTS["tilted"])
    dense = replace(plan, schedule=replace(plan.schedule, reads_per_interval=8))
    summary = {**summary_of(dense), "reads_per_interval": 8}
    write_cycle(tmp_path, summary, dense, "paper")
    got = read_plan(tmp_path, physics)
    assert got.schedule == dense.schedule and got.schedule.reads_per_interval == 8
    energy = dense.evaluate("paper").total_j
    assert got.evaluate("paper").total_j == pytest.approx(energy, rel=RTOL)
    assert energy != pytest.approx(plan.evaluate("paper").total_j, rel=1e-6)  # it is another rule


# --- the errors: one line naming the file and the field ------------------------------------------


def copied(out, tmp_path):
    copy = tmp_path / "cycle"
    shutil.copytree(out, copy)
    return copy


def read_columns(directory):
    with (directory / "plan.csv").open(newline="") as handle:
        rows = list(csv.reader(handle))
    return {name: [float(r[c]) for r in rows[1:]] for c, name in enumerate(rows[0])}


def write_columns(directory, columns):
    with (directory / "plan.csv").open("w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(columns)
        for row in zip(*columns.values(), strict=True):
            writer.writerow([repr(v) for v in row])


def edit_summary(**changes):
    def edit(directory, physics):
        path = directory / "summary.json"
        summary = json.loads(path.read_text())
        for key, value in changes.items():
            if value is DELETE:
                del summary[key]
            else:
                summary[key] = value
        path.write_text(json.dumps(summary))

    return edit


def edit_columns(change):
    def edit(directory, physics):
        columns = read_columns(directory)
        change(columns, physics)
        write_columns(directory, columns)

    return edit


DELETE = object()


def drop_last_row(columns, physics):
    for values in columns.values():
        values.pop()


def shift_time(columns, physics):
    columns["t_s"][4] += 2e-9


def drop(name):
    def change(columns, physics):
        del columns[name.format(joint=physics.joint_names[4], foot=physics.feet[2])]

    return change


def pitch_row(degrees):
    def change(columns, physics):
        quat = pin.Quaternion(pin.rpy.rpyToMatrix(0.1, math.radians(degrees), -0.2)).coeffs()
        for axis, value in zip("xyzw", quat, strict=True):
            columns[f"base_quat_{axis}"][2] = float(value)

    return change


def scale_quaternion(columns, physics):
    for axis in "xyzw":
        columns[f"base_quat_{axis}"][5] *= 1.01


ERRORS = {
    "another robot": (edit_summary(robot="hyq"), "summary.json", ["robot 'hyq'", "'go1'"]),
    "no robot": (edit_summary(robot=DELETE), "summary.json", ["robot None"]),
    "a row short": (edit_columns(drop_last_row), "plan.csv", ["rows", "nodes"]),
    "off the node times": (edit_columns(shift_time), "plan.csv", ["t_s in row 5"]),
    "no joint angle": (edit_columns(drop("{joint}_q_rad")), "plan.csv", ["FR_thigh_joint_q_rad"]),
    "no joint acceleration": (
        edit_columns(drop("{joint}_a_rad_s2")),
        "plan.csv",
        ["FR_thigh_joint_a_rad_s2"],
    ),
    "no foot force": (edit_columns(drop("{foot}_force_y_n")), "plan.csv", ["FL_foot_force_y_n"]),
    "no trunk rate": (
        edit_columns(drop("base_ang_acc_z_rad_s2")),
        "plan.csv",
        ["base_ang_acc_z_rad_s2"],
    ),
    "steep pitch": (edit_columns(pitch_row(81.0)), "plan.csv", ["base_quat", "row 3", "81.0 deg"]),
    "no unit quaternion": (edit_columns(scale_quaternion), "plan.csv", ["base_quat", "norm"]),
    "duty off the nodes": (edit_summary(duty_cycle=0.43), "summary.json", ["duty_cycle 0.43"]),
    "nodes not whole": (edit_summary(nodes=17.5), "summary.json", ["nodes 17.5"]),
    **{
        f"reads_per_interval {value!r}": (
            edit_summary(reads_per_interval=value),
            "summary.json",
            [f"reads_per_interval {float(value)!r}", "even whole number from 2 to 64"],
        )
        for value in (3, 0, 128, 6.5)
    },
    "reads_per_interval text": (
        edit_summary(reads_per_interval="8"),
        "summary.json",
        ["reads_per_interval", "not a number"],
    ),
    **{
        f"no {key}": (edit_summary(**{key: DELETE}), "summary.json", [f"no field '{key}'"])
        for key in ("period_s", "duty_cycle", "nodes", "speed_m_s")
    },
    **{
        f"{key} {value!r}": (edit_summary(**{key: value}), "summary.json", [key, "not a number"])
        for key, value in (
            ("period_s", "0.35"),
            ("duty_cycle", None),
            ("nodes", True),
            ("speed_m_s", [0.5]),
        )
    },
}


@pytest.fixture(scope="module")
def tilted_dir(physics, tmp_path_factory):
    plan = tilted_plan(physics, TILTS["tilted"])
    out = tmp_path_factory.mktemp("cycle_errors")
    write_cycle(out, summary_of(plan), plan, "paper")
    return out


@pytest.mark.parametrize("case", list(ERRORS))
def test_a_broken_file_is_named_in_one_line(case, tilted_dir, physics, tmp_path):
    edit, file_name, words = ERRORS[case]
    copy = copied(tilted_dir, tmp_path)
    edit(copy, physics)
    with pytest.raises(ConfigError) as info:
        read_plan(copy, physics)
    message = str(info.value)
    assert info.value.field == "from"
    assert "\n" not in message
    assert message.startswith(f"{copy / file_name}: "), message
    for word in words:
        assert word in message, message


def test_a_pitch_just_inside_the_limit_is_read(tilted_dir, physics, tmp_path):
    copy = copied(tilted_dir, tmp_path)
    edit_columns(pitch_row(79.0))(copy, physics)
    assert read_plan(copy, physics).x[4, 2] == pytest.approx(math.radians(79.0), abs=1e-12)

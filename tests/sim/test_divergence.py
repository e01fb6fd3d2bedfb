"""A run whose integration MuJoCo found diverged is stopped there and is never a verdict.

MuJoCo does not stop a run whose state goes bad: it resets the robot to its initial pose and only
counts a warning (:mod:`scalf_opt.sim.divergence`). Each referee is made to diverge at a known
step, cheaply (two cycles, the run stopping early): the sagittal one by an enormous push on the
trunk for one step (MuJoCo's bad accelerations), the 3-D one by a controller that returns NaN
torques once (MuJoCo's bad controls). Each must stop at that step, say so in its file, its report
and its verdict, and an ensemble member that diverged must make the plan not refereeable.
"""

import json
from dataclasses import replace

import mujoco
import numpy as np
import pytest

from scalf_opt.api import simulate, simulate_3d
from scalf_opt.sim import run as sagittal_run
from scalf_opt.sim.divergence import clear_divergence, divergence
from scalf_opt.sim.ensemble import NOMINAL, MemberResult, Perturbation, ensemble_verdict
from scalf_opt.sim.report import energy_goal_line, ensemble_lines
from scalf_opt.sim.whole_body_control import WholeBodyController
from scalf_opt.types import LEG_NAMES
from scalf_opt.viz.plotting import close

PENDULUM = """<mujoco><worldbody><body><joint name="j"/><geom size=".1" pos=".2 0 0"/>
</body></worldbody><actuator><motor joint="j"/></actuator></mujoco>"""


def _spoil_velocity(data):
    data.qvel[0] = 1e30


def _spoil_position(data):
    data.qpos[0] = np.nan


def _push(data):
    data.xfrc_applied[1, 1] = 1e30


def _spoil_torque(data):
    data.ctrl[0] = np.nan


@pytest.mark.parametrize(
    "spoil, words",
    [
        (_spoil_velocity, "bad velocities, MuJoCo's BADQVEL"),
        (_spoil_position, "bad positions, MuJoCo's BADQPOS"),
        (_push, "bad accelerations, MuJoCo's BADQACC"),
        (_spoil_torque, "torques NaN or huge, MuJoCo's BADCTRL"),
    ],
)
def test_each_of_mujocos_checks_is_read(spoil, words):
    model = mujoco.MjModel.from_xml_string(PENDULUM)
    data = mujoco.MjData(model)
    data.qpos[0], data.qvel[0] = 0.3, 1.0
    mujoco.mj_step(model, data)
    assert divergence(data) is None
    spoil(data)
    mujoco.mj_step(model, data)
    assert divergence(data) == words
    clear_divergence(data)
    assert divergence(data) is None


PUSH_STEP = 700
"""The sagittal run's step the push diverges (0.35 s at SCalf's 0.5 ms: within the second
cycle, after the start-up)."""


def _assert_figure_marks(fig, panels, at_s, warning):
    """``simulation.png`` marks the divergence as it marks a fall: a line at ``at_s`` on each of
    its first ``panels`` panels (those over time), the warning named on the first."""
    try:
        for ax in fig.axes[:panels]:
            assert any(np.allclose(line.get_xdata(), at_s) for line in ax.lines), ax.get_ylabel()
        assert any(
            f"MuJoCo diverged at {at_s:.3f} s" in t.get_text() and warning in t.get_text()
            for t in fig.axes[0].texts
        )
        fig.canvas.draw()  # the NaN samples after the divergence drawn without an error
    finally:
        close(fig)


def _member(name, diff):
    energy = {leg: 100.0 * (1 + diff) for leg in LEG_NAMES}
    return MemberResult(Perturbation(name), dict.fromkeys(LEG_NAMES, diff), energy, diff, None, 0.0)


def test_the_sagittal_referee_stops_where_mujoco_diverged(monkeypatch, tmp_path):
    record_contacts = sagittal_run._record_contacts

    def pushed(sim, data, foot_leg, k, *rest):
        record_contacts(sim, data, foot_leg, k, *rest)
        if k == PUSH_STEP - 1:  # an enormous push on the trunk over the next step
            data.xfrc_applied[sim.model.body("trunk").id, 2] = 1e30

    monkeypatch.setattr(sagittal_run, "_record_contacts", pushed)
    result = simulate("scalf", cycles=2, ensemble=False)
    data, record = result.data, result.record
    at = float(record.t_s[PUSH_STEP])
    assert record.diverged_at_s == at == data["diverged_at_s"]
    assert data["divergence"] == record.divergence == "bad accelerations, MuJoCo's BADQACC"
    # the record holds the run up to the step MuJoCo flagged, nothing after it: MuJoCo had put
    # the robot back at its initial pose
    before, after = slice(0, PUSH_STEP), slice(PUSH_STEP, None)
    for leg in LEG_NAMES:
        for values in (record.q_rad, record.qd_rad_s, record.tau_nm, record.grf_n):
            assert np.isfinite(values[leg][:, before]).all()
            assert np.isnan(values[leg][:, after]).all()
    assert np.abs(record.trunk[1, before] - record.start_trunk_height_m).max() < 0.01
    assert np.isnan(record.trunk[:, after]).all()
    # no verdict: not met, and why, in words
    assert not data["goals"]["joint_energy_met"]
    assert energy_goal_line(data).endswith(
        f"NOT met (MuJoCo's integration diverged at t = {at:.3f} s "
        "(bad accelerations, MuJoCo's BADQACC))"
    )
    result.write(tmp_path)
    written = json.loads((tmp_path / "simulation.json").read_text())
    assert written["diverged_at_s"] == at and "BADQACC" in written["divergence"]
    assert written["joint_energy_per_cycle_j"]["RF"]["simulated"] is None  # nothing measured
    assert "MuJoCo's integration diverged at t = 0.350 s" in (tmp_path / "report.txt").read_text()
    _assert_figure_marks(result.figure(), 3, at, "BADQACC")

    # as an ensemble's member: the plan is not refereeable, the member named; the medians are
    # the members' that measured
    members = [MemberResult.of(NOMINAL, data), *(_member(f"m{i}", 0.01 * i) for i in range(3))]
    verdict = ensemble_verdict(data, members, 0.05)
    assert verdict["ensemble"]["members"][0]["diverged_at_s"] == at
    assert not verdict["goals"]["refereeable"] and not verdict["goals"]["joint_energy_met"]
    assert verdict["ensemble"]["diverged"] == ["nominal"] and verdict["ensemble"]["fell"] == []
    assert verdict["joint_energy_per_cycle_j"]["RF"]["relative_difference"] == 0.01
    assert energy_goal_line(verdict).endswith(
        "NOT refereeable (MuJoCo's integration diverged under: nominal)"
    )
    assert ensemble_lines(verdict)[3].endswith(
        f"diverged at {at:.3f} s (bad accelerations, MuJoCo's BADQACC)"
    )


def test_a_member_that_diverged_and_one_that_fell_are_both_named():
    members = [
        _member("a", 0.0),
        replace(_member("b", 0.01), diverged_at_s=0.5, divergence="bad velocities"),
        replace(_member("c", 0.02), fell_at_s=1.0),
    ]
    nominal = {
        "joint_energy_per_cycle_j": {
            leg: {"simulated": 100.0, "model": 100.0, "relative_difference": 0.0}
            for leg in LEG_NAMES
        },
        "total_energy_per_cycle_j": {"simulated": 400.0, "model": 400.0, "relative_difference": 0},
        "goals": {"joint_energy_relative_difference_at_most": 0.05, "joint_energy_met": True},
    }
    verdict = ensemble_verdict(nominal, members, 0.05)
    assert not verdict["goals"]["refereeable"]
    assert energy_goal_line(verdict).endswith(
        "NOT refereeable (MuJoCo's integration diverged under: b; the robot fell under: c)"
    )


NAN_STEP = 500
"""The 3-D run's step whose torques the controller returns NaN (0.25 s at Go1's 0.5 ms)."""


def test_the_3d_referee_stops_where_mujoco_diverged(monkeypatch, tmp_path):
    torques = WholeBodyController.torques
    calls = []

    def spoiled(self, *args):
        out = torques(self, *args)
        calls.append(None)
        if len(calls) == NAN_STEP + 1:
            return replace(out, tau_nm=np.full_like(out.tau_nm, np.nan))
        return out

    monkeypatch.setattr(WholeBodyController, "torques", spoiled)
    result = simulate_3d("go1", cycles=2, ensemble=False)
    data, record = result.data, result.record
    at = NAN_STEP * record.timestep_s
    # the record stops before the step MuJoCo flagged, the run with it
    assert record.t_s.size == NAN_STEP == len(calls) - 1
    assert record.diverged_at_s == pytest.approx(at, abs=1e-12) and record.fell_at_s is None
    assert data["divergence"] == "torques NaN or huge, MuJoCo's BADCTRL"
    assert data["goals"]["did_not_diverge"] is False and not data["goals"]["joint_energy_met"]
    assert energy_goal_line(data).endswith(
        f"NOT met (MuJoCo's integration diverged at t = {at:.3f} s "
        "(torques NaN or huge, MuJoCo's BADCTRL))"
    )
    result.write(tmp_path)
    written = json.loads((tmp_path / "simulation.json").read_text())
    assert written["diverged_at_s"] == pytest.approx(at, abs=1e-12)
    assert "BADCTRL" in written["divergence"]
    assert "MuJoCo's integration diverged at t = 0.250 s" in (tmp_path / "report.txt").read_text()
    _assert_figure_marks(result.figure(), 4, at, "BADCTRL")

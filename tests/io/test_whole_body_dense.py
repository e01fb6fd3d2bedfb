"""``export --from`` a 3-D cycle: the plan at any rate over several cycles, re-checked against
Pinocchio's own inverse dynamics at every instant (not only at the nodes)."""

import csv

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.cli import main
from tests.optimize.whole_body_checks import forces_as_fext, free_flyer_model

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group(name="whole_body_cycle")]


@pytest.fixture(scope="module")
def saved(go1_cycle, tmp_path_factory):
    from scalf_opt.io.whole_body_export import write_cycle

    problem, solution = go1_cycle
    folder = tmp_path_factory.mktemp("cycle")
    summary = {
        "model": "3d",
        "robot": "go1",
        "period_s": problem.schedule.period_s,
        "duty_cycle": problem.schedule.duty_cycle,
        "nodes": problem.schedule.intervals,
        "speed_m_s": problem.speed_m_s,
        "accounting": "paper",
    }
    write_cycle(folder, summary, solution.plan, "paper")
    return problem, solution.plan, folder


def _table(path):
    rows = list(csv.DictReader(path.open()))
    return {c: np.array([float(r[c]) for r in rows]) for c in rows[0]}


def test_the_dense_export_is_the_plan_pinocchio_recomputes_at_every_instant(saved, tmp_path):
    problem, plan, folder = saved
    out = tmp_path / "dense.csv"
    code = main(
        ["export", "--from", str(folder), "--rate", "300", "--cycles", "2", "--out", str(out)]
    )
    assert code == 0
    table = _table(out)
    nodes = _table(folder / "plan.csv")
    assert set(table) == set(nodes)
    per_cycle = len(table["t_s"]) // 2
    step = per_cycle // problem.schedule.intervals
    assert per_cycle == step * problem.schedule.intervals and step >= 2
    # every node's row is plan.csv's row; the second cycle one stride ahead, else the same
    for name, values in nodes.items():
        if name in ("t_s", "base_pos_x_m"):
            continue
        np.testing.assert_allclose(table[name][:per_cycle:step], values, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(table[name][per_cycle:], table[name][:per_cycle])
    np.testing.assert_allclose(
        table["base_pos_x_m"][per_cycle:] - table["base_pos_x_m"][:per_cycle], plan.stride_m
    )
    np.testing.assert_allclose(np.diff(table["t_s"]), plan.schedule.period_s / per_cycle)
    # between the nodes too: Pinocchio's rnea with the exported forces gives the exported torques
    physics = problem.physics
    model = free_flyer_model(physics)
    data = model.createData()
    joints = [model.names[j] for j in range(2, model.njoints)]
    scale = max(np.abs(table[f"{j}_tau_nm"]).max() for j in joints)
    for k in range(1, per_cycle, 3):
        row = {c: v[k] for c, v in table.items()}
        quat = np.array([row[f"base_quat_{a}"] for a in "xyzw"])
        rot = pin.Quaternion(quat[3], *quat[:3]).toRotationMatrix()
        body_vel = rot.T @ np.array([row[f"base_lin_vel_{a}_m_s"] for a in "xyz"])
        body_ang = rot.T @ np.array([row[f"base_ang_vel_{a}_rad_s"] for a in "xyz"])
        lin_acc = np.array([row[f"base_lin_acc_{a}_m_s2"] for a in "xyz"])
        ang_acc = np.array([row[f"base_ang_acc_{a}_rad_s2"] for a in "xyz"])
        q = np.concatenate(
            [[row[f"base_pos_{a}_m"] for a in "xyz"], quat, [row[f"{j}_q_rad"] for j in joints]]
        )
        v = np.concatenate([body_vel, body_ang, [row[f"{j}_v_rad_s"] for j in joints]])
        a = np.concatenate(
            [
                rot.T @ lin_acc - np.cross(body_ang, body_vel),
                rot.T @ ang_acc,
                [row[f"{j}_a_rad_s2"] for j in joints],
            ]
        )
        forces = np.array([row[f"{f}_force_{a}_n"] for f in physics.feet for a in "xyz"])
        tau = pin.rnea(model, data, q, v, a, forces_as_fext(model, data, q, forces, physics.feet))
        np.testing.assert_allclose(
            tau[6:], [row[f"{j}_tau_nm"] for j in joints], rtol=0, atol=1e-9 * scale
        )


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--out", "x.mcap"], "a 3-D cycle is exported to .csv or .json"),
    ],
)
def test_a_3d_export_refuses_a_bag(saved, tmp_path, capsys, argv, message):
    _, _, folder = saved
    argv = [a.replace("x.mcap", str(tmp_path / "x.mcap")) for a in argv]
    assert main(["export", "--from", str(folder), "--rate", "100", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_a_sagittal_folder_is_not_a_3d_cycle(tmp_path, capsys):
    (tmp_path / "summary.json").write_text('{"model": "sagittal"}')
    code = main(
        [
            "export",
            "--model",
            "3d",
            "--from",
            str(tmp_path),
            "--rate",
            "100",
            "--out",
            str(tmp_path / "o.csv"),
        ]
    )
    assert code == 2
    assert "not a 3-D cycle" in capsys.readouterr().err

"""``view --from DIR`` of a 3-D cycle: the whole robot walking its plan, checked independently.

The cycles are kinematic, no NLP solved: the kinematic start trot (:func:`starting_plan`) with its
trunk made to roll, pitch and yaw (up to 7 degrees) and every joint re-solved here by Pinocchio's
inverse kinematics so that the feet stay where the start put them at every node, written as
``optimize --model 3d --out`` writes a cycle (:func:`write_cycle`) and read back as ``view`` reads
it. Go1 (knees bent backwards) and Solo12 (front knees forwards, hind knees backwards).

The checks use a fresh free-flyer Pinocchio model of the URDF and the plan's own Pinocchio state
(its quaternion, not the view's roll-pitch-yaw matrix): the drawn foot paths and the animated feet
are where that model puts the feet; at every stance node a foot is on the ground at its foothold;
the trunk's pose in the page is the plan's.
"""

import base64
import json
import re

import numpy as np
import pinocchio as pin
import pytest
import umsgpack
from matplotlib import image

from scalf_opt.cli import main
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.io.whole_body_export import read_cycle, read_plan, write_cycle
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.periodic_spline import fit
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize.whole_body_start import starting_plan
from scalf_opt.types import LEG_NAMES
from scalf_opt.viz.browser import render_page
from scalf_opt.viz.html import scene_page
from scalf_opt.viz.scene import SceneOptions
from scalf_opt.viz.visuals import load_visuals
from scalf_opt.viz.whole_body_walk import ShownPlan, WholeBodyWalk, build_plan_scene
from tests.viz.test_view import (
    MIN_CHANGED_SHARE,
    PIXEL_TOLERANCE,
    needs_chromium,
    one_chromium_at_a_time,
)

ROBOTS = ("go1", "solo12")
ROLL, PITCH, YAW = 0.12, 0.08, 0.05
"""Amplitudes of the trunk's roll, pitch and yaw over a cycle [rad]."""


def tilted_plan(robot):
    """The kinematic start with a rolling, pitching, yawing trunk, its feet kept at the nodes."""
    gait = default_gait_for(robot)
    physics = WholeBodyPhysics.of(robot)
    schedule = trot_schedule(gait.period_s, 0.5, 40.0)
    start = starting_plan(physics, schedule, gait.speed_m_s, gait.stance_height_m, gait.clearance_m)
    model = physics.model
    data = model.createData()
    feet = [model.getFrameId(f) for f in physics.feet]
    phase = 2 * np.pi * schedule.times_s / schedule.period_s
    x = start.x.copy()
    x[3:6] = [ROLL * np.sin(phase), PITCH * np.cos(phase), YAW * np.sin(phase)]
    for k in range(schedule.intervals):
        q = start.pinocchio_states[0][:, k].copy()
        pin.framesForwardKinematics(model, data, q)
        targets = np.concatenate([data.oMf[f].translation for f in feet])
        q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(*x[3:6, k])).coeffs()
        for _ in range(100):
            pin.computeJointJacobians(model, data, q)
            pin.updateFramePlacements(model, data)
            error = targets - np.concatenate([data.oMf[f].translation for f in feet])
            if np.abs(error).max() < 1e-13:
                break
            jac = np.vstack(
                [
                    pin.getFrameJacobian(model, data, f, pin.LOCAL_WORLD_ALIGNED)[:3, 6:]
                    for f in feet
                ]
            )
            q[7:] += np.linalg.lstsq(jac, error, rcond=None)[0]
        assert np.abs(error).max() < 1e-12
        x[6:, k] = q[7:]
    xd, xdd = fit(x, schedule.step_s, physics.stride_shift(start.stride_m))
    return WholeBodyPlan(
        physics, schedule, start.speed_m_s, x, xd, xdd, start.forces_n, start.footholds_m
    )


@pytest.fixture(scope="module", params=ROBOTS)
def cycle(request, tmp_path_factory):
    """``(folder, plan read back, visuals)`` of a robot's tilted cycle, written as optimize does."""
    from scalf_opt.robots.loading import load_robot

    robot = load_robot(request.param)
    plan = tilted_plan(robot)
    energy = plan.evaluate("paper")
    legs = np.asarray(plan.physics.joint_legs)
    summary = {
        "model": "3d",
        "robot": robot.name,
        "period_s": plan.schedule.period_s,
        "duty_cycle": plan.schedule.duty_cycle,
        "speed_m_s": plan.speed_m_s,
        "stride_m": plan.stride_m,
        "accounting": "paper",
        "nodes": plan.schedule.intervals,
        "energy_per_cycle_j": energy.total_j,
        "cost_of_transport": plan.cost_of_transport(energy.total_j),
        "leg_energy_per_cycle_j": {
            leg: float(energy.joint_energy_j[legs == i].sum()) for i, leg in enumerate(LEG_NAMES)
        },
    }
    out = tmp_path_factory.mktemp(f"{robot.name}-3d") / f"{robot.name}-3d"
    write_cycle(out, summary, plan, "paper")
    return out, read_plan(out, plan.physics), load_visuals(robot)


def fresh_feet(plan, times):
    """The feet's world positions (n, 4, 3) by a fresh free-flyer model of the URDF.

    ``q`` = the plan's own Pinocchio state at ``t mod T`` (trunk position, quaternion, joints),
    the trunk one stride further per cycle.
    """
    robot = plan.physics.robot
    model = pin.buildModelFromUrdf(str(robot.urdf_path), pin.JointModelFreeFlyer())
    assert tuple(model.names[2:]) == plan.physics.joint_names
    data = model.createData()
    frames = [model.getFrameId(robot.leg(leg).foot_frame) for leg in LEG_NAMES]
    period = plan.schedule.period_s
    cycles = np.floor(times / period)
    q = plan.samples(np.clip(times - cycles * period, 0.0, None)).q
    q[0] += cycles * plan.stride_m
    out = np.empty((times.size, len(frames), 3))
    for k in range(times.size):
        pin.framesForwardKinematics(model, data, q[:, k])
        out[k] = [data.oMf[f].translation for f in frames]
    return out


def decoded(commands):
    return [umsgpack.unpackb(c) for c in commands]


def animation_clips(commands):
    animation = next(c for c in decoded(commands) if c["type"] == "set_animation")
    return {a["path"]: a["clip"] for a in animation["animations"]}


def key_poses(clip):
    """The clip's key times [s] and world poses (n, 4, 4)."""
    tracks = {t["name"]: t for t in clip["tracks"]}
    position = np.array([k["value"] for k in tracks[".position"]["keys"]])
    quaternion = np.array([k["value"] for k in tracks[".quaternion"]["keys"]])
    times = np.array([k["time"] for k in tracks[".position"]["keys"]]) / clip["fps"]
    poses = np.tile(np.eye(4), (times.size, 1, 1))
    for k in range(times.size):
        x, y, z, w = quaternion[k]
        poses[k, :3, :3] = pin.Quaternion(w, x, y, z).matrix()
        poses[k, :3, 3] = position[k]
    return times, poses


def rpy_matrix(roll, pitch, yaw):
    """``R_z(yaw) R_y(pitch) R_x(roll)``, written out."""
    cr, sr, cp, sp, cy, sy = (f(a) for a in (roll, pitch, yaw) for f in (np.cos, np.sin))
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def test_drawn_paths_are_the_plans_feet_and_stance_feet_stand_on_their_footholds(cycle):
    _, plan, _ = cycle
    walk = WholeBodyWalk(plan, "paper", n_cycles=2)
    paths = walk.foot_paths()
    times = paths["RF"].t_s
    np.testing.assert_allclose(times[-1], walk.duration_s, rtol=1e-12)
    expected = fresh_feet(plan, times)
    schedule = plan.schedule
    per = round((times.size - 1) / (2 * schedule.intervals))
    assert per >= 2  # samples between the nodes too
    for i, leg in enumerate(LEG_NAMES):
        path = paths[leg]
        np.testing.assert_allclose(path.position_m, expected[:, i], rtol=0, atol=1e-9)
        # at every stance node the foot is on the ground at its foothold (the stance that began
        # in the previous cycle one stride behind), one stride further per cycle walked
        sample = np.arange(times.size)
        node, cycles = (sample // per) % schedule.intervals, sample // (per * schedule.intervals)
        at_stance_node = (sample % per == 0) & schedule.stance[i, node]
        assert at_stance_node.sum() >= schedule.stance_nodes
        stride = plan.stride_m
        hold = np.stack(
            [
                plan.footholds_m[0, i] + stride * (cycles - schedule.previous_stance[i, node]),
                np.full(times.size, plan.footholds_m[1, i]),
                np.zeros(times.size),
            ],
            axis=1,
        )
        np.testing.assert_allclose(
            path.position_m[at_stance_node], hold[at_stance_node], rtol=0, atol=1e-9
        )
        assert path.swing[~schedule.stance[i, node]].all()
        assert not path.swing[schedule.loaded[i, node] & (sample % per == 0)].any()
    # the trunk really rolls and pitches: a level trunk would leave the feet elsewhere
    assert np.ptp(plan.x[3]) > 0.2 and np.ptp(plan.x[4]) > 0.15


def test_animated_feet_are_on_the_drawn_paths(cycle):
    _, plan, visuals = cycle
    robot = plan.physics.robot
    walk = WholeBodyWalk(plan, "paper", n_cycles=1)
    paths = walk.foot_paths()
    samples = paths["RF"].t_s.size - 1
    # key frames on the paths' samples: one per sample of the cycle
    options = SceneOptions(n_cycles=1, frame_rate_hz=samples / plan.schedule.period_s)
    scene = build_plan_scene([ShownPlan.of(read_cycle(cycle[0]), plan.physics)], options, visuals)
    clips = animation_clips(scene.commands)
    model = robot.model
    for leg in LEG_NAMES:
        frame = model.frames[model.getFrameId(robot.leg(leg).foot_frame)]
        # any visual carried by the foot frame's joint: its pose gives the joint's, then the foot's
        visual = next(v for v in visuals[0] if v.parent_joint == frame.parentJoint)
        times, poses = key_poses(clips[f"/meshcat/trajectories/0/robot/{visual.name}"])
        np.testing.assert_allclose(times, paths[leg].t_s, rtol=0, atol=1e-12)
        joint = poses @ np.linalg.inv(visual.placement)
        feet = joint[:, :3, :3] @ frame.placement.translation + joint[:, :3, 3]
        np.testing.assert_allclose(feet, paths[leg].position_m, rtol=0, atol=1e-9)


def page_commands(page):
    text = page.read_text()
    encoded = json.loads(re.search(r"var commands = (\[.*?\]);", text).group(1))
    return [base64.b64decode(c) for c in encoded]


def test_cli_writes_the_page_with_the_plans_trunk_pose(cycle, tmp_path, capsys):
    folder, plan, visuals = cycle
    out = tmp_path / "view.html"
    code = main(["view", "--from", str(folder), "--cycles", "2", "--out", str(out)])
    printed = capsys.readouterr().out.splitlines()
    assert code == 0
    robot = plan.physics.robot.name
    summary = json.loads((folder / "summary.json").read_text())
    assert printed == [
        f"{folder}: {robot}, T = {plan.schedule.period_s:.4g} s, {plan.speed_m_s:.3g} m/s, "
        f"{summary['energy_per_cycle_j']:.3f} J per cycle, cost of transport "
        f"{summary['cost_of_transport']:.4f}",
        f"wrote {out} (open it in a browser; it needs no network)",
    ]
    assert f"{robot}: 3-D whole-body trot" in out.read_text()
    clips = animation_clips(page_commands(out))
    trunk = next(v for v in visuals[0] if v.parent_joint == 0)  # carried by the root link
    times, poses = key_poses(clips[f"/meshcat/trajectories/0/robot/{trunk.name}"])
    assert times[-1] == pytest.approx(2 * plan.schedule.period_s, rel=1e-12)
    period = plan.schedule.period_s
    for k in (0, 7, 23, len(times) // 2, len(times) - 5):
        t = times[k]
        cycles = np.floor(t / period)
        x = plan.states_at(np.array([t - cycles * period]))[0][:, 0]
        expected = np.eye(4)
        expected[:3, :3] = rpy_matrix(*x[3:6])
        expected[:3, 3] = x[:3] + np.array([cycles * plan.stride_m, 0.0, 0.0])
        np.testing.assert_allclose(poses[k], expected @ trunk.placement, rtol=0, atol=1e-9)
    assert np.ptp([np.arctan2(p[2, 1], p[2, 2]) for p in poses]) > 0.2  # it rolls


@pytest.mark.parametrize("cycle", ["go1"], indirect=True)  # the routing, not the robot
def test_the_python_view_shows_a_3d_cycle_as_the_cli_does(cycle, tmp_path, capsys):
    """``scalf_opt.api.view(from_dirs=DIR)`` of a 3-D cycle: the robot from the folder, the same
    page as ``scalf-opt view --from DIR`` (byte for byte); a mix with a sagittal folder, a gait
    or loads refused in one sentence naming the field, nothing written."""
    from scalf_opt.api import view
    from scalf_opt.api.presentation import view_cycles
    from scalf_opt.errors import ConfigError

    folder = cycle[0]
    page, shown = view(tmp_path / "api.html", from_dirs=folder)
    assert shown == [] and page == tmp_path / "api.html"
    assert main(["view", "--from", str(folder), "--out", str(tmp_path / "cli.html")]) == 0
    assert page.read_bytes() == (tmp_path / "cli.html").read_bytes()
    _, plans = view_cycles(tmp_path / "again.html", [folder, folder])
    assert [p.headline for p in plans] == [capsys.readouterr().out.splitlines()[0]] * 2
    sagittal = tmp_path / "sagittal"
    sagittal.mkdir()
    (sagittal / "summary.json").write_text("{}")
    refused = [
        ({"from_dirs": [folder, sagittal]}, "from_dirs", "3-D and sagittal results are shown"),
        ({"from_dirs": folder, "loads": "trunk"}, "loads", "give no gait or loads"),
        ({"from_dirs": folder, "robot": "solo12"}, None, "not of 'solo12'"),
    ]
    for kwargs, field, words in refused:
        with pytest.raises(ConfigError, match=words) as raised:
            view(tmp_path / "no.html", **kwargs)
        assert field is None or raised.value.field == field
        assert not (tmp_path / "no.html").exists()


def test_cli_refusals_are_one_line_and_write_nothing(cycle, tmp_path, capsys):
    folder = cycle[0]
    sagittal = tmp_path / "sagittal"
    sagittal.mkdir()
    (sagittal / "summary.json").write_text("{}")
    other = "solo12" if "go1" in folder.name else "go1"
    cases = [
        (["--from", str(sagittal), "--model", "3d"], f"--from {sagittal}: not a 3-D cycle"),
        (["--from", str(folder), "--model", "sagittal"], f"--from {folder}: a 3-D cycle, not a"),
        (["--from", str(folder), "--from", str(sagittal)], f"--from {sagittal}: not a 3-D cycle"),
        (["--from", str(sagittal), "--from", str(folder)], "3-D and sagittal results are shown"),
        (["--model", "3d"], "--model 3d: give --from DIR"),
        (["--from", str(folder), "--period", "0.3"], "--period and --from"),
        (["--from", str(folder), "--gait", str(tmp_path / "g.toml")], "--gait and --from"),
        (["--from", str(folder), "--loads", "trunk"], "--loads and --from"),
        (["--from", str(folder), "--accounting", "positive"], "--accounting and --from"),
        (["--from", str(folder), "--beside-parent"], "--beside-parent and --from"),
        (["--from", str(folder), "--robot", other], f"not of '{other}'"),
        (["--from", str(folder), "--cycles", "0"], "cycles must be in 1..50"),
    ]
    out = tmp_path / "no.html"
    for argv, message in cases:
        code = main(["view", *argv, "--out", str(out)])
        err = capsys.readouterr().err
        assert code == 2, (argv, err)
        assert message in err and len(err.strip().splitlines()) == 1, (argv, err)
        assert not out.exists() and list(tmp_path.glob("*.html")) == []


@needs_chromium
@one_chromium_at_a_time
@pytest.mark.parametrize("cycle", ["go1"], indirect=True)  # one robot's screenshot is enough
def test_cli_screenshot_of_a_3d_cycle(cycle, tmp_path, capsys):
    folder, plan, visuals = cycle
    shot = tmp_path / "shot.png"
    argv = ["view", "--from", str(folder), "--cycles", "1", "--color-by", "power"]
    code = main([*argv, "--out", str(tmp_path / "view.html"), "--screenshot", str(shot)])
    assert code == 0 and f"wrote {shot}" in capsys.readouterr().out
    # the same page without the ground, robot and paths: the scene must change the picture
    scene = build_plan_scene(
        [ShownPlan.of(read_cycle(folder), plan.physics)], SceneOptions(n_cycles=1), visuals
    )
    kept = ("set_property", "set_transform")
    scene.commands = [c for c in scene.commands if umsgpack.unpackb(c)["type"] in kept]
    empty = tmp_path / "empty.html"
    empty.write_text(scene_page(scene))
    still = 0.4 * plan.schedule.period_s
    rendering = render_page(empty, tmp_path / "empty.png", fragment=f"t={still:g}")
    assert rendering.errors == []
    pictures = [image.imread(p)[:, :, :3] for p in (shot, rendering.screenshot)]
    assert pictures[0].shape == pictures[1].shape
    changed = np.any(np.abs(pictures[0] - pictures[1]) > PIXEL_TOLERANCE, axis=2)
    assert changed.mean() > MIN_CHANGED_SHARE, changed.mean()

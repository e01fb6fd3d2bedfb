"""The 3-D scene: where the robots, feet and paths are, checked against independent facts.

A stance foot rests on the ground and does not slip (world frame); the trunk advances at the gait's
speed; the animated foot is where the drawn path is; the swing clears H at mid-swing; the commands
are what meshcat's viewer reads, and the same inputs give the same bytes.
"""

import html

import numpy as np
import pytest
import umsgpack

from scalf_opt.errors import ConfigError, ModelError
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.robots.catalog import CATALOG
from scalf_opt.viz.scene import SceneOptions, build_scene, tube
from scalf_opt.viz.visuals import load_visuals
from scalf_opt.viz.walk import Walk
from tests.viz.conftest import coarse_pipeline


def commands(scene):
    return [umsgpack.unpackb(c) for c in scene.commands]


@pytest.mark.parametrize("name", ["scalf", "hyq", "solo12"])
def test_stance_feet_rest_on_the_ground_and_the_trunk_advances(name, request):
    robot = request.getfixturevalue(name)
    pipeline = coarse_pipeline(robot)
    cycle = pipeline.robot_cycle(make_family("reference"))
    walk = Walk(robot, cycle, n_cycles=2)
    gait = cycle.gait
    for leg, path in walk.foot_paths().items():
        stance = ~path.swing
        # a foot in stance is on the ground (z = 0) and still in the world, to round-off
        assert np.abs(path.position_m[stance, 2]).max() < 1e-9, leg
        for c in range(2):
            t0 = c * gait.period_s + (0.0 if leg in ("RF", "LH") else gait.period_s / 2)
            rest = (
                stance
                & (path.t_s >= t0 - 1e-12)
                & (path.t_s <= t0 + gait.stance_duration_s + 1e-12)
            )
            x = path.position_m[rest, 0]
            assert x.size > 2 and np.ptp(x) < 1e-9, leg
        # the swing clears H at mid-swing (decision 14), its ends on the ground
        swing = path.swing
        assert path.position_m[swing, 2].max() >= gait.clearance_m - 1e-9
    trunk = walk.trunk_position_m(np.array([0.0, 0.5, 1.0]))
    np.testing.assert_allclose(np.diff(trunk[:, 0]), 0.5 * gait.speed_m_s, rtol=1e-12)


def test_configurations_reproduce_the_samples(scalf):
    pipeline = coarse_pipeline(scalf)
    cycle = pipeline.robot_cycle(make_family("reference"))
    walk = Walk(scalf, cycle)
    for leg, leg_cycle in cycle.legs.items():
        hip, knee = scalf.leg(leg).joint_names
        i_hip = scalf.model.joints[scalf.model.getJointId(hip)].idx_q
        i_knee = scalf.model.joints[scalf.model.getJointId(knee)].idx_q
        for phase in (leg_cycle.stance, leg_cycle.swing):
            # the same cycle times one period later: the walk repeats the cycle
            q = walk.configurations(phase.t_s + cycle.gait.period_s)
            np.testing.assert_allclose(q[:, [i_hip, i_knee]].T, phase.values["q"], atol=1e-12)


def test_animated_foot_follows_the_drawn_path(scalf, scalf_shown):
    _, shown = scalf_shown
    options = SceneOptions(n_cycles=1, frame_rate_hz=40.0)
    scene = build_scene(scalf, shown, options)
    cmds = commands(scene)
    animation = next(c for c in cmds if c["type"] == "set_animation")
    assert animation["options"] == {"play": True, "repetitions": float("inf")}
    clips = {a["path"]: a["clip"] for a in animation["animations"]}
    visuals, _ = load_visuals(scalf)
    foot = next(v for v in visuals if v.name.startswith("RF_foot"))
    for index, trajectory in enumerate(shown):
        clip = clips[f"/meshcat/trajectories/{index}/robot/{foot.name}"]
        track = next(t for t in clip["tracks"] if t["name"] == ".position")
        keys = np.array([k["value"] for k in track["keys"]])
        frames = np.array([k["time"] for k in track["keys"]])
        t = frames / clip["fps"]  # playback speed 1: animation time is walk time
        offset = scene.legend[index].lateral_offset_m
        walk = Walk(scalf, trajectory.cycle, 1, lateral_offset_m=offset)
        path = walk.foot_paths()["RF"]
        # at the cycle's own sample times the key frames and the path agree exactly; between
        # them the path is sampled, so compare where both exist
        common = np.isin(np.round(t, 9), np.round(path.t_s, 9))
        assert common.sum() >= 10
        by_time = {round(float(s), 9): p for s, p in zip(path.t_s, path.position_m, strict=True)}
        expected = np.array([by_time[round(float(s), 9)] for s in t[common]])
        np.testing.assert_allclose(keys[common], expected, atol=1e-9)


def test_scene_commands_are_meshcats_and_deterministic(scalf, scalf_shown):
    _, shown = scalf_shown
    options = SceneOptions(n_cycles=1, frame_rate_hz=20.0)
    first = build_scene(scalf, shown, options)
    second = build_scene(scalf, shown, options)
    assert first.commands == second.commands  # same inputs, same bytes (no random UUIDs)
    cmds = commands(first)
    assert {c["type"] for c in cmds} == {
        "set_object",
        "set_transform",
        "set_property",
        "set_animation",
    }
    objects = [c["path"] for c in cmds if c["type"] == "set_object"]
    visuals, skipped = load_visuals(scalf)
    assert not skipped
    for index in range(len(shown)):
        for leg in ("RF", "LH", "LF", "RH"):
            assert f"/meshcat/trajectories/{index}/feet/{leg}" in objects
        robot_parts = [p for p in objects if p.startswith(f"/meshcat/trajectories/{index}/robot/")]
        assert len(robot_parts) == len(visuals)
    assert [e.label for e in first.legend] == [t.label for t in shown]
    assert first.legend[0].energy_j == pytest.approx(shown[0].cycle.energy_j, rel=1e-15)


def test_power_colouring_spans_the_swings(scalf, scalf_shown):
    _, shown = scalf_shown
    scene = build_scene(
        scalf, shown, SceneOptions(n_cycles=1, color_by="power", frame_rate_hz=10.0)
    )
    swing_max = max(
        leg.swing.values["power"].sum(axis=0).max() for t in shown for leg in t.cycle.legs.values()
    )
    assert scene.power_range_w == pytest.approx((0.0, swing_max), rel=1e-12)


def test_tube_surrounds_its_polyline():
    s = np.linspace(0.0, np.pi, 30)
    points = np.stack([s, np.zeros_like(s), np.sin(s)], axis=1)
    points = np.concatenate([points[:1], points])  # a repeated point (a resting foot) is merged
    colors = np.ones((points.shape[0], 3))
    vertices, faces, vertex_colors = tube(points, 0.01, colors, sides=8)
    assert vertices.shape == (30 * 8, 3) and vertex_colors.shape == vertices.shape
    assert faces.shape == (2 * 8 * 29, 3) and faces.max() == vertices.shape[0] - 1
    rings = vertices.reshape(30, 8, 3)
    distance = np.linalg.norm(rings - points[1:, None, :], axis=2)
    np.testing.assert_allclose(distance, 0.01, rtol=1e-12)


def test_a_densely_sampled_path_gets_a_ring_per_tube_radius_of_arc():
    # a semicircle of 0.1 m sampled every 0.03 mm, as a bound's swing at several kHz is
    angle = np.linspace(0.0, np.pi, 10_001)
    points = 0.1 * np.stack([np.cos(angle), np.zeros_like(angle), np.sin(angle)], axis=1)
    colors = np.stack([angle / np.pi, 1.0 - angle / np.pi, np.zeros_like(angle)], axis=1)
    radius, sides = 0.01, 8
    vertices, faces, vertex_colors = tube(points, radius, colors, sides=sides)
    rings = vertices.reshape(-1, sides, 3)
    centres = rings.mean(axis=1)
    arc = 0.1 * np.pi
    assert arc / radius <= len(rings) <= arc / radius + 2  # 32 or 33 rings, not 10,001
    np.testing.assert_allclose(centres[[0, -1]], points[[0, -1]], atol=1e-15)
    gaps = np.linalg.norm(np.diff(centres, axis=0), axis=1)
    assert 0.99 * radius < gaps[:-1].min() and gaps.max() < 1.01 * radius  # about one radius
    # each ring has the colour of the sample it stands on
    nearest = np.argmin(np.linalg.norm(points[None, :, :] - centres[:, None, :], axis=2), axis=1)
    np.testing.assert_array_equal(vertex_colors.reshape(-1, sides, 3)[:, 0], colors[nearest])
    assert faces.shape == (2 * sides * (len(rings) - 1), 3)


@pytest.mark.parametrize("name", ["hyq", "solo12"])
def test_meshes_of_other_robots_load(name, request):
    robot = request.getfixturevalue(name)
    visuals, skipped = load_visuals(robot)
    meshes = [v for v in visuals if v.shape == "mesh"]
    assert len(meshes) >= 12 and not skipped
    for mesh in meshes:
        assert mesh.faces.max() < mesh.vertices.shape[0]
        assert np.ptp(mesh.vertices, axis=0).max() < 1.5  # metres: the URDF's scale applied


def test_missing_mesh_is_a_model_error(tmp_path):
    entry = CATALOG["scalf"]
    text = entry.urdf().read_text()
    text = text.replace(
        '<sphere radius="0.03"/>', '<mesh filename="package://nowhere/foot.stl"/>', 1
    )
    urdf = tmp_path / "broken.urdf"
    urdf.write_text(text)
    robot = Robot.from_urdf(urdf, [entry.naming])
    with pytest.raises(ModelError, match=r"broken\.urdf"):
        load_visuals(robot)


def test_bad_options_are_refused():
    with pytest.raises(ConfigError, match="cycles"):
        SceneOptions(n_cycles=0)
    with pytest.raises(ConfigError, match="color by"):
        SceneOptions(color_by="rainbow")  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="nothing to show"):
        build_scene(None, [])  # type: ignore[arg-type]


def test_the_legend_names_each_trajectorys_loads_and_accounting(scalf, scalf_shown):
    """The energies depend on the load model (up to a sixth between the two whole-body
    distributions on ANYmal C): the legend says which model each trajectory was evaluated with."""
    from scalf_opt.viz.html import legend_html
    from scalf_opt.viz.trajectories import Trajectory

    pipeline, shown = scalf_shown
    trunk = pipeline.with_loads("trunk").with_accounting("positive")
    shown = [*shown, Trajectory("trunk-only", trunk.robot_cycle(make_family("reference")))]
    scene = build_scene(scalf, shown, SceneOptions(n_cycles=1, frame_rate_hz=20.0))
    models = [entry.energy_model for entry in scene.legend]
    rate = f"{shown[0].cycle.gait.sample_rate_hz:.4g} Hz"
    assert models == [f"loads 'whole-body', accounting 'paper', {rate}"] * 2 + [
        f"loads 'trunk', accounting 'positive', {rate}"
    ]
    page = legend_html(scene)
    assert all(f"({html.escape(model)})" in page for model in models)


def test_the_legend_prints_the_energies_as_the_command_line_does(scalf, scalf_shown):
    """Every energy in the legend to the millijoule and every power to 10 mW, as ``view`` prints
    them (``0.230`` beside ``0.125``, not ``0.23`` beside ``0.1249``)."""
    from scalf_opt.viz.html import legend_html

    _, shown = scalf_shown
    scene = build_scene(scalf, shown, SceneOptions(n_cycles=1, frame_rate_hz=20.0))
    page = legend_html(scene)
    for trajectory in shown:
        cycle = trajectory.cycle
        swing = ", ".join(f"{leg} {c.swing_energy_j:.3f}" for leg, c in cycle.legs.items())
        assert (
            f"{cycle.energy_j:.3f} J per cycle, {cycle.average_power_w:.2f} W; swing [J]: {swing}"
        ) in page

"""The SCalf URDF: loads in Pinocchio and yourdfpy, physical inertias, Tables 1 and 4.

The expected numbers are written here from the paper's tables, not imported from the generator.
"""

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

from scalf_opt.robots.files import shipped_file
from scalf_opt.robots.scalf.description import main, scalf_urdf_xml, write_scalf_urdf

URDF = shipped_file("scalf.urdf")
LEGS = ("RF", "LF", "RH", "LH")
REVOLUTE = sorted(f"{leg}_{j}" for leg in LEGS for j in ("hip_roll", "hip_pitch", "knee"))


def signs(leg):
    """(sx, sy): +1 front / -1 hind, +1 left / -1 right."""
    return (1 if leg.endswith("F") else -1), (1 if leg.startswith("L") else -1)


@pytest.fixture(scope="module")
def model():
    return pin.buildModelFromUrdf(str(URDF))


@pytest.fixture(scope="module")
def parsed():
    return yourdfpy.URDF.load(str(URDF), build_scene_graph=True, load_meshes=False)


def test_loads_in_yourdfpy_with_all_joints(parsed):
    assert parsed.robot.name == "scalf"
    revolute = [j.name for j in parsed.robot.joints if j.type == "revolute"]
    assert sorted(revolute) == REVOLUTE
    assert {f"{leg}_foot" for leg in LEGS} <= set(parsed.link_map)
    assert parsed.base_link == "trunk"  # fixed base: the trunk is the root, no floating joint


def test_loads_in_pinocchio(model):
    assert model.nq == 12
    assert sorted(model.names[1:]) == REVOLUTE
    for leg in LEGS:
        frame = model.frames[model.getFrameId(f"{leg}_foot")]
        assert model.existFrame(f"{leg}_foot")
        assert model.names[frame.parentJoint] == f"{leg}_knee"


def assert_physical(name, mass, inertia):
    assert mass > 0, name
    np.testing.assert_allclose(inertia, inertia.T, err_msg=name)
    moments = np.linalg.eigvalsh(inertia)
    assert np.all(moments > 0), name
    a, b, c = moments
    assert a + b >= c and a + c >= b and b + c >= a, name


def test_every_link_inertia_is_physical(parsed):
    # every link of the file, as written (feet are massless points: no <inertial>)
    for name, link in parsed.link_map.items():
        if name.endswith("_foot"):
            assert link.inertial is None, name
            continue
        assert_physical(name, link.inertial.mass, link.inertial.inertia)


def test_every_body_inertia_is_physical(model):
    # the bodies Pinocchio builds (a link merged with its fixed children)
    for i in range(1, model.njoints):
        inertia = model.inertias[i]
        assert_physical(model.names[i], inertia.mass, inertia.inertia)
    assert_physical("trunk", model.inertias[0].mass, model.inertias[0].inertia)


def joint(model, name):
    return model.getJointId(name)


@pytest.mark.parametrize("leg", LEGS)
def test_table_1_values(model, leg):
    hind = leg.endswith("H")
    for joint_name, mass, dist, eps, iyy in (
        ("hip_pitch", 4.10, 0.21043, 0.037, 0.178),  # thigh
        ("knee", 2.24, 0.22720, -0.083, 0.057),  # shank
    ):
        inertia = model.inertias[joint(model, f"{leg}_{joint_name}")]
        assert inertia.mass == pytest.approx(mass, abs=1e-9)
        e = -eps if hind else eps  # decision 5: hind legs mirrored
        np.testing.assert_allclose(
            inertia.lever, [-dist * math.sin(e), 0.0, -dist * math.cos(e)], atol=1e-9
        )
        # decision 2: Table 1's moment is about the COM, axis parallel to the joint axis (y)
        assert inertia.inertia[1, 1] == pytest.approx(iyy, abs=1e-9)
    knee = model.jointPlacements[joint(model, f"{leg}_knee")]
    np.testing.assert_allclose(knee.translation, [0, 0, -0.45099], atol=1e-9)  # l1
    foot = model.frames[model.getFrameId(f"{leg}_foot")].placement
    np.testing.assert_allclose(foot.translation, [0, 0, -0.40487], atol=1e-9)  # l2


@pytest.mark.parametrize("leg", LEGS)
def test_hip_offsets_and_table_4_limits(model, leg):
    sx, sy = signs(leg)
    roll = model.jointPlacements[joint(model, f"{leg}_hip_roll")].translation
    np.testing.assert_allclose(roll, [sx * 0.68, sy * 0.20, -0.15], atol=1e-12)
    pitch = model.jointPlacements[joint(model, f"{leg}_hip_pitch")].translation
    np.testing.assert_allclose(pitch, [0, sy * 0.057, -0.045], atol=1e-12)  # decision 4
    hip = (-2.032, 0.047) if sx > 0 else (-0.047, 2.032)
    knee = (0.491, 2.570) if sx > 0 else (-2.570, -0.491)
    roll_limits = (-0.35, 0.35)  # chosen, +-20 deg
    for name, (lo, hi) in (
        (f"{leg}_hip_pitch", hip),
        (f"{leg}_knee", knee),
        (f"{leg}_hip_roll", roll_limits),
    ):
        q = model.joints[joint(model, name)].idx_q
        assert (model.lowerPositionLimit[q], model.upperPositionLimit[q]) == (lo, hi)


@pytest.mark.parametrize("leg", LEGS)
def test_axes_effort_and_velocity_limits(parsed, leg):
    axes = {"hip_roll": [1, 0, 0], "hip_pitch": [0, 1, 0], "knee": [0, 1, 0]}
    for name, axis in axes.items():
        j = parsed.joint_map[f"{leg}_{name}"]
        np.testing.assert_array_equal(j.axis, axis)
        # chosen: 14,000 N x largest moment arm (b = 56.87 / 56.89 mm) = 796 N m -> 800 N m
        assert j.limit.effort == 800.0
        assert j.limit.velocity == 10.0
    assert parsed.joint_map[f"{leg}_foot_fixed"].type == "fixed"


@pytest.mark.parametrize("leg", LEGS)
def test_hip_housing(parsed, leg):
    _, sy = signs(leg)
    inertial = parsed.link_map[f"{leg}_hip"].inertial
    assert inertial.mass == 2.0
    np.testing.assert_allclose(inertial.origin[:3, 3], [0, sy * 0.0285, -0.0225], atol=1e-15)
    box = 2.0 / 12 * np.array([0.08**2 + 0.08**2, 0.10**2 + 0.08**2, 0.10**2 + 0.08**2])
    np.testing.assert_allclose(np.diag(inertial.inertia), box, rtol=1e-14)


def test_trunk_mass_com_and_box_inertia(model):
    trunk = model.inertias[0]
    assert trunk.mass == 200.0  # decision 1
    np.testing.assert_array_equal(trunk.lever, [0, 0, 0])  # precondition (c)
    x, y, z = 1.50, 0.45, 0.30
    box = 200.0 / 12 * np.array([y * y + z * z, x * x + z * z, x * x + y * y])
    np.testing.assert_allclose(np.diag(trunk.inertia), box, rtol=1e-14)


def test_paper_numbers_appear_verbatim():
    text = URDF.read_text(encoding="utf-8")
    for snippet in (
        'xyz="0 0 -0.45099"',
        'xyz="0 0 -0.40487"',
        'lower="-2.032" upper="0.047"',
        'lower="0.491" upper="2.57"',  # 2.570 rad
        'lower="-0.047" upper="2.032"',
        'lower="-2.57" upper="-0.491"',
        '<mass value="4.1"/>',
        '<mass value="2.24"/>',
        'iyy="0.178"',
        'iyy="0.057"',
        'xyz="0.68 -0.2 -0.15"',
        'xyz="0 -0.057 -0.045"',
    ):
        assert snippet in text, snippet
    assert "0000000" not in text and "9999999" not in text  # no float noise


def test_committed_urdf_is_the_generator_output():
    assert Path(URDF).read_text(encoding="utf-8") == scalf_urdf_xml()


def test_write_and_command_line(tmp_path, capsys):
    target = tmp_path / "out" / "scalf.urdf"
    assert write_scalf_urdf(target) == target
    assert target.read_text(encoding="utf-8") == scalf_urdf_xml()
    again = tmp_path / "again.urdf"
    assert main([str(again)]) == 0
    assert again.read_bytes() == target.read_bytes()
    assert str(again) in capsys.readouterr().out
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []

"""The SCalf URDF: loads in Pinocchio and yourdfpy, physical inertias, Tables 1 and 4."""

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

from scalf_opt.robot import default_urdf_path
from scalf_opt.scalf_description import scalf_urdf_xml

URDF = default_urdf_path()
LEGS = ("RF", "LF", "RH", "LH")


@pytest.fixture(scope="module")
def model():
    return pin.buildModelFromUrdf(str(URDF))


def test_loads_in_yourdfpy_with_all_joints():
    robot = yourdfpy.URDF.load(str(URDF), build_scene_graph=True, load_meshes=False)
    revolute = [j.name for j in robot.robot.joints if j.type == "revolute"]
    assert sorted(revolute) == sorted(
        f"{leg}_{j}" for leg in LEGS for j in ("hip_roll", "hip_pitch", "knee")
    )
    assert {f"{leg}_foot" for leg in LEGS} <= set(robot.link_map)


def test_loads_in_pinocchio(model):
    assert model.nq == 12
    for leg in LEGS:
        assert model.existFrame(f"{leg}_foot")


def test_every_inertia_is_physical(model):
    for i, inertia in enumerate(model.inertias):
        if inertia.mass == 0:
            continue
        moments = np.linalg.eigvalsh(inertia.inertia)
        assert np.all(moments > 0), model.names[i]
        a, b, c = moments
        assert a + b >= c and a + c >= b and b + c >= a, model.names[i]


def joint(model, name):
    return model.getJointId(name)


@pytest.mark.parametrize("leg", LEGS)
def test_table_1_values(model, leg):
    hind = leg.endswith("H")
    for _link, joint_name, mass, dist, eps, iyy in (
        ("thigh", "hip_pitch", 4.10, 0.21043, 0.037, 0.178),
        ("shank", "knee", 2.24, 0.22720, -0.083, 0.057),
    ):
        inertia = model.inertias[joint(model, f"{leg}_{joint_name}")]
        assert inertia.mass == pytest.approx(mass, abs=1e-9)
        e = -eps if hind else eps  # decision 5: hind legs mirrored
        np.testing.assert_allclose(
            inertia.lever, [-dist * math.sin(e), 0.0, -dist * math.cos(e)], atol=1e-9
        )
        assert inertia.inertia[1, 1] == pytest.approx(iyy, abs=1e-9)
    knee = model.jointPlacements[joint(model, f"{leg}_knee")]
    np.testing.assert_allclose(knee.translation, [0, 0, -0.45099], atol=1e-9)
    foot = model.frames[model.getFrameId(f"{leg}_foot")].placement
    np.testing.assert_allclose(foot.translation, [0, 0, -0.40487], atol=1e-9)


@pytest.mark.parametrize("leg", LEGS)
def test_hip_offsets_and_table_4_limits(model, leg):
    sx = 1 if leg.endswith("F") else -1
    sy = 1 if leg.startswith("L") else -1
    roll = model.jointPlacements[joint(model, f"{leg}_hip_roll")].translation
    np.testing.assert_allclose(roll[[0, 2]], [sx * 0.68, -0.15], atol=1e-12)
    pitch = model.jointPlacements[joint(model, f"{leg}_hip_pitch")].translation
    np.testing.assert_allclose(pitch, [0, sy * 0.057, -0.045], atol=1e-12)
    hip = (-2.032, 0.047) if sx > 0 else (-0.047, 2.032)
    knee = (0.491, 2.570) if sx > 0 else (-2.570, -0.491)
    for name, (lo, hi) in ((f"{leg}_hip_pitch", hip), (f"{leg}_knee", knee)):
        q = model.joints[joint(model, name)].idx_q
        assert (model.lowerPositionLimit[q], model.upperPositionLimit[q]) == (lo, hi)


def test_trunk_mass_and_com(model):
    assert model.inertias[0].mass == 200.0
    np.testing.assert_array_equal(model.inertias[0].lever, [0, 0, 0])


def test_committed_urdf_is_the_generator_output():
    assert Path(URDF).read_text(encoding="utf-8") == scalf_urdf_xml()

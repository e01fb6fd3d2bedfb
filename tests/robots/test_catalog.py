"""The six robots: stance height from their standing posture (checked on the whole Pinocchio
model), a Froude-similar default trot that every one of them can walk, and defaults that are the
robot's own, never SCalf's."""

import math

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.cli import main
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.robots.catalog import CATALOG
from scalf_opt.robots.files import shipped_file
from scalf_opt.robots.loading import load_robot
from scalf_opt.robots.similarity import REFERENCE_LEG_LENGTH_M
from scalf_opt.types import LEG_NAMES

WITH_POSTURE = [name for name, e in CATALOG.items() if e.srdf is not None]


@pytest.mark.parametrize("name", WITH_POSTURE)
def test_stance_height_is_the_standing_posture(name):
    # the whole robot at its SRDF standing state with the roll joints at zero, by plain FK
    robot = load_robot(name)
    model = pin.buildModelFromUrdf(str(CATALOG[name].urdf()))
    pin.loadReferenceConfigurations(model, str(CATALOG[name].srdf()), False)
    q = np.array(model.referenceConfigurations["standing"])
    heights = []
    for leg in LEG_NAMES:
        names = robot.naming.names(leg)
        q[model.joints[model.getJointId(names.roll)].idx_q] = 0.0
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    for leg in LEG_NAMES:
        names = robot.naming.names(leg)
        hip = data.oMi[model.getJointId(names.pitch)].translation[2]
        heights.append(hip - data.oMf[model.getFrameId(names.foot)].translation[2])
    assert robot.nominal_stance_height_m == pytest.approx(np.mean(heights), rel=1e-12)


def test_known_stance_heights():
    # README, "Robots": SCalf's decision 6; the others from their postures
    expected = {"scalf": 0.75, "hyq": 0.5093, "solo12": 0.2229, "anymal_c": 0.5149}
    for name, height in expected.items():
        assert load_robot(name).nominal_stance_height_m == pytest.approx(height, abs=1e-4)


@pytest.mark.parametrize("name", list(CATALOG))
def test_default_trot_is_froude_similar_and_walkable(name):
    robot = load_robot(name)
    gait = default_gait_for(robot)
    froude = gait.speed_m_s**2 / (9.81 * robot.leg_length_m)
    assert froude == pytest.approx(1.0**2 / (9.81 * REFERENCE_LEG_LENGTH_M), rel=1e-12)
    assert gait.step_length_m / robot.leg_length_m == pytest.approx(0.25 / REFERENCE_LEG_LENGTH_M)
    assert gait.phase_times_s("swing").size == 51  # the same resolution as SCalf's
    assert gait.stance_height_m == robot.nominal_stance_height_m
    # the paper's symmetry (LF repeats RF) is exact for symmetric legs under the trunk-only
    # loads; under whole-body loads Go1's and A1's left-right mass layout makes it 0.7-1.5 %
    cycle = EnergyPipeline(robot, gait, loads="trunk").robot_cycle(make_family("reference"))
    assert math.isfinite(cycle.energy_j) and cycle.energy_j > 0
    # mirror-image legs, up to the robots' own small asymmetries (Solo12, ANYmal: 1e-4)
    assert cycle.symmetry_error < 1e-3


def test_scalfs_default_is_the_papers_trot():
    assert default_gait_for(load_robot("scalf")) == Gait()


def test_a_catalog_urdf_given_by_path_is_that_robot():
    robot = load_robot(urdf=CATALOG["go1"].urdf())
    assert robot.name == "go1" and robot.actuator_path == shipped_file("go1_actuators.toml")
    assert robot.nominal_stance_height_m == load_robot("go1").nominal_stance_height_m


def test_a_urdf_without_posture_stands_like_scalf_scaled(tmp_path):
    urdf = tmp_path / "copy.urdf"
    urdf.write_text(shipped_file("scalf.urdf").read_text())
    robot = load_robot(urdf=urdf)
    assert robot.nominal_stance_height_m == pytest.approx(0.75, rel=1e-15)
    assert robot.actuator_path is None  # no file beside the copy: ideal drives


def test_a_gait_file_without_stance_height_takes_the_robots(tmp_path, capsys):
    # the report: HyQ fell back to SCalf's 0.75 m, a value the user never wrote
    gait = tmp_path / "gait.toml"
    gait.write_text("[gait]\nperiod_s = 0.6\n")
    assert main(["evaluate", "--robot", "hyq", "--gait", str(gait)]) == 0
    out = capsys.readouterr().out
    assert "T=0.6 s" in out and "z0=0.5093 m" in out

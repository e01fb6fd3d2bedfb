"""Whole-body stance loads against a brute-force floating-base RNEA, on every catalog robot.

The load model writes the wrench the stance feet supply as a constant plus one CasADi term per
leg, distributes it over the feet and charges each leg ``RNEA_leg - J^T F``. The independent
check: Pinocchio's own floating-base model of the same URDF (a free-flyer root, built here from
the file, not from scalf-opt's model), moving with a random constant trunk velocity, all four
legs in random states, the contact forces applied as external forces. Its base rows must be
the unbalanced moment (zero with three or four feet) and its leg rows the leg torques, to 1e-9.
"""

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.energy.loads import LOAD_MODELS, stance_loads, static_wrench
from scalf_opt.energy.physics import LegPhysics
from scalf_opt.energy.robot_physics import RobotPhysics
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.forces import (
    min_norm_contact_forces,
    min_norm_foot_forces,
    sagittal_contact_maps,
)
from scalf_opt.model.urdf_file import read_urdf_text
from scalf_opt.robots.catalog import robot_names
from scalf_opt.robots.loading import load_robot
from scalf_opt.types import LEG_NAMES

N_STATES = 12
TOL = 1e-9  # relative to the largest entry: the maths is exact, round-off only
STANCES = (("RF", "LH"), ("LF", "RH"), ("RF", "LH", "LF"), ("RF", "LH", "LF", "RH"))


def close(actual, expected):
    scale = max(1.0, float(np.max(np.abs(expected))))
    np.testing.assert_allclose(actual, expected, rtol=0, atol=TOL * scale)


def floating_model(robot):
    return pin.buildModelFromXML(read_urdf_text(robot.urdf_path), pin.JointModelFreeFlyer())


@pytest.mark.parametrize("name", robot_names())
def test_whole_body_torques_are_a_floating_base_rnea_with_the_contact_forces(name):
    robot = load_robot(name)
    physics = RobotPhysics.build(robot, {})
    fb = floating_model(robot)
    data = fb.createData()
    rng = np.random.default_rng(21)
    for trial in range(N_STATES):
        stance = STANCES[trial % len(STANCES)]
        q_fb = pin.neutral(fb)
        v_fb = np.zeros(fb.nv)
        a_fb = np.zeros(fb.nv)
        v_fb[0:3] = rng.normal(0.0, 1.0, 3)  # any constant trunk velocity (Galilean invariance)
        wrench = static_wrench(robot)
        motion, feet = {}, {}
        for leg in LEG_NAMES:
            model_leg = robot.leg(leg)
            lo = np.maximum(model_leg.lower_limits_rad, -np.pi)
            hi = np.minimum(model_leg.upper_limits_rad, np.pi)
            q, qd, qdd = rng.uniform(lo, hi), rng.normal(0, 3, 2), rng.normal(0, 30, 2)
            motion[leg] = (q, qd, qdd)
            for i, joint in enumerate(model_leg.joint_names):
                jid = fb.getJointId(joint)
                q_fb[fb.joints[jid].idx_q] = q[i]
                v_fb[fb.joints[jid].idx_v] = qd[i]
                a_fb[fb.joints[jid].idx_v] = qdd[i]
            leg_physics = physics.leg(leg)
            wrench = wrench + np.array(leg_physics.wrench_function("joint")(q, qd, qdd)).ravel()
            feet[leg] = np.array(model_leg.symbolic.frame_position(q, model_leg.foot_frame)).ravel()
        forces, unbalanced = min_norm_contact_forces(
            np.column_stack([feet[leg] for leg in stance]), wrench
        )
        if len(stance) > 2:
            close(unbalanced, np.zeros(3))
        pin.forwardKinematics(fb, data, q_fb)
        fext = [pin.Force.Zero() for _ in range(fb.njoints)]
        for k, leg in enumerate(stance):
            foot = robot.model.frames[robot.model.getFrameId(robot.leg(leg).foot_frame)]
            jid = fb.getJointId(robot.model.names[foot.parentJoint])
            f = forces[:, k]
            fext[jid] += data.oMi[jid].actInv(pin.Force(f, np.cross(feet[leg], f)))
        tau_fb = pin.rnea(fb, data, q_fb, v_fb, a_fb, fext)
        close(tau_fb[0:3], np.zeros(3))  # the feet supply any force
        close(tau_fb[3:6], unbalanced)
        free = pin.rnea(fb, data, q_fb, v_fb, a_fb)[0:6]  # no contact: the wrench itself
        close(free, wrench)
        for leg in LEG_NAMES:
            leg_physics: LegPhysics = physics.leg(leg)
            grf = forces[[0, 2], stance.index(leg)] if leg in stance else np.zeros(2)
            out = leg_physics.sample_function("joint")(*motion[leg], grf)
            tau = np.array(out[leg_physics.output_names.index("tau")]).ravel()
            rows = [fb.joints[fb.getJointId(j)].idx_v for j in robot.leg(leg).joint_names]
            close(tau, tau_fb[rows])


def test_two_feet_leave_only_the_moment_about_the_line_joining_them():
    feet = np.array([[0.5, -0.4, 0.0], [-0.5, 0.4, 0.0]]).T
    rng = np.random.default_rng(3)
    for _ in range(20):
        wrench = rng.normal(0.0, 100.0, 6)
        forces, unbalanced = min_norm_contact_forces(feet, wrench)
        line = (feet[:, 1] - feet[:, 0]) / np.linalg.norm(feet[:, 1] - feet[:, 0])
        close(np.cross(unbalanced, line), np.zeros(3))  # along the line
        supplied = np.concatenate(
            [forces.sum(axis=1), np.cross(feet.T, forces.T).sum(axis=0) + unbalanced]
        )
        close(supplied, wrench)
        # no internal force: the forces' difference has no component along the line
        assert abs(float((forces[:, 0] - forces[:, 1]) @ line)) < 1e-9 * np.abs(wrench).max()


def test_the_sagittal_maps_supply_the_forward_and_vertical_forces_and_the_pitch_moment():
    rng = np.random.default_rng(5)
    for k in (2, 3, 4):
        feet = rng.normal(0.0, 0.4, (3, k))
        forces_map, unbalanced_map = sagittal_contact_maps(feet)
        for _ in range(5):
            wrench = rng.normal(0.0, 100.0, 6)
            wrench[1] = 0.0  # legs that move in their sagittal planes need no lateral force
            forces = (forces_map @ wrench).reshape(k, 3).T
            close(forces[1], np.zeros(k))  # no lateral foot force
            close(forces.sum(axis=1)[[0, 2]], wrench[[0, 2]])
            moment = np.cross(feet.T, forces.T).sum(axis=0)
            close(moment[1], wrench[4])  # the whole pitch moment
            close(moment + unbalanced_map @ wrench, wrench[3:6])  # the rest is reported
        # a pure weight is shared as the paper's sagittal distribution shares it (Eq. 29-35),
        # computed there from the (x, z) positions alone
        weight = np.array([0.0, 0.0, 9.81 * 40.0, 0.0, 0.0, 0.0])
        paper = min_norm_foot_forces(feet[[0, 2]], 40.0)
        close((forces_map @ weight).reshape(k, 3).T[[0, 2]], paper)


def test_the_registry_names_its_models_and_refuses_others():
    assert list(LOAD_MODELS) == ["whole-body", "trunk", "whole-body-sagittal"]
    for name, model in LOAD_MODELS.items():
        assert stance_loads(name) is model
    with pytest.raises(ConfigError, match="whole-body"):
        stance_loads("legs")


def test_the_leg_wrench_is_one_casadi_function_for_numbers_and_symbols(scalf):
    physics = RobotPhysics.build(scalf, {}).leg("RF")
    fn = physics.wrench_function("joint")
    y = ca.SX.sym("y", 2)
    symbolic = ca.Function("w", [y], [fn(y, ca.DM([1.0, -2.0]), ca.DM([3.0, 4.0]))])
    q = np.array([0.1, -0.5])
    close(np.array(symbolic(q)), np.array(fn(q, [1.0, -2.0], [3.0, 4.0])))

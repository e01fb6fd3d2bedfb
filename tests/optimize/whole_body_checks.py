"""Independent checks of an optimized 3-D plan: Pinocchio's own free-flyer model, rebuilt from
the URDF (not the model the NLP's CasADi twin was built from), and the contacts' conditions."""

import numpy as np
import pinocchio as pin

from scalf_opt.locomotion.contact_schedule import DEFAULT_FRICTION
from scalf_opt.model.urdf_file import read_urdf_text

REL_TOL = 1e-6  # Ipopt's constraint tolerance is 1e-8 on rows scaled by the weight


def forces_as_fext(model, data, q, forces, feet):
    """The feet's world-axis forces (12,) as Pinocchio's per-joint external forces (local)."""
    pin.framesForwardKinematics(model, data, q)
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    for i, foot in enumerate(feet):
        frame = model.frames[model.getFrameId(foot)]
        local = data.oMi[frame.parentJoint].rotation.T @ forces[3 * i : 3 * i + 3]
        fext[frame.parentJoint] += pin.Force(local, np.cross(frame.placement.translation, local))
    return fext


def free_flyer_model(physics):
    """Pinocchio's own model of the robot on a free-flyer root, built from its URDF."""
    return pin.buildModelFromXML(read_urdf_text(physics.robot.urdf_path), pin.JointModelFreeFlyer())


def assert_pinocchio_agrees(problem, plan):
    """At every node, ``pin.rnea`` with the plan's contact forces gives the plan's joint torques
    and no wrench on the trunk, to ``REL_TOL`` of the largest torque, the weight and the weight
    times the stance height."""
    physics = problem.physics
    model = free_flyer_model(physics)
    data = model.createData()
    q, v, a = plan.pinocchio_states
    tau = plan.node_outputs("paper")["tau"]
    scale = np.abs(tau).max()
    for k in range(problem.schedule.intervals):
        fext = forces_as_fext(model, data, q[:, k], plan.forces_n[:, k], physics.feet)
        out = pin.rnea(model, data, q[:, k], v[:, k], a[:, k], fext)
        assert np.abs(out[:3]).max() < REL_TOL * physics.weight_n
        assert np.abs(out[3:6]).max() < REL_TOL * physics.weight_n * problem.stance_height_m
        np.testing.assert_allclose(out[6:], tau[:, k], rtol=0, atol=REL_TOL * scale)


def assert_contacts_hold(problem, plan):
    """Stance forces push (unilateral) inside the friction cone; swing feet carry nothing."""
    forces = plan.forces_n.reshape(4, 3, -1)  # (foot, xyz, node)
    stance = problem.schedule.stance
    assert (forces[:, 2][stance] >= -1e-9 * plan.physics.weight_n).all()
    tangential = np.hypot(forces[:, 0], forces[:, 1])
    assert (tangential <= DEFAULT_FRICTION * forces[:, 2] * (1 + 1e-6) + 1e-6).all()
    assert (forces.transpose(0, 2, 1)[~stance] == 0).all()

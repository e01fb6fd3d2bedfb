r"""A robot's own default trot: the paper's trot on SCalf, scaled to the robot's leg length.

With ``k = L / L_SCalf`` (:func:`~scalf_opt.robots.similarity.length_scale`, ``L`` the thigh
plus shank length; SCalf's is 0.85586 m) the default gait is dynamically similar to SCalf's trot
(equal Froude number ``v^2 / (g L)``, Alexander and Jayes 1983):

.. math::

    T = 0.5\,\mathrm{s}\,\sqrt{k}, \quad S = 0.25\,\mathrm{m}\,k, \quad H = 0.08\,\mathrm{m}\,k,
    \quad v = \frac{S}{d\,T} = 1.0\,\mathrm{m/s}\,\sqrt{k}, \quad
    f_s = 200\,\mathrm{Hz} / \sqrt{k}

with the duty cycle ``d = 0.5``, 10 cycles, and every phase sampled with the same number of
samples as SCalf's (51). The stance height is the robot's own
(:attr:`~scalf_opt.model.robot.Robot.nominal_stance_height_m`: its standing posture, or SCalf's
0.75 m scaled by ``k``). For SCalf ``k = 1`` exactly and this is the paper's trot. A variant
(:attr:`~scalf_opt.model.robot.Robot.parent`) walks its parent's default trot instead, so that
its energy differs from the parent's only through its geometry.
"""

from __future__ import annotations

import math

from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.robot import Robot
from scalf_opt.robots.similarity import length_scale


def similar_gait(k: float, stance_height_m: float) -> Gait:
    """The paper's trot with lengths scaled by ``k`` and times by ``sqrt(k)``."""
    paper = Gait()
    root = math.sqrt(k)
    return Gait(
        period_s=paper.period_s * root,
        duty_cycle=paper.duty_cycle,
        step_length_m=paper.step_length_m * k,
        clearance_m=paper.clearance_m * k,
        stance_height_m=stance_height_m,
        sample_rate_hz=paper.sample_rate_hz / root,
        cycles=paper.cycles,
    )


def default_gait_for(robot: Robot) -> Gait:
    """The robot's default trot: SCalf's, Froude-scaled to its leg length, at its stance height.

    A variant's is its parent's (see the module's docstring).
    """
    if robot.parent is not None:
        return default_gait_for(robot.parent)
    height = robot.nominal_stance_height_m
    k = length_scale(robot.leg_length_m)
    return similar_gait(k, height if height is not None else Gait().stance_height_m * k)


def default_gait_origin(robot: Robot) -> str:
    """Where the robot's default trot comes from, in words, for reports and provenance."""
    if robot.parent is not None:
        return (
            f"the default trot of {robot.parent.name} ({robot.parent.urdf_path.name}), the robot "
            f"{robot.name} is a variant of: {default_gait_origin(robot.parent)}"
        )
    if math.isclose(length_scale(robot.leg_length_m), 1.0, rel_tol=1e-9):
        return "the paper's trot (Section 6.1)"
    return f"the paper's trot scaled to {robot.name}'s legs at the same Froude number"

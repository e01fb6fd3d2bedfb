"""The swing problem's constraints as families: one per kernel row, each with its samples,
bounds, round-off and reason."""

import numpy as np
import pytest

from scalf_opt.energy.margins import NO_LIFT_PROFILE, LiftProfile, LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.constraints import (
    FEASIBILITY_TOLERANCE,
    GroundClearance,
    LandingSpeed,
    LeavesFromAbove,
    LimitRows,
    Reach,
)
from scalf_opt.optimize.problem import SwingProblem


@pytest.mark.parametrize("family", ["joint-6", "fourier-4"])
def test_each_kernel_row_has_its_family_and_bounds(scalf, family):
    problem = SwingProblem(EnergyPipeline(scalf, Gait(), loads="trunk"), "RF", make_family(family))
    kinds = [type(f) for f in problem.constraints]
    n_limits = len(problem.bounds)
    assert kinds[:n_limits] == [LimitRows] * n_limits
    assert kinds[n_limits:] == [GroundClearance, LandingSpeed, LeavesFromAbove] + (
        [Reach] if family.startswith("fourier") else []
    )
    lower, upper = problem.constraint_bounds
    grid = problem.grid
    z = problem.kernel.row("foot_z")
    assert np.isneginf(lower[z, [0, -1]]).all()
    assert lower[z, 1] > grid.ground_z_m == -Gait().stance_height_m  # the lift profile
    assert lower[z, grid.mid_index] == pytest.approx(grid.ground_z_m + Gait().clearance_m, 1e-15)
    accel = problem.kernel.row("foot_z_accel")
    assert (lower[accel, [0, -1]] == 0.0).all() and np.isneginf(lower[accel, 1:-1]).all()
    for i, b in enumerate(problem.bounds):
        assert (lower[i] == b.lower).all() and (upper[i] == b.upper).all()
        assert problem.constraint_tolerance[i, 0] == b.tolerance()
    assert problem.constraint_tolerance[z, 0] == FEASIBILITY_TOLERANCE


def test_a_crossing_is_told_by_its_familys_reason(scalf):
    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    lifted = SwingProblem(pipeline, "RF", make_family("joint-6"))
    z, v = lifted.kernel.row("foot_z"), lifted.kernel.row("foot_z_vel")
    grid = lifted.grid
    assert lifted.constraints[z].reason(grid.mid_index, grid) == "mid-swing clearance"
    assert lifted.constraints[z].reason(1, grid) == (
        "foot below its lift profile (16 mm up by 15 % of the swing)"
    )
    assert lifted.constraints[v].reason(grid.n_samples - 2, grid) == (
        "foot lands faster than 0.832 m/s"
    )
    assert lifted.constraints[0].reason(3, grid).endswith(lifted.bounds[0].source)
    # the paper family (two parameters) cannot shape its lift: it keeps the foot above the
    # ground alone; its members that cross a limit, or leave the ground from below, say which
    problem = SwingProblem(pipeline, "RF", make_family("paper"))
    assert problem.margins == LimitMargins(lift=NO_LIFT_PROFILE)
    assert problem.constraints[z].reason(1, problem.grid) == "foot below ground"
    assert problem.evaluate(np.array([0.0, -30.0])).reason == (
        "qd_knee beyond its URDF velocity limit"
    )
    assert problem.evaluate(np.array([30.0, 0.0])).reason == (
        "foot leaves or meets the ground from below"
    )


def _times(problem):
    t = problem.path.t_s
    return t, (t - t[0]) / (t[-1] - t[0])


def test_the_lift_profile_is_a_constant_acceleration_ramp_to_its_height(scalf):
    """SCalf's default trot (H 80 mm, swing 0.25 s): the foot at least 16 mm (H/5) up from 15 %
    of the swing to 85 %, at least 16 mm (s / 0.15)^2 before, mirrored after; it lands no faster
    than 2.6 H / 0.25 s = 0.832 m/s over the last 15 %. Written out here from the times alone."""
    problem = SwingProblem(
        EnergyPipeline(scalf, Gait(), loads="trunk"), "RF", make_family("joint-6")
    )
    lower, upper = problem.constraint_bounds
    t, s = _times(problem)
    assert t[-1] - t[0] == pytest.approx(0.25, rel=1e-12)
    ground = -0.75
    expected = ground + 0.016 * np.minimum(np.minimum(s, 1 - s) / 0.15, 1.0) ** 2
    expected[problem.mid_index] = ground + 0.08
    z = problem.kernel.row("foot_z")
    np.testing.assert_allclose(lower[z, 1:-1], expected[1:-1], rtol=0, atol=1e-15)
    middle = (s >= 0.15) & (s <= 0.85)
    middle[problem.mid_index] = False
    assert middle.sum() > 10 and np.allclose(lower[z, middle], -0.734, rtol=0, atol=1e-15)
    v = problem.kernel.row("foot_z_vel")
    landing = s >= 0.85 - 1e-12
    np.testing.assert_allclose(lower[v, landing], -0.832, rtol=1e-12)
    assert np.isneginf(lower[v, ~landing]).all() and np.isposinf(upper[v]).all()


def test_without_a_lift_profile_the_foot_only_stays_above_the_ground(scalf):
    margins = LimitMargins(lift=NO_LIFT_PROFILE)
    problem = SwingProblem(
        EnergyPipeline(scalf, Gait(), loads="trunk"), "RF", make_family("joint-6"), margins=margins
    )
    lower, _ = problem.constraint_bounds
    z, v = problem.kernel.row("foot_z"), problem.kernel.row("foot_z_vel")
    interior = np.delete(lower[z, 1:-1], problem.mid_index - 1)
    assert (interior == -0.75).all() and np.isneginf(lower[v]).all()
    assert problem.constraints[z].reason(1, problem.grid) == "foot below ground"


def test_a_lift_profile_of_the_users_own_is_resolved_on_the_gait(scalf):
    gait = Gait(period_s=0.6, clearance_m=0.05)  # swing 0.3 s
    margins = LimitMargins(lift=LiftProfile(height_m=0.01, fraction=0.25))
    problem = SwingProblem(
        EnergyPipeline(scalf, gait, loads="trunk"), "RF", make_family("joint-6"), margins=margins
    )
    grid = problem.grid
    assert grid.lift_height_m == 0.01 and grid.lift_fraction == 0.25
    assert grid.touchdown_speed_m_s == pytest.approx(2.6 * 0.05 / 0.3, rel=1e-12)
    record = margins.to_dict(gait)
    assert record["lift_height_mm"] == 10.0 and record["lift_fraction"] == 0.25
    assert record["touchdown_speed_m_s"] == pytest.approx(2.6 / 6, rel=1e-12)


@pytest.mark.parametrize("family", ["joint-6", "fourier-4"])
def test_the_foot_speed_row_is_the_time_derivative_of_the_foot_height_row(scalf, family):
    """The kernel's foot_z_vel (J qd in joint space, the sample's own rate in foot space)
    against a central difference of its foot_z at 40 kHz: an independent check of the row the
    landing bound reads. The difference errs by dt^2/6 times the third derivative: < 1e-5 m/s."""
    gait = Gait(sample_rate_hz=40_000.0)
    problem = SwingProblem(EnergyPipeline(scalf, gait, loads="trunk"), "RF", make_family(family))
    # coefficients of -1..1 degrees or centimetres: in reach
    theta = problem.family.from_fourier_coefficients(np.linspace(-1.0, 1.0, problem.n_params))
    c = problem.outputs(theta)["c"]
    z, v = c[problem.kernel.row("foot_z")], c[problem.kernel.row("foot_z_vel")]
    t = problem.path.t_s
    difference = (z[2:] - z[:-2]) / (t[2:] - t[:-2])
    assert np.max(np.abs(v)) > 0.3  # a real motion
    np.testing.assert_allclose(v[1:-1], difference, rtol=0, atol=1e-5)
    assert abs(v[0]) < 1e-9 and abs(v[-1]) < 1e-9  # at rest vertically at both ends


@pytest.mark.parametrize("name", ["scalf", "hyq", "solo12", "anymal_c", "go1", "a1"])
def test_the_reference_swing_keeps_the_default_lift_profile(name):
    """On every catalog robot's default trot the paper's reference swing (Froude-scaled) is at
    least on the default lift profile and lands no faster than its touch-down speed (its
    descent, by central differences at 20 kHz-ish rates): no optimum need be dearer than the
    reference for the lift profile's sake. Measured margins: 8 % on the height at 15 % of the
    swing, 3 % on the landing speed."""
    from dataclasses import replace

    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.optimize.constraints import SwingGrid
    from scalf_opt.robots.loading import load_robot

    robot = load_robot(name)
    gait = default_gait_for(robot)
    gait = replace(gait, sample_rate_hz=20 * gait.sample_rate_hz)
    pipeline = EnergyPipeline(robot, gait, loads="trunk")
    for leg in ("RF", "LH"):
        swing = pipeline.swing(leg, *pipeline.reference_swings()[leg])
        t, z = swing.t_phase_s, swing.values["foot"][1]
        grid = SwingGrid.on(t, z[0], gait.clearance_m, LiftProfile())
        assert np.all(z[1:-1] >= grid.lift_z_m()[1:-1])
        descent = (z[2:] - z[:-2]) / (t[2:] - t[:-2])
        assert np.all(descent[grid.landing()[1:-1]] >= -grid.touchdown_speed_m_s)

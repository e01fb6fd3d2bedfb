"""Actuator limits: where they come from, that optima respect them, peaks, and what is refused."""

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.energy.limits import leg_bounds, violations
from scalf_opt.energy.margins import NO_LIFT_PROFILE, LimitMargins
from scalf_opt.energy.peaks import cycle_peaks, cycle_violations
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import Settings, optimize_swings
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.sampling import with_rate


@pytest.fixture(scope="module")
def model(scalf):
    return EnergyPipeline(scalf, Gait(), loads="trunk")


def by_name(bounds):
    return {b.name: b for b in bounds}


def test_scalf_bounds_come_from_the_urdf_and_the_actuator_file(model):
    bounds = by_name(leg_bounds(model.physics("RF")))
    assert bounds["q_hip"].lower == -2.032 and bounds["q_knee"].upper == 2.57  # Table 4
    assert bounds["qd_hip"].upper == 10.0 and bounds["qd_hip"].symmetric  # URDF velocity
    assert bounds["tau_knee"].upper == 800.0  # URDF effort
    assert bounds["cyl_force_hip"].upper == 14000.0  # force sensor range (Section 2)
    assert bounds["cyl_vel_knee"].upper == pytest.approx(0.569)
    lo, hi = bounds["cyl_len_hip"].lower, bounds["cyl_len_hip"].upper
    assert hi - lo == pytest.approx(0.098)  # the stroke
    hind = by_name(leg_bounds(model.physics("LH")))
    assert hind["q_hip"].lower == -0.047 and hind["q_hip"].upper == 2.032


def test_ideal_drives_bound_only_the_urdf_limits(hyq):
    pipeline = EnergyPipeline(hyq, Gait(stance_height_m=0.55), drives={}, loads="trunk")
    bounds = by_name(leg_bounds(pipeline.physics("RF")))
    assert set(bounds) == {"q_hip", "qd_hip", "tau_hip", "q_knee", "qd_knee", "tau_knee"}
    assert bounds["tau_hip"].upper == 150.0 and bounds["qd_knee"].upper == 12.0
    # HyQ's own valve-fed cylinders add their stroke and the force the supply can exert
    cylinders = by_name(
        leg_bounds(EnergyPipeline(hyq, Gait(stance_height_m=0.55), loads="trunk").physics("RF"))
    )
    assert {"cyl_len_hip", "cyl_force_hip", "cyl_len_knee", "cyl_force_knee"} <= set(cylinders)


def test_a_cylinder_without_limits_declares_only_its_stroke(model):
    cylinder = model.physics("RF").drives[0]
    assert isinstance(cylinder, HydraulicCylinder)
    free = dataclasses.replace(cylinder, max_force_n=np.inf, max_speed_m_s=np.inf)
    assert set(free.output_bounds(-2.0, 0.0)) == {"cyl_len"}
    assert set(cylinder.output_bounds(-2.0, 0.0)) == {"cyl_len", "cyl_force", "cyl_vel"}


def test_an_optimum_never_exceeds_a_limit_and_the_reference_neither(model):
    run = optimize_swings(model, ("RF", "LH"), make_family("joint-6"))
    cycle = run.cycle()
    physics = {leg: model.physics(leg) for leg in cycle.legs}
    assert cycle_violations(cycle, physics) == []
    assert cycle_violations(model.robot_cycle(make_family("reference")), physics) == []
    peaks = {(p.leg, p.joint, p.quantity): p for p in cycle_peaks(cycle, physics)}
    hip_torque = peaks[("RF", "hip", "tau")]
    assert hip_torque.limit == 800.0 and not hip_torque.exceeds
    # the peak equals the largest magnitude over the cycle's samples
    swing, stance = cycle.legs["RF"].swing, cycle.legs["RF"].stance
    largest = max(np.abs(swing.values["tau"][0]).max(), np.abs(stance.values["tau"][0]).max())
    assert abs(hip_torque.value) == largest
    assert peaks[("LH", "knee", "cyl_force")].limit == 14000.0
    assert peaks[("LH", "knee", "power")].limit is None


def test_a_tighter_limit_binds_and_the_optimum_respects_it(scalf):
    # the free joint-6 optimum pulls up to ~6 kN in the hip cylinders; allow 4 kN
    tight = {}
    for joint, drive in EnergyPipeline(scalf, Gait(), loads="trunk").robot_physics.drives.items():
        tight[joint] = dataclasses.replace(drive, max_force_n=4000.0)
    pipeline = EnergyPipeline(scalf, Gait(), drives=tight, loads="trunk")
    # the limit itself, not less the effort margin, is what binds here
    settings = Settings(margins=LimitMargins(effort_share=0.0))
    free = optimize_swings(
        EnergyPipeline(scalf, Gait(), loads="trunk"), ("RF",), make_family("joint-6"), settings
    )
    bound = optimize_swings(pipeline, ("RF",), make_family("joint-6"), settings)
    assert bound.success
    swing = bound.pipeline.swing("RF", bound.family, bound.legs["RF"].best.theta)
    force = np.abs(swing.values["cyl_force_hip"])
    assert force.max() <= 4000.0 * (1 + 1e-9)
    assert force.max() >= 4000.0 * (1 - 1e-6)  # active
    assert bound.legs["RF"].best.swing_energy_j > free.legs["RF"].best.swing_energy_j


@pytest.fixture(scope="module")
def weak_cycle(scalf):
    """The reference cycle of SCalf with cylinders of 3000 N (beyond it in stance): its physics."""
    weak = {}
    for joint, drive in EnergyPipeline(scalf, Gait(), loads="trunk").robot_physics.drives.items():
        weak[joint] = dataclasses.replace(drive, max_force_n=3000.0)
    pipeline = EnergyPipeline(scalf, Gait(), drives=weak, loads="trunk")
    cycle = pipeline.robot_cycle(make_family("reference"))
    return cycle, {leg: pipeline.physics(leg) for leg in cycle.legs}


def test_an_exceeded_limit_is_flagged(weak_cycle):
    cycle, physics = weak_cycle
    found = cycle_violations(cycle, physics)
    assert found and all(v.violation.bound.quantity == "cyl_force" for v in found)
    assert "exceeds its cylinder cyl_force limit" in found[0].message()
    assert any(p.exceeds for p in cycle_peaks(cycle, physics))


def test_a_limit_message_gives_the_unit_as_printed_and_the_share_over(weak_cycle):
    """The message says newtons (not the column name's ``n``) and how far over, in per cent."""
    worst = cycle_violations(*weak_cycle)[0]
    value = abs(worst.violation.value)
    over = 100.0 * (value - 3000.0) / 3000.0
    assert f" {worst.violation.value:.6g} N exceeds" in worst.message()
    assert f"(limit 3000) by {over:.2g} % in " in worst.message()


def test_regenerative_is_refused_where_every_swing_costs_the_same(hyq):
    pipeline = EnergyPipeline(
        hyq, Gait(stance_height_m=0.55), "regenerative", drives={}, loads="trunk"
    )
    with pytest.raises(ConfigError, match=r"regenerative.*nothing to optimize"):
        optimize_swings(pipeline, ("RF",), make_family("joint-4"))


def mechanical_energy_j(leg_model, q, qd):
    data = leg_model.createData()
    kinetic = pin.computeKineticEnergy(leg_model, data, q, qd)
    return kinetic + pin.computePotentialEnergy(leg_model, data, q)


def test_regenerative_is_bounded_on_scalf_by_the_work_energy_theorem(scalf):
    # the charged joint power integrates to the change of the leg's mechanical energy (the
    # same for every swing), so the optimum only lowers the friction heat: checked against
    # Pinocchio's kinetic and potential energies at lift-off and touch-down
    pipeline = EnergyPipeline(scalf, Gait(), "regenerative", loads="trunk")
    # compared with the reference swing, which keeps no lift profile: nor does this optimum
    margins = LimitMargins(lift=NO_LIFT_PROFILE)
    run = optimize_swings(pipeline, ("RF",), make_family("joint-3"), Settings(margins=margins))
    assert run.success
    result = run.legs["RF"]
    swing = run.pipeline.swing("RF", run.family, result.best.theta)
    leg_model = pipeline.physics("RF").leg.model
    q, qd = swing.values["q"], swing.values["qd"]
    change = mechanical_energy_j(leg_model, q[:, -1], qd[:, -1]) - mechanical_energy_j(
        leg_model, q[:, 0], qd[:, 0]
    )
    fine = run.pipeline.with_gait(with_rate(run.pipeline.gait, 10 * run.rate_hz))
    fine_swing = fine.swing("RF", run.family, result.best.theta)
    work = float(fine_swing.energy_j.sum() - fine_swing.loss_j.sum())
    # trapezoidal quadrature of tau qd at ten times the rate: O(h^2), well below 1 mJ here
    assert work == pytest.approx(change, abs=2e-3)
    heat = float(fine_swing.loss_j.sum())
    assert heat > 0
    assert result.check_energy_j == pytest.approx(change + heat, abs=2e-3)
    # it is no worse than the reference's heat, and every limit holds
    reference = fine.swing("RF", make_family("reference"))
    assert heat <= float(reference.loss_j.sum())
    problem = SwingProblem(run.pipeline, "RF", run.family, margins=margins)
    assert violations(swing.values, problem.bounds) == []


def test_starts_are_deterministic_and_the_best_is_kept(model):
    settings = Settings(starts=3)
    first = optimize_swings(model, ("LH",), make_family("joint-4"), settings)
    again = optimize_swings(model, ("LH",), make_family("joint-4"), settings)
    result = first.legs["LH"]
    assert [s.label for s in result.starts][:2] == ["zero", "closest to the reference"]
    assert len(result.starts) == 3
    energies = [s.optimum.swing_energy_j for s in result.starts if s.converged]
    assert result.best.swing_energy_j == min(energies)
    assert result.spread_j == pytest.approx(max(energies) - min(energies))
    np.testing.assert_array_equal(
        [s.optimum.theta for s in result.starts], [s.optimum.theta for s in again.legs["LH"].starts]
    )
    single = optimize_swings(model, ("LH",), make_family("joint-4"))
    np.testing.assert_array_equal(
        single.legs["LH"].starts[0].optimum.theta, result.starts[0].optimum.theta
    )


def test_a_failed_start_is_reported_not_fatal(model, monkeypatch):
    from scalf_opt.optimize import solve

    real = solve.run_ipopt
    seen: list[tuple] = []
    retried = []

    def flaky(problem, theta0, ipopt, screen=False):
        key = tuple(theta0)
        if key not in seen:
            seen.append(key)
        optimum = real(problem, theta0, ipopt, screen)
        if seen.index(key) == 1:  # every solve from the second start fails, its retry too
            optimum = dataclasses.replace(
                optimum, success=False, status="Maximum_Iterations_Exceeded"
            )
            retried.append((ipopt or {}).get("mu_strategy"))
        return optimum

    monkeypatch.setattr(solve, "run_ipopt", flaky)
    run = optimize_swings(model, ("RF",), make_family("joint-3"), Settings(starts=3))
    result = run.legs["RF"]
    assert run.success and result.success
    assert [s.converged for s in result.starts] == [True, False, True]
    assert retried == [None, "monotone", "monotone"]  # every strategy tried, then reported


def test_the_member_closest_to_a_path_recovers_it(model):
    from scalf_opt.optimize.starts import closest_member

    problem = SwingProblem(model, "RF", make_family("joint-5"))
    theta = np.random.default_rng(7).normal(scale=10.0, size=problem.n_params)
    np.testing.assert_allclose(
        closest_member(problem, problem.path.values(theta)), theta, atol=1e-9
    )


def test_the_pattern_search_on_a_rich_family_starts_at_the_reference(model):
    from scalf_opt.optimize.solvers import solver
    from scalf_opt.optimize.starts import closest_to_reference, default_start

    problem = SwingProblem(model, "LH", make_family("joint-6"))
    label, theta = default_start(problem, solver("pattern"))
    assert label == "closest to the reference"
    np.testing.assert_array_equal(theta, closest_to_reference(problem))
    # that member is close to the reference in energy too (it is its least-squares fit)
    reference = model.swing("LH", make_family("reference")).energy_j.sum()
    assert problem.energy_j(theta) == pytest.approx(reference, rel=0.1)
    assert (
        default_start(SwingProblem(model, "LH", make_family("paper")), solver("pattern"))[0]
        == "zero"
    )


def test_a_one_sided_drive_limit_is_in_the_peaks_with_its_side(hyq):
    """HyQ's cylinders push up to 3.2 kN but pull only 1.96 kN: the force is among the peaks."""
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.viz.optimization_report import peaks_table

    pipeline = EnergyPipeline(hyq, default_gait_for(hyq), loads="trunk")
    cycle = pipeline.robot_cycle(make_family("reference"))
    physics = {leg: pipeline.physics(leg) for leg in cycle.legs}
    forces = [p for p in cycle_peaks(cycle, physics) if p.quantity == "cyl_force"]
    assert len(forces) == 8 and all(p.one_sided for p in forces)
    for p in forces:
        (bound,) = (
            b
            for b in leg_bounds(physics[p.leg])
            if b.quantity == "cyl_force" and b.joint == ("hip", "knee").index(p.joint)
        )
        assert p.limit == (bound.upper if p.value >= 0 else -bound.lower)
        # the peak is the sample nearest its side's limit: no sample uses more of its own side
        use = abs(p.value) / p.limit
        for phase in (cycle.legs[p.leg].stance, cycle.legs[p.leg].swing):
            values = phase.values[f"cyl_force_{p.joint}"]
            sides = np.where(values >= 0, bound.upper, -bound.lower)
            assert np.max(np.abs(values) / sides) <= use * (1 + 1e-12)
    assert "cyl_force [N]" in peaks_table(cycle_peaks(cycle, physics))  # signed: no |.|

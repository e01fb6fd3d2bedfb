"""The simulated trot: what it measures, checked against independent physics.

Tests run three cycles (the first is the start-up; the log analysis needs a whole cycle from a
touch-down); ``studies/simulation_validation.py`` and ``studies/whole_robot_validation.py`` run
ten.
"""

from dataclasses import replace

import numpy as np
import pytest

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.forces import GRAVITY_M_S2
from scalf_opt.locomotion.gait import Gait
from scalf_opt.logs.analysis import analyze_log, leg_cylinders
from scalf_opt.logs.sensors import JointMotion, SensorModel, sensor_log
from scalf_opt.robots.loading import load_robot
from scalf_opt.sim.experiment import run_trot
from scalf_opt.sim.metrics import joint_power_w, windowed_mechanical_energy_j
from scalf_opt.sim.plan import REFERENCE_SWINGS, TrotPlan, planned_cycle
from scalf_opt.sim.settings import SimSettings
from scalf_opt.types import LEG_NAMES


@pytest.fixture(scope="module")
def robot():
    return load_robot("scalf")


@pytest.fixture(scope="module")
def pipeline(robot):
    return EnergyPipeline(robot, Gait())


@pytest.fixture(scope="module")
def reference(robot, pipeline):
    return run_trot(robot, pipeline, REFERENCE_SWINGS, SimSettings(), cycles=3)


def test_the_plan_is_the_pipelines_samples(pipeline):
    """At its own grid times the plan returns the pipeline's samples; lift-off starts the swing."""
    plan = TrotPlan.build(pipeline, REFERENCE_SWINGS, 2000.0)
    gait = pipeline.gait
    for leg in LEG_NAMES:
        cycle = plan.cycle.legs[leg]
        for phase in (cycle.stance, cycle.swing):
            t = phase.t_s[:-1]  # a phase's last sample is the next phase's first
            sampled = plan.sample(leg, t)
            for name in ("q", "qd", "tau"):
                np.testing.assert_allclose(sampled[name], phase.values[name][:, :-1], atol=1e-9)
        lift_off = np.array([cycle.swing.t_s[0]])
        assert not plan.in_stance(leg, lift_off)[0]
        np.testing.assert_allclose(
            plan.sample(leg, lift_off)["tau"][:, 0], cycle.swing.values["tau"][:, 0]
        )
    # the model's energy does not depend on the plan's finer grid beyond its O(h^2) quadrature
    coarse = planned_cycle(pipeline, REFERENCE_SWINGS).energy_j
    fine = replace(pipeline, gait=replace(gait, sample_rate_hz=2000.0))
    assert planned_cycle(fine, REFERENCE_SWINGS).energy_j == pytest.approx(coarse, rel=2e-3)


def test_the_reference_trot_keeps_the_papers_assumptions(reference, pipeline):
    result = reference.result
    assert result["cycles_averaged"] == 2
    assert result["diverged_at_s"] is None and result["divergence"] is None
    assert result["fell_at_s"] is None
    assert result["trunk_height_fluctuation_m"] <= 0.004  # the paper's Section 6.3
    assert abs(result["trunk_height_mean_m"] - result["trunk_height_planned_m"]) < 0.002
    assert result["trunk_pitch_peak_rad"] < 0.005
    # nearly point feet and the stance loop on the trunk: the planned speed (30 mm feet rolled
    # the trunk 3.5 % fast)
    assert result["forward_speed_m_s"] == pytest.approx(pipeline.gait.speed_m_s, rel=1e-3)
    assert max(result["foot_slip_m"].values()) < 0.002
    assert max(result["torque_saturation_fraction"].values()) == 0.0
    assert result["goals"]["trunk_height_met"]


def test_the_ground_carries_the_whole_robot(reference, robot):
    """Momentum balance over a cycle: the mean vertical ground force is the robot's weight.

    Under the whole-body loads the model's stance feet carry the whole robot too: each holds
    half its weight on average (within the stance grid's sampling of the legs' momentum, 0.2 %).
    """
    result = reference.result
    assert result["checks"]["mean_vertical_ground_force_over_weight"] == pytest.approx(
        1.0, abs=5e-3
    )
    half_weight = robot.total_mass_kg * GRAVITY_M_S2 / 2
    for leg in LEG_NAMES:
        assert result["model_stance_force_mean_n"][leg] == pytest.approx(half_weight, rel=2e-3)
        assert result["stance_force_mean_n"][leg] == pytest.approx(half_weight, rel=0.03)


def test_the_work_of_the_joints_and_contacts_is_the_change_of_energy(robot, pipeline):
    """Work-energy balance with MuJoCo's own kinetic and potential energy.

    Semi-implicit Euler is first order: the error halves with the step, and the joint energy
    hardly moves (measured: error 3.2e-4 and 1.6e-4 of the gross joint work, energy 377.82 and
    378.02 J at 0.5 and 0.25 ms).
    """
    errors, energies = [], []
    for dt in (0.0005, 0.00025):
        run = run_trot(robot, pipeline, REFERENCE_SWINGS, SimSettings(timestep_s=dt), cycles=2)
        errors.append(run.result["checks"]["energy_balance_error_over_gross_work"])
        energies.append(run.result["total_energy_per_cycle_j"]["simulated"])
    assert abs(errors[1]) < 1e-3
    assert abs(errors[1]) == pytest.approx(abs(errors[0]) / 2, rel=0.2)
    assert energies[1] == pytest.approx(energies[0], rel=1e-3)


def test_joint_energy_two_ways(reference, pipeline):
    """Torque times joint rate (the record) = cylinder force times the rate of its length.

    The second way never sees a joint rate: a noiseless 2 kHz cylinder log of the run (lengths
    from the angles, forces from the torques), its lengths differentiated by the log pipeline's
    filter over a short window (4 ms: no noise to smooth), integrated over the same cycles.
    They agree to 0.12 % (the touch-down transients, 2 ms long, are what the 4 ms fit smooths).
    """
    record = reference.record
    motions = {
        leg: JointMotion(record.t_s, record.q_rad[leg], record.tau_nm[leg], record.in_contact(leg))
        for leg in LEG_NAMES
    }
    cylinders = {leg: leg_cylinders(pipeline, leg) for leg in LEG_NAMES}
    log = sensor_log(motions, cylinders, SensorModel.exact(2000.0), seed=0)
    analysis = analyze_log(log, pipeline, period_s=pipeline.gait.period_s, half_window_s=0.002)
    for leg, energy in analysis.legs.items():
        by_record = windowed_mechanical_energy_j(pipeline, record, leg, energy.windows_s)
        assert energy.mechanical_j["cycle"] == pytest.approx(by_record, rel=3e-3)
        assert np.array(joint_power_w(pipeline, record, leg)).shape == (2, record.t_s.size)


def test_the_referee_spends_what_the_plan_needs(reference, robot):
    """The simulated joint energy is the plan's own, per leg and phase, within 2 %.

    The plan's own: MuJoCo's inverse dynamics of the whole robot put on the plan, no servo, no
    contact model (:mod:`scalf_opt.sim.inverse`; its dynamics equal Pinocchio's,
    ``test_mujoco_model.py``). Measured: stance -1.3 %, swing -0.2 to +0.6 %. The servo's
    feedback supplies what the model's torques lack, and adds no energy of its own.
    """
    result = reference.result
    plan = result["plan_inverse_dynamics"]
    weight = robot.total_mass_kg * GRAVITY_M_S2
    assert sum(plan["stance_force_mean_n"].values()) / 2 == pytest.approx(weight, rel=1e-3)
    for leg in LEG_NAMES:
        phases = result["joint_energy_per_phase_j"][leg]
        for phase in ("stance", "swing"):
            own = plan["joint_energy_per_phase_j"][leg][phase]
            assert phases[phase]["simulated"] == pytest.approx(own, rel=0.02), (leg, phase)
        total = phases["stance"]["simulated"] + phases["swing"]["simulated"]
        energy = result["joint_energy_per_cycle_j"][leg]
        assert total == pytest.approx(energy["simulated"], rel=1e-12)
        assert result["stance_force_mean_n"][leg] == pytest.approx(
            plan["stance_force_mean_n"][leg], rel=0.01
        )


def test_a_simulation_is_deterministic(robot, pipeline):
    first = run_trot(robot, pipeline, REFERENCE_SWINGS, SimSettings(), cycles=2).result
    second = run_trot(robot, pipeline, REFERENCE_SWINGS, SimSettings(), cycles=2).result
    assert first["joint_energy_per_cycle_j"] == second["joint_energy_per_cycle_j"]
    assert first["trunk_height_fluctuation_m"] == second["trunk_height_fluctuation_m"]


def test_a_reference_impossible_at_the_saved_stance_is_skipped_with_a_note(
    robot, pipeline, monkeypatch
):
    """``simulate --from`` a free stance: the reference is simulated only where it exists.

    At the free stance ``optimize --free-stance`` finds on SCalf (z0 = 0.8 m, feet +93.75 and
    -95 mm) the reference swing takes LH's knee out of its range: planning it is a GaitError.
    The optimum is still simulated, and the file says in one line why there is no reference.
    """
    from scalf_opt.errors import GaitError
    from scalf_opt.sim import experiment
    from scalf_opt.sim.report import simulation_report

    free = replace(
        pipeline.gait,
        stance_height_m=0.8,
        stance_x_offset_front_m=0.09375,
        stance_x_offset_hind_m=-0.095,
    )
    with pytest.raises(GaitError, match="LH_knee"):
        planned_cycle(replace(pipeline, gait=free), REFERENCE_SWINGS)

    real = experiment.run_trot
    refused = []

    def run_trot_at_free_stance(robot, pipeline, swings, settings, cycles):
        if swings is REFERENCE_SWINGS:  # as at the free stance, without its 40 s optimization
            refused.append(True)
            planned_cycle(replace(pipeline, gait=free), swings)
        return real(robot, pipeline, swings, settings, cycles)

    monkeypatch.setattr(experiment, "run_trot", run_trot_at_free_stance)
    swings = {leg: ("joint-6", np.zeros(18)) for leg in LEG_NAMES}
    data, run = experiment.simulation_file(
        robot, pipeline, swings, SimSettings(), 2, ensemble=False
    )
    assert refused and "reference" not in data and "saving_vs_reference" not in data
    assert data["reference_skipped"].startswith(
        "the reference swing is impossible at this gait: gait fields"
    )
    report = simulation_report(data, "title")
    assert "\nreference not simulated: the reference swing is impossible" in report
    assert run.result["joint_energy_per_cycle_j"]["RF"]["simulated"] > 0


def test_the_height_goal_is_the_paper_s_4_mm_or_1_percent_of_a_lower_stance():
    from scalf_opt.sim.metrics import height_goal_m

    assert height_goal_m(0.75) == 0.004  # SCalf: the paper's Section 6.3
    assert height_goal_m(0.254) == pytest.approx(0.00254, rel=1e-12)  # Go1: 1 % of z0

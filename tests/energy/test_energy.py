"""The energy pipeline: force balance, energy conservation, statics, quadrature order, mirror
symmetry, and the compiled CasADi evaluator against an independent Pinocchio loop."""

from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scalf_opt.actuators.drive import IdealDrive
from scalf_opt.energy.evaluator import CycleEvaluator
from scalf_opt.energy.phase import PhaseSamples, evaluate_phase
from scalf_opt.energy.physics import LegPhysics, trapezoid_weights
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import GaitError
from scalf_opt.locomotion.forces import balance_matrix
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.kinematics import LegKinematics
from tests.reference_loop import phase_energy

REFERENCE = make_family("reference")


@pytest.fixture(scope="module")
def model(scalf):
    return EnergyPipeline(scalf, Gait())


@pytest.fixture(scope="module")
def cycle(model):
    return model.robot_cycle(REFERENCE)


def foot_in_trunk_xz(robot, leg, p_leg):
    hip = robot.leg(leg).hip_origin_m - robot.trunk_com_m
    return p_leg + np.array([[hip[0]], [hip[2]]])


def test_stance_forces_balance_the_trunk(model, scalf):
    f_rf, f_lh = model.trunk_stance_forces["RF"], model.trunk_stance_forces["LH"]
    stance = model.stance_paths["RF"]
    feet_rf = foot_in_trunk_xz(scalf, "RF", stance[0])
    feet_lh = foot_in_trunk_xz(scalf, "LH", stance[0])
    weight = scalf.trunk_mass_kg * 9.81
    for j in range(f_rf.shape[1]):
        feet = np.column_stack([feet_rf[:, j], feet_lh[:, j]])
        forces = np.concatenate([f_rf[:, j], f_lh[:, j]])
        residual = balance_matrix(feet) @ forces - np.array([0.0, weight, 0.0])
        assert np.max(np.abs(residual)) < 1e-9
    # mid-stance the feet are symmetric about the COM: half the trunk weight each (Fig. 13: 980 N)
    mid = f_rf.shape[1] // 2
    assert f_rf[1, mid] == pytest.approx(weight / 2, abs=1e-9)
    assert f_lh[1, mid] == pytest.approx(weight / 2, abs=1e-9)
    assert np.all(np.abs(f_rf[1] - 981.0) < 0.2 * 981.0)


def test_periodic_swing_without_friction_conserves_energy(scalf):
    # ideal actuators (no cylinder data): power = tau * qd, so the work over a period is the
    # change of kinetic plus potential energy: zero for a periodic motion
    leg = scalf.leg("RF")
    physics = LegPhysics(LegKinematics(leg), tuple(IdealDrive(j) for j in leg.joint_names))
    period, n = 0.4, 801
    t = np.linspace(0.0, period, n)
    w = 2 * np.pi / period
    q0, a, b = np.array([-0.5, 1.0]), np.array([0.4, 0.5]), np.array([0.2, -0.3])
    q = q0[:, None] + a[:, None] * np.sin(w * t) + b[:, None] * np.cos(2 * w * t)
    qd = a[:, None] * w * np.cos(w * t) - b[:, None] * 2 * w * np.sin(2 * w * t)
    qdd = -a[:, None] * w**2 * np.sin(w * t) - b[:, None] * 4 * w**2 * np.cos(2 * w * t)
    fn = physics.sample_function("joint", "regenerative").map(n)
    out = dict(zip(physics.output_names, fn(q, qd, qdd, np.zeros((2, n))), strict=True))
    weights = trapezoid_weights(t)
    work = np.array(out["power"]) @ weights
    gross = np.abs(np.array(out["p_mech"])) @ weights
    assert np.all(np.array(out["p_loss"]) == 0.0)
    assert abs(work.sum()) < 1e-6 * gross.sum()


@settings(max_examples=60, deadline=None)
@given(
    q1=st.floats(-2.0, 0.0),
    q2=st.floats(0.5, 2.5),
    qd1=st.floats(-8, 8),
    qd2=st.floats(-8, 8),
    fx=st.floats(-300, 300),
    fz=st.floats(0, 2000),
)
def test_friction_heat_is_never_negative(scalf, q1, q2, qd1, qd2, fx, fz):
    physics = _physics(scalf, "RF")
    out = dict(
        zip(
            physics.output_names,
            physics.sample_function("joint")([q1, q2], [qd1, qd2], [0, 0], [fx, fz]),
            strict=True,
        )
    )
    heat = np.array(out["p_loss"]).ravel()
    assert np.all(heat >= 0.0)
    assert np.all(np.array(out["power"]).ravel() >= heat)


_PHYSICS: dict = {}


def _physics(robot, leg):
    if leg not in _PHYSICS:
        _PHYSICS[leg] = EnergyPipeline(robot, Gait()).physics(leg)
    return _PHYSICS[leg]


@pytest.mark.parametrize("leg", ["RF", "LH"])
def test_static_posture_torques(scalf, leg):
    physics = _physics(scalf, leg)
    q = np.array([-0.45, 1.0]) * (-1 if leg == "LH" else 1)
    force = np.array([35.0, 950.0])
    out = dict(
        zip(
            physics.output_names,
            physics.sample_function("joint")(q, [0, 0], [0, 0], force),
            strict=True,
        )
    )
    model, data = physics.leg.model, physics.leg.model.createData()
    gravity = pin.computeGeneralizedGravity(model, data, q)
    jac = pin.computeFrameJacobian(
        model, data, q, physics.leg.foot_frame_id, pin.LOCAL_WORLD_ALIGNED
    )
    expected = gravity - jac[[0, 2]].T @ force
    np.testing.assert_allclose(np.array(out["tau"]).ravel(), expected, rtol=1e-12)
    assert np.all(np.array(out["p_mech"]) == 0.0)


def test_energy_converges_with_the_sample_rate(scalf):
    """Trapezoidal quadrature: order 2 on a smooth integrand; inside an O(h^2) envelope otherwise.

    With ideal actuators and regenerative accounting the integrand tau * qd is smooth within each
    phase, so halving the step divides the error by 4. The paper's accounting integrates
    |tau qd| + friction heat, whose kinks at velocity reversals fall at arbitrary places inside a
    step: the error then stays below C h^2 but is not monotone.
    """
    rates = (200, 400, 800, 1600)

    def energies(accounting, drives):
        out = []
        for rate in (*rates, 6400):
            m = EnergyPipeline(scalf, Gait(sample_rate_hz=rate), accounting, drives)
            out.append(m.leg_cycle("RF", REFERENCE).energy_j)
        return np.array(out)

    smooth = energies("regenerative", {})
    differences = np.diff(smooth[:-1])
    orders = np.log2(differences[:-1] / differences[1:])
    np.testing.assert_allclose(orders, 2.0, atol=0.1)

    exact = energies("paper", None)
    errors = np.abs(exact[:-1] - exact[-1])
    h = 1.0 / np.array(rates)
    envelope = errors[0] / h[0] ** 2
    assert np.all(errors <= envelope * h**2 * (1 + 1e-9))
    assert errors[-1] < 1e-4 * exact[-1]


def test_hind_leg_through_the_mirror_equals_the_direct_computation(model, cycle):
    # Mirror LH across the trunk's y-z plane: it becomes a front leg (RF's geometry) walking the
    # path x -> -x with force F_x -> -F_x; joint angles and torques change sign.
    rf = model.physics("RF")
    stance, tau = model.stance_paths["RF"], model.stance_times_s
    mirror = np.array([-1.0, 1.0])[None, :, None]
    grf = cycle.legs["LH"].stance.values["grf"] * np.array([[-1.0], [1.0]])
    mirrored = evaluate_phase(
        rf, PhaseSamples("stance", "foot", stance * mirror, grf, tau, 0.0, 0.5)
    )
    direct = cycle.legs["LH"].stance
    np.testing.assert_allclose(mirrored.energy_j, direct.energy_j, rtol=1e-12)
    np.testing.assert_allclose(-mirrored.values["q"], direct.values["q"], atol=1e-12)
    np.testing.assert_allclose(-mirrored.values["tau"], direct.values["tau"], rtol=1e-10, atol=1e-9)
    swing = model.swing_path("LH", REFERENCE).values()
    mirrored_swing = evaluate_phase(
        rf,
        PhaseSamples(
            "swing",
            "foot",
            swing * mirror,
            np.zeros((2, swing.shape[-1])),
            model.gait.phase_times_s("swing"),
            0.0,
            0.5,
        ),
    )
    np.testing.assert_allclose(mirrored_swing.energy_j, cycle.legs["LH"].swing.energy_j, rtol=1e-12)


def test_paper_symmetry_between_diagonal_pairs(cycle):
    assert cycle.symmetry_error < 1e-12
    for leg in ("RF", "LF", "RH", "LH"):
        assert cycle.legs[leg].energy_j > 0


@pytest.mark.parametrize("leg", ["RF", "LH"])
def test_casadi_pipeline_equals_plain_pinocchio_loop(model, cycle, leg):
    stance, tau = model.stance_paths[leg], model.stance_times_s
    physics_leg = model.physics(leg).leg
    grf = cycle.legs[leg].stance.values["grf"]
    e_stance, tau_stance = phase_energy(physics_leg, *stance, grf, tau)
    np.testing.assert_allclose(cycle.legs[leg].stance.energy_j, e_stance, rtol=1e-9)
    np.testing.assert_allclose(
        cycle.legs[leg].stance.values["tau"], tau_stance, rtol=1e-9, atol=1e-9
    )
    swing = model.swing_path(leg, REFERENCE).values()
    e_swing, _ = phase_energy(
        physics_leg, *swing, np.zeros((2, swing.shape[-1])), model.gait.phase_times_s("swing")
    )
    np.testing.assert_allclose(cycle.legs[leg].swing.energy_j, e_swing, rtol=1e-9)


@pytest.mark.parametrize("compiled", [False, True])
def test_fast_evaluator_equals_the_loop(model, cycle, compiled):
    evaluator = CycleEvaluator(model, ("RF", "LH"), compiled=compiled)
    energies = evaluator(evaluator.inputs(REFERENCE))
    for i, leg in enumerate(("RF", "LH")):
        np.testing.assert_allclose(energies[i, 0], cycle.legs[leg].stance.energy_j, rtol=1e-12)
        np.testing.assert_allclose(energies[i, 1], cycle.legs[leg].swing.energy_j, rtol=1e-12)


def test_accountings_are_consistent(scalf):
    results = {
        acc: EnergyPipeline(scalf, Gait(), acc).leg_cycle("RF", REFERENCE).energy_j
        for acc in ("paper", "positive", "regenerative")
    }
    # paper = pos + |neg| + heat, regenerative = pos - |neg| + heat, positive = pos + heat
    assert results["paper"] + results["regenerative"] == pytest.approx(
        2 * results["positive"], rel=1e-12
    )
    assert results["regenerative"] < results["positive"] < results["paper"]


@pytest.mark.parametrize(
    ("changes", "match"),
    [({"stance_height_m": 0.9}, "reach"), ({"step_length_m": 0.9}, "outside its limits|reach")],
)
def test_gaits_leaving_the_workspace_are_refused(scalf, changes, match):
    model = EnergyPipeline(scalf, replace(Gait(), **changes))
    with pytest.raises(GaitError, match=match):
        model.leg_cycle("RF", REFERENCE)


def test_cost_of_transport_and_average_power(cycle, scalf):
    assert cycle.average_power_w == pytest.approx(cycle.energy_j / 0.5)
    distance = 1.0 * 0.5  # 1 m/s for one 0.5 s cycle
    assert cycle.cost_of_transport == pytest.approx(
        cycle.energy_j / (scalf.total_mass_kg * 9.81 * distance)
    )


def test_smooth_heat_is_close_to_exact(scalf):
    physics = _physics(scalf, "RF")
    exact = physics.sample_function("joint")
    smooth = physics.sample_function("joint", heat_eps=1e-4)
    i = physics.output_names.index("p_loss")
    for qd in np.linspace(-3, 3, 61):
        a = np.array(exact([-0.5, 1.0], [qd, -qd], [0, 0], [0, 0])[i])
        b = np.array(smooth([-0.5, 1.0], [qd, -qd], [0, 0], [0, 0])[i])
        assert np.all(b >= a - 1e-12) and np.all(b - a <= 50.0 * 1e-4)  # F_s * eps / 2 per side


def test_results_are_deterministic(scalf):
    first = EnergyPipeline(scalf, Gait()).robot_cycle(REFERENCE)
    second = EnergyPipeline(scalf, Gait()).robot_cycle(REFERENCE)
    for leg in first.legs:
        for phase in ("stance", "swing"):
            a, b = getattr(first.legs[leg], phase), getattr(second.legs[leg], phase)
            for key in a.values:
                np.testing.assert_array_equal(a.values[key], b.values[key])


@pytest.mark.parametrize("family", ["reference", "paper", "joint-4", "fourier-3"])
def test_joint_motion_is_continuous_across_phase_changes(model, family):
    swing_family = make_family(family)
    theta = np.random.default_rng(2).normal(0, 2, swing_family.n_params)
    for leg in ("RF", "LH"):
        stance = model.stance(leg).values
        swing = model.swing_path(leg, swing_family)
        samples = swing.values(theta)
        kin = model.physics(leg).kin
        if swing.space == "foot":
            q, qd, _ = kin.joint_motion(samples[0], samples[1], samples[2])
        else:
            q, qd = samples[0], samples[1]
        # lift-off: end of stance = start of swing; touch-down: end of swing = start of stance
        np.testing.assert_allclose(q[:, 0], stance["q"][:, -1], atol=1e-12)
        np.testing.assert_allclose(qd[:, 0], stance["qd"][:, -1], atol=1e-11)
        np.testing.assert_allclose(q[:, -1], stance["q"][:, 0], atol=1e-12)
        np.testing.assert_allclose(qd[:, -1], stance["qd"][:, 0], atol=1e-11)


TOY = "import casadi as ca; x = ca.SX.sym('x'); toy = ca.Function('toy', [x], [2 * ca.sin(x)])"


def test_compiled_cache_survives_a_damaged_library(tmp_path, monkeypatch):
    import shutil
    import subprocess
    import sys

    from scalf_opt.energy import codegen

    if codegen._compiler() is None:
        pytest.skip("no C compiler: the virtual-machine fallback is covered by the other tests")
    monkeypatch.setenv("SCALF_OPT_CACHE", str(tmp_path))
    # compile in another process, so that this one never maps the library we then damage
    script = f"{TOY}; from scalf_opt.energy.codegen import compile_function; compile_function(toy)"
    subprocess.run([sys.executable, "-c", script], check=True)
    (library,) = tmp_path.glob("toy_*.so")
    damaged = tmp_path / "damaged"
    damaged.write_bytes(b"not a shared library")
    shutil.move(damaged, library)  # a new file, as a broken copy or disk would leave it
    namespace: dict = {}
    exec(TOY, namespace)
    compiled = codegen.compile_function(namespace["toy"])  # checksum mismatch: recompiled
    assert float(compiled(0.5)) == pytest.approx(2 * np.sin(0.5), rel=1e-15)
    assert library.read_bytes().startswith(b"\x7fELF")


def test_legs_without_parameters_keep_the_reference_swing(model, cycle):
    paper = make_family("paper")
    theta = np.array([1.9, -11.7])
    partial = model.robot_cycle(paper, {"RF": theta})
    # RF and its twin LF use the optimized member; LH and RH were not optimized: reference
    np.testing.assert_array_equal(partial.legs["LF"].swing_theta, theta)
    assert partial.legs["LF"].swing_energy_j == pytest.approx(partial.legs["RF"].swing_energy_j)
    for leg in ("LH", "RH"):
        assert partial.legs[leg].swing_family == "reference"
        assert partial.legs[leg].swing_energy_j == cycle.legs[leg].swing_energy_j
        # under whole-body loads LH stands while LF swings the optimized member: its stance
        # carries a different load; under the trunk-only loads it does not
        assert partial.legs[leg].stance_energy_j != cycle.legs[leg].stance_energy_j
    trunk = model.with_loads("trunk")
    partial, reference = trunk.robot_cycle(paper, {"RF": theta}), trunk.robot_cycle(REFERENCE)
    for leg in ("LH", "RH"):
        assert partial.legs[leg].energy_j == reference.legs[leg].energy_j

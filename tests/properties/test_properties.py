"""Properties that must hold for any input in range, checked on examples hypothesis draws.

The examples are derandomized (tests/conftest.py): the same on every run and machine.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.forces import balance_matrix, min_norm_foot_forces
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.kinematics import LegKinematics

unit = st.floats(0.0, 1.0)


@pytest.fixture(scope="module")
def pipeline(scalf):
    return EnergyPipeline(scalf, Gait())


@settings(max_examples=80)
@given(leg=st.sampled_from(["RF", "LH", "LF", "RH"]), a=unit, b=unit)
def test_ik_after_fk_is_the_identity_inside_the_joint_limits(scalf, leg, a, b):
    model_leg = scalf.leg(leg)
    kin = LegKinematics(model_leg)
    lo, hi = model_leg.lower_limits_rad, model_leg.upper_limits_rad
    q = lo + np.array([a, b]) * (hi - lo)
    np.testing.assert_allclose(kin.inverse(kin.forward(q)), q, atol=1e-9)


@settings(max_examples=80)
@given(
    feet=st.lists(
        st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, -0.3)), min_size=2, max_size=4, unique=True
    ),
    mass=st.floats(1.0, 500.0),
    accel=st.floats(-3.0, 3.0),
)
def test_foot_forces_always_balance_the_trunk(feet, mass, accel):
    xz = np.array(feet).T
    if np.ptp(xz[0]) < 0.05:  # feet on one vertical line carry no moment: not a stance
        return
    forces = min_norm_foot_forces(xz, mass, accel)
    wrench = balance_matrix(xz) @ forces.T.ravel()
    np.testing.assert_allclose(wrench, [mass * accel, mass * 9.81, 0.0], atol=1e-9 * mass * 10)


@settings(max_examples=25)
@given(
    leg=st.sampled_from(["RF", "LH"]),
    family=st.sampled_from(["paper", "joint-3", "fourier-3"]),
    scale=st.floats(0.0, 2.0),
    seed=st.integers(0, 1000),
)
def test_energy_and_losses_are_never_negative(pipeline, leg, family, scale, seed):
    swing_family = make_family(family)
    theta = scale * np.random.default_rng(seed).normal(size=swing_family.n_params)
    path = pipeline.swing_path(leg, swing_family)
    values = path.values(theta)
    fn = pipeline.physics(leg).sample_function(path.space)
    out = fn.map(path.t_s.size)(values[0], values[1], values[2], np.zeros((2, path.t_s.size)))
    result = dict(zip(pipeline.physics(leg).output_names, out, strict=True))
    power, loss = np.array(result["power"]), np.array(result["p_loss"])
    finite = np.isfinite(power).all(axis=0)  # an unreachable member has NaN samples, no energy
    assert np.all(loss[:, finite] >= 0.0)
    assert np.all(power[:, finite] >= loss[:, finite] - 1e-12)


@settings(max_examples=25)
@given(
    family=st.sampled_from(["joint-4", "fourier-4"]),
    seed=st.integers(0, 10_000),
    scale=st.floats(0.0, 10.0),
)
def test_every_family_member_meets_the_boundary_conditions(pipeline, family, seed, scale):
    swing_family = make_family(family)
    theta = scale * np.random.default_rng(seed).normal(size=swing_family.n_params)
    for leg in ("RF", "LH"):
        path = pipeline.swing_path(leg, swing_family)
        reference = pipeline.swing_path(leg, make_family("reference"))
        a, b = path.values(theta), reference.values()
        if path.space == "joint":
            kin = pipeline.kinematics(leg)
            q, qd, _ = kin.joint_motion(b[0], b[1], b[2])
            b = np.array([q, qd, q])
        for d in (0, 1):
            np.testing.assert_allclose(a[d][:, [0, -1]], b[d][:, [0, -1]], atol=1e-10)


@settings(max_examples=15)
@given(period=st.floats(0.4, 0.8), step=st.floats(0.1, 0.3), height=st.floats(0.7, 0.8))
def test_mirror_symmetry_of_the_diagonal_pairs(scalf, period, step, height):
    gait = Gait(period_s=period, step_length_m=step, stance_height_m=height, sample_rate_hz=100)
    cycle = EnergyPipeline(scalf, gait).robot_cycle(make_family("reference"))
    assert cycle.symmetry_error < 1e-10


@pytest.fixture(scope="module")
def scale_one_variants(tmp_path_factory):
    """Every catalog robot and its variant at scale 1, derived through yourdfpy and reloaded."""
    from scalf_opt.robots.catalog import CATALOG
    from scalf_opt.robots.loading import load_robot
    from scalf_opt.robots.variants import VariantScales, derive_variant

    folder = tmp_path_factory.mktemp("variants")
    pairs = {}
    for name in CATALOG:
        robot = load_robot(name)
        urdf = derive_variant(robot, VariantScales(), folder / f"{name}.urdf").urdf_path
        pairs[name] = (robot, load_robot(urdf=urdf))
    return pairs


@settings(max_examples=30)
@given(
    name=st.sampled_from(["scalf", "hyq", "solo12", "anymal_c", "go1", "a1"]), seed=st.integers(0)
)
def test_a_variant_at_scale_one_is_the_original(scale_one_variants, name, seed):
    """The whole tree's dynamics (masses, inertias, joint placements, axes) are unchanged:
    inverse dynamics at a random state agree to round-off."""
    import pinocchio as pin

    original, variant = (r.model for r in scale_one_variants[name])
    assert [original.names[i] for i in range(original.njoints)] == [
        variant.names[i] for i in range(variant.njoints)
    ]
    rng = np.random.default_rng(seed)
    q = pin.randomConfiguration(original, -np.ones(original.nq), np.ones(original.nq))
    v, a = rng.normal(size=(2, original.nv))
    tau = [pin.rnea(m, m.createData(), q, v, a) for m in (original, variant)]
    np.testing.assert_allclose(tau[1], tau[0], rtol=1e-12, atol=1e-9)
    for leg in ("RF", "LH"):
        a_leg, b_leg = (r.leg(leg) for r in scale_one_variants[name])
        assert b_leg.thigh_length_m == pytest.approx(a_leg.thigh_length_m, rel=1e-12)
        assert b_leg.shank_length_m == pytest.approx(a_leg.shank_length_m, rel=1e-12)

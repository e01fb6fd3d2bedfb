"""URDF variants: the stretch law against a cloud of point masses, lengths and masses as asked,
physical inertias, all scales 1 give back the original's energies, the pipeline runs on them."""

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.actuators.sidecar import load_sidecar, sidecar_path_for
from scalf_opt.cli import main
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.inertia import inertia_problems
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import run_ipopt
from scalf_opt.robots.files import shipped_file
from scalf_opt.robots.loading import load_robot
from scalf_opt.robots.variants import (
    VariantScales,
    derive_variant,
    stretch_matrix,
    stretched_inertia,
    variant_xml,
)
from scalf_opt.types import LEG_NAMES


def cloud_inertia(points, masses):
    com = masses @ points / masses.sum()
    r = points - com
    inertia = sum(
        m * (ri @ ri * np.eye(3) - np.outer(ri, ri)) for m, ri in zip(masses, r, strict=True)
    )
    return com, inertia


def test_the_stretch_law_is_what_a_stretched_body_has():
    # an independent check: stretch a cloud of point masses and compute its inertia directly
    rng = np.random.default_rng(7)
    points = rng.normal(size=(400, 3)) * [0.03, 0.02, 0.2] + [0.01, 0.0, -0.2]
    masses = rng.uniform(0.5, 1.5, 400)
    com, inertia = cloud_inertia(points, masses)
    d = np.array([0.3, 0.1, -1.0]) / np.linalg.norm([0.3, 0.1, -1.0])
    for s, mu in ((1.3, 1.0), (0.6, 2.5), (1.0, 0.7)):
        S = stretch_matrix(d, s)
        new_com, new_inertia = cloud_inertia(points @ S.T, mu * masses)
        np.testing.assert_allclose(S @ com, new_com, rtol=1e-12)
        np.testing.assert_allclose(stretched_inertia(inertia, S, mu), new_inertia, rtol=1e-11)


@pytest.fixture(scope="module")
def scaled(tmp_path_factory, scalf):
    out = tmp_path_factory.mktemp("variant") / "long.urdf"
    scales = VariantScales(
        thigh_length_scale=1.2, shank_length_scale=0.9, thigh_mass_scale=1.5, trunk_mass_scale=0.8
    )
    derive_variant(scalf, scales, out)
    return load_robot(urdf=out)


def test_lengths_masses_com_and_inertia_change_as_asked(scaled, scalf):
    for leg in LEG_NAMES:
        old, new = scalf.leg(leg), scaled.leg(leg)
        assert new.thigh_length_m == pytest.approx(1.2 * old.thigh_length_m, rel=1e-12)
        assert new.shank_length_m == pytest.approx(0.9 * old.shank_length_m, rel=1e-12)
        thigh_old, thigh_new = old.model.inertias[1], new.model.inertias[1]
        assert thigh_new.mass == pytest.approx(1.5 * thigh_old.mass, rel=1e-12)
        # SCalf's thigh hangs along -z: the COM's z stretches, its x offset stays
        np.testing.assert_allclose(
            thigh_new.lever, thigh_old.lever * [1.0, 1.0, 1.2], rtol=1e-12, atol=1e-15
        )
        # slender rod about its COM, by hand: Sigma = tr(I)/2 - I, the z moment stretched
        i_xx, i_yy, i_zz = np.diag(thigh_old.inertia)
        sx, sy, sz = (i_yy + i_zz - i_xx) / 2, (i_xx + i_zz - i_yy) / 2, (i_xx + i_yy - i_zz) / 2
        sz *= 1.2**2
        expected = 1.5 * np.array([sy + sz, sx + sz, sx + sy])
        np.testing.assert_allclose(np.diag(thigh_new.inertia), expected, rtol=1e-12)
        shank_old, shank_new = old.model.inertias[2], new.model.inertias[2]
        assert shank_new.mass == pytest.approx(shank_old.mass, rel=1e-12)
    assert scaled.trunk_mass_kg == pytest.approx(0.8 * scalf.trunk_mass_kg, rel=1e-12)
    assert inertia_problems(scaled.model) == []


def test_the_actuator_file_goes_beside_with_the_same_mounts(scaled, scalf):
    path = sidecar_path_for(scaled.urdf_path)
    assert path.is_file()
    assert load_sidecar(path) == load_sidecar(shipped_file("scalf_actuators.toml"))


def test_all_scales_one_give_back_the_original(tmp_path, scalf):
    out = tmp_path / "same.urdf"
    derive_variant(scalf, VariantScales(), out)
    same = load_robot(urdf=out)
    assert default_gait_for(same) == Gait()  # same leg length: the paper's trot at 0.75 m
    family = make_family("joint-4")
    thetas = {"RF": np.linspace(-2, 2, 10), "LH": np.linspace(1, -1, 10)}
    original = EnergyPipeline(scalf, Gait()).robot_cycle(family, thetas)
    variant = EnergyPipeline(same, default_gait_for(same)).robot_cycle(family, thetas)
    for leg in LEG_NAMES:
        for phase in ("stance", "swing"):
            np.testing.assert_allclose(
                getattr(variant.legs[leg], phase).energy_j,
                getattr(original.legs[leg], phase).energy_j,
                rtol=1e-12,
            )


@pytest.mark.parametrize("name", ["anymal_c", "go1"])
def test_other_robots_and_their_fixed_links(tmp_path, name):
    # ANYmal's knee hangs from a drive housing fixed to the thigh; Go1 has meshes and an SRDF
    robot = load_robot(name)
    same = load_robot(urdf=derive_variant(robot, VariantScales(), tmp_path / "a.urdf").urdf_path)
    gait = default_gait_for(robot)
    assert default_gait_for(same) == gait
    family = make_family("reference")
    e0 = EnergyPipeline(robot, gait).robot_cycle(family).energy_j
    assert EnergyPipeline(same, gait).robot_cycle(family).energy_j == pytest.approx(e0, rel=1e-12)
    scales = VariantScales(thigh_length_scale=0.8, shank_length_scale=1.25, shank_mass_scale=2.0)
    model = pin.buildModelFromXML(variant_xml(robot, scales))
    assert inertia_problems(model) == []
    longer = load_robot(urdf=derive_variant(robot, scales, tmp_path / "b.urdf").urdf_path)
    for leg in ("RF", "LH"):
        assert longer.leg(leg).thigh_length_m == pytest.approx(0.8 * robot.leg(leg).thigh_length_m)
        assert longer.leg(leg).shank_length_m == pytest.approx(1.25 * robot.leg(leg).shank_length_m)
    assert (tmp_path / "b.srdf").is_file() and (tmp_path / "b_actuators.toml").is_file()


def test_the_pipeline_runs_on_a_variant(scaled, tmp_path, capsys):
    # it stands like SCalf scaled to its legs, but walks its parent's trot (the paper's)
    own = 0.75 * (1.2 * 0.45099 + 0.9 * 0.40487) / 0.85586
    assert scaled.nominal_stance_height_m == pytest.approx(own)
    gait = default_gait_for(scaled)
    assert gait.stance_height_m == 0.75 and gait.period_s == 0.5
    problem = SwingProblem(EnergyPipeline(scaled, gait), "RF", make_family("joint-3"))
    assert run_ipopt(problem).success
    assert main(["evaluate", "--urdf", str(scaled.urdf_path), "--out", str(tmp_path)]) == 0
    assert "cyl_len_hip_m" in (tmp_path / "samples.csv").read_text().splitlines()[0]
    capsys.readouterr()


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["--out", "x.txt"], "must end in .urdf"),
        (["--thigh-length-scale", "-1", "--out", "v.urdf"], "thigh_length_scale = -1.0"),
        (["--out", str(shipped_file("scalf.urdf"))], "the robot's own URDF"),
    ],
)
def test_bad_variant_requests(tmp_path, capsys, argv, match, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["variant", *argv]) == 2
    err = capsys.readouterr().err
    assert match in err and err.count("\n") == 1
    assert not (tmp_path / "v.urdf").exists()


def test_unknown_variant_field():
    with pytest.raises(ConfigError, match="unknown variant field 'hip_scale'"):
        VariantScales.from_mapping({"hip_scale": 2.0})

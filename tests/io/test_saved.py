"""Reading the swings and gait back from a summary.json."""

import json

import numpy as np
import pytest

from scalf_opt.cli import main
from scalf_opt.errors import ConfigError, GaitError
from scalf_opt.io.saved import read_saved_swings


@pytest.fixture(scope="module")
def summary(tmp_path_factory):
    out = tmp_path_factory.mktemp("opt")
    assert main(["optimize", "--family", "paper", "--leg", "RF", "--out", str(out)]) == 0
    return json.loads((out / "summary.json").read_text())


def test_the_swings_and_the_gait_come_back(tmp_path, summary, capsys):
    capsys.readouterr()
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    planned = read_saved_swings(tmp_path)
    assert planned.gait.period_s == 0.5 and planned.gait.sample_rate_hz == 200.0
    # optimize --leg RF: LF repeats RF, the hind legs keep the reference
    assert planned.swings["RF"][0] == planned.swings["LF"][0] == "paper"
    assert planned.swings["LH"] == ("reference", pytest.approx(np.zeros(0)))
    np.testing.assert_array_equal(
        planned.swings["RF"][1], summary["legs"]["RF"]["swing_parameters"]
    )


def edit(summary, change):
    data = json.loads(json.dumps(summary))
    change(data)
    return data


@pytest.mark.parametrize(
    ("change", "error", "message"),
    [
        (lambda d: d.pop("legs"), ConfigError, "missing field 'legs'"),
        (lambda d: d["legs"].clear(), ConfigError, "legs holds none of RF, LH, LF, RH"),
        (lambda d: d["legs"]["RF"].pop("swing_family"), ConfigError, "legs.RF.swing_family"),
        (
            lambda d: d["legs"]["RF"].update(swing_parameters=[1.0]),
            ConfigError,
            "must be 2 finite numbers for family 'paper'",
        ),
        (
            lambda d: d["legs"]["RF"].update(swing_parameters=["x", 1]),
            ConfigError,
            "must be 2 finite numbers",
        ),
        (
            lambda d: d["legs"]["RF"].update(swing_parameters=[10**400, 1]),
            ConfigError,
            "must be 2 finite numbers",  # a float cannot hold it: refused, not a crash
        ),
        (lambda d: d["legs"]["RF"].update(swing_family="bogus"), ConfigError, "bogus"),
        (lambda d: d["gait"].update(duty_cycle=0.2), GaitError, "duty_cycle"),
        (
            lambda d: d["legs"]["RF"].update(swing_parameter_names=["a", "b"]),
            ConfigError,
            "legs.RF.swing_parameter_names: family paper: parameters named",
        ),
        (
            lambda d: d["legs"]["RF"].update(swing_parameter_names="hip"),
            ConfigError,
            "legs.RF.swing_parameter_names must be a list of names",
        ),
    ],
)
def test_a_bad_summary_is_refused_naming_the_field(tmp_path, summary, change, error, message):
    (tmp_path / "summary.json").write_text(json.dumps(edit(summary, change)))
    with pytest.raises(error, match=message.replace(".", r"\.")):
        read_saved_swings(tmp_path)


def test_a_summary_from_before_the_modes_reads_back_as_the_same_member(tmp_path):
    # joint-N's parameters were its terms' coefficients until they became its modes' amplitudes:
    # a file without the parameters' names holds coefficients, and reads back as the member
    # it was written for
    from scalf_opt.locomotion.swing.registry import make_family

    out = tmp_path / "opt"
    assert main(["optimize", "--family", "joint-3", "--leg", "RF", "--out", str(out)]) == 0
    saved = json.loads((out / "summary.json").read_text())
    record = saved["legs"]["RF"]
    family = make_family("joint-3")
    assert record["swing_parameter_names"] == family.parameter_names
    theta = np.array(record["swing_parameters"])
    old = edit(saved, lambda d: d["legs"]["RF"].pop("swing_parameter_names"))
    old["legs"]["RF"]["swing_parameters"] = list(family.fourier_coefficients(theta))
    (tmp_path / "summary.json").write_text(json.dumps(old))
    np.testing.assert_allclose(read_saved_swings(tmp_path).swings["RF"][1], theta, atol=1e-12)
    np.testing.assert_array_equal(read_saved_swings(out).swings["RF"][1], theta)


def test_a_simulation_needs_every_leg(tmp_path, summary):
    (tmp_path / "summary.json").write_text(json.dumps(edit(summary, lambda d: d["legs"].pop("RH"))))
    saved = read_saved_swings(tmp_path)
    assert set(saved.swings) == {"RF", "LH", "LF"}
    with pytest.raises(ConfigError, match=r"missing field legs\.RH"):
        saved.require_all_legs()


def test_not_json(tmp_path):
    (tmp_path / "summary.json").write_text("{")
    with pytest.raises(ConfigError, match="not valid JSON"):
        read_saved_swings(tmp_path)


def test_swings_of_another_robot_are_refused(tmp_path, summary):
    from scalf_opt.robots.loading import load_robot

    assert summary["provenance"]["robot"] == "scalf"
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    saved = read_saved_swings(tmp_path)
    saved.check_robot(load_robot("scalf"))
    assert saved.swings["RF"][0] == "paper"
    with pytest.raises(ConfigError, match=r"field provenance\.robot is 'scalf', not 'hyq'"):
        saved.check_robot(load_robot("hyq"))
    # the same name, another URDF (a variant written over a copy): the hash tells
    other = tmp_path / "scalf.urdf"
    other.write_text(load_robot("scalf").urdf_path.read_text() + "<!-- changed -->\n")
    with pytest.raises(ConfigError, match=r"field provenance\.urdf_sha256 is not the SHA-256"):
        saved.check_robot(load_robot(urdf=other))
    # a file without provenance (older versions): the robot's mass tells
    anonymous = {k: v for k, v in summary.items() if k != "provenance"}
    (tmp_path / "summary.json").write_text(json.dumps(anonymous))
    with pytest.raises(ConfigError, match=r"total_mass_kg is 233\.36 kg, but hyq weighs"):
        read_saved_swings(tmp_path).check_robot(load_robot("hyq"))

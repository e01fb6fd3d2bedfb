"""A variant records its parent: it walks the parent's default trot (so that its energy differs
from the parent's only through its geometry), every report says which gait it walks and where
that came from, and a variant of a robot with meshes keeps them reachable as package references."""

import json

import pytest

import scalf_opt as so
from scalf_opt.cli import main
from scalf_opt.errors import ConfigError
from scalf_opt.robots.variants import (
    VariantScales,
    derive_variant,
    read_variant_record,
    variant_record_for,
)


@pytest.fixture(scope="module")
def scalf():
    return so.load_robot("scalf")


@pytest.fixture(scope="module")
def long_thigh(scalf, tmp_path_factory):
    out = tmp_path_factory.mktemp("variant") / "long.urdf"
    variant = derive_variant(scalf, VariantScales(thigh_length_scale=1.2), out)
    return so.load_robot(urdf=variant.urdf_path)


def test_the_variant_records_its_parent_and_scales(long_thigh):
    record = read_variant_record(variant_record_for(long_thigh.urdf_path))
    assert record.parent_robot == "scalf" and record.parent_urdf is None
    assert record.scales == VariantScales(thigh_length_scale=1.2)
    assert long_thigh.parent is not None and long_thigh.parent.name == "scalf"


def test_a_variant_walks_its_parents_default_trot(scalf, long_thigh):
    assert so.read_gait(robot=long_thigh) == so.read_gait(robot=scalf)
    assert long_thigh.leg_length_m > scalf.leg_length_m * 1.05  # a longer leg, the same trot


def test_the_energy_differs_only_through_the_geometry(scalf, long_thigh):
    parent_gait = so.read_gait(robot=scalf)
    by_default = so.evaluate(long_thigh)
    given = so.evaluate(long_thigh, parent_gait)  # the parent's gait given explicitly
    assert by_default.energy_j == given.energy_j  # the same evaluation, to the last bit
    assert by_default.cycle.gait == so.evaluate(scalf).cycle.gait
    assert by_default.energy_j != so.evaluate(scalf).energy_j  # the geometry changed it
    identity = derive_variant(scalf, VariantScales(), long_thigh.urdf_path.with_name("same.urdf"))
    same = so.evaluate(so.load_robot(urdf=identity.urdf_path))
    assert same.energy_j == pytest.approx(so.evaluate(scalf).energy_j, rel=1e-12)


def test_a_gait_given_still_wins(long_thigh):
    assert so.read_gait(robot=long_thigh, period_s=0.45).period_s == 0.45


def test_every_report_says_which_gait_and_where_from(long_thigh, capsys):
    assert main(["evaluate", "--urdf", str(long_thigh.urdf_path), "--period", "0.45"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith("gait: the default trot of scalf (scalf.urdf)")
    assert "variant of" in first and first.endswith("under --period")
    assert main(["evaluate", "--urdf", str(long_thigh.urdf_path), "--json"]) == 0
    provenance = json.loads(capsys.readouterr().out)["provenance"]
    assert provenance["variant_of"]["robot"] == "scalf"
    assert provenance["default_gait"].startswith("the default trot of scalf")
    assert main(["evaluate", "--robot", "hyq"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "gait: the paper's trot scaled to hyq's legs at the same Froude number"


def test_a_variant_of_a_robot_with_meshes_can_be_viewed(tmp_path, capsys):
    pytest.importorskip("meshcat")
    from scalf_opt.viz.visuals import visual_model

    go1 = so.load_robot("go1")
    variant = derive_variant(go1, VariantScales(thigh_length_scale=1.1), tmp_path / "g.urdf")
    text = variant.urdf_path.read_text()
    assert 'filename="package://go1_description/meshes/' in text
    assert str(tmp_path) not in text and "site-packages" not in text
    assert visual_model(so.load_robot(urdf=variant.urdf_path)).ngeoms > 0


def test_a_bad_record_is_refused_naming_the_file(tmp_path):
    record = tmp_path / "x_variant.toml"
    record.write_text('[variant]\nparent_robot = "nobody"\n')
    with pytest.raises(ConfigError, match=r"x_variant\.toml: parent_robot 'nobody'"):
        read_variant_record(record)
    record.write_text('[variant]\nparent_urdf = "missing.urdf"\n')
    with pytest.raises(ConfigError, match="no such file"):
        read_variant_record(record)


def test_the_variant_command_names_the_trot_the_variant_walks(tmp_path, capsys):
    """It printed the trot scaled to the variant's own legs (its staged copy had no parent yet)."""
    out = tmp_path / "long.urdf"
    assert main(["variant", "--thigh-length-scale", "1.2", "--out", str(out)]) == 0
    gait = so.read_gait(robot=so.load_robot(urdf=out))
    assert gait == so.read_gait(robot=so.load_robot("scalf"))
    assert (
        f"the variant walks scalf's default trot (T={gait.period_s:.4g} s, "
        f"S={gait.step_length_m:.4g} m, z0={gait.stance_height_m:.4g} m)"
    ) in capsys.readouterr().out

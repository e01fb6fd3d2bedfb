"""Legs found in the kinematic tree: the same names as the catalog's for all six robots; clear
errors for trees that are not a quadruped's; a legs file where the guess fails."""

import re

import pytest

from scalf_opt.errors import ConfigError, ModelError
from scalf_opt.model.discovery import chains, discover_legs
from scalf_opt.robots.catalog import CATALOG
from scalf_opt.robots.files import shipped_file
from scalf_opt.robots.loading import load_robot
from scalf_opt.types import LEG_NAMES

TAIL = """
  <joint name="tail_pitch" type="revolute">
    <parent link="trunk"/><child link="tail_1"/>
    <origin xyz="-0.8 0 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="tail_1"><inertial><mass value="0.5"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="tail_bend" type="revolute">
    <parent link="tail_1"/><child link="tail_2"/>
    <origin xyz="-0.2 0 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="tail_2"><inertial><mass value="0.5"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="tail_tip_fixed" type="fixed">
    <parent link="tail_2"/><child link="tail_foot"/><origin xyz="-0.2 0 0" rpy="0 0 0"/>
  </joint>
  <link name="tail_foot"/>
</robot>"""

LEGS_FILE = "\n".join(
    f'[legs.{leg}]\nroll = "{leg}_hip_roll"\npitch = "{leg}_hip_pitch"\nknee = "{leg}_knee"\n'
    f'foot = "{leg}_foot"'
    for leg in LEG_NAMES
)


def scalf_xml(change=lambda text: text):
    return change(shipped_file("scalf.urdf").read_text())


@pytest.mark.parametrize("name", list(CATALOG))
def test_the_tree_names_the_legs_as_the_catalog_does(name):
    robot = load_robot(name)
    found = discover_legs(robot.model, name)
    for leg in LEG_NAMES:
        assert found.names(leg) == robot.naming.names(leg)


def test_a_urdf_by_path_needs_no_known_names(tmp_path):
    # SCalf with every name changed: the legs are still found from the tree and the positions
    urdf = tmp_path / "renamed.urdf"
    xml = scalf_xml()
    for old, new in (("RF_", "front_right_"), ("LH_", "rear_left_"), ("_knee", "_kfe")):
        xml = xml.replace(old, new)
    urdf.write_text(xml)
    robot = load_robot(urdf=urdf)
    assert robot.naming.names("RF").pitch == "front_right_hip_pitch"
    assert robot.naming.names("LH").knee == "rear_left_kfe"
    assert robot.leg("LH").thigh_length_m == pytest.approx(0.45099, abs=1e-12)


def test_a_fifth_chain_is_reported_and_a_legs_file_resolves_it(tmp_path):
    urdf = tmp_path / "tailed.urdf"
    urdf.write_text(scalf_xml(lambda text: text.replace("</robot>", TAIL)))
    with pytest.raises(ModelError) as info:
        load_robot(urdf=urdf)
    message = str(info.value)
    assert "found 5 legs" in message and "tail_pitch -> tail_bend" in message
    assert "name the legs in tailed_legs.toml beside the URDF" in message
    assert len(re.findall(r"foot \w+ at x=", message)) == 5 and "\n" not in message
    (tmp_path / "tailed_legs.toml").write_text(LEGS_FILE)
    robot = load_robot(urdf=urdf)
    assert robot.naming.names("LF").foot == "LF_foot"
    assert len(chains(robot.model)) == 5


def test_two_hips_in_one_quadrant(tmp_path):
    urdf = tmp_path / "bad.urdf"
    # move LH's hip forward: two left-front legs
    urdf.write_text(
        scalf_xml(lambda t: t.replace('origin xyz="-0.68 0.2 -0.15"', 'origin xyz="0.5 0.2 -0.15"'))
    )
    with pytest.raises(ModelError, match="two legs have their hip in the LF quadrant"):
        load_robot(urdf=urdf)


def test_a_leg_without_a_foot(tmp_path):
    urdf = tmp_path / "nofoot.urdf"
    xml = scalf_xml()
    start = xml.index('<joint name="RF_foot_fixed"')
    end = xml.index("</link>", xml.index('<link name="RF_foot"')) + len("</link>")
    urdf.write_text(xml[:start] + xml[end:])
    with pytest.raises(ModelError, match=r"found 3 legs .*RF_knee \(2 joints about y, no foot"):
        load_robot(urdf=urdf)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (
            LEGS_FILE.replace('[legs.RH]\nroll = "RH_hip_roll"', "[other]\nroll = 1"),
            "unknown table other",
        ),
        (LEGS_FILE.replace("[legs.RH]", "[legs.XX]"), "unknown leg legs.XX"),
        (LEGS_FILE.replace('knee = "LF_knee"', ""), "legs.LF.knee must be a URDF name"),
        (LEGS_FILE + "\nankle = 3", "unknown key legs.RH.ankle"),
        (
            LEGS_FILE.replace('pitch = "RF_hip_pitch"', 'pitch = "nope"'),
            "leg RF has no joint 'nope'",
        ),
    ],
)
def test_legs_file_errors(tmp_path, text, match):
    urdf = tmp_path / "s.urdf"
    urdf.write_text(scalf_xml())
    (tmp_path / "s_legs.toml").write_text(text)
    with pytest.raises((ConfigError, ModelError), match=match):
        load_robot(urdf=urdf).leg("RF")

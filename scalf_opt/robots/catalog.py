"""The catalog of known robots: naming convention, URDF, SRDF and actuator files, stance height.

Plain data, cheap to import (the command line reads the robot names from it); loading a robot is
:mod:`scalf_opt.robots.loading`. SCalf's files ship with scalf-opt; the other robots' URDFs and
SRDFs come from example-robot-data, their actuator files ship with scalf-opt (``urdf/``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from scalf_opt.errors import ModelError
from scalf_opt.model.naming import LegNaming
from scalf_opt.robots.files import shipped_file
from scalf_opt.types import LEG_NAMES


@dataclass(frozen=True)
class RobotEntry:
    """One known robot.

    Attributes:
        name: Catalog name (``scalf``, ``hyq``, ``solo12``, ...).
        naming: How its legs' joints and feet are named (the kinematic tree says the same: a
            test checks it).
        nominal_stance_height_m: Pitching hip above the ground when standing [m], the default
            gait's ``stance_height_m``; ``None``: the hip height of the SRDF's standing posture.
        urdf: Returns the path of its URDF.
        summary: One line for listings.
        srdf: Returns the path of its SRDF, whose ``standing`` state is the legs' reference
            posture (IK branch) and standing height; ``None`` when it has none (the joint ranges'
            middle is used).
        actuators: Returns the path of its actuator file, when it is not beside the URDF.
    """

    name: str
    naming: LegNaming
    nominal_stance_height_m: float | None
    urdf: Callable[[], Path]
    summary: str
    srdf: Callable[[], Path] | None = None
    actuators: Callable[[], Path] | None = None

    STANDING_STATE = "standing"


def _example_robot(relative: str) -> Callable[[], Path]:
    def locate() -> Path:
        # imported here: reading the installed distributions' metadata costs tens of ms, and
        # listing the catalog (the command line does) must not pay it
        from scalf_opt.robots.example_robot_data import example_robot_data_dir

        return example_robot_data_dir() / relative

    return locate


def _shipped(name: str) -> Callable[[], Path]:
    return lambda: shipped_file(name)


def _unitree(name: str) -> LegNaming:
    """Unitree's convention (Go1, A1): FR/FL/RR/RL legs, hip (roll), thigh, calf joints."""
    return LegNaming(
        name=name,
        leg_prefix={"RF": "FR", "LF": "FL", "RH": "RR", "LH": "RL"},
        roll_joint="{p}_hip_joint",
        pitch_joint="{p}_thigh_joint",
        knee_joint="{p}_calf_joint",
        foot_frame="{p}_foot",
    )


CATALOG: dict[str, RobotEntry] = {
    entry.name: entry
    for entry in (
        RobotEntry(
            name="scalf",
            naming=LegNaming(
                name="scalf",
                leg_prefix={leg: leg for leg in LEG_NAMES},
                roll_joint="{p}_hip_roll",
                pitch_joint="{p}_hip_pitch",
                knee_joint="{p}_knee",
                foot_frame="{p}_foot",
            ),
            nominal_stance_height_m=0.75,  # decision 6
            urdf=_shipped("scalf.urdf"),
            summary="SCalf, the paper's hydraulic quadruped (shipped with scalf-opt)",
        ),
        RobotEntry(
            name="hyq",
            naming=LegNaming(
                name="hyq",
                leg_prefix={"RF": "rf", "LF": "lf", "RH": "rh", "LH": "lh"},
                roll_joint="{p}_haa_joint",
                pitch_joint="{p}_hfe_joint",
                knee_joint="{p}_kfe_joint",
                foot_frame="{p}_foot",
            ),
            nominal_stance_height_m=None,
            urdf=_example_robot("hyq_description/robots/hyq_no_sensors.urdf"),
            summary="HyQ, IIT's hydraulic quadruped (example-robot-data)",
            srdf=_example_robot("hyq_description/srdf/hyq.srdf"),
            actuators=_shipped("hyq_actuators.toml"),
        ),
        RobotEntry(
            name="solo12",
            naming=LegNaming(
                name="solo12",
                leg_prefix={"RF": "FR", "LF": "FL", "RH": "HR", "LH": "HL"},
                roll_joint="{p}_HAA",
                pitch_joint="{p}_HFE",
                knee_joint="{p}_KFE",
                foot_frame="{p}_FOOT",
            ),
            nominal_stance_height_m=None,
            urdf=_example_robot("solo_description/robots/solo12.urdf"),
            summary="Solo12, ODRI's electric quadruped (example-robot-data)",
            srdf=_example_robot("solo_description/srdf/solo.srdf"),
            actuators=_shipped("solo12_actuators.toml"),
        ),
        RobotEntry(
            name="anymal_c",
            naming=LegNaming(
                name="anymal_c",
                leg_prefix={leg: leg for leg in LEG_NAMES},
                roll_joint="{p}_HAA",
                pitch_joint="{p}_HFE",
                knee_joint="{p}_KFE",
                foot_frame="{p}_FOOT",
            ),
            nominal_stance_height_m=None,
            urdf=_example_robot("anymal_c_simple_description/urdf/anymal.urdf"),
            summary="ANYmal C, ANYbotics' electric quadruped (example-robot-data)",
            srdf=_example_robot("anymal_c_simple_description/srdf/anymal.srdf"),
            actuators=_shipped("anymal_c_actuators.toml"),
        ),
        RobotEntry(
            name="go1",
            naming=_unitree("go1"),
            nominal_stance_height_m=None,
            urdf=_example_robot("go1_description/urdf/go1.urdf"),
            summary="Unitree Go1, electric quadruped (example-robot-data)",
            srdf=_example_robot("go1_description/srdf/go1.srdf"),
            actuators=_shipped("go1_actuators.toml"),
        ),
        RobotEntry(
            name="a1",
            naming=_unitree("a1"),
            nominal_stance_height_m=None,
            urdf=_example_robot("a1_description/urdf/a1.urdf"),
            summary="Unitree A1, electric quadruped (example-robot-data)",
            srdf=_example_robot("a1_description/srdf/a1.srdf"),
            actuators=_shipped("a1_actuators.toml"),
        ),
    )
}


def robot_names() -> tuple[str, ...]:
    """Names of the catalog's robots."""
    return tuple(CATALOG)


def entry(name: str) -> RobotEntry:
    """The catalog entry ``name``.

    Raises:
        ModelError: No such robot; the message lists the known ones.
    """
    if name not in CATALOG:
        raise ModelError(f"unknown robot {name!r}: choose one of {', '.join(CATALOG)}")
    return CATALOG[name]

"""How a robot names its legs' joints and foot frames, and which convention a URDF follows."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

from scalf_opt.errors import ModelError
from scalf_opt.types import LEG_NAMES

if TYPE_CHECKING:
    import pinocchio as pin


class LegJoints(NamedTuple):
    """URDF names of one leg's hip roll, hip pitch and knee joints and its foot frame."""

    roll: str
    pitch: str
    knee: str
    foot: str


@dataclass(frozen=True)
class LegNaming:
    """A naming convention for the legs of one robot family.

    Attributes:
        name: Convention name (the robot family: ``scalf``, ``hyq``, ``solo12``).
        leg_prefix: Map from scalf-opt leg name (RF, LH, LF, RH) to the robot's own prefix.
        roll_joint: Format string of the hip roll (abduction) joint, ``{p}`` is the prefix.
        pitch_joint: Format string of the hip pitch (flexion) joint.
        knee_joint: Format string of the knee joint.
        foot_frame: Format string of the foot frame.
    """

    name: str
    leg_prefix: dict[str, str]
    roll_joint: str
    pitch_joint: str
    knee_joint: str
    foot_frame: str

    def names(self, leg: str) -> LegJoints:
        """The joint and frame names of ``leg``.

        Raises:
            ModelError: ``leg`` is not a leg name.
        """
        if leg not in self.leg_prefix:
            raise ModelError(f"unknown leg {leg!r}: choose one of {', '.join(LEG_NAMES)}")
        p = self.leg_prefix[leg]
        return LegJoints(
            self.roll_joint.format(p=p),
            self.pitch_joint.format(p=p),
            self.knee_joint.format(p=p),
            self.foot_frame.format(p=p),
        )

    def matches(self, model: pin.Model) -> bool:
        """Every leg's three joints exist in ``model``."""
        return all(model.existJointName(n) for leg in LEG_NAMES for n in self.names(leg)[:3])


def detect_naming(model: pin.Model, candidates: Iterable[LegNaming], source: str) -> LegNaming:
    """The first of ``candidates`` whose joint names ``model`` has.

    Raises:
        ModelError: None matches; the message names ``source`` and the conventions tried.
    """
    tried = []
    for naming in candidates:
        if naming.matches(model):
            return naming
        tried.append(naming.name)
    raise ModelError(
        f"{source}: joint names match no known robot ({', '.join(tried)}); "
        "name the legs' joints like SCalf's ({L}_hip_roll, {L}_hip_pitch, {L}_knee, {L}_foot)"
    )

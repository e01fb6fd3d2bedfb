"""How a robot names its legs' joints and foot frames.

Two ways to say it, with one interface (:class:`LegNames`): a naming convention with a prefix per
leg (:class:`LegNaming`, the catalog's robots), or an explicit map from leg to names
(:class:`LegMap`: found in the kinematic tree by :mod:`scalf_opt.model.discovery`, or read from a
legs file by :func:`read_leg_map`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple, Protocol

from scalf_opt.errors import ConfigError, ModelError
from scalf_opt.tables import Table
from scalf_opt.types import LEG_NAMES


class LegJoints(NamedTuple):
    """URDF names of one leg's joints and foot frame (the hip roll is ``None`` if it has none)."""

    roll: str | None
    pitch: str
    knee: str
    foot: str


class LegNames(Protocol):
    """What the robot model needs: a name for messages and the names of each leg."""

    @property
    def name(self) -> str:
        """Where the names come from (a convention, ``discovered``, a file)."""
        ...

    def names(self, leg: str) -> LegJoints:
        """The joint and frame names of ``leg`` (RF, LH, LF, RH)."""
        ...


def _unknown_leg(leg: str) -> ModelError:
    return ModelError(f"unknown leg {leg!r}: choose one of {', '.join(LEG_NAMES)}")


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
            raise _unknown_leg(leg)
        p = self.leg_prefix[leg]
        return LegJoints(
            self.roll_joint.format(p=p),
            self.pitch_joint.format(p=p),
            self.knee_joint.format(p=p),
            self.foot_frame.format(p=p),
        )


@dataclass(frozen=True)
class LegMap:
    """The names of every leg, given one by one.

    Attributes:
        name: Where they come from, for messages (``discovered``, a file's path).
        legs: Leg name (RF, LH, LF, RH) to its names.
    """

    name: str
    legs: dict[str, LegJoints]

    def names(self, leg: str) -> LegJoints:
        """The joint and frame names of ``leg``.

        Raises:
            ModelError: ``leg`` is not a leg name.
        """
        if leg not in self.legs:
            raise _unknown_leg(leg)
        return self.legs[leg]


_LEG_KEYS = ("roll", "pitch", "knee", "foot")


def legs_file_for(urdf_path: Path) -> Path:
    """The optional legs file of a URDF: ``<name>_legs.toml`` beside it."""
    return urdf_path.with_name(f"{urdf_path.stem}_legs.toml")


def read_leg_map(path: Path) -> LegMap:
    """Read a legs file: one ``[legs.<RF|LH|LF|RH>]`` table per leg with the URDF names.

    Keys ``pitch``, ``knee`` (joints) and ``foot`` (a frame: a link or joint name) are required,
    ``roll`` (the hip roll joint) is optional. Whether the names exist is checked when the legs
    are built.

    Raises:
        ConfigError: Unreadable file, a missing leg or key, an unknown key, a name that is not
            text; the message names the file and the key.
    """
    file = Table.read(path, "legs")
    extra = sorted(set(file.data) - {"legs"})
    if extra:
        raise file.error(f"unknown table {extra[0]} (the file has one table, [legs])")
    if not isinstance(file.data.get("legs"), dict):
        raise file.error("missing table [legs] (one [legs.RF], [legs.LH], ... per leg)")
    legs = file.table("legs")
    unknown = sorted(set(legs.data) - set(LEG_NAMES))
    if unknown:
        raise file.error(f"unknown leg legs.{unknown[0]} (legs: {', '.join(LEG_NAMES)})")
    out = {}
    for leg in LEG_NAMES:
        if not isinstance(legs.data.get(leg), dict):
            raise file.error(f"missing table [legs.{leg}]")
        table = legs.table(leg)
        table.only(_LEG_KEYS)
        for key in _LEG_KEYS:
            value = table.data.get(key)
            if value is None and key == "roll":
                continue
            if not isinstance(value, str) or not value:
                raise file.error(f"{table.key(key)} must be a URDF name, got {value!r}")
        given = table.data
        out[leg] = LegJoints(given.get("roll"), given["pitch"], given["knee"], given["foot"])
    seen: dict[str, str] = {}
    for leg, names in out.items():
        for key, name in zip(_LEG_KEYS, names, strict=True):
            if name is None:
                continue
            if name in seen:
                raise ConfigError(
                    f"{path}: legs.{leg}.{key} = {name!r} is already {seen[name]}: each joint "
                    "and foot belongs to one leg, once"
                )
            seen[name] = f"legs.{leg}.{key}"
    return LegMap(str(path), out)

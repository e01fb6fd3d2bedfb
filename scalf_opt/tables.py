"""One validating reader for the tables of every TOML input file (actuator, gait and study files).

A :class:`Table` is one table of a file being read: the file, the table's key path and its
values. Its methods check a key and return its value in the type the reader needs, or raise a
:class:`~scalf_opt.errors.ConfigError` whose one line names the file and the full key path
(``robot_actuators.toml: cylinders.RF_knee.a_mm must be a positive number, got -3``). Every
reader of a TOML file goes through it, so one kind of mistake reads the same in every file.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scalf_opt.errors import ConfigError, did_you_mean
from scalf_opt.files import read_toml

MAX_MAGNITUDE = 1e6
"""Largest magnitude a bounded number may have, in the file's units (mm, deg, bar, N, N s/m, m/s,
N m/A, ohm): far beyond any robot's (SCalf's largest: 4000 N), below where the energy's
arithmetic overflows."""

MIN_POSITIVE = 1e-6
"""Smallest value of a bounded number that must be positive (a torque constant or a stroke of
1e-300 would divide the energy into infinity)."""


def is_number(value: Any, finite: bool = True) -> bool:
    """An integer or a float, finite unless ``finite`` is false (``true`` is not a number)."""
    typed = isinstance(value, int | float) and not isinstance(value, bool)
    return typed and (not finite or math.isfinite(value))


def number_value(path: Path, label: str, value: Any, finite: bool = True) -> float | int:
    """``value``, a TOML number (an entry of a list, say); ``label`` names it in the message.

    Args:
        path: The file.
        label: What the value is (``gait.period_s``, ``gait field period_s``).
        value: The value as parsed.
        finite: Refuse ``nan`` and ``inf`` too (else the caller's range check names them).
    """
    if not is_number(value, finite):
        raise ConfigError(f"{path}: {label} must be a number, got {value!r}")
    return value


@dataclass(frozen=True)
class Table:
    """One table of a TOML file being read.

    Attributes:
        path: The file (named in every message).
        name: The table's key path (``cylinders.RF_knee``); ``""`` for the file's top level.
        data: The table's values, as parsed.
    """

    path: Path
    name: str
    data: Mapping[str, Any]

    @classmethod
    def read(cls, path: str | Path, kind: str) -> Table:
        """The top level of the TOML file ``path``; ``kind`` names the file (``actuator``).

        Raises:
            ConfigError: See :func:`scalf_opt.files.read_toml`.
        """
        return cls(Path(path), "", read_toml(Path(path), kind))

    def key(self, key: str) -> str:
        """The full key path of ``key`` in this table."""
        return f"{self.name}.{key}" if self.name else key

    def error(self, text: str) -> ConfigError:
        """An error about this file: ``<file>: <text>``."""
        return ConfigError(f"{self.path}: {text}")

    def __contains__(self, key: object) -> bool:
        return key in self.data

    def only(self, allowed: Iterable[str]) -> None:
        """Refuse a key that is not in ``allowed`` (the first in sorted order is named)."""
        allowed = tuple(allowed)
        extra = sorted(set(self.data) - set(allowed))
        if extra:
            near = did_you_mean(extra[0], allowed)
            raise self.error(
                f"unknown key {self.key(extra[0])}{near} (allowed: {', '.join(allowed)})"
            )

    def require(self, keys: Iterable[str]) -> None:
        """Refuse the table when one of ``keys`` is missing (the first is named)."""
        for key in keys:
            if key not in self.data:
                raise self.error(f"missing key {self.key(key)}")

    def table(self, key: str) -> Table:
        """The sub-table ``key``, which must be there."""
        if key not in self.data:
            raise self.error(f"missing table [{self.key(key)}]")
        value = self.data[key]
        if not isinstance(value, dict):
            raise self.error(f"{self.key(key)} must be a table, got {value!r}")
        return Table(self.path, self.key(key), value)

    def tables(self, key: str) -> dict[str, Table]:
        """The named tables under ``key`` (``[electric.<name>]``), in file order; ``{}`` without."""
        if key not in self.data:
            return {}
        group = self.table(key)
        return {name: group.table(name) for name in group.data}

    def number(
        self,
        key: str,
        positive: bool = True,
        zero: bool = False,
        default: float | None = None,
        bounded: bool = True,
    ) -> float:
        """A finite number.

        Args:
            key: The key; it must be there unless ``default`` is given.
            positive: It must be above zero (at or above with ``zero``).
            zero: With ``positive``: zero is allowed.
            default: The value when the key is left out.
            bounded: Its magnitude is at most :data:`MAX_MAGNITUDE` and, when positive, at
                least :data:`MIN_POSITIVE`.
        """
        if key not in self.data and default is not None:
            return default
        self.require((key,))
        value = self.data[key]
        if not is_number(value) or (positive and (value < 0 if zero else value <= 0)):
            need = "a number >= 0" if zero else "a positive number" if positive else "a number"
            raise self.error(f"{self.key(key)} must be {need}, got {value!r}")
        if bounded and (abs(value) > MAX_MAGNITUDE or (positive and 0 < value < MIN_POSITIVE)):
            low = "0" if zero else f"{MIN_POSITIVE:g}" if positive else f"{-MAX_MAGNITUDE:g}"
            raise self.error(
                f"{self.key(key)} = {value!r} is out of range [{low}, {MAX_MAGNITUDE:g}] "
                "(in the file's units)"
            )
        return float(value)

    def integer(self, key: str, label: str | None = None) -> int:
        """An integer (``1.0`` and ``true`` are not); ``label`` replaces the key in messages."""
        self.require((key,))
        value = self.data[key]
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(f"{label or self.key(key)} must be an integer, got {value!r}")
        return value

    def sign(self, key: str) -> int:
        """``+1`` or ``-1``."""
        self.require((key,))
        value = self.data[key]
        if isinstance(value, bool) or not isinstance(value, int) or value not in (1, -1):
            raise self.error(f"{self.key(key)} must be +1 or -1, got {value!r}")
        return value

    def boolean(self, key: str, default: bool) -> bool:
        """``true`` or ``false``; ``default`` when left out."""
        value = self.data.get(key, default)
        if not isinstance(value, bool):
            raise self.error(f"{self.key(key)} must be true or false")
        return value

    def names(self, key: str, what: str = "joint names") -> list[str]:
        """A non-empty list of non-empty texts (``joints = ["RF_knee", ...]``)."""
        self.require((key,))
        value = self.data[key]
        if (
            not isinstance(value, list)
            or not value
            or not all(isinstance(v, str) and v for v in value)
        ):
            raise self.error(f"{self.key(key)} must be a non-empty list of {what}")
        return value

    def text(self, key: str, max_length: int | None = None) -> str | None:
        """A non-empty text (of at most ``max_length`` characters); ``None`` when left out."""
        if key not in self.data:
            return None
        value = self.data[key]
        short = max_length is None or (isinstance(value, str) and len(value) <= max_length)
        if not isinstance(value, str) or not value or not short:
            most = f" of at most {max_length} characters" if max_length is not None else ""
            raise self.error(f"{self.key(key)} must be a non-empty text{most}, got {value!r}")
        return value

"""Drive kinds of the actuator file, in reading order: :data:`DRIVE_KINDS`.

A kind (:class:`~scalf_opt.actuators.drive.DriveKind`) names the top-level tables of the
actuator file it reads and the reader that turns them into drives. A new drive is one module
(its :class:`~scalf_opt.actuators.drive.Drive` subclass and its reader, as
:mod:`scalf_opt.actuators.electric` is) and one line here, or one :func:`register_drive_kind`
call from outside the package: the actuator file then takes its table, and every command its
drives (the tests add a toy drive and evaluate and optimize a robot with it).
"""

from __future__ import annotations

from scalf_opt.actuators.cylinder import CYLINDERS
from scalf_opt.actuators.drive import DriveKind
from scalf_opt.actuators.electric import MOTORS
from scalf_opt.actuators.valve_cylinder import SUPPLIES
from scalf_opt.errors import ConfigError

DRIVE_KINDS: list[DriveKind] = [CYLINDERS, SUPPLIES, MOTORS]
"""Every kind of drive, read in this order (a supply replaces the cylinders read before it)."""

OTHER_TABLES = ("sources",)
"""Top-level tables of the actuator file that no drive kind reads."""


def register_drive_kind(kind: DriveKind) -> None:
    """Add a kind of drive, read after those already there.

    Raises:
        ConfigError: One of its tables is already another kind's.
    """
    taken = {t for k in DRIVE_KINDS for t in k.tables} | set(OTHER_TABLES)
    clash = sorted(set(kind.tables) & taken)
    if clash:
        raise ConfigError(f"actuator table [{clash[0]}] is already read by another drive kind")
    DRIVE_KINDS.append(kind)


def file_tables() -> tuple[str, ...]:
    """Every top-level table an actuator file may have."""
    return (*(t for k in DRIVE_KINDS for t in k.tables), *OTHER_TABLES)

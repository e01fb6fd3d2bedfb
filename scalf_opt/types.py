"""Names shared by every layer: the modes as ``Literal`` types, leg names, the CasADi alias.

The fixed modes (space, phase) are ``Literal`` types; the extensible ones (accounting, solver)
are names checked against their registries in the floors that define them. A ``Literal``'s allowed
values are read from the type with :func:`choices`, so the command line, the file readers and the
code agree on one list. :func:`check_choice` turns a wrong value into a one-line
:class:`~scalf_opt.errors.ConfigError` that names the field.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any, Literal, TypeAlias, get_args

from scalf_opt.errors import ConfigError

Expr: TypeAlias = Any
"""A CasADi expression or value: SX, MX or DM (or a float where a formula accepts it).

CasADi's type stubs treat SX, MX and DM as unrelated classes, while every formula in scalf-opt is
written once for all three; the alias says so instead of a union that the stubs cannot follow."""

LegName = Literal["RF", "LH", "LF", "RH"]
"""Right/left, front/hind."""

LEG_NAMES: tuple[str, ...] = get_args(LegName)
"""The one leg order of every table, file and loop: the paper's diagonal pair RF + LH first (it
starts the cycle in stance), then LF and RH, which repeat them half a cycle later."""

FIRST_PAIR: tuple[str, ...] = LEG_NAMES[:2]
"""The diagonal pair in stance first (RF, LH): the legs the paper reports."""

Space = Literal["foot", "joint"]
"""What a path's coordinates are: the foot ``(x, z)`` in the leg frame [m], or the joint angles
``(hip pitch, knee)`` [rad]."""

Phase = Literal["stance", "swing"]
"""A leg's phase in the gait cycle (stance first)."""

PHASES: tuple[Phase, ...] = get_args(Phase)

Accounting: TypeAlias = str
"""The name of a power accounting: how signed joint power ``tau qd`` is charged (``paper``
``|tau qd|``, decision 9, the default; ``positive``; ``regenerative``). The names and what each
charges live in one registry, :data:`scalf_opt.energy.accounting.ACCOUNTINGS`."""

Method: TypeAlias = str
"""The name of a swing solver (``ipopt``, the default, or ``pattern``, the paper's pattern
search). The names live in one registry, :data:`scalf_opt.optimize.solvers.SOLVERS`."""

JOINT_ROLES: tuple[str, str] = ("hip", "knee")
"""The two joints of the sagittal leg, in vector order (hip pitch first)."""


def choices(kind: Any) -> tuple[str, ...]:
    """The allowed values of a ``Literal`` mode, e.g. ``choices(Space)``."""
    return tuple(get_args(kind))


def check_choice(value: object, kind: Any, field: str) -> str:
    """Return ``value`` if it is one of ``kind``'s values, else raise a one-line error.

    Args:
        value: What the user gave.
        kind: A ``Literal`` type (``Space``, ``Phase``, ...).
        field: Name of the field or option, for the message.

    Raises:
        ConfigError: ``value`` is not allowed; the message names ``field`` and the choices.
    """
    allowed = choices(kind)
    if value not in allowed:
        raise ConfigError(f"{field} = {value!r} is not one of {', '.join(allowed)}", field=field)
    return str(value)


def leg_tuple(legs: str | Sequence[str], field: str = "legs") -> tuple[str, ...]:
    """Legs as a user gives them, in :data:`LEG_NAMES`' spelling.

    One name or ``pair`` (RF and LH), or a sequence of names; any case, each leg once.

    Raises:
        ConfigError: An unknown leg (the message names ``field`` and the legs), a leg twice, or
            no leg.
    """
    try:
        given = [legs] if isinstance(legs, str) else list(legs)
    except TypeError:  # a number, None: not a leg nor a sequence of them
        raise ConfigError(f"{field}: give a leg name or names, got {legs!r}", field=field) from None
    if len(given) == 1 and isinstance(given[0], str) and given[0].upper() == "PAIR":
        return FIRST_PAIR
    names = []
    for leg in given:
        name = leg.upper() if isinstance(leg, str) else leg
        if name not in LEG_NAMES:
            raise ConfigError(
                f"{field}: unknown leg {leg!r} (legs: {', '.join(LEG_NAMES)}, or pair)",
                field=field,
            )
        if name in names:
            raise ConfigError(f"{field}: leg {name} given twice", field=field)
        names.append(name)
    if not names:
        raise ConfigError(f"{field}: no leg given", field=field)
    return tuple(names)


_NOT_IDENTIFIER = re.compile(r"[^A-Za-z0-9]+")


def casadi_name(*parts: str) -> str:
    """A valid CasADi function name from arbitrary parts (letters, digits, single underscores).

    URDF names may hold any character (``LH-foot``, ``genou_gauche_é``); CasADi accepts a letter
    followed by letters, digits and single underscores, and refuses ``null``, ``jac`` and
    ``hess``.
    """
    name = _NOT_IDENTIFIER.sub("_", "_".join(parts)).strip("_")
    if not name[:1].isalpha() or name in ("null", "jac", "hess"):
        name = f"f_{name}".rstrip("_")
    return name

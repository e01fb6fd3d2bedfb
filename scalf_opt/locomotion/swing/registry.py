"""Swing families by name, from a registry of kinds: :data:`FAMILY_KINDS`.

A kind is a name pattern, the factory that builds a family from a matching name, one line of
help for the error an unknown name gets, and the names it suggests for a near miss. The built-in
kinds are ``reference``, ``paper``, ``fourier-N`` and ``joint-N`` (N in 2..12) and the
free-trajectory bound's ``bspline-K``. A new family is one module and one
:func:`register_family_kind` call: every command, study file and saved result then takes its
name (the tests add a toy kind and optimize with it end to end).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from scalf_opt.errors import ConfigError, did_you_mean
from scalf_opt.locomotion.swing.bspline import BSplineFamily
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.locomotion.swing.fourier import PAPER_FREE_TERMS, FourierFamily, order_terms
from scalf_opt.locomotion.swing.names import BSPLINE_PATTERN, MAX_ORDER, MIN_ORDER
from scalf_opt.locomotion.swing.reference import ReferenceSpline
from scalf_opt.types import Space


@dataclass(frozen=True)
class FamilyKind:
    """One kind of swing family in the registry.

    Attributes:
        pattern: The names of this kind (matched whole).
        build: The family of a matching name (may refuse it: an order out of range).
        help: How the kind's names are written, for the error an unknown name gets.
        names: The kind's names, suggested for a near miss (a few, not necessarily all).
    """

    pattern: re.Pattern[str]
    build: Callable[[re.Match[str]], SwingFamily]
    help: str
    names: tuple[str, ...] = ()


def _fourier(match: re.Match[str]) -> SwingFamily:
    order = int(match.group(2))
    if not MIN_ORDER <= order <= MAX_ORDER:
        raise ConfigError(
            f"family {match.group(0)!r}: order N must be in {MIN_ORDER}..{MAX_ORDER}, got {order}",
            field="family",
        )
    terms = order_terms(order)
    space: Space = "foot" if match.group(1) == "fourier" else "joint"
    return FourierFamily(match.group(0), space, (terms, terms), modes=True)


FAMILY_KINDS: list[FamilyKind] = [
    FamilyKind(re.compile("reference"), lambda _: ReferenceSpline(), "reference", ("reference",)),
    FamilyKind(
        re.compile("paper"),
        lambda _: FourierFamily("paper", "joint", PAPER_FREE_TERMS),
        "paper",
        ("paper",),
    ),
    FamilyKind(
        re.compile(r"(fourier|joint)-(\d+)"),
        _fourier,
        f"fourier-N (foot space) or joint-N (joint space) with N in {MIN_ORDER}..{MAX_ORDER}",
        tuple(
            f"{kind}-{n}" for kind in ("joint", "fourier") for n in range(MIN_ORDER, MAX_ORDER + 1)
        ),
    ),
    FamilyKind(
        BSPLINE_PATTERN,
        lambda match: BSplineFamily(int(match.group(1))),
        "",  # the free-trajectory bound's own: not offered to a user
    ),
]
"""Every kind of swing family, tried in order (:func:`make_family`)."""


def register_family_kind(kind: FamilyKind) -> None:
    """Add a kind of swing family; its names then work wherever a family is named.

    Raises:
        ConfigError: A kind already takes one of its suggested names.
    """
    for name in kind.names:
        for other in FAMILY_KINDS:
            if other.pattern.fullmatch(name):
                raise ConfigError(f"family kind {kind.help!r}: {name!r} is already a family name")
    FAMILY_KINDS.append(kind)


def make_family(name: str, also: Iterable[str] = ()) -> SwingFamily:
    """Build a family from its name (:data:`FAMILY_KINDS`).

    ``also``: other names the caller accepts (``free``), among the suggestions for an unknown
    name.

    Raises:
        ConfigError: An unknown name (the kinds' ways of writing one, and the nearest names), or
            one its kind refuses (an order outside 2..12).
    """
    for kind in FAMILY_KINDS:
        match = kind.pattern.fullmatch(str(name))
        if match:
            return kind.build(match)
    also = tuple(also)
    helps = [kind.help for kind in FAMILY_KINDS if kind.help]
    known = [n for kind in FAMILY_KINDS for n in kind.names] + list(also)
    ways = ", ".join(helps)
    raise ConfigError(
        f"unknown family {name!r}: use {ways}{''.join(f', or {other}' for other in also)}"
        f"{did_you_mean(str(name), known)}",
        field="family",
    )


def check_optimizable(family: SwingFamily) -> SwingFamily:
    """``family``, when it has parameters to optimize (every family but the reference).

    Raises:
        ConfigError: It has none (the message names the field ``family``).
    """
    if family.n_params == 0:
        raise ConfigError(
            f"family {family.name!r} has no free parameter to optimize", field="family"
        )
    return family


def optimizable_family(name: str) -> SwingFamily:
    """The family ``name`` names, when it has parameters to optimize (:func:`make_family`).

    Raises:
        ConfigError: Unknown name, or a family without parameters.
    """
    return check_optimizable(make_family(name))

"""Swing families by name: ``reference``, ``paper``, ``fourier-N`` and ``joint-N``."""

from __future__ import annotations

from collections.abc import Iterable

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.swing.bspline import BSplineFamily
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.locomotion.swing.fourier import PAPER_FREE_TERMS, FourierFamily, order_terms
from scalf_opt.locomotion.swing.names import parse_bspline_name, parse_fourier_name
from scalf_opt.locomotion.swing.reference import ReferenceSpline


def make_family(name: str, also: Iterable[str] = ()) -> SwingFamily:
    """Build a family from its name.

    ``reference``, ``paper``, ``fourier-N``, ``joint-N``, or ``bspline-K`` (the
    free-trajectory bound's dense B-splines). ``also``: other names the caller accepts, among
    the suggestions for an unknown name.

    Raises:
        ConfigError: Unknown name or an order outside 2..12.
    """
    if name == "reference":
        return ReferenceSpline()
    if name == "paper":
        return FourierFamily("paper", "joint", PAPER_FREE_TERMS)
    spans = parse_bspline_name(name)
    if spans is not None:
        return BSplineFamily(spans)
    space, order = parse_fourier_name(name, also)
    terms = order_terms(order)
    return FourierFamily(name, space, (terms, terms))


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

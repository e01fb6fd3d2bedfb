r"""Power accountings: how a joint's signed mechanical power ``p = tau qd`` is charged.

Each accounting is one object that knows three things, so that nothing else in scalf-opt asks
which accounting it has:

* its **exact** charge ``A(p)`` (what every report prints; non-smooth);
* its **smooth NLP form**: the slack variables per charged joint and sample that make ``A(p)``
  smooth without changing its value at an optimum, their linear constraints against ``p``, the
  cost they add, and a consistent start for them;
* whether the swing energy is **bounded below** by something an optimizer can minimise when the
  drives lose nothing (see :meth:`Accounting.optimizable_without_losses`).

The three accountings (decision 9):

.. math::

    A_\text{paper}(p) = |p|, \qquad A_\text{positive}(p) = \max(p, 0), \qquad
    A_\text{regenerative}(p) = p.

A new accounting is one subclass here and one line in :data:`ACCOUNTINGS`; the command line's
choices, the file readers and the NLP read that registry.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import ClassVar

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.types import Expr

AbsFn = Callable[[Expr], Expr] | None
"""An absolute value to use instead of CasADi's ``fabs`` (``None``: ``fabs``)."""


def _fabs(x: Expr) -> Expr:
    import casadi as ca  # here: the registry's names load without CasADi (the command line)

    return ca.fabs(x)


def _fmax0(x: Expr) -> Expr:
    import casadi as ca

    return ca.fmax(x, 0)


class PowerAccounting(ABC):
    """How signed joint power is charged (exact and smooth forms)."""

    name: ClassVar[str]
    description: ClassVar[str]
    slacks: ClassVar[int]
    """Slack variables per charged joint and sample in the NLP."""

    @abstractmethod
    def charge(self, power_w: Expr, abs_fn: AbsFn = None) -> Expr:
        """The exact charged power ``A(p)`` [W] of a signed joint power ``p`` [W]."""

    def slack_rows(self, power_w: Expr, slacks: list[Expr]) -> Expr | None:
        """The slacks' linear constraint rows against ``p`` (``None`` without slacks)."""
        return None

    def slack_row_bounds(self) -> tuple[float, float]:
        """Lower and upper bound of every slack row."""
        return 0.0, 0.0

    def smooth_cost(self, power_w: Expr, slacks: list[Expr]) -> Expr:
        """The NLP's per-sample cost of the charged joints (rows: joints, columns: samples)."""
        return power_w

    def initial_slacks(self, power_w: np.ndarray) -> list[np.ndarray]:
        """Slack values consistent with a start whose signed powers are ``power_w``."""
        return []

    def optimizable_without_losses(self) -> bool:
        """Whether the swing energy still depends on the swing when the drives lose nothing.

        ``False`` for an accounting under which the charged power integrates to the change of
        the leg's mechanical energy, the same for every swing between the same end states.
        """
        return True


class AbsolutePower(PowerAccounting):
    """``|tau qd|``: the paper's (decision 9); slacks ``s+ - s- = p``, cost ``s+ + s-``."""

    name = "paper"
    description = "|tau qd|: positive and negative work both cost (the paper's)"
    slacks = 2

    def charge(self, power_w: Expr, abs_fn: AbsFn = None) -> Expr:  # noqa: D102
        return (abs_fn or _fabs)(power_w)

    def slack_rows(self, power_w: Expr, slacks: list[Expr]) -> Expr | None:  # noqa: D102
        return slacks[0] - slacks[1] - power_w

    def smooth_cost(self, power_w: Expr, slacks: list[Expr]) -> Expr:  # noqa: D102
        return slacks[0] + slacks[1]

    def initial_slacks(self, power_w: np.ndarray) -> list[np.ndarray]:  # noqa: D102
        return [np.maximum(power_w, 0.0), np.maximum(-power_w, 0.0)]


class PositivePower(PowerAccounting):
    """``max(tau qd, 0)``: negative work is free; slack ``u >= p``, ``u >= 0``, cost ``u``."""

    name = "positive"
    description = "max(tau qd, 0): negative work costs nothing"
    slacks = 1

    def charge(self, power_w: Expr, abs_fn: AbsFn = None) -> Expr:  # noqa: D102
        return _fmax0(power_w)

    def slack_rows(self, power_w: Expr, slacks: list[Expr]) -> Expr | None:  # noqa: D102
        return slacks[0] - power_w

    def slack_row_bounds(self) -> tuple[float, float]:  # noqa: D102
        return 0.0, np.inf

    def smooth_cost(self, power_w: Expr, slacks: list[Expr]) -> Expr:  # noqa: D102
        return slacks[0]

    def initial_slacks(self, power_w: np.ndarray) -> list[np.ndarray]:  # noqa: D102
        return [np.maximum(power_w, 0.0)]


class SignedPower(PowerAccounting):
    """``tau qd``: negative work is recovered; smooth as it is."""

    name = "regenerative"
    description = "tau qd: negative work is recovered"
    slacks = 0

    def charge(self, power_w: Expr, abs_fn: AbsFn = None) -> Expr:  # noqa: D102
        return power_w

    def optimizable_without_losses(self) -> bool:  # noqa: D102
        # the work-energy theorem: the integral of tau qd over a swing is the change of the
        # leg's mechanical energy, fixed by the swing's end states (the leg frame is inertial)
        return False


ACCOUNTINGS: dict[str, PowerAccounting] = {
    a.name: a for a in (AbsolutePower(), PositivePower(), SignedPower())
}
"""Every accounting by name (the choices of ``--accounting``, in this order)."""

PAPER_ACCOUNTING = AbsolutePower.name
"""The paper's accounting (decision 9), everybody's default."""


def accounting(name: str) -> PowerAccounting:
    """The accounting called ``name``.

    Raises:
        ConfigError: No accounting has that name; the message lists the choices.
    """
    if name not in ACCOUNTINGS:
        raise ConfigError(
            f"accounting = {name!r} is not one of {', '.join(ACCOUNTINGS)}", field="accounting"
        )
    return ACCOUNTINGS[name]

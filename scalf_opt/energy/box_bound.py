"""A box bound on one per-sample quantity of a leg: what every actuator limit is made of.

:mod:`scalf_opt.energy.limits` builds a leg's bounds from its URDF and drives,
:mod:`scalf_opt.energy.margins` keeps a plan inside them, the optimizers turn them into
constraints and the reports into violations; all of them speak of :class:`Bound`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from scalf_opt.types import JOINT_ROLES

LIMIT_TOLERANCE = 1e-9
"""Relative round-off allowed beyond a bound before a sample counts as exceeding it."""

PRINTED_UNITS = {
    "nm": "N m",
    "rad_s": "rad/s",
    "n": "N",
    "m_s": "m/s",
    "w": "W",
    "m": "m",
    "rad": "rad",
}
"""Column-name units (:attr:`Bound.unit`) as printed for people."""


def printed_unit(unit: str) -> str:
    """A column-name unit as printed for people (``N m`` for ``nm``)."""
    return PRINTED_UNITS.get(unit, unit)


@dataclass(frozen=True)
class Bound:
    """A box bound ``lower <= value <= upper`` on one per-sample quantity of a leg.

    Attributes:
        output: Name of the per-sample output (:attr:`LegPhysics.output_names`): ``q``, ``qd``,
            ``tau`` (two rows, hip and knee) or a drive output (``cyl_force_hip``, one row).
        row: Row of a two-row output (the joint), ``None`` for a one-row drive output.
        joint: The joint it belongs to: 0 hip pitch, 1 knee.
        lower: Lower bound (SI, the output's unit; may be ``-inf``).
        upper: Upper bound (may be ``inf``).
        source: Where the bound comes from, for messages (``URDF effort limit``).
        unit: Unit as in column names (``rad``, ``rad_s``, ``nm``, ``m``, ``n``, ``m_s``).
    """

    output: str
    row: int | None
    joint: int
    lower: float
    upper: float
    source: str
    unit: str

    @property
    def size(self) -> float:
        """What an excess is measured against: the larger magnitude of the finite ends, or 1."""
        ends = [abs(x) for x in (self.lower, self.upper) if math.isfinite(x)]
        return max(ends, default=0.0) or 1.0

    @property
    def printed_unit(self) -> str:
        """The unit as printed for people (``N m`` for ``nm``)."""
        return printed_unit(self.unit)

    @property
    def quantity(self) -> str:
        """The quantity without the joint: ``q``, ``qd``, ``tau``, ``cyl_force``."""
        suffix = f"_{JOINT_ROLES[self.joint]}"
        return self.output[: -len(suffix)] if self.output.endswith(suffix) else self.output

    @property
    def name(self) -> str:
        """Quantity and joint, e.g. ``tau_hip``, ``cyl_force_knee``."""
        return f"{self.quantity}_{JOINT_ROLES[self.joint]}"

    @property
    def symmetric(self) -> bool:
        """A limit on the magnitude: ``lower == -upper``."""
        return self.lower == -self.upper

    def select(self, outputs: dict[str, Any]) -> Any:
        """The bounded quantity from per-sample outputs: numeric arrays or CasADi expressions."""
        value = outputs[self.output]
        return value[self.row] if self.row is not None else value

    def values(self, outputs: dict[str, np.ndarray]) -> np.ndarray:
        """The bounded quantity's samples, shape (n,), from a phase's output arrays."""
        return np.asarray(self.select(outputs), dtype=float).ravel()

    def excess(self, value: np.ndarray) -> np.ndarray:
        """How far each sample lies beyond the bound (0 inside), in the bound's unit."""
        return np.maximum(np.maximum(self.lower - value, value - self.upper), 0.0)

    def tolerance(self) -> float:
        """Round-off allowed beyond the bound: relative to its size, at least 1e-9."""
        finite = [abs(b) for b in (self.lower, self.upper) if math.isfinite(b)]
        return LIMIT_TOLERANCE * max([1.0, *finite])

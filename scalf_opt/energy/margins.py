"""The margins an optimized plan keeps inside the joint range and the cylinder stroke.

A plan that rides an end stop is one no servo can follow: the smallest tracking error puts the
joint on its stop, whose reaction the energy model does not have (a free-stance optimum planned
1.5 mrad from SCalf's knee stop went 3 mrad beyond it in the simulation, where the stop and the
contacts dissipated 13 J per cycle). Every optimizer (the NLP, the pattern search, the bound, the
free stance) applies :meth:`LimitMargins.apply` to the bounds of
:func:`~scalf_opt.energy.limits.leg_bounds`; the reports check the limits themselves.

This module imports nothing heavy, so the command line reads its defaults at start-up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from scalf_opt.errors import ConfigError

if TYPE_CHECKING:
    from scalf_opt.energy.box_bound import Bound

DEFAULT_STOP_MARGIN_RAD = math.radians(2.0)
"""Default margin of a planned joint angle to either end of the joint range [rad]: 2 degrees.

The trot simulation's servo (:mod:`scalf_opt.sim`) tracks the reference swing within 0.5 degrees
on SCalf and within 2.1 degrees on every robot (ANYmal C's knee) with the trunk-only loads,
``docs/simulation-referee.md``."""

FULL_TURN_RAD = 2 * math.pi
"""A joint range at least this wide has no end stop to keep a margin from [rad]."""

DEFAULT_STROKE_MARGIN_M = 0.002
"""Default margin of a planned cylinder length to either end of its stroke [m]: 2 mm (about
2 degrees of SCalf's knee)."""


@dataclass(frozen=True)
class LimitMargins:
    """How far inside the joint range and the cylinder stroke an optimized plan stays.

    Attributes:
        stop_rad: Margin of every joint angle to either end of its range [rad].
        stroke_m: Margin of every drive length (a cylinder's) to either end of its stroke [m].
    """

    stop_rad: float = DEFAULT_STOP_MARGIN_RAD
    stroke_m: float = DEFAULT_STROKE_MARGIN_M

    def __post_init__(self) -> None:
        for name in ("stop_rad", "stroke_m"):
            value = getattr(self, name)
            ok = isinstance(value, int | float) and not isinstance(value, bool)
            if not (ok and math.isfinite(value) and value >= 0):
                raise ConfigError(f"limit margin {name} = {value!r} must be >= 0", field=name)

    def margin(self, bound: Bound) -> float:
        """The margin this bound gets (SI, the bound's unit).

        0 for a rate, torque or force, and for a joint range of a full turn or more: that is no
        end stop a joint can ride but a URDF's placeholder (Solo12's and ANYmal C's +-10 rad).
        """
        if bound.output == "q":
            return self.stop_rad if bound.upper - bound.lower < FULL_TURN_RAD else 0.0
        if bound.row is None and bound.unit == "m":  # a drive's length: the stroke
            return self.stroke_m
        return 0.0

    def apply(self, bounds: tuple[Bound, ...]) -> tuple[Bound, ...]:
        """The bounds moved inwards by their margins (a finite end only).

        Raises:
            ConfigError: A margin that leaves no room: the two ends would cross.
        """
        out = []
        for b in bounds:
            m = self.margin(b)
            if m == 0.0:
                out.append(b)
                continue
            lower = b.lower + m if math.isfinite(b.lower) else b.lower
            upper = b.upper - m if math.isfinite(b.upper) else b.upper
            if lower >= upper:
                field = "stop_rad" if b.output == "q" else "stroke_m"
                raise ConfigError(
                    f"limit margin {field} = {m:g} leaves no room in {b.name}'s {b.source} "
                    f"[{b.lower:g}, {b.upper:g}] {b.unit}",
                    field=field,
                )
            out.append(replace(b, lower=lower, upper=upper, source=f"{b.source}, less margin"))
        return tuple(out)

    def to_dict(self) -> dict[str, float]:
        """The margins at the edges' units: ``stop_margin_deg``, ``stroke_margin_mm``."""
        return {
            "stop_margin_deg": math.degrees(self.stop_rad),
            "stroke_margin_mm": 1e3 * self.stroke_m,
        }


DEFAULT_MARGINS = LimitMargins()
"""The margins every optimizer keeps unless told otherwise."""

NO_MARGINS = LimitMargins(0.0, 0.0)
"""The limits themselves."""

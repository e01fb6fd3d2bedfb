"""The limits a leg's motion must respect, as box bounds on its per-sample quantities.

One list per leg, :func:`leg_bounds`, read once from the leg and its drives, serves everything
that checks a limit: the optimizers' constraints (the NLP and the pattern search), the
feasibility of a stance, and the peaks and violations the reports print.

* the joint range (URDF ``lower``/``upper``) on ``q`` [rad];
* the joint velocity limit (URDF ``velocity``) on ``|qd|`` [rad/s];
* the joint effort limit (URDF ``effort``) on ``|tau|`` [N m];
* every bound a joint's drive declares (:meth:`~scalf_opt.actuators.drive.Drive.output_bounds`;
  SCalf's cylinder: its stroke on the length, its force and speed limits).

A URDF velocity or effort limit that is not a positive finite number means "no limit".

The optimizers (the NLP, the pattern search, the bound, the free stance) keep a margin inside
the joint range and the cylinders' stroke (:mod:`scalf_opt.energy.margins`): a plan that rides an
end stop is one no servo can follow. The reports check the limits themselves (:func:`leg_bounds`
as it is).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scalf_opt.energy.box_bound import (  # noqa: F401  (the bound is the limits' unit)
    LIMIT_TOLERANCE,
    PRINTED_UNITS,
    Bound,
    printed_unit,
)
from scalf_opt.energy.margins import (  # noqa: F401  (the margins live beside the limits)
    DEFAULT_MARGINS,
    DEFAULT_STOP_MARGIN_RAD,
    DEFAULT_STROKE_MARGIN_M,
    NO_MARGINS,
    LimitMargins,
)
from scalf_opt.energy.physics import LegPhysics


def _urdf_limit(value: float) -> float | None:
    return float(value) if math.isfinite(value) and value > 0 else None


def leg_bounds(physics: LegPhysics) -> tuple[Bound, ...]:
    """Every bound of a leg's per-sample quantities: joint range, URDF limits, drive bounds.

    Order: per joint (hip, knee) the range, velocity and effort limits; then the drives'
    bounds in the order of the drive outputs (the ``samples.csv`` column order).
    """
    leg = physics.leg
    lo, hi = leg.lower_limits_rad, leg.upper_limits_rad
    out: list[Bound] = []
    for j in range(2):
        out.append(Bound("q", j, j, float(lo[j]), float(hi[j]), "joint range (URDF)", "rad"))
        velocity = _urdf_limit(leg.velocity_limits_rad_s[j])
        if velocity is not None:
            out.append(Bound("qd", j, j, -velocity, velocity, "URDF velocity limit", "rad_s"))
        effort = _urdf_limit(leg.effort_limits_nm[j])
        if effort is not None:
            out.append(Bound("tau", j, j, -effort, effort, "URDF effort limit", "nm"))
    for output in physics.drive_outputs:
        drive = physics.drives[output.joint]
        bounds = drive.output_bounds(float(lo[output.joint]), float(hi[output.joint]))
        if output.channel.name in bounds:
            b_lo, b_hi = bounds[output.channel.name]
            source = f"{drive.kind} {output.channel.name} limit (actuator file)"
            out.append(
                Bound(output.name, None, output.joint, b_lo, b_hi, source, output.channel.unit)
            )
    return tuple(out)


@dataclass(frozen=True)
class Violation:
    """The worst sample of a quantity beyond its bound.

    Attributes:
        bound: The bound.
        value: The quantity at the worst sample (SI).
        index: Index of that sample.
        excess: How far beyond the bound (SI, > tolerance).
    """

    bound: Bound
    value: float
    index: int
    excess: float

    @property
    def share(self) -> float:
        """The excess as a share of the bound's size."""
        return self.excess / self.bound.size


def violations(outputs: dict[str, np.ndarray], bounds: tuple[Bound, ...]) -> list[Violation]:
    """Bounds that some sample exceeds (by more than the round-off tolerance), worst sample each."""
    out = []
    for bound in bounds:
        value = bound.values(outputs)
        excess = bound.excess(value)
        k = int(np.argmax(excess)) if excess.size else 0
        if excess.size and excess[k] > bound.tolerance():
            out.append(Violation(bound, float(value[k]), k, float(excess[k])))
    return out

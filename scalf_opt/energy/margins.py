"""The margins an optimized plan keeps inside its limits and above the ground.

A plan that rides an end stop is one no servo can follow: the smallest tracking error puts the
joint on its stop, whose reaction the energy model does not have (a free-stance optimum planned
1.5 mrad from SCalf's knee stop went 3 mrad beyond it in the simulation, where the stop and the
contacts dissipated 13 J per cycle). Every optimizer (the NLP, the pattern search, the bound, the
free stance, the gait search) applies :meth:`LimitMargins.apply` to the bounds of
:func:`~scalf_opt.energy.limits.leg_bounds`; the reports check the limits themselves.

The same holds for effort: a plan on its torque or force limit leaves the servo nothing to
correct with (ANYmal C's optimum rode its 80 N m limit and was saturated 5-9 % of the time in
the simulation), so torques and drive forces keep a share of the limit in reserve. And for the
ground: a swing foot that leaves the ground at a grazing angle skims it in any servo's lag
(SCalf's optimum's hind feet were 0.1 mm up 5 ms after lift-off), so the swing follows a
:class:`LiftProfile`.

This module imports nothing heavy, so the command line reads its defaults at start-up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from scalf_opt.errors import ConfigError

if TYPE_CHECKING:
    from scalf_opt.energy.box_bound import Bound
    from scalf_opt.locomotion.gait import Gait

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

DEFAULT_EFFORT_SHARE = 0.05
"""Default share of each effort and force limit (a joint's torque, a cylinder's force) a plan
keeps in reserve for the servo: it stays within 95 % of the limit."""

DEFAULT_LIFT_SHARE = 0.2
"""Default lift height as a share of the gait's mid-swing clearance H: H/5 (16 mm on SCalf's
H = 80 mm; H itself is Froude-scaled to each robot's leg length)."""

DEFAULT_LIFT_FRACTION = 0.15
"""Default share of the swing over which the foot lifts to, and comes down from, the lift height.
With the default height and touch-down speed, the paper's reference swing keeps the profile on
every robot (Froude-scaled, the same shape): it is 17.3 mm up at 15 % of SCalf's swing, above
16 mm (s / 0.15)^2 all the way, and comes down at up to 2.52 H / T_sw over the last 15 %. So no
optimum need be dearer than the reference for its lift; a profile the reference breaks made
``joint-3`` optima up to 40 % dearer than it (measured: ``docs/speed-log.md``)."""

DEFAULT_TOUCHDOWN_FACTOR = 2.6
"""Default touch-down speed as a multiple of H / swing duration: the foot comes down no faster
than 2.6 H / T_sw over the last lift fraction of the swing (0.832 m/s on SCalf's default trot),
just above the reference swing's 2.52 H / T_sw. With 3 H / T_sw the referee ensemble's verdict
on SCalf's default optimum spread 5.8 points (its softer-ground member cost the hind legs
+5.6 %); with 2.6 H / T_sw, 4.9 points (``docs/speed-log.md``)."""

LIFT_SHAPING_PARAMETERS = 3
"""The fewest free parameters with which a swing family can shape its lift-off: a family with one
free term per coordinate (two parameters: the paper family, ``joint-2``, ``fourier-2``) has its
lift set by the end conditions and cannot hold a lift profile (both legs' problems of the paper
family, and HyQ's ``joint-2`` and ``fourier-2``, were infeasible under the default one); it keeps
the foot at or above the ground (:meth:`LimitMargins.for_family`)."""

EFFORT_UNITS = ("nm", "n")
"""Bound units that are an effort or a force: a joint torque [N m], a drive's force [N]."""


def _number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


@dataclass(frozen=True)
class LiftProfile:
    """How a swing foot leaves and meets the ground: a lower bound on its height, a speed bound.

    Over the first ``fraction`` of the swing the foot rises at least as fast as a constant
    acceleration that takes it to ``height_m``: its height above the ground at swing phase
    ``s`` (0 at lift-off, 1 at touch-down) is at least ``height_m * (s / fraction)**2``; it stays
    at least ``height_m`` up until the last ``fraction``, which mirrors the first. Over that last
    fraction it comes down no faster than ``touchdown_speed_m_s``.

    Attributes:
        height_m: The lift height [m]; ``None``: a fifth of the gait's clearance H
            (:data:`DEFAULT_LIFT_SHARE`); 0 turns the height profile off.
        fraction: The share of the swing the lift and the landing take, in (0, 0.5].
        touchdown_speed_m_s: The largest downward foot speed over the landing [m/s]; ``None``:
            2.6 H / swing duration (:data:`DEFAULT_TOUCHDOWN_FACTOR`); ``inf`` turns it off.
    """

    height_m: float | None = None
    fraction: float = DEFAULT_LIFT_FRACTION
    touchdown_speed_m_s: float | None = None

    def __post_init__(self) -> None:
        checks = {
            "lift_height_m": (self.height_m, lambda v: v is None or (math.isfinite(v) and v >= 0)),
            "lift_fraction": (self.fraction, lambda v: 0 < v <= 0.5),
            "touchdown_speed_m_s": (self.touchdown_speed_m_s, lambda v: v is None or v > 0),
        }
        for name, (value, ok) in checks.items():
            if not ((value is None or _number(value)) and ok(value)):
                rule = (
                    "in (0, 0.5]"
                    if name == "lift_fraction"
                    else ">= 0"
                    if "height" in name
                    else "> 0"
                )
                raise ConfigError(f"lift profile {name} = {value!r} must be {rule}", field=name)

    def height_for(self, clearance_m: float) -> float:
        """The lift height [m] on a gait of mid-swing clearance ``clearance_m``."""
        return DEFAULT_LIFT_SHARE * clearance_m if self.height_m is None else self.height_m

    def touchdown_speed_for(self, clearance_m: float, swing_duration_s: Any) -> Any:
        """The largest downward landing speed [m/s] on a gait of this clearance and swing time.

        ``swing_duration_s`` [s] may be a number or an expression (the 3-D NLP's free period).
        """
        if self.touchdown_speed_m_s is not None:
            return self.touchdown_speed_m_s
        return DEFAULT_TOUCHDOWN_FACTOR * clearance_m / swing_duration_s


NO_LIFT_PROFILE = LiftProfile(height_m=0.0, touchdown_speed_m_s=math.inf)
"""No lift height and no landing speed bound: the foot at or above the ground, nothing more."""


@dataclass(frozen=True)
class LimitMargins:
    """How far inside its limits and above the ground an optimized plan stays.

    Attributes:
        stop_rad: Margin of every joint angle to either end of its range [rad].
        stroke_m: Margin of every drive length (a cylinder's) to either end of its stroke [m].
        effort_share: Share of every effort and force limit kept in reserve (each finite end
            moves inwards by this share of its own magnitude), in [0, 0.5].
        lift: How the swing foot leaves and meets the ground.
    """

    stop_rad: float = DEFAULT_STOP_MARGIN_RAD
    stroke_m: float = DEFAULT_STROKE_MARGIN_M
    effort_share: float = DEFAULT_EFFORT_SHARE
    lift: LiftProfile = field(default_factory=LiftProfile)

    def __post_init__(self) -> None:
        for name in ("stop_rad", "stroke_m", "effort_share"):
            value = getattr(self, name)
            if not (_number(value) and math.isfinite(value) and value >= 0):
                raise ConfigError(f"limit margin {name} = {value!r} must be >= 0", field=name)
        if self.effort_share > 0.5:
            raise ConfigError(
                f"limit margin effort_share = {self.effort_share!r} must be at most 0.5",
                field="effort_share",
            )

    def margin(self, bound: Bound) -> float:
        """The largest margin this bound gets (SI, the bound's unit): the larger of its insets."""
        return max(self._insets(bound))

    def field_of(self, bound: Bound) -> str:
        """The name of the margin that moves ``bound`` (for messages)."""
        if bound.output == "q":
            return "stop_rad"
        return "effort_share" if bound.unit in EFFORT_UNITS else "stroke_m"

    def _insets(self, bound: Bound) -> tuple[float, float]:
        """How far the lower and the upper end move inwards (SI, the bound's unit).

        The stop margin for a joint range, except one of a full turn or more: that is no end
        stop a joint can ride but a URDF's placeholder (Solo12's and ANYmal C's +-10 rad); the
        stroke margin for a drive's length; for an effort or force limit the effort share of
        each finite end's own magnitude; 0 for a rate.
        """
        if bound.output == "q":
            m = self.stop_rad if bound.upper - bound.lower < FULL_TURN_RAD else 0.0
            return m, m
        if bound.row is None and bound.unit == "m":  # a drive's length: the stroke
            return self.stroke_m, self.stroke_m
        if bound.unit in EFFORT_UNITS:
            share = self.effort_share
            low = share * abs(bound.lower) if math.isfinite(bound.lower) else 0.0
            high = share * abs(bound.upper) if math.isfinite(bound.upper) else 0.0
            return low, high
        return 0.0, 0.0

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
            low, high = self._insets(b)
            lower = b.lower + low if math.isfinite(b.lower) else b.lower
            upper = b.upper - high if math.isfinite(b.upper) else b.upper
            if lower >= upper:
                name = self.field_of(b)
                raise ConfigError(
                    f"limit margin {name} = {getattr(self, name):g} leaves no room in "
                    f"{b.name}'s {b.source} [{b.lower:g}, {b.upper:g}] {b.unit}",
                    field=name,
                )
            out.append(replace(b, lower=lower, upper=upper, source=f"{b.source}, less margin"))
        return tuple(out)

    def for_family(self, n_params: int) -> LimitMargins:
        """The margins a swing family of ``n_params`` free parameters keeps.

        These margins, but without a lift profile for a family too small to shape its lift-off
        (:data:`LIFT_SHAPING_PARAMETERS`): so the paper family keeps the paper's problem and its
        tables (the effort margin does not bind it, measured on SCalf and HyQ).
        """
        if n_params >= LIFT_SHAPING_PARAMETERS:
            return self
        return replace(self, lift=NO_LIFT_PROFILE)

    def to_dict(self, gait: Gait) -> dict[str, float]:
        """The margins at the edges' units, the lift profile's resolved on ``gait``.

        ``stop_margin_deg``, ``stroke_margin_mm``, ``effort_margin_pct``, ``lift_height_mm``,
        ``lift_fraction``, ``touchdown_speed_m_s`` (``inf``: no bound).
        """
        clearance_m, swing_duration_s = gait.clearance_m, gait.swing_duration_s
        lift = self.lift
        return {
            "stop_margin_deg": math.degrees(self.stop_rad),
            "stroke_margin_mm": 1e3 * self.stroke_m,
            "effort_margin_pct": 100 * self.effort_share,
            "lift_height_mm": 1e3 * lift.height_for(clearance_m),
            "lift_fraction": lift.fraction,
            "touchdown_speed_m_s": lift.touchdown_speed_for(clearance_m, swing_duration_s),
        }


DEFAULT_MARGINS = LimitMargins()
"""The margins every optimizer keeps unless told otherwise."""

NO_MARGINS = LimitMargins(0.0, 0.0, 0.0, NO_LIFT_PROFILE)
"""The limits themselves, and the foot at or above the ground."""

"""The trot gait: its fields, their validation and the phase timing.

A gait is periodic with period ``T``. Each leg spends ``duty * T`` in stance, then the rest of the
cycle in swing. Time inside a phase, ``t_phase``, starts at 0 at the phase's beginning; the
diagonal pairing of the trot is in :mod:`scalf_opt.locomotion.trot`.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from scalf_opt.errors import GaitError, did_you_mean
from scalf_opt.tables import is_number
from scalf_opt.types import Phase, check_choice

FRONT_LEGS: tuple[str, ...] = ("RF", "LF")
"""The legs whose stance takes ``stance_x_offset_front_m`` (the others are hind legs)."""

MIN_SAMPLES_PER_PHASE = 4
"""The coarsest grid a phase may have (intervals)."""

PHASE_EDGE_TOLERANCE_S = 1e-12
"""A foot exactly at touch-down or lift-off (within this) carries nothing."""

EVENT_SIDE_S = 1e-9
"""A jump of a stance's load (the other pair's lift-off or touch-down) is sampled this close on
each side [s], so that the trapezoidal rule integrates each side with its own value and every
limit sees both (the 2 ns between carry a power's 2e-9 J per W)."""

MAX_SAMPLES_PER_PHASE = 20_000
"""The finest grid a phase may have (intervals): 100x the paper's 200 Hz over a 0.5 s phase; the
energy has converged to 1e-4 relative long before (README, "How it is verified")."""

MAX_CYCLES = 1000
"""Most cycles a gait may average over (they are identical; the paper averages 10)."""

MAX_PERIOD_S = 60.0
"""Longest gait period [s] (a gait file's, an option's)."""

MAX_GAIT_LENGTH_M = 10.0
"""Largest step length, clearance or stance height [m] (the reach limits them much further: a
10 m leg is no robot's)."""

_MAXIMA = {
    "period_s": MAX_PERIOD_S,
    "step_length_m": MAX_GAIT_LENGTH_M,
    "clearance_m": MAX_GAIT_LENGTH_M,
    "stance_height_m": MAX_GAIT_LENGTH_M,
}


@dataclass(frozen=True)
class Gait:
    """A trot gait (defaults: the paper's Section 6.1).

    Attributes:
        period_s: Gait cycle T [s].
        duty_cycle: Fraction of the period a foot is on the ground, in [0.5, 1).
        step_length_m: Step length S: foot travel relative to the hip during stance [m].
        clearance_m: Mid-swing clearance H above the ground [m].
        stance_height_m: Height z0 of the pitching hip above the ground [m].
        sample_rate_hz: Sampling rate of the time grid [Hz].
        cycles: Number of cycles the reported energies are averaged over (the paper: 10).
        stance_x_offset_front_m: Where the front feet (RF, LF) stand relative to their pitching
            hip at mid-stance, forward positive [m] (the paper: 0, the foot passes under the
            hip; ``scalf-opt optimize --free-stance`` optimizes it).
        stance_x_offset_hind_m: The same for the hind feet (LH, RH) [m].
    """

    period_s: float = 0.5
    duty_cycle: float = 0.5
    step_length_m: float = 0.25
    clearance_m: float = 0.08
    stance_height_m: float = 0.75
    sample_rate_hz: float = 200.0
    cycles: int = 10
    stance_x_offset_front_m: float = 0.0
    stance_x_offset_hind_m: float = 0.0

    def __post_init__(self) -> None:
        for name in ("period_s", "step_length_m", "clearance_m", "stance_height_m"):
            _positive(name, getattr(self, name))
        _positive("sample_rate_hz", self.sample_rate_hz)
        for name in ("stance_x_offset_front_m", "stance_x_offset_hind_m"):
            value = getattr(self, name)
            if not is_number(value):
                raise GaitError(f"gait field {name} = {value!r} must be a finite number")
        if not (isinstance(self.duty_cycle, int | float) and 0.5 <= self.duty_cycle < 1.0):
            raise GaitError(
                f"gait field duty_cycle = {self.duty_cycle!r} must be in [0.5, 1): below 0.5 a "
                "trot has a flight phase, which the constant-height trunk model cannot carry",
                field="duty_cycle",
            )
        if (
            isinstance(self.cycles, bool)
            or not isinstance(self.cycles, int)
            or not 1 <= self.cycles <= MAX_CYCLES
        ):
            raise GaitError(
                f"gait field cycles = {self.cycles!r} must be an integer in 1..{MAX_CYCLES}",
                field="cycles",
            )
        for name, duration in (
            ("stance", self.stance_duration_s),
            ("swing", self.swing_duration_s),
        ):
            if duration * self.sample_rate_hz < MIN_SAMPLES_PER_PHASE:
                raise GaitError(
                    f"gait field sample_rate_hz = {self.sample_rate_hz!r} is too low: the {name} "
                    f"phase ({duration:g} s) needs at least {MIN_SAMPLES_PER_PHASE} samples",
                    field="sample_rate_hz",
                )
            if duration * self.sample_rate_hz > MAX_SAMPLES_PER_PHASE:
                raise GaitError(
                    f"gait field sample_rate_hz = {self.sample_rate_hz!r} is too high: the {name} "
                    f"phase ({duration:g} s) would have more than {MAX_SAMPLES_PER_PHASE} samples",
                    field="sample_rate_hz",
                )

    @classmethod
    def field_names(cls) -> tuple[str, ...]:
        """The gait's field names, in order."""
        return tuple(f.name for f in fields(cls))

    @classmethod
    def unknown_field(cls, name: str) -> str:
        """The message for a gait field ``name`` that does not exist: the closest and the known."""
        known = cls.field_names()
        return f"unknown gait field {name!r}{did_you_mean(name, known)} (known: {', '.join(known)})"

    def to_dict(self) -> dict[str, float | int]:
        """The fields as plain data."""
        return {name: getattr(self, name) for name in self.field_names()}

    @property
    def trot_text(self) -> str:
        """The gait in one line for reports and figures, four significant digits.

        ``trot T=0.5 s, duty 0.5, S=0.25 m, H=0.08 m, z0=0.75 m`` (a scaled gait's exact values
        are in the files written with it).
        """
        return (
            f"trot T={self.period_s:.4g} s, duty {self.duty_cycle:.4g}, "
            f"S={self.step_length_m:.4g} m, H={self.clearance_m:.4g} m, "
            f"z0={self.stance_height_m:.4g} m"
        )

    @property
    def stance_duration_s(self) -> float:
        """Duration of the stance phase [s]."""
        return self.duty_cycle * self.period_s

    @property
    def swing_duration_s(self) -> float:
        """Duration of the swing phase [s]."""
        return (1.0 - self.duty_cycle) * self.period_s

    def stance_x_offset_m(self, leg: str) -> float:
        """Mid-stance foot x relative to the hip of ``leg`` (front or hind offset) [m]."""
        return self.stance_x_offset_front_m if leg in FRONT_LEGS else self.stance_x_offset_hind_m

    @property
    def speed_m_s(self) -> float:
        """Forward speed of the trunk [m/s]: S / T_stance (the paper: 1.0 m/s)."""
        return self.step_length_m / self.stance_duration_s

    def with_speed(self, speed_m_s: float) -> Gait:
        """The same gait with the step length that walks it at ``speed_m_s``: ``S = v d T``.

        Raises:
            GaitError: That step length is out of range (the message names ``step_length_m``).
        """
        return replace(self, step_length_m=speed_m_s * self.stance_duration_s)

    @property
    def distance_per_cycle_m(self) -> float:
        """Distance the trunk travels in one cycle [m]."""
        return self.speed_m_s * self.period_s

    def phase_duration_s(self, phase: Phase) -> float:
        """Duration of ``phase`` [s]."""
        check_choice(phase, Phase, "phase")
        return self.stance_duration_s if phase == "stance" else self.swing_duration_s

    def stance_load_jumps_s(self) -> list[float]:
        """The other pair's lift-off and touch-down inside a stance, since its touch-down [s].

        With a duty cycle above 0.5 the other pair lifts off ``(d - 0.5) T`` and touches down
        ``T / 2`` into a leg's stance, and the stance feet's load jumps there (four feet on the
        ground, then two, then four). Empty at 0.5, where both instants are the stance's own
        ends; an instant within ``2`` :data:`EVENT_SIDE_S` of an end counts as that end.

        Returns:
            ``[lift-off, touch-down]``, or ``[]``.
        """
        duration = self.stance_duration_s
        return [
            e
            for e in (duration - 0.5 * self.period_s, 0.5 * self.period_s)
            if 2.0 * EVENT_SIDE_S < e < duration - 2.0 * EVENT_SIDE_S
        ]

    def phase_times_s(self, phase: Phase) -> np.ndarray:
        """Sample times inside a phase since its start, both ends included, shape (n,) [s].

        The grid is uniform with ``round(duration * sample_rate_hz)`` intervals, rounded up to an
        even number so that mid-phase is a sample (the clearance is checked there); at the
        paper's 200 Hz a 0.25 s phase has 51 samples 5 ms apart. With a duty cycle above 0.5 the
        stance grid also has a sample on each side of the other pair's lift-off and touch-down,
        where the stance feet's load jumps (two feet on the ground, or four): without them a
        limit could be crossed just before a jump that no sample sees, and the trapezoidal rule
        mixed the two sides' values over the interval holding the jump.
        """
        duration = self.phase_duration_s(phase)
        intervals = max(MIN_SAMPLES_PER_PHASE, round(duration * self.sample_rate_hz))
        intervals += intervals % 2
        grid = np.linspace(0.0, duration, intervals + 1)
        if phase == "swing":
            return grid
        keep = np.ones(grid.size, dtype=bool)
        sides = []
        for event in self.stance_load_jumps_s():
            keep &= np.abs(grid - event) > 2.0 * EVENT_SIDE_S
            sides += [event - EVENT_SIDE_S, event + EVENT_SIDE_S]
        return np.union1d(grid[keep], sides)


def _positive(name: str, value: object) -> None:
    if not (is_number(value) and value > 0):  # type: ignore[operator]
        raise GaitError(f"gait field {name} = {value!r} must be a finite number > 0", field=name)
    if name in _MAXIMA and value > _MAXIMA[name]:  # type: ignore[operator]
        raise GaitError(
            f"gait field {name} = {value!r} must be at most {_MAXIMA[name]:g} "
            f"{'s' if name.endswith('_s') else 'm'}",
            field=name,
        )

"""Gait description, phase timing, trot pairing and the stance foot path (Table 3).

A gait is periodic with period ``T``. Each leg spends ``duty * T`` in stance, then the rest of the
cycle in swing. Time inside a phase, ``tau``, starts at 0 at the phase's beginning. In a trot the
diagonal pair RF + LH starts its stance at cycle time 0 and LF + RH half a period later.

Stance path (Table 3, in the leg frame, origin at the pitching hip): the foot stays on the ground
while the trunk moves forward at constant speed ``v = S / T_stance``::

    x(tau) = S/2 - v tau,   z(tau) = -z0,   tau in [0, T_stance]

which is the unique cubic meeting the four boundary conditions of Table 3 (positions +-S/2,
velocities -v at both ends). The trunk's acceleration is ``-x''(tau) = 0``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from scalf_opt.errors import ConfigError, GaitError
from scalf_opt.tomlfile import read_toml

TROT_PHASE_OFFSET: dict[str, float] = {"RF": 0.0, "LH": 0.0, "LF": 0.5, "RH": 0.5}
"""Start of each leg's stance as a fraction of the period (trot: diagonal pairs)."""

DIAGONAL_PARTNER: dict[str, str] = {"RF": "LH", "LH": "RF", "LF": "RH", "RH": "LF"}
"""The leg that shares each leg's stance in a trot."""

SYMMETRIC_TWIN: dict[str, str] = {"RF": "LF", "LF": "RF", "RH": "LH", "LH": "RH"}
"""The leg that repeats each leg's motion half a cycle later (the paper's symmetry)."""


@dataclass(frozen=True)
class GaitSpec:
    """A trot gait (defaults: the paper's Section 6.1).

    Attributes:
        period_s: Gait cycle T [s].
        duty_cycle: Fraction of the period a foot is on the ground, in [0.5, 1).
        step_length_m: Step length S: foot travel relative to the hip during stance [m].
        clearance_m: Mid-swing clearance H above the ground [m].
        stance_height_m: Height z0 of the pitching hip above the ground [m].
        sample_rate_hz: Sampling rate of the time grid [Hz].
        cycles: Number of cycles the reported energies are averaged over (the paper: 10).
    """

    period_s: float = 0.5
    duty_cycle: float = 0.5
    step_length_m: float = 0.25
    clearance_m: float = 0.08
    stance_height_m: float = 0.75
    sample_rate_hz: float = 200.0
    cycles: int = 10

    def __post_init__(self) -> None:
        def positive(name: str, value: float) -> None:
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise GaitError(f"gait field {name} = {value!r} must be a finite number > 0")

        for name in ("period_s", "step_length_m", "clearance_m", "stance_height_m"):
            positive(name, getattr(self, name))
        positive("sample_rate_hz", self.sample_rate_hz)
        if not (isinstance(self.duty_cycle, int | float) and 0.5 <= self.duty_cycle < 1.0):
            raise GaitError(
                f"gait field duty_cycle = {self.duty_cycle!r} must be in [0.5, 1): below 0.5 a "
                "trot has a flight phase, which the constant-height trunk model cannot carry"
            )
        if isinstance(self.cycles, bool) or not isinstance(self.cycles, int) or self.cycles < 1:
            raise GaitError(f"gait field cycles = {self.cycles!r} must be an integer >= 1")
        for name, duration in (
            ("stance", self.stance_duration_s),
            ("swing", self.swing_duration_s),
        ):
            if duration * self.sample_rate_hz < 4:
                raise GaitError(
                    f"gait field sample_rate_hz = {self.sample_rate_hz!r} is too low: the {name} "
                    f"phase ({duration:g} s) needs at least 4 samples"
                )

    @classmethod
    def from_toml(cls, path: str | Path) -> GaitSpec:
        """Read a gait file: a TOML table ``[gait]`` (or top-level keys) with the field names.

        Raises:
            ConfigError: The file cannot be read, is not TOML, or has an unknown or mistyped key.
            GaitError: A value is out of its allowed range.
        """
        path = Path(path)
        data = read_toml(path, "gait")
        table = data.get("gait", data)
        if not isinstance(table, dict):
            raise ConfigError(f"{path}: [gait] must be a table")
        known = {f.name: f.type for f in fields(cls)}
        values: dict[str, float | int] = {}
        for key, value in table.items():
            if key not in known:
                raise ConfigError(f"{path}: unknown gait field {key!r} (known: {', '.join(known)})")
            if key == "cycles":
                if isinstance(value, bool) or not isinstance(value, int):
                    raise ConfigError(
                        f"{path}: gait field cycles must be an integer, got {value!r}"
                    )
            elif isinstance(value, bool) or not isinstance(value, int | float):
                raise ConfigError(f"{path}: gait field {key} must be a number, got {value!r}")
            values[key] = value
        try:
            return cls(**values)  # type: ignore[arg-type]
        except GaitError as exc:
            raise GaitError(f"{path}: {exc}") from exc

    def with_(self, **changes: float) -> GaitSpec:
        """Return a copy with some fields changed (validated)."""
        return replace(self, **changes)  # type: ignore[arg-type]

    # --- timing --------------------------------------------------------------------------------
    @property
    def stance_duration_s(self) -> float:
        """Duration of the stance phase [s]."""
        return self.duty_cycle * self.period_s

    @property
    def swing_duration_s(self) -> float:
        """Duration of the swing phase [s]."""
        return (1.0 - self.duty_cycle) * self.period_s

    @property
    def speed_m_s(self) -> float:
        """Forward speed of the trunk [m/s]: S / T_stance (the paper: 1.0 m/s)."""
        return self.step_length_m / self.stance_duration_s

    @property
    def distance_per_cycle_m(self) -> float:
        """Distance the trunk travels in one cycle [m]."""
        return self.speed_m_s * self.period_s

    def phase_times_s(self, phase: str) -> np.ndarray:
        """Sample times inside a phase, both ends included, shape (n,) [s].

        The grid is uniform with ``round(duration * sample_rate_hz)`` intervals, rounded up to an
        even number so that mid-phase is a sample (the clearance is checked there); at the
        paper's 200 Hz a 0.25 s phase has 51 samples 5 ms apart.
        """
        duration = self.stance_duration_s if phase == "stance" else self.swing_duration_s
        if phase not in ("stance", "swing"):
            raise ValueError(f"phase must be 'stance' or 'swing', got {phase!r}")
        intervals = max(4, round(duration * self.sample_rate_hz))
        intervals += intervals % 2
        return np.linspace(0.0, duration, intervals + 1)

    def stance_offset_s(self, leg: str) -> float:
        """Cycle time at which ``leg``'s stance begins [s] (trot pairing)."""
        return TROT_PHASE_OFFSET[leg] * self.period_s

    # --- stance path ---------------------------------------------------------------------------
    def stance_path(self, tau_s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Stance foot position, velocity, acceleration in the leg frame, each (2, n).

        Args:
            tau_s: Times since touch-down [s], shape (n,).
        """
        tau = np.asarray(tau_s, dtype=float)
        v = self.speed_m_s
        p = np.vstack(
            [0.5 * self.step_length_m - v * tau, np.full_like(tau, -self.stance_height_m)]
        )
        pd = np.vstack([np.full_like(tau, -v), np.zeros_like(tau)])
        return p, pd, np.zeros((2, tau.size))

    def trunk_acceleration_m_s2(self, tau_s: np.ndarray) -> np.ndarray:
        """Forward acceleration of the trunk during stance [m/s^2], shape (n,): ``-x''(tau)``."""
        return -self.stance_path(tau_s)[2][0]

    def stance_legs_at(self, cycle_time_s: float, leg: str) -> list[str]:
        """Legs on the ground at ``cycle_time_s`` while ``leg`` is in stance.

        ``leg`` and its diagonal partner always count; another leg counts when the time lies
        strictly inside its stance (a foot exactly at touch-down or lift-off carries nothing).
        """
        support = [leg, DIAGONAL_PARTNER[leg]]
        for other in TROT_PHASE_OFFSET:
            if other in support:
                continue
            local = (cycle_time_s - self.stance_offset_s(other)) % self.period_s
            if 1e-12 < local < self.stance_duration_s - 1e-12:
                support.append(other)
        return support

    def local_stance_time_s(self, cycle_time_s: float, leg: str) -> float:
        """Time since ``leg``'s touch-down at cycle time ``cycle_time_s`` [s]."""
        return (cycle_time_s - self.stance_offset_s(leg)) % self.period_s

"""A joint log of a robot without cylinders: angles, rates and torques, and its energy.

A robot whose legs have no hydraulic cylinder (an electric quadruped: Solo-12, ANYmal, Go1)
logs its joints, not cylinder lengths and forces: a ROS 2 bag's ``/joint_states`` or the CSV of
``scalf-opt export``. Its mechanical power is ``sum_j |tau_j qd_j|`` over the hip pitch and knee,
with the logged rates (else the angles differentiated by the log filter,
:mod:`~scalf_opt.logs.derivative`), and beside it what the drives draw beyond it, by their model
at the logged state (an electric drive: its copper loss and joint friction, less what its
regeneration recovers; ``LegEnergy.friction_heat_j`` holds it). Cycles and phases
as in :mod:`~scalf_opt.logs.analysis`: from the contact flags when the log has them, else the
trot's schedule with the period given or the motion's own (:func:`period_of_motion_s`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import LogError
from scalf_opt.logs.analysis import (
    LegEnergy,
    LogAnalysis,
    charged_power,
    cycle_windows,
    leg_energy,
    touchdowns,
)
from scalf_opt.logs.derivative import (
    DEFAULT_DEGREE,
    DEFAULT_HALF_WINDOW_S,
    half_window_samples,
    local_polynomial_derivative,
)

MIN_PERIOD_S = 0.1
"""The shortest period searched [s]; the longest leaves this much of the log to compare."""


@dataclass(frozen=True)
class JointLegLog:
    """One leg's joint samples, in time order.

    Attributes:
        t_s: Sample times, shape (n,) [s].
        q_rad: (hip pitch, knee) angles, shape (2, n) [rad].
        qd_rad_s: Their rates, shape (2, n) [rad/s], or ``None`` (not logged).
        tau_nm: Joint torques, shape (2, n) [N m].
        contact: Foot on the ground, shape (n,), or ``None``.
        rows: The message index (bag) or file row (CSV) of each sample, shape (n,).
    """

    t_s: np.ndarray
    q_rad: np.ndarray
    qd_rad_s: np.ndarray | None
    tau_nm: np.ndarray
    contact: np.ndarray | None
    rows: np.ndarray


@dataclass(frozen=True)
class JointLog:
    """A whole joint log.

    Attributes:
        source: The file and topic (for messages).
        legs: Per leg present, its samples, in :data:`~scalf_opt.types.LEG_NAMES` order.
    """

    source: str
    legs: dict[str, JointLegLog]

    @property
    def has_contact(self) -> bool:
        """Whether the log has contact flags."""
        return any(leg.contact is not None for leg in self.legs.values())


def _mean_squared_differences(signals: np.ndarray, max_lag: int) -> np.ndarray:
    """``D(lag) = mean((x[:, lag:] - x[:, :n - lag])**2)`` for every lag in ``0..max_lag``.

    By cumulative sums of the squares and one FFT autocorrelation: ``O(n log n)`` rather than a
    pass over the signals per lag (quadratic: hours for a 3-hour log).
    """
    m, n = signals.shape
    lags = np.arange(max_lag + 1)
    squares = np.concatenate([np.zeros((m, 1)), np.cumsum(signals**2, axis=1)], axis=1)
    tail = squares[:, n : n + 1] - squares[:, lags]  # sum of x_i^2 for i >= lag
    head = squares[:, n - lags]  # sum of x_i^2 for i < n - lag
    spectrum = np.fft.rfft(signals, 2 * n, axis=1)
    products = np.fft.irfft(spectrum * np.conj(spectrum), 2 * n, axis=1)[:, : max_lag + 1]
    return (tail + head - 2.0 * products).sum(axis=0) / (m * (n - lags))


def period_of_motion_s(source: str, series: list[tuple[np.ndarray, np.ndarray]]) -> float:
    """The period of a motion [s]: each ``(t_s, values (m, n))`` a leg's signals.

    On a uniform grid at the median step, the mean squared difference ``D(lag)`` of every signal
    with itself a lag later; the period is the first lag where ``D`` has a local minimum below a
    fifth of its mean, refined between samples by a parabola through it and its neighbours.

    Raises:
        LogError: Too short to hold two periods, or not periodic.
    """
    dt = float(np.median(np.concatenate([np.diff(t) for t, _ in series])))
    start = max(float(t[0]) for t, _ in series)
    end = min(float(t[-1]) for t, _ in series)
    grid = np.arange(start, end, dt)
    signals = np.vstack([np.interp(grid, t, row) for t, values in series for row in values])
    signals -= signals.mean(axis=1, keepdims=True)
    signals /= np.maximum(signals.std(axis=1, keepdims=True), 1e-300)  # each signal counts alike
    n = grid.size
    lo = max(2, int(MIN_PERIOD_S / dt))
    hi = n - lo - 2
    if hi <= lo + 2:
        raise LogError(
            f"{source}: {end - start:.3g} s of motion is too short to find its period "
            "(give --period)"
        )
    d = _mean_squared_differences(signals, hi)
    threshold = 0.2 * float(np.mean(d[lo:hi]))
    for lag in range(lo, hi):
        if d[lag] <= d[lag - 1] and d[lag] <= d[lag + 1] and d[lag] < threshold:
            curvature = d[lag - 1] - 2 * d[lag] + d[lag + 1]
            shift = 0.5 * (d[lag - 1] - d[lag + 1]) / curvature if curvature > 0 else 0.0
            return float((lag + shift) * dt)
    raise LogError(
        f"{source}: the motion repeats at no lag between {lo * dt:.3g} and {hi * dt:.3g} s: "
        "not a periodic gait, or too short (give --period)"
    )


def analyze_joint_log(
    log: JointLog,
    pipeline: EnergyPipeline,
    period_s: float | None = None,
    half_window_s: float = DEFAULT_HALF_WINDOW_S,
    degree: int = DEFAULT_DEGREE,
) -> tuple[LogAnalysis, dict[str, tuple[np.ndarray, np.ndarray]], str]:
    """Energies of every leg in a joint log (module docstring).

    Returns:
        The analysis, per leg the times and the mechanical power [W], and the velocity's source
        (``measured`` or ``filter``).

    Raises:
        LogError: A log shorter than one complete cycle or than the filter's window, one whose
            period cannot be found.
    """
    gait = pipeline.gait
    if period_s is not None:
        period, period_source = period_s, "--period"
    elif log.has_contact:
        intervals = [
            np.diff(touchdowns(d.contact, d.t_s))
            for d in log.legs.values()
            if d.contact is not None
        ]
        every = np.concatenate(intervals) if intervals else np.zeros(0)
        period, period_source = (
            (float(np.median(every)), "contact") if every.size else (gait.period_s, "gait")
        )
    else:
        series = [(d.t_s, d.q_rad) for d in log.legs.values()]
        period, period_source = period_of_motion_s(log.source, series), "motion"
    measured = all(d.qd_rad_s is not None for d in log.legs.values())
    legs: dict[str, LegEnergy] = {}
    power_of: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for leg, data in log.legs.items():
        t = data.t_s
        stance, windows = cycle_windows(t, data.contact, gait, leg, period, log.source)
        qd = data.qd_rad_s
        if qd is None:
            half = half_window_samples(1.0 / float(np.median(np.diff(t))), half_window_s, degree)
            if t.size < 2 * half + 1:
                raise LogError(
                    f"{log.source}: leg {leg} has {t.size} samples, fewer than the velocity "
                    f"filter's {2 * half + 1}"
                )
            qd = local_polynomial_derivative(t, data.q_rad, half, degree)
        mechanical = np.abs(data.tau_nm * qd).sum(axis=0)
        drawn, _ = charged_power(pipeline, leg, data.q_rad, qd, data.tau_nm)
        loss = drawn - mechanical  # what the drives draw beyond the joints' mechanical power
        legs[leg] = leg_energy(leg, t, mechanical, loss, stance, windows)
        power_of[leg] = (t, mechanical)
    steps = np.concatenate([np.diff(d.t_s) for d in log.legs.values()])
    analysis = LogAnalysis(
        source=log.source,
        period_s=period,
        period_source=period_source,
        sample_rate_hz=float(1.0 / np.median(steps)),
        half_window_s=half_window_s,
        degree=degree,
        legs=legs,
        duty_cycle=None if log.has_contact else gait.duty_cycle,
    )
    return analysis, power_of, "measured" if measured else "filter"

"""How finely an optimization samples the swing, so that its optimum is a converged energy.

The energy is the trapezoidal integral of the power over the samples. An optimizer given
coarse samples can find a swing whose sampled energy is far from its true energy: power that
peaks between samples is not seen (at 200 Hz the ``joint-12`` optimum claimed 2.7 % of the
robot's energy that was not there once the swing was sampled finely), and the transients at
lift-off and touch-down are under-resolved. So:

1. the optimization starts at ``max(gait rate, SAMPLES_PER_SHORTEST_PERIOD / T_min)``, where
   ``T_min`` is the period of the family's fastest variation (``2 T_sw / N`` for a Fourier
   family of order N);
2. its optimum's swing energy is evaluated again at :data:`CHECK_FACTOR` times that rate;
3. if the two differ by more than :data:`SAMPLING_TOLERANCE`, the rate is doubled and the
   optimization repeated from the optimum found, until they agree (or :data:`MAX_RATE_HZ`).

Every energy a command then reports is at the rate the optimization converged at.

A :class:`Transcription` is that choice as an object, apart from the problem it samples (the
robot, gait, family and margins): its rate, :meth:`Transcription.refined` for the next rate, its
check grid, and the scheme the NLP takes (:func:`scheme`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import MAX_SAMPLES_PER_PHASE, Gait
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.types import PHASES

SAMPLES_PER_SHORTEST_PERIOD = 25
"""Samples per period of the family's fastest variation at the first rate tried.

Measured on SCalf's RF leg, ``joint-6`` (fastest period 83 ms at the paper's gait): its optimum
at 10 samples per period (120 Hz, the gait's 200 Hz being finer, 16.7) was 1.4 % off its energy
at ten times the rate; at 25 (300 Hz), 0.15 %.
"""

SAMPLING_TOLERANCE = 0.005
"""Largest relative difference between an optimum's swing energy at the optimization's rate and
at :data:`CHECK_FACTOR` times that rate (0.5 %)."""

CHECK_FACTOR = 10
"""The check rate as a multiple of the optimization's rate."""

BETWEEN_SAMPLES_RTOL = 0.01
"""A bound the optimizer meets at every sample may be crossed between samples; on the check's
ten times finer samples, by at most this share of the bound's size, else the rate is refined
(measured before this check: HyQ's joint-7, joint-9 and joint-10 optima at 350-500 Hz crossed
the hip cylinder's 1960 N pull limit by 2.0-3.6 %)."""

MAX_RATE_HZ = 10_000.0
"""The finest rate an optimization may use before it is reported as not converged [Hz]."""


def initial_rate_hz(gait: Gait, family: SwingFamily) -> float:
    """The first rate to optimize ``family`` at: the gait's, or finer for a fast family [Hz]."""
    needed = SAMPLES_PER_SHORTEST_PERIOD / family.shortest_period_s(gait.swing_duration_s)
    return max(gait.sample_rate_hz, float(needed))


def check_rate_hz(gait: Gait, rate_hz: float | None = None) -> float:
    """The rate an optimum at ``rate_hz`` (default: ``gait``'s rate) is checked at [Hz].

    :data:`CHECK_FACTOR` times the rate, but no finer than the finest grid a gait may have
    (:data:`~scalf_opt.locomotion.gait.MAX_SAMPLES_PER_PHASE` intervals in its longer phase):
    at the free-trajectory bound's finest level (8,192 Hz) that is 9.8 times the rate.
    """
    longest_s = max(gait.phase_duration_s(phase) for phase in PHASES)
    rate = gait.sample_rate_hz if rate_hz is None else rate_hz
    return min(rate * CHECK_FACTOR, MAX_SAMPLES_PER_PHASE / longest_s)


def with_rate(gait: Gait, rate_hz: float) -> Gait:
    """``gait`` sampled at ``rate_hz``."""
    return replace(gait, sample_rate_hz=float(rate_hz))


CONDENSED_MAX_PARAMS = 2
"""Families with at most this many parameters get the condensed NLP (``Y`` eliminated): with
so few parameters the lifted variables cost more than they save (measured: docs/speed-log.md,
"Measurements behind choices")."""

Scheme = Literal["condensed", "lifted"]
"""How the NLP holds a leg's samples: eliminated (condensed) or as variables (lifted)."""


def scheme(n_params: int) -> Scheme:
    """The NLP scheme of a family with ``n_params`` parameters per leg."""
    return "condensed" if n_params <= CONDENSED_MAX_PARAMS else "lifted"


@dataclass(frozen=True)
class Transcription:
    """How a swing problem is sampled: the rate of its grid, the grid it is checked on.

    The problem (robot, gait, loads, family, margins) is the physics; the transcription is a
    choice made to solve it, refined until the answer does not depend on it (module docstring).
    :meth:`on` is the one place an optimizer changes the sampling.

    Attributes:
        rate_hz: Samples per second of the cycle's grid [Hz].
    """

    rate_hz: float

    @classmethod
    def first(cls, gait: Gait, family: SwingFamily) -> Transcription:
        """The first rate to try ``family`` on ``gait`` at (:func:`initial_rate_hz`)."""
        return cls(initial_rate_hz(gait, family))

    @classmethod
    def of(cls, pipeline: EnergyPipeline) -> Transcription:
        """The transcription ``pipeline`` is sampled at."""
        return cls(pipeline.gait.sample_rate_hz)

    def refined(self, factor: float = 2.0) -> Transcription:
        """``factor`` times as many samples."""
        return Transcription(self.rate_hz * factor)

    @property
    def finest(self) -> bool:
        """No refinement by two is left below :data:`MAX_RATE_HZ`."""
        return self.rate_hz * 2 > MAX_RATE_HZ

    def check(self, gait: Gait) -> Transcription:
        """The grid an optimum at this rate is checked on (:func:`check_rate_hz`)."""
        return Transcription(check_rate_hz(gait, self.rate_hz))

    def on(self, pipeline: EnergyPipeline) -> EnergyPipeline:
        """The same robot, gait and models, sampled at this rate."""
        return pipeline.with_gait(with_rate(pipeline.gait, self.rate_hz))


def on_check_grid(pipeline: EnergyPipeline) -> EnergyPipeline:
    """The pipeline on the check grid of an optimum found at its rate (:func:`check_rate_hz`)."""
    return Transcription.of(pipeline).check(pipeline.gait).on(pipeline)


def relative_difference(value: float, check: float) -> float:
    """``|value - check| / |check|`` (the check, at the finer rate, is the better estimate).

    ``inf`` when the check is ``inf`` (a check that failed), never NaN.
    """
    if math.isinf(check):
        return math.inf
    return abs(value - check) / max(abs(check), 1e-12)

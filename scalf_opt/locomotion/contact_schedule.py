"""A trot's contact schedule on a periodic grid of nodes, with or without a flight phase.

One gait cycle of period ``T`` is cut into ``N`` equal intervals; node ``k`` sits at
``t_k = k T / N`` and node ``N`` is node ``0`` of the next cycle. The diagonal pair RF, LH is in
stance over ``[0, D T]`` and LF, RH over ``[T/2, T/2 + D T]`` (duty factor ``D``; the scalf-opt
convention: stance first for RF and LH). Both ends of a stance belong to it: the foot is on the
ground at its touch-down and lift-off nodes. With ``D < 0.5`` the robot flies between a pair's
lift-off and the other pair's touch-down; with ``D > 0.5`` all four feet share the ground around
the switches.

``N`` is chosen so that every phase boundary falls on a node (:func:`trot_schedule`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from scalf_opt.errors import GaitError
from scalf_opt.locomotion.periodic_spline import READS_PER_INTERVAL, read_points
from scalf_opt.types import LEG_NAMES

STANCE_START_SHARE = {"RF": 0.0, "LH": 0.0, "LF": 0.5, "RH": 0.5}
"""Each leg's touch-down as a share of the period."""

DEFAULT_FRICTION = 0.8
"""The feet's friction coefficient in the 3-D model's contact cones unless told otherwise."""

MIN_DUTY = 0.2
"""The smallest duty factor a schedule accepts: below it the flight dominates the cycle."""

MAX_DUTY = 0.8
"""The largest duty factor a schedule accepts (a walk-like trot)."""


@dataclass(frozen=True)
class TrotSchedule:
    """Which foot is on the ground at which node of one periodic trot cycle.

    Attributes:
        period_s: The gait period ``T`` [s].
        duty_cycle: The share ``D`` of the period each foot spends on the ground.
        intervals: The number ``N`` of equal intervals (and nodes) in one period.
        reads_per_interval: Where a plan on this grid is read (its energy, its limits): at this
            many points of each interval
            (:func:`~scalf_opt.locomotion.periodic_spline.read_points`).
    """

    period_s: float
    duty_cycle: float
    intervals: int
    reads_per_interval: int = READS_PER_INTERVAL

    @property
    def read_points(self) -> tuple[tuple[float, float], ...]:
        """Each read point's fraction of its interval and weight in units of the interval."""
        return read_points(self.reads_per_interval)

    @property
    def step_s(self) -> float:
        """The interval between nodes [s]."""
        return self.period_s / self.intervals

    @property
    def times_s(self) -> np.ndarray:
        """The node times ``t_k`` (N,) [s]."""
        return np.arange(self.intervals) * self.step_s

    @property
    def stance_nodes(self) -> int:
        """Intervals a stance lasts (``D N``)."""
        return round(self.duty_cycle * self.intervals)

    def touchdown_node(self, leg: str) -> int:
        """The node at which ``leg`` touches down in the cycle."""
        return round(STANCE_START_SHARE[leg] * self.intervals)

    @cached_property
    def stance(self) -> np.ndarray:
        """``stance[i, k]``: foot ``i`` (:data:`LEG_NAMES` order) is on the ground at node ``k``."""
        out = np.zeros((len(LEG_NAMES), self.intervals), dtype=bool)
        for i, leg in enumerate(LEG_NAMES):
            start = self.touchdown_node(leg)
            out[i, (start + np.arange(self.stance_nodes + 1)) % self.intervals] = True
        return out

    @cached_property
    def previous_stance(self) -> np.ndarray:
        """``[i, k]``: node ``k``'s stance of foot ``i`` began in the previous cycle.

        There the foot stands on the previous cycle's foothold, one stride behind this cycle's.
        """
        out = np.zeros_like(self.stance)
        for i, leg in enumerate(LEG_NAMES):
            start = self.touchdown_node(leg)
            nodes = start + np.arange(self.stance_nodes + 1)
            out[i, nodes[nodes >= self.intervals] - self.intervals] = True
        return out

    @cached_property
    def loaded(self) -> np.ndarray:
        """``[i, k]``: foot ``i`` may carry a force at node ``k``.

        In stance, but not at its touch-down or lift-off node: there its force is zero, so no
        contact begins or ends with a jump of force.
        """
        stance = self.stance
        return stance & np.roll(stance, 1, axis=1) & np.roll(stance, -1, axis=1)

    @cached_property
    def flight(self) -> np.ndarray:
        """Nodes at which no foot is on the ground (N,) bool."""
        return np.logical_not(self.stance.any(axis=0))

    def swing_progress(self, leg: str, position: np.ndarray) -> np.ndarray:
        """How far ``leg``'s swing has gone at ``position``: 0 at lift-off, 1 at touch-down.

        ``position`` (any shape) counts nodes from the cycle's start (any real: ``t / h``,
        periodic). In stance the value goes past 1 and means nothing.
        """
        lift = self.touchdown_node(leg) + self.stance_nodes
        swing = self.intervals - self.stance_nodes
        return ((np.asarray(position, dtype=float) - lift) % self.intervals) / swing

    def swing_phase(self, leg: str) -> np.ndarray:
        """The swing phase ``s`` in (0, 1) of ``leg`` at each node (N,); NaN in stance."""
        s = self.swing_progress(leg, np.arange(self.intervals))
        return np.where(self.stance[LEG_NAMES.index(leg)], np.nan, s)

    def stance_at(self, position: np.ndarray) -> np.ndarray:
        """Which feet are on the ground at ``position`` (n,), counted in nodes (any real) (4, n).

        Strictly between two stance nodes, or at a stance node (within 1e-9 of a node's
        position: times divided by the step are not exact).
        """
        n = self.intervals
        position = np.mod(np.asarray(position, dtype=float), n)
        nearest = np.round(position)
        at_node = np.abs(position - nearest) < 1e-9
        k = np.where(at_node, nearest, np.floor(position)).astype(int) % n
        stance = self.stance
        return (stance[:, k] & stance[:, (k + 1) % n]) | (stance[:, k] & at_node)


def trot_schedule(period_s: float, duty_cycle: float, sample_rate_hz: float) -> TrotSchedule:
    """The trot schedule of the fewest nodes (``sample_rate_hz`` or more) with edges on nodes.

    Raises:
        GaitError: The duty factor is outside [:data:`MIN_DUTY`, :data:`MAX_DUTY`], or no grid of
            up to four times the rate puts its edges on nodes (a duty factor of more than three
            decimals).
    """
    if not MIN_DUTY <= duty_cycle <= MAX_DUTY:
        raise GaitError(
            f"duty_cycle = {duty_cycle:g} is outside [{MIN_DUTY:g}, {MAX_DUTY:g}] for the 3-D trot",
            field="duty_cycle",
        )
    target = max(8, int(np.ceil(period_s * sample_rate_hz - 1e-9)))
    for n in range(target, 4 * target + 1):
        if n % 2 == 0 and abs(duty_cycle * n - round(duty_cycle * n)) < 1e-9:
            return TrotSchedule(period_s, duty_cycle, n)
    raise GaitError(
        f"duty_cycle = {duty_cycle:g}: no grid of {target} to {4 * target} nodes puts the phase "
        "edges on nodes (give the duty factor with at most three decimals)",
        field="duty_cycle",
    )

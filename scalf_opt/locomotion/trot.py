"""The trot's pairing: which legs are on the ground together, and when each stance begins.

In a trot the diagonal pair RF + LH starts its stance at cycle time 0 and LF + RH half a period
later (the paper's precondition d).
"""

from __future__ import annotations

from typing import TypeVar

import numpy as np

from scalf_opt.locomotion.gait import PHASE_EDGE_TOLERANCE_S, Gait

TROT_PHASE_OFFSET: dict[str, float] = {"RF": 0.0, "LH": 0.0, "LF": 0.5, "RH": 0.5}
"""Start of each leg's stance as a fraction of the period (trot: diagonal pairs)."""

DIAGONAL_PARTNER: dict[str, str] = {"RF": "LH", "LH": "RF", "LF": "RH", "RH": "LF"}
"""The leg that shares each leg's stance in a trot."""

SYMMETRIC_TWIN: dict[str, str] = {"RF": "LF", "LF": "RF", "RH": "LH", "LH": "RH"}
"""The leg that repeats each leg's motion half a cycle later (the paper's symmetry)."""


def stance_start_s(gait: Gait, leg: str) -> float:
    """Cycle time at which ``leg``'s stance begins [s]."""
    return TROT_PHASE_OFFSET[leg] * gait.period_s


def swing_start_s(gait: Gait, leg: str) -> float:
    """Cycle time at which ``leg``'s swing begins [s]."""
    return stance_start_s(gait, leg) + gait.stance_duration_s


Times = TypeVar("Times", float, np.ndarray)
"""One time [s] or an array of times."""


def time_since_touchdown_s(gait: Gait, cycle_time_s: Times, leg: str) -> Times:
    """Time since ``leg``'s touch-down at cycle time ``cycle_time_s`` [s], in [0, T).

    A float for a float, an array for an array of times.
    """
    return (cycle_time_s - stance_start_s(gait, leg)) % gait.period_s


def support_masks(gait: Gait, cycle_times_s: np.ndarray, leg: str) -> dict[str, np.ndarray]:
    """Which legs are on the ground at each of ``cycle_times_s`` while ``leg`` is in stance.

    ``leg`` and its diagonal partner always count; another leg counts when the time lies
    strictly inside its stance (a foot exactly at touch-down or lift-off carries nothing).

    Returns:
        Per leg, a boolean array over the times; the legs in the order ``leg``, its diagonal
        partner, then the others.
    """
    times = np.asarray(cycle_times_s, dtype=float)
    out = {leg: np.ones(times.shape, dtype=bool)}
    out[DIAGONAL_PARTNER[leg]] = np.ones(times.shape, dtype=bool)
    for other in TROT_PHASE_OFFSET:
        if other in out:
            continue
        local = time_since_touchdown_s(gait, times, other)
        edge = PHASE_EDGE_TOLERANCE_S
        out[other] = (edge < local) & (local < gait.stance_duration_s - edge)
    return out


def support_groups(standing: dict[str, np.ndarray]) -> list[tuple[np.ndarray, list[str]]]:
    """The times of :func:`support_masks`' answer grouped by the legs on the ground.

    Returns:
        Per set of legs on the ground: the indices of its times, and the legs, in ``standing``'s
        order (so that one stacked computation serves every time of a group).
    """
    patterns = np.array(list(standing.values())).T
    groups = []
    for pattern in np.unique(patterns, axis=0):
        at = np.flatnonzero((patterns == pattern).all(axis=1))
        groups.append((at, [leg for leg, down in zip(standing, pattern, strict=True) if down]))
    return groups

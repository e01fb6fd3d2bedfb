"""A 3-D cycle at any rate over several cycles: ``export --from DIR`` of ``optimize --model 3d``.

``plan.csv`` holds the plan at its nodes. A controller wants it at its own rate: this module reads
the plan's spline and forces at ``k`` samples per node interval (so that a sample falls on every
node, hence on every touch-down and lift-off, which are nodes), computes each instant's joint
torques from the whole-body model with the forces there (the plan's own dynamics, as at its
nodes), and repeats the cycle: each further cycle's trunk ``x`` is one stride ahead, every other
column periodic. The columns are ``plan.csv``'s
(:mod:`~scalf_opt.io.whole_body_export`), SI units, one row per instant.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass, replace

import numpy as np

from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.io.whole_body_export import plan_columns
from scalf_opt.locomotion.contact_schedule import TrotSchedule
from scalf_opt.types import Accounting

DENSE_FORMATS = (".csv", ".json")
"""The files a 3-D cycle is exported to (a ROS 2 bag holds the sagittal export's messages)."""


@dataclass(frozen=True)
class DenseExport:
    """A 3-D plan sampled densely over ``cycles`` cycles.

    Attributes:
        columns: Every column by name, each (cycles * samples,) [SI].
        rate_hz: The sample rate [Hz] (a whole number of samples per node interval).
        requested_rate_hz: The rate asked for [Hz].
        samples_per_cycle: Instants per cycle.
        cycles: Cycles exported.
        period_s: The cycle's period [s].
    """

    columns: dict[str, np.ndarray]
    rate_hz: float
    requested_rate_hz: float
    samples_per_cycle: int
    cycles: int
    period_s: float

    def csv_text(self) -> str:
        """The CSV: a header of the column names, one row per instant (``repr`` of each)."""
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(self.columns)
        for row in zip(*self.columns.values(), strict=True):
            writer.writerow([repr(float(value)) for value in row])
        return buffer.getvalue()

    def json_text(self, robot: str) -> str:
        """The JSON: the rate, period and cycles, and ``columns`` (name -> list) [SI]."""
        return (
            json.dumps(
                {
                    "robot": robot,
                    "rate_hz": self.rate_hz,
                    "period_s": self.period_s,
                    "cycles": self.cycles,
                    "columns": {k: v.tolist() for k, v in self.columns.items()},
                }
            )
            + "\n"
        )


def samples_per_interval(plan: WholeBodyPlan, rate_hz: float) -> int:
    """Samples per node interval nearest ``rate_hz`` (at least one)."""
    return max(1, round(rate_hz * plan.schedule.step_s))


def dense_plan(plan: WholeBodyPlan, per_interval: int) -> WholeBodyPlan:
    """``plan`` read ``per_interval`` times per node interval: its spline, its linear forces."""
    schedule = plan.schedule
    dense = TrotSchedule(schedule.period_s, schedule.duty_cycle, schedule.intervals * per_interval)
    x, xd, xdd = plan.states_at(dense.times_s)
    forces = plan.forces_at(dense.times_s)
    return replace(plan, schedule=dense, x=x, xd=xd, xdd=xdd, forces_n=forces)


def dense_export(
    plan: WholeBodyPlan, accounting: Accounting, rate_hz: float, cycles: int
) -> DenseExport:
    """``plan`` at about ``rate_hz`` over ``cycles`` cycles (module docstring)."""
    if not (math.isfinite(rate_hz) and rate_hz > 0):
        raise ValueError(f"rate_hz = {rate_hz!r} must be > 0")
    per_interval = samples_per_interval(plan, rate_hz)
    dense = dense_plan(plan, per_interval)
    one = plan_columns(dense, accounting)
    n = dense.schedule.intervals
    period = plan.schedule.period_s
    columns = {name: np.tile(values, cycles) for name, values in one.items()}
    repeat = np.repeat(np.arange(cycles), n)
    columns["t_s"] = columns["t_s"] + repeat * period
    columns["base_pos_x_m"] = columns["base_pos_x_m"] + repeat * plan.stride_m
    return DenseExport(columns, n / period, rate_hz, n, cycles, period)

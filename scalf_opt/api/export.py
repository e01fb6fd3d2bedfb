"""``export_plan``: a saved optimum sampled for a controller (CSV, JSON, ROS 2 bag)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scalf_opt.api.gaits import as_robot, command_tuple
from scalf_opt.io.provenance import provenance
from scalf_opt.model.robot import Robot


@dataclass(frozen=True)
class ExportResult:
    """The planned trot at a rate, over cycles (:class:`scalf_opt.io.plan_export.PlanExport`).

    Attributes:
        robot: The robot.
        export: The samples: per leg and joint angle, velocity, acceleration, feed-forward
            torque, contact, foot in the hip frame, and the cylinders' length, speed, force.
        command: The command line that asked for it (``None`` from Python).
    """

    robot: Robot
    export: Any
    command: tuple[str, ...] | None = None

    @property
    def samples(self) -> int:
        """Instants per leg."""
        return int(self.export.t_s.size)

    def write(self, path: str | Path) -> Path:
        """Write the export, atomically; its format by the suffix.

        ``.csv``, ``.json`` (with the provenance) or ``.mcap`` (a ROS 2 bag).
        """
        if Path(path).suffix == ".json":
            from scalf_opt.files import write_atomic
            from scalf_opt.io.results import to_json

            return write_atomic(path, to_json(self.to_dict()))
        return Path(self.export.write(path))

    def to_dict(self) -> dict[str, Any]:
        """Plain data: the JSON file's content, with the provenance."""
        return {"provenance": provenance(self.robot, self.command), **self.export.to_dict()}


def export_plan(
    source: str | Path,
    robot: str | Robot | None = None,
    *,
    rate_hz: float,
    cycles: int = 1,
    command: Sequence[str] | None = None,
) -> ExportResult:
    """The optimum saved in ``source`` sampled at ``rate_hz`` over ``cycles`` gait cycles.

    Every sample is evaluated from the saved swing family and parameters and the stance at that
    rate (not resampled from ``samples.csv``); the cycles follow each other seamlessly.

    Args:
        source: A directory written by ``optimize --out`` (or its ``summary.json``).
        robot: The robot it was computed on (default: SCalf).
        rate_hz: Sample rate [Hz]; one that puts no sample on every touch-down and lift-off
            becomes the nearest that does (the paper's trot: any multiple of 4 Hz; the result's
            ``export.rate_hz``).
        cycles: Gait cycles, 1..1000.
        command: The command line, recorded in the provenance.

    Raises:
        ConfigError: A bad or foreign ``summary.json``, a rate too coarse or too fine, bad
            cycles.
    """
    from scalf_opt.io.plan_export import export_plan as sample
    from scalf_opt.io.saved import read_saved_swings

    robot = as_robot(robot)
    saved = read_saved_swings(source)
    return ExportResult(robot, sample(robot, saved, rate_hz, cycles), command_tuple(command))

"""``optimize_gait``: the cheapest trot at a speed, with its timing, posture and swings optimized.

The search is :func:`scalf_opt.optimize.gait_search.optimize_gait` (a coarse grid over the
period and duty cycle, then the pattern search over them and the stance, the swings optimized
inside by the one solve path); ``scalf-opt gait`` runs it for many speeds on the study engine
and writes the same rows and files as :meth:`GaitResult.write` does for one.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scalf_opt.api.gaits import as_robot, command_tuple, read_gait
from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.loads import DEFAULT_LOADS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.files import write_atomic
from scalf_opt.io.provenance import provenance
from scalf_opt.io.results import checked_summary, samples_csv_text, write_results_json
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family, optimizable_family
from scalf_opt.model.robot import Robot
from scalf_opt.optimize.driver import Settings
from scalf_opt.optimize.gait_search import GaitGoal, GaitSearch
from scalf_opt.optimize.gait_search import optimize_gait as search_gait
from scalf_opt.optimize.solvers import DEFAULT_SOLVER
from scalf_opt.studies.gait_case import gait_details, gait_row
from scalf_opt.types import Accounting, Method

GAIT_FILE = "gait.toml"
"""The cheapest gait as a gait file (``evaluate --gait``)."""


def gait_toml(gait: Gait, robot: str | None = None) -> str:
    """A gait file (TOML ``[gait]`` table) holding every field of ``gait``, exactly.

    ``robot``: the robot it was found for (the file's ``robot`` key; a command that walks it on
    another robot says so).
    """
    lines = [f"robot = {json.dumps(robot)}", ""] if robot is not None else []
    lines.append("[gait]")
    for name, value in gait.to_dict().items():
        lines.append(f"{name} = {value!r}")
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class GaitResult:
    """The cheapest trot at one speed.

    Attributes:
        robot: The robot.
        row: Its ``gaits.csv`` row (:data:`~scalf_opt.studies.gait_case.GAIT_COLUMNS`).
        details: The swings' parameters and records (:func:`~scalf_opt.studies.gait_case
            .gait_details`).
        cycle: The robot's cycle with the cheapest gait and its optimized swings, at the rate
            they converged at (``None`` when no feasible gait was found).
        pipeline: The pipeline of that cycle (``None`` with it).
        search: The search itself (``None`` when rebuilt from a study's row).
        command: The command line that asked for it (``None`` from Python).
    """

    robot: Robot
    row: dict[str, Any]
    details: dict[str, Any]
    cycle: RobotCycle | None
    pipeline: EnergyPipeline | None
    search: GaitSearch | None = None
    command: tuple[str, ...] | None = None

    @classmethod
    def from_row(
        cls,
        robot: Robot,
        row: dict[str, Any],
        details: dict[str, Any],
        search: GaitSearch | None = None,
        command: Sequence[str] | None = None,
    ) -> GaitResult:
        """The result of a row and its details: the optimum's cycle rebuilt from its swings.

        The same gait, accounting, loads (the run record's), family and parameters at the same
        rate give the same samples, so the cycle is the search's own.
        """
        cycle = pipeline = None
        if "parameters" in details:
            gait = Gait(**details["gait"])
            loads = details["optimization_run"]["loads"]  # the loads it was optimized under
            pipeline = EnergyPipeline(robot, gait, details["accounting"], loads=loads)
            family = make_family(details["family"])
            names = details.get("parameter_names")  # none in a cache of an older version
            thetas = {
                leg: family.theta_from_record(p, names) for leg, p in details["parameters"].items()
            }
            cycle = pipeline.robot_cycle(family, thetas)
        return cls(robot, row, details, cycle, pipeline, search, command_tuple(command))

    @property
    def success(self) -> bool:
        """The search converged to a feasible gait whose swings are solved."""
        return self.row["status"] == "ok" and self.cycle is not None

    @property
    def gait(self) -> Gait:
        """The cheapest gait (at the rate its swings converged at).

        Raises:
            ConfigError: No feasible gait was found.
        """
        if self.cycle is None:
            raise ConfigError(f"no feasible gait at {self.row['speed_m_s']:g} m/s")
        return self.cycle.gait

    @property
    def cost_of_transport(self) -> float:
        """The cheapest gait's cost of transport (NaN when none was found)."""
        return self.cycle.cost_of_transport if self.cycle is not None else math.nan

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``summary.json`` of the cheapest gait (its cycle, swings and search)."""
        data: dict[str, Any] = {"provenance": provenance(self.robot, self.command)}
        if self.cycle is not None and self.pipeline is not None:
            data.update(checked_summary(self.cycle, self.pipeline))
        data["solved"] = self.cycle is not None
        data["converged"] = self.success
        data["status"] = "converged" if self.success else f"not converged: {self.row['error']}"
        data["cheapest_gait_row"] = self.row
        data.update({k: v for k, v in self.details.items() if k not in data})
        return data

    def write(self, out_dir: str | Path) -> list[Path]:
        """Write ``gait.toml``, ``summary.json`` and ``samples.csv`` into ``out_dir``.

        ``evaluate --gait DIR/gait.toml`` walks the gait; ``view --from DIR`` and ``simulate
        --from DIR`` read the swings.

        Raises:
            ConfigError: No feasible gait was found: there is nothing to write.
        """
        if self.cycle is None:
            speed = self.row["speed_m_s"]
            raise ConfigError(f"no feasible gait at {speed:g} m/s: nothing to write")
        out = Path(out_dir)
        return [
            write_atomic(out / GAIT_FILE, gait_toml(self.cycle.gait, self.robot.name)),
            *write_results_json(out / "summary.json", self.to_dict()),
            write_atomic(out / "samples.csv", samples_csv_text(self.cycle)),
        ]


def optimize_gait(
    robot: str | Robot,
    speed: float,
    *,
    family: str = DEFAULT_FAMILY,
    method: Method = DEFAULT_SOLVER,
    accounting: Accounting = "paper",
    gait: Gait | None = None,
    command: Sequence[str] | None = None,
    loads: str = DEFAULT_LOADS,
) -> GaitResult:
    """The cheapest trot of ``robot`` at ``speed`` [m/s].

    The period, duty cycle (at least 0.5: a trot without a flight phase), stance height and
    stance x-offsets are optimized with the diagonal pair's swings inside; the step length is
    ``speed * duty * period``. Every gait tried respects every joint and drive limit; the
    answer is compared with the robot's default trot at the same speed, with optimized swings
    and with the reference swing (``row``), and a limit or search-box edge that pins it is named
    (``row["pinned_by"]``).

    Args:
        robot: The robot.
        speed: Target speed [m/s].
        family: The swing family (``joint-N``, ``fourier-N``, ``paper``).
        method: The swings' solver (``ipopt`` or ``pattern``).
        accounting: Power accounting.
        gait: The base gait (default: the robot's default trot): its clearance, rate and
            cycles are kept, its period, duty and stance are the search's centre.
        command: The command line, recorded in the result's provenance.
        loads: The stance load model: ``whole-body`` (default), ``whole-body-sagittal`` or
            ``trunk`` (the paper's).

    Raises:
        ConfigError: A speed out of range, a family without parameters, an unknown load model.
    """
    robot = as_robot(robot)
    swing_family = optimizable_family(family)
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot), accounting, loads=loads)
    search = search_gait(pipeline, GaitGoal(speed, swing_family, Settings(method=method)))
    row = gait_row(search, robot.name)
    return GaitResult.from_row(robot, row, gait_details(search), search, command)


def speed_folder(out: Path, speed_m_s: float) -> Path:
    """Where the cheapest gait at ``speed_m_s`` of a sweep is written: ``out/speed_<v>``."""
    return out / f"speed_{speed_m_s:g}"


@dataclass(frozen=True)
class GaitSweep:
    """The cheapest trot at every speed of a sweep (:func:`sweep_gaits`).

    Attributes:
        robot: The robot.
        rows: One ``gaits.csv`` row per speed, in speed order
            (:data:`~scalf_opt.studies.gait_case.GAIT_COLUMNS`).
        written: ``gaits.csv`` and ``gaits.png``.
        cached: How many speeds came from the cache of an earlier run.
        out: The folder (also a folder ``speed_<v>`` per solved speed).
    """

    robot: Robot
    rows: list[dict[str, Any]]
    written: list[Path]
    cached: int
    out: Path

    @property
    def failed(self) -> list[dict[str, Any]]:
        """The rows of the speeds whose search did not succeed."""
        return [r for r in self.rows if r["status"] != "ok"]


def sweep_gaits(
    robot: Robot,
    speeds: Sequence[float],
    out: str | Path,
    *,
    catalog_name: str | None = None,
    urdf: str | Path | None = None,
    family: str = DEFAULT_FAMILY,
    method: Method = DEFAULT_SOLVER,
    accounting: Accounting = "paper",
    loads: str = DEFAULT_LOADS,
    workers: int | None = None,
    scheduler: str | None = None,
    quiet: bool = False,
    command: Sequence[str] | None = None,
) -> GaitSweep:
    """The cheapest trot at every speed, each speed a case of the study engine.

    Writes ``out/gaits.csv``, ``out/gaits.png`` and per solved speed ``out/speed_<v>/``
    (``gait.toml``, ``summary.json``, ``samples.csv``); finished speeds are cached in ``out``,
    so a stopped sweep resumes.

    Args:
        robot: The robot (loaded).
        speeds: Target speeds [m/s].
        out: The output folder.
        catalog_name: The robot's catalog name, when it is one (the cases load it by name).
        urdf: Its URDF otherwise.
        family: The swing family of every gait's swings.
        method: The swings' solver.
        accounting: Power accounting.
        loads: The stance load model.
        workers: Local worker processes (default: one per usable core).
        scheduler: A Dask scheduler's address instead of local workers.
        quiet: No progress line.
        command: The command line, recorded in each speed's provenance.

    Raises:
        ConfigError: Both ``workers`` and ``scheduler``; a speed out of range; a family without
            parameters; a scheduler that cannot be reached.
    """
    from scalf_opt.io.results import rows_csv_text
    from scalf_opt.studies.gait_case import GAIT_COLUMNS
    from scalf_opt.studies.runner import choose_runner, run_cases
    from scalf_opt.studies.study_file import speed_study
    from scalf_opt.viz.figures import save_atomic
    from scalf_opt.viz.gait_figure import gait_figure

    runner = choose_runner(workers, scheduler)
    optimizable_family(family)
    out = Path(out)
    study = speed_study(
        list(speeds),
        robot=catalog_name or (None if urdf else "scalf"),
        urdf=str(urdf) if urdf else None,
        family=family,
        method=method,
        accounting=accounting,
        name=f"cheapest trot of {robot.name}",
        loads=loads,
    )
    full, cached = run_cases(study, out, runner, label="gait", quiet=quiet)
    rows: list[dict[str, Any]] = [{c: full[i].get(c) for c in GAIT_COLUMNS} for i in sorted(full)]
    title = f"{study.name}: {family} swings, loads '{loads}', accounting '{accounting}'"
    written = [
        write_atomic(out / "gaits.csv", rows_csv_text(rows)),
        save_atomic(gait_figure(rows, title), out / "gaits.png"),
    ]
    for index, row in zip(sorted(full), rows, strict=True):
        details = full[index].get("details") or {}
        if row["status"] == "ok" and "parameters" in details:
            result = GaitResult.from_row(robot, row, details, command=command)
            result.write(speed_folder(out, float(row["speed_m_s"])))
    return GaitSweep(robot, rows, written, cached, out)

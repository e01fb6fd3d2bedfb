"""One case of a study: optimize, and report one row of results beside the reference.

The optimum comes from the one optimization driver (:func:`scalf_opt.optimize.driver
.optimize_swings`, under ``scalf-opt optimize`` too, with its defaults), so a one-case study
prints the energies ``optimize`` prints; the reference in the row is at the optimum's converged
rate, as there.

:func:`run_case` is what a worker runs (a local process or a Dask worker): it takes a
:class:`~scalf_opt.studies.study_file.Case` (plain data) and returns a plain dict, never raises
for a case that fails (the row records the error), and writes nothing but temporary files (a
variant's URDF, in a temporary folder it removes).

:func:`case_key` is the hash a finished case is cached under: the case's inputs, the contents of
every file they read (URDF, actuator and legs files) and scalf-opt's version, so a changed input
never picks up an old result.
"""

from __future__ import annotations

import hashlib
import json
import traceback
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

from scalf_opt.actuators.sidecar import robot_sidecar_path
from scalf_opt.energy.cycle import RobotCycle, change_percent
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ModelError, ScalfError
from scalf_opt.files import read_untrusted, scratch_folder
from scalf_opt.io.study_columns import RESULT_COLUMNS
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.naming import legs_file_for
from scalf_opt.model.robot import Robot
from scalf_opt.model.urdf_file import MAX_URDF_BYTES
from scalf_opt.optimize.driver import Settings, optimize_swings
from scalf_opt.optimize.gait_search import GaitGoal, optimize_gait
from scalf_opt.robots.loading import load_robot
from scalf_opt.robots.variants import VariantScales, derive_variant
from scalf_opt.studies.gait_case import gait_details, gait_row
from scalf_opt.studies.study_file import Case
from scalf_opt.types import FIRST_PAIR, LEG_NAMES
from scalf_opt.version import __version__
from scalf_opt.workers import worker_progress

STATUS_OK = "ok"
STATUS_NOT_SOLVED = "not solved"
STATUS_ERROR = "error"


def _robot(case: Case, folder: Path) -> Robot:
    robot = load_robot(name=case.robot, urdf=case.urdf, legs=case.legs, actuators=case.actuators)
    scales = VariantScales.from_mapping(dict(case.variant))
    if scales.is_identity:
        return robot
    variant = derive_variant(robot, scales, folder / f"{robot.name}_variant.urdf")
    return load_robot(urdf=variant.urdf_path, actuators=case.actuators)


def _gait(case: Case, robot: Robot) -> Gait:
    """The robot's default trot with the case's gait fields (a field out of range: GaitError)."""
    return replace(default_gait_for(robot), **case.gait)


def check_setup(case: Case, folder: Path) -> None:
    """Set the case up as :func:`run_case` does, without optimizing.

    The robot, its variant, the gait, the family and the reference cycle: what fails here fails
    the case before it runs.

    Args:
        case: The case.
        folder: A scratch folder for a variant's URDF.

    Raises:
        ScalfError: The case's robot, variant, gait or family is invalid, or its reference
            motion leaves the legs' reach.
    """
    robot = _robot(case, folder)
    gait = _gait(case, robot)
    make_family(case.family)
    pipeline = EnergyPipeline(robot, gait, case.accounting, loads=case.loads)
    pipeline.robot_cycle(make_family("reference"))


def _legs(optimize_choice: str) -> tuple[str, ...]:
    if optimize_choice == "pair":
        return FIRST_PAIR
    if optimize_choice == "all":
        return LEG_NAMES
    return (optimize_choice,)


def _energies(row: dict[str, Any], cycle: RobotCycle, kind: str) -> None:
    row[f"{kind}_energy_j"] = cycle.energy_j
    row[f"{kind}_power_w"] = cycle.average_power_w
    row[f"cost_of_transport_{kind}"] = cycle.cost_of_transport
    for leg, result in cycle.legs.items():
        row[f"{leg}_{kind}_j"] = result.energy_j


def run_case(case: Case) -> dict[str, Any]:
    """Run one case: the row of ``results.csv`` (every column of :data:`RESULT_COLUMNS`).

    ``status`` is ``ok``, ``not solved`` (an optimizer did not converge: no optimized energy) or
    ``error`` (the case could not be set up or run; ``error`` says why, with the exception's
    type when it is not one of scalf-opt's own errors, which are the input's fault). The row has
    ``unexpected = True`` in that last case (a bug, not an input): the runner does not cache it.
    """
    row: dict[str, Any] = {"case": case.index, **case.swept}
    row.update(dict.fromkeys(RESULT_COLUMNS, None))
    row["robot"] = case.robot or Path(case.urdf or "").stem
    row["error"] = ""
    try:
        with scratch_folder("case") as folder:
            robot = _robot(case, folder)
            gait = _gait(case, robot)
            row["speed_m_s"] = gait.speed_m_s
            rf = robot.leg("RF")
            row["total_mass_kg"] = robot.total_mass_kg
            row["thigh_length_m"] = rf.thigh_length_m
            row["shank_length_m"] = rf.shank_length_m
            row["thigh_to_shank"] = rf.thigh_length_m / rf.shank_length_m
            pipeline = EnergyPipeline(robot, gait, case.accounting, loads=case.loads)
            settings = Settings(method=case.method)
            if case.speed_m_s is not None:
                return _gait_case(row, case, pipeline, settings)
            run = optimize_swings(
                pipeline, _legs(case.optimize), make_family(case.family), settings
            )
            reference = run.reference_cycle()
            _energies(row, reference, "reference")
            if not run.success:
                row["status"] = STATUS_NOT_SOLVED
                row["error"] = run.failure()
                return row
            cycle = run.cycle()
            _energies(row, cycle, "optimized")
            row["saving_pct"] = -change_percent(cycle.energy_j, reference.energy_j)
            row["status"] = STATUS_OK
    except ScalfError as exc:
        row["status"], row["error"] = STATUS_ERROR, str(exc)
    except Exception as exc:  # a bug: recorded so the other cases go on, never cached
        last = traceback.extract_tb(exc.__traceback__)[-1]
        row["status"] = STATUS_ERROR
        row["error"] = f"{type(exc).__name__}: {exc} ({Path(last.filename).name}:{last.lineno})"
        row["unexpected"] = True
    return row


def _gait_case(
    row: dict[str, Any], case: Case, pipeline: EnergyPipeline, settings: Settings
) -> dict[str, Any]:
    """The cheapest trot at the case's speed: its ``gaits.csv`` columns and the study's.

    The study's ``reference`` is the robot's default trot at that speed with the reference
    swing, its ``optimized`` the cheapest gait with its optimized swings.
    """
    assert case.speed_m_s is not None
    goal = GaitGoal(case.speed_m_s, make_family(case.family), settings)
    search = optimize_gait(pipeline, goal, progress=worker_progress)
    gait = gait_row(search, row["robot"])
    row.update({k: v for k, v in gait.items() if k not in row or row[k] is None})
    row["status"], row["error"] = gait["status"], gait["error"]
    row["speed_m_s"] = case.speed_m_s
    row["details"] = gait_details(search)
    if search.reference is not None:
        _energies(row, search.reference, "reference")
    if search.best.run is not None and search.best.run.success:
        cycle = search.cycle()
        _energies(row, cycle, "optimized")
        if search.reference is not None:  # per metre: the two gaits' cycles differ in length
            row["saving_pct"] = row["saving_vs_reference_pct"]
    return row


def _digest(path: str | Path | None) -> str | None:
    if path is None:
        return None
    data = read_untrusted(path, "input", MAX_URDF_BYTES, ModelError)  # the largest input kind
    return hashlib.sha256(data).hexdigest()


def _input_files(case: Case) -> dict[str, str | None]:
    """Hashes of every file the case's robot is read from (URDF, actuator and legs files)."""
    robot = load_robot(name=case.robot, urdf=case.urdf, legs=case.legs, actuators=case.actuators)
    beside = legs_file_for(robot.urdf_path)
    legs_path = case.legs or (str(beside) if beside.exists() else None)
    return {
        "urdf": _digest(robot.urdf_path),
        "actuators": _digest(robot_sidecar_path(robot)),
        "legs": _digest(legs_path),
    }


def case_key(case: Case, memo: dict[tuple[Any, ...], dict[str, str | None]] | None = None) -> str:
    """The hash a case's result is cached under (inputs, input files' contents, version).

    Args:
        case: The case.
        memo: Hashes of robots' files already read in this run (keyed by robot, URDF, legs and
            actuator paths), filled as needed.

    Raises:
        ScalfError: The case's robot cannot be loaded (the case will fail the same way).
    """
    memo = {} if memo is None else memo
    robot_key = (case.robot, case.urdf, case.legs, case.actuators)
    if robot_key not in memo:
        memo[robot_key] = _input_files(case)
    inputs = asdict(case)
    inputs.pop("index")  # the same case at another place in a study is the same case
    if inputs["speed_m_s"] is None:  # a fixed gait's case: its key as before speeds existed
        inputs.pop("speed_m_s")
    inputs["files"] = memo[robot_key]
    inputs["version"] = __version__
    text = json.dumps(inputs, sort_keys=True, default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:32]

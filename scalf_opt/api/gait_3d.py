"""``gait --model 3d``: the cheapest whole-body trot at every speed, one NLP per start.

At each speed the 3-D cycle NLP (:mod:`~scalf_opt.optimize.whole_body_nlp`) is solved with the
period free inside a range (a decision variable beside every joint's and the trunk's motion and
the contact forces; its objective the mean drawn power, at a fixed speed the energy per metre)
from each start: a duty factor (the contact schedule, fixed during a solve) and a first period.
The cheapest converged start's cost of transport is the speed's answer. The speeds run in worker
processes (:func:`~scalf_opt.workers.map_in_processes`) in chains of three consecutive speeds
(:data:`CHAIN_LENGTH`): in a chain each speed starts from the previous speed's answer.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scalf_opt.energy.margins import DEFAULT_MARGINS, LimitMargins
from scalf_opt.errors import ScalfError
from scalf_opt.files import write_atomic
from scalf_opt.locomotion.contact_schedule import DEFAULT_FRICTION
from scalf_opt.types import Accounting
from scalf_opt.workers import map_in_processes, worker_progress

PERIOD_RANGE_SHARES = (0.5, 2.0)
"""The free period's default range as shares of the robot's default period (its Froude-scaled
trot's)."""

DEFAULT_GAIT_RATE_HZ = 25.0
"""The node rate of ``gait --model 3d`` unless ``--rate`` says otherwise [Hz]: the ten-times
rule refines the grid where the energy needs more (Go1's and SCalf's trots hold it at 25 Hz)."""


@dataclass(frozen=True)
class SpeedCase:
    """One speed of a sweep: what a worker needs to solve it (plain data: it is pickled).

    Attributes:
        robot_name: The catalog robot, or ``None`` with ``urdf``.
        urdf: Its URDF otherwise.
        speed_m_s: The average forward speed [m/s].
        starts: ``(duty factor, first period [s])`` of each start.
        period_range_s: The period's bounds [s].
        sample_rate_hz: The node rate [Hz].
        friction: The contacts' friction coefficient.
        margins: The limit margins.
        accounting: How joint power is charged.
    """

    robot_name: str | None
    urdf: str | None
    speed_m_s: float
    starts: tuple[tuple[float, float], ...]
    period_range_s: tuple[float, float]
    sample_rate_hz: float
    friction: float = DEFAULT_FRICTION
    margins: LimitMargins = DEFAULT_MARGINS
    accounting: Accounting = "paper"


@dataclass(frozen=True)
class StartAnswer:
    """What one start of a speed came to.

    Attributes:
        duty_cycle: The start's duty factor.
        start_period_s: Its first period [s].
        converged: Every solve converged and the ten-times rule holds.
        failure: Why not, in words (empty when it converged).
        summary: The cycle's ``summary.json`` data (``None`` when no plan came back).
        plan_csv: The plan's ``plan.csv`` text (empty without a plan).
    """

    duty_cycle: float
    start_period_s: float
    converged: bool
    failure: str
    summary: dict[str, Any] | None
    plan_csv: str

    @property
    def cost_of_transport(self) -> float:
        """The plan's cost of transport (NaN without a plan)."""
        return math.nan if self.summary is None else float(self.summary["cost_of_transport"])


def _labelled(label: str) -> Callable[[str], None]:
    """A progress callback that puts ``label`` before each text (to the worker's progress)."""

    def progress(text: str) -> None:
        worker_progress(f"{label}: {text}")

    return progress


CHAIN_LENGTH = 3
"""Speeds per chain: a chain's speeds (consecutive, slowest first) run in one worker, each start
from the previous speed's answer of the same start (its grid, not the coarse one). Measured on
Go1's 0.6 -> 0.8 and 0.8 -> 1.0 m/s: 61 and 151 Ipopt iterations (12 and 30 s) against about 80 s
of a cold speed's three grids, and cheaper answers (CoT 0.3085 and 0.2958 against 0.3103 and
0.2966). A fixed length, not one chain per worker: the answers do not depend on ``--workers``."""


def solve_speed(case: SpeedCase) -> list[StartAnswer]:
    """Every start of ``case`` from the kinematic start, in order (a start that raises fails)."""
    return _solve_speed(case, _physics(case), {})[0]


def solve_chain(chain: tuple[SpeedCase, ...]) -> list[list[StartAnswer]]:
    """Each speed of ``chain`` in order, each start from the previous speed's answer.

    See :data:`CHAIN_LENGTH`.

    A start whose previous speed did not converge starts from the kinematic start again.
    """
    physics = _physics(chain[0])  # one robot per sweep: its model and kernels built once
    previous: dict[tuple[float, float], Any] = {}
    out = []
    for case in chain:
        answers, previous = _solve_speed(case, physics, previous)
        out.append(answers)
    return out


def solve_cases(
    cases: Sequence[SpeedCase], workers: int, progress: Callable[[str], None] | None = None
) -> list[list[StartAnswer]]:
    """Every case's starts (``cases``' order), in chains of :data:`CHAIN_LENGTH` by speed."""
    order = sorted(range(len(cases)), key=lambda i: cases[i].speed_m_s)
    chains = [
        tuple(cases[i] for i in order[k : k + CHAIN_LENGTH])
        for k in range(0, len(order), CHAIN_LENGTH)
    ]
    chained = map_in_processes(solve_chain, chains, workers, progress)
    solved = [speed_answers for chain in chained for speed_answers in chain]
    answers: list[list[StartAnswer]] = [[] for _ in cases]
    for index, speed_answers in zip(order, solved, strict=True):
        answers[index] = speed_answers
    return answers


def _physics(case: SpeedCase) -> Any:
    """The 3-D model of ``case``'s robot."""
    from scalf_opt.energy.whole_body import WholeBodyPhysics
    from scalf_opt.robots.loading import load_robot

    return WholeBodyPhysics.of(load_robot(name=case.robot_name, urdf=case.urdf))


def _solve_speed(
    case: SpeedCase, physics: Any, previous: dict[tuple[float, float], Any]
) -> tuple[list[StartAnswer], dict[tuple[float, float], Any]]:
    """Every start of ``case`` on ``physics``, each from ``previous``'s plan of the same start.

    Returns the answers and the converged starts' plans (by start).
    """
    from scalf_opt.io.whole_body_export import plan_csv
    from scalf_opt.io.whole_body_summary import cycle_summary
    from scalf_opt.locomotion.contact_schedule import trot_schedule
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.optimize.whole_body_driver import optimize_cycle
    from scalf_opt.optimize.whole_body_nlp import CycleProblem

    gait = default_gait_for(physics.robot)
    answers = []
    plans: dict[tuple[float, float], Any] = {}
    for duty, period in case.starts:
        label = f"{case.speed_m_s:g} m/s from duty {duty:g}, T {period:g} s"
        worker_progress(label)
        try:
            problem = CycleProblem(
                physics,
                trot_schedule(period, duty, case.sample_rate_hz),
                case.speed_m_s,
                gait.stance_height_m,
                gait.clearance_m,
                case.friction,
                case.margins,
                case.accounting,
                case.period_range_s,
            )
            warm = previous.get((duty, period))
            result = optimize_cycle(problem, case.sample_rate_hz, _labelled(label), warm)
        except ScalfError as exc:
            answers.append(StartAnswer(duty, period, False, str(exc), None, ""))
            continue
        summary = cycle_summary(problem, result)
        summary["start"] = {"duty_cycle": duty, "period_s": period}
        csv_text = plan_csv(result.plan, case.accounting)
        answers.append(
            StartAnswer(duty, period, result.converged, result.failure(), summary, csv_text)
        )
        if result.converged:
            plans[(duty, period)] = result.plan
    return answers, plans


GAIT_3D_COLUMNS = (
    "speed_m_s",
    "status",
    "robot",
    "period_s",
    "duty_cycle",
    "stride_m",
    "step_length_m",
    "energy_per_cycle_j",
    "average_power_w",
    "cost_of_transport",
    "rate_difference",
    "grid_change",
    "nodes",
    "start_duty_cycle",
    "start_period_s",
    "starts_converged",
    "pinned_by",
    "solve_s",
    "error",
)
"""The columns of ``gaits.csv`` of ``gait --model 3d`` (one row per speed; SI units)."""


def speed_row(robot: str, speed_m_s: float, answers: Sequence[StartAnswer]) -> dict[str, Any]:
    """The ``gaits.csv`` row of a speed: its cheapest converged start (or why none converged)."""
    row: dict[str, Any] = dict.fromkeys(GAIT_3D_COLUMNS, "")
    converged = [a for a in answers if a.converged and a.summary is not None]
    row.update(speed_m_s=speed_m_s, robot=robot, starts_converged=len(converged))
    row["solve_s"] = sum(
        s["seconds"] for a in answers if a.summary is not None for s in a.summary["solves"]
    )
    if not converged:
        row["status"] = "not converged"
        row["error"] = "; ".join(
            f"duty {a.duty_cycle:g}, T {a.start_period_s:g} s: {a.failure}" for a in answers
        )
        return row
    best = min(converged, key=lambda a: a.cost_of_transport)
    data = best.summary
    assert data is not None  # a converged start has its plan
    period, duty = data["period_s"], data["duty_cycle"]
    row.update(
        status="ok",
        period_s=period,
        duty_cycle=duty,
        stride_m=data["stride_m"],
        step_length_m=speed_m_s * duty * period,
        energy_per_cycle_j=data["energy_per_cycle_j"],
        average_power_w=data["energy_per_cycle_j"] / period,
        cost_of_transport=data["cost_of_transport"],
        rate_difference=data["rate_difference"],
        grid_change="" if data.get("grid_change") is None else data["grid_change"],
        nodes=data["nodes"],
        start_duty_cycle=best.duty_cycle,
        start_period_s=best.start_period_s,
        pinned_by="; ".join(data["pinned_by"]),
    )
    return row


def speed_folder(out: Path, speed_m_s: float) -> Path:
    """Where a sweep writes the cheapest cycle at ``speed_m_s``: ``out/speed_<v>``."""
    return out / f"speed_{speed_m_s:g}"


@dataclass(frozen=True)
class Gait3dSweep:
    """The cheapest 3-D trot at every speed (:func:`sweep_gaits_3d`).

    Attributes:
        robot: The robot's name.
        rows: One ``gaits.csv`` row per speed (:data:`GAIT_3D_COLUMNS`), in speed order.
        answers: Every start of every speed, in the same order.
        written: The files written (``gaits.csv``, ``gaits.png``, each solved speed's files).
    """

    robot: str
    rows: list[dict[str, Any]]
    answers: list[list[StartAnswer]]
    written: list[Path]

    @property
    def failed(self) -> list[dict[str, Any]]:
        """The rows of the speeds no start converged at."""
        return [r for r in self.rows if r["status"] != "ok"]


def default_starts(
    default_period_s: float, duties: Sequence[float] | None, periods: Sequence[float] | None
) -> tuple[tuple[float, float], ...]:
    """Every pair of the given duty factors and first periods (defaults: 0.5, the robot's)."""
    return tuple(
        (float(d), float(t)) for d in (duties or (0.5,)) for t in (periods or (default_period_s,))
    )


def sweep_gaits_3d(
    cases: Sequence[SpeedCase],
    out: Path,
    robot: str,
    workers: int,
    progress: Callable[[str], None] | None = None,
    compare: list[dict[str, Any]] | None = None,
) -> Gait3dSweep:
    """Solve every case (one per speed) and write ``out``'s files.

    ``out/gaits.csv`` (:data:`GAIT_3D_COLUMNS`), ``out/gaits.png`` (the cost of transport and
    the answers' timing against speed, beside ``compare``'s sagittal rows when given) and per
    converged speed ``out/speed_<v>/`` with the cheapest start's ``summary.json`` (every start's
    outcome under ``starts``) and ``plan.csv``.
    """
    import json

    from scalf_opt.io.results import rows_csv_text
    from scalf_opt.viz.figures import save_atomic
    from scalf_opt.viz.whole_body_gait_figure import gait_3d_figure

    answers = solve_cases(cases, workers, progress)
    rows = [speed_row(robot, c.speed_m_s, a) for c, a in zip(cases, answers, strict=True)]
    written = [write_atomic(out / "gaits.csv", rows_csv_text(rows))]
    accounting = cases[0].accounting
    title = f"cheapest 3-D trot of {robot} per speed (period free, accounting '{accounting}')"
    written.append(save_atomic(gait_3d_figure(rows, answers, title, compare), out / "gaits.png"))
    for case, row, speed_answers in zip(cases, rows, answers, strict=True):
        if row["status"] != "ok":
            continue
        best = min(
            (a for a in speed_answers if a.converged and a.summary is not None),
            key=lambda a: a.cost_of_transport,
        )
        assert best.summary is not None
        summary = {
            **best.summary,
            "starts": [
                {
                    "duty_cycle": a.duty_cycle,
                    "start_period_s": a.start_period_s,
                    "converged": a.converged,
                    "failure": a.failure,
                    "period_s": None if a.summary is None else a.summary["period_s"],
                    "cost_of_transport": None if a.summary is None else a.cost_of_transport,
                }
                for a in speed_answers
            ],
        }
        folder = speed_folder(out, case.speed_m_s)
        folder.mkdir(parents=True, exist_ok=True)
        written.append(write_atomic(folder / "plan.csv", best.plan_csv))
        written.append(write_atomic(folder / "summary.json", json.dumps(summary, indent=2) + "\n"))
    return Gait3dSweep(robot, rows, answers, written)

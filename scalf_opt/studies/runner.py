"""Run a study's cases: in this process, on a local process pool, or on a Dask cluster.

Every case is independent (:func:`~scalf_opt.studies.case.run_case`). A finished case is written
at once to ``<out>/cache/<key>.json`` (its key hashes its inputs, see
:func:`~scalf_opt.studies.case.case_key`), so a rerun, or a run that was killed half-way, runs
only the cases not yet there. A case that fails is a row with its error; the others go on. When
every case has a row, ``results.csv`` (one row per case, in the study's order) and the figure
``study.png`` are written; the rows do not depend on where or in which order the cases ran.

Backends: ``workers == 1`` runs the cases here, one after the other; ``workers > 1`` on a pool of
that many local processes (default: one per CPU); ``scheduler`` sends them to a Dask cluster
(``tcp://host:port``; every worker needs scalf-opt installed).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scalf_opt.errors import ConfigError, ScalfError
from scalf_opt.files import scratch_folder, write_atomic
from scalf_opt.interrupts import raise_if_stopped
from scalf_opt.io.results import rows_csv_text, to_json
from scalf_opt.io.saved import read_json
from scalf_opt.io.study_columns import RESULT_COLUMNS
from scalf_opt.studies.case import (
    STATUS_ERROR,
    STATUS_OK,
    case_key,
    check_setup,
    run_case,
)
from scalf_opt.studies.gait_case import GAIT_COLUMNS
from scalf_opt.studies.progress import Progress
from scalf_opt.studies.scheduler import check_scheduler, scheduler_endpoint
from scalf_opt.studies.study_file import Case, Study
from scalf_opt.viz.figures import save_atomic
from scalf_opt.viz.study_figures import study_figure
from scalf_opt.workers import WorkerDiedError, imap_in_processes, progress_to

RESULTS_FILE = "results.csv"
FIGURE_FILE = "study.png"
CACHE_DIR = "cache"

Runner = Callable[[list[Case]], Iterator[tuple[Case, dict[str, Any]]]]


@dataclass(frozen=True)
class StudyRun:
    """What a study run produced.

    Attributes:
        rows: One row per case, in the study's order.
        columns: The columns of ``results.csv``.
        results_path: ``results.csv``.
        figure_path: The figure.
        cached: Cases taken from the cache (not run again).
    """

    rows: list[dict[str, Any]]
    columns: list[str]
    results_path: Path
    figure_path: Path
    cached: int

    @property
    def failed(self) -> list[dict[str, Any]]:
        """Rows whose status is not ``ok``."""
        return [r for r in self.rows if r["status"] != STATUS_OK]


def _failure(case: Case, message: str) -> dict[str, Any]:
    """The row of a case whose worker died (not cached: a rerun runs it again)."""
    row: dict[str, Any] = {"case": case.index, **case.swept, **dict.fromkeys(RESULT_COLUMNS)}
    row.update(status=STATUS_ERROR, error=message, unexpected=True)
    row["robot"] = case.robot or Path(case.urdf or "").stem
    return row


def _serial(cases: list[Case]) -> Iterator[tuple[Case, dict[str, Any]]]:
    for case in cases:
        raise_if_stopped()
        yield case, run_case(case)


def _pool(workers: int) -> Runner:
    def run(cases: list[Case]) -> Iterator[tuple[Case, dict[str, Any]]]:
        # fresh interpreters (scalf_opt.workers): no fork of this process's CasADi/Pinocchio
        # state, and unlike multiprocessing's spawn, the caller's script is not run again in
        # each worker (a script without an `if __name__ == "__main__":` guard works)
        for index, row in imap_in_processes(run_case, cases, workers):
            case = cases[index]
            if isinstance(row, WorkerDiedError):
                yield case, _failure(case, f"worker process died ({row})")
            elif isinstance(row, Exception):
                raise row  # run_case makes a row of every error of the input: a bug
            else:
                yield case, row

    return run


def _dask(address: str) -> Runner:
    scheduler_endpoint(address)  # a mistyped address is refused before anything runs
    try:
        from dask.distributed import Client
        from dask.distributed import as_completed as dask_completed
    except ImportError as exc:
        raise ConfigError(
            f"--scheduler {address}: needs dask.distributed (pip install 'scalf-opt[sweep]')"
        ) from exc

    def run(cases: list[Case]) -> Iterator[tuple[Case, dict[str, Any]]]:
        checked = check_scheduler(address)
        try:
            client = Client(checked, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise ConfigError(
                f"--scheduler {address}: cannot reach the Dask scheduler ({exc})"
            ) from exc
        try:
            futures = {client.submit(run_case, case, pure=False): case for case in cases}
            for future in dask_completed(list(futures)):
                case = futures[future]
                try:
                    yield case, future.result()
                except Exception as exc:  # the worker died or lost the task
                    yield case, _failure(case, f"Dask worker failed: {type(exc).__name__}: {exc}")
        finally:
            client.close()

    return run


def choose_runner(workers: int | None = None, scheduler: str | None = None) -> Runner:
    """The backend: Dask with a scheduler address, else a pool of ``workers`` processes.

    Raises:
        ConfigError: Both given; ``workers`` is below 1 or above :func:`usable_cores`; a
            scheduler address that is not plain TCP, or Dask is missing.
    """
    if workers is not None and scheduler is not None:
        raise ConfigError("give --workers or --scheduler, not both")
    if scheduler is not None:
        return _dask(scheduler)
    cores = usable_cores()
    n = cores if workers is None else workers
    if n < 1:
        raise ConfigError(f"--workers must be at least 1, got {workers}")
    if n > cores:
        raise ConfigError(
            f"--workers {n}: more than the {cores} cores this process may use (each worker "
            "solves on a core of its own: more would only share them, at a few hundred MB of "
            "memory each)"
        )
    return _serial if n == 1 else _pool(n)


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity, else the machine's count)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _cached(path: Path, case: Case) -> dict[str, Any] | None:
    if not path.exists():
        return None
    try:
        row = read_json(path, "cache entry")
    except ScalfError:
        return None  # damaged, or not a regular file: run the case again (written anew)
    if not isinstance(row, dict):
        return None
    row.update({"case": case.index, **case.swept})
    return row


MAX_SETUP_TRIES = 50
"""Cases set up before a study none of whose cases runs is refused: a fixed field no case can
walk fails them all, and 10,000 of them would take minutes to try."""


def check_some_case_runs(study: Study) -> None:
    """Refuse, before any case runs, a study none of whose cases can be set up.

    The cases are set up in turn (:func:`~scalf_opt.studies.case.check_setup`) until one
    passes, at most :data:`MAX_SETUP_TRIES` of them: a fixed gait field the robot cannot walk,
    say, fails every case, which is the study file's fault and is said once, with nothing
    written, rather than as a table of failures.

    Raises:
        ScalfError: Every case fails its setup; the first case's error, naming the study file.
    """
    first: ScalfError | None = None
    tried = study.cases[:MAX_SETUP_TRIES]
    with scratch_folder("check") as folder:
        for case in tried:
            raise_if_stopped()
            try:
                check_setup(case, folder)
                return
            except ScalfError as exc:
                first = first or exc
    if first is not None:
        which = (
            f"{len(tried)} tried"
            if len(tried) == len(study.cases)
            else f"the first {len(tried)} of {len(study.cases)} tried; put a case that can run "
            "first if there is one"
        )
        raise type(first)(
            f"{study.path}: no case can run ({which}); case 1: {first}", field=first.field
        )


def _columns(study: Study) -> list[str]:
    swept = list(dict.fromkeys(f for case in study.cases for f in case.swept))
    columns = ["case", *swept, *[c for c in RESULT_COLUMNS if c not in swept]]
    if any(case.speed_m_s is not None for case in study.cases):  # the cheapest gaits' too
        columns += [c for c in GAIT_COLUMNS if c not in columns]
    return columns


def run_cases(
    study: Study,
    out: str | Path,
    runner: Runner | None = None,
    progress: Progress | None = None,
    label: str = "study",
    quiet: bool = False,
) -> tuple[dict[int, dict[str, Any]], int]:
    """Run every case not yet cached under ``out/cache``: each case's full row, by index.

    A row holds every key its case produced (a cheapest-gait case's ``details`` too), not only
    the columns of ``results.csv``. Also returns how many rows came from the cache. ``label``
    names the command in the progress lines; ``quiet`` shows none (no bar, no heartbeat).

    Raises:
        ConfigError: The output folder cannot be written; the Dask scheduler cannot be reached.
        ScalfError: No case can be set up (:func:`check_some_case_runs`).
    """
    cache = Path(out) / CACHE_DIR
    check_some_case_runs(study)
    runner = runner or choose_runner()
    rows: dict[int, dict[str, Any]] = {}
    keys: dict[int, str | None] = {}
    memo: dict[tuple[Any, ...], dict[str, str | None]] = {}
    todo = []
    for case in study.cases:
        try:
            keys[case.index] = case_key(case, memo)
        except ScalfError:
            keys[case.index] = None  # the case fails the same way when it runs: not cached
        key = keys[case.index]
        row = _cached(cache / f"{key}.json", case) if key else None
        if row is None:
            todo.append(case)
        else:
            rows[case.index] = row
    cached = len(rows)
    progress = progress or Progress(len(todo), label=label, enabled=False if quiet else None)
    try:
        with progress_to(progress.note):  # what a case is doing, as it says it
            for case, row in runner(todo):
                key = keys[case.index]
                if key and not row.get("unexpected"):
                    write_atomic(cache / f"{key}.json", to_json(row))
                rows[case.index] = row
                progress.update(row["status"] == STATUS_OK)
    finally:
        progress.close()
    return rows, cached


def run_study(
    study: Study,
    out: str | Path,
    runner: Runner | None = None,
    progress: Progress | None = None,
    quiet: bool = False,
) -> StudyRun:
    """Run every case not yet cached under ``out``, then write ``results.csv`` and the figure.

    Args:
        study: The study.
        out: Output folder (the cache lives in ``out/cache``).
        runner: The backend (:func:`choose_runner`; default: one process per CPU).
        progress: Progress display (default: a bar on a terminal, a heartbeat elsewhere).
        quiet: No progress display at all (``--quiet``).

    Raises:
        ConfigError: The output folder cannot be written; the Dask scheduler cannot be reached.
    """
    out = Path(out)
    rows, cached = run_cases(study, out, runner, progress, quiet=quiet)
    columns = _columns(study)
    ordered = [{c: rows[i].get(c) for c in columns} for i in sorted(rows)]
    results = write_atomic(out / RESULTS_FILE, rows_csv_text(ordered))
    figure = save_atomic(study_figure(ordered, study.plot_x, study.name), out / FIGURE_FILE)
    return StudyRun(ordered, columns, results, figure, cached)

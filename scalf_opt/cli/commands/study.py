"""``scalf-opt study``: run a declared sweep, locally or on a Dask cluster."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import Outputs, bounded

MAX_WORKERS = 256
"""Most local worker processes."""

WORKERS_HELP = (
    "local worker processes, at most one per core this process may use (the default; 1 runs "
    "the cases in this process)"
)
"""``--workers``' help, the same wherever a command takes it."""

NAME = "study"
HELP = "run a sweep declared in a study file (local processes or a Dask cluster)"
JSON = True
EXAMPLES = (
    ("scalf-opt study speed.toml", "every case (results/study/speed)"),
    ("scalf-opt study speed.toml --workers 1 --json", "in this process; the rows as JSON"),
    ("scalf-opt study speed.toml --scheduler tcp://host:8786", "on a Dask cluster"),
)


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    parser.add_argument("file", type=Path, metavar="FILE", help="the study file (TOML)")
    parser.add_argument(
        "--workers",
        type=bounded(int, MAX_WORKERS),
        metavar="N",
        help=WORKERS_HELP,
    )
    parser.add_argument(
        "--scheduler",
        metavar="URL",
        help="a Dask scheduler, tcp://host:port (e.g. tcp://host:8786)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        metavar="DIR",
        help="output folder (default results/study/<study file stem>)",
    )


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every case succeeded, 3 when some did not (``results.csv`` says why)."""
    from scalf_opt.io.provenance import run_provenance
    from scalf_opt.studies.runner import choose_runner, run_study
    from scalf_opt.studies.study_file import read_study
    from scalf_opt.studies.table import results_table

    runner = choose_runner(args.workers, args.scheduler)  # before the file: a wrong option first
    study = read_study(args.file)
    out = output_folder(args)
    result = run_study(study, out, runner, quiet=args.quiet)
    args.console.text(results_table(study.name, result))
    args.console.json(
        {
            "provenance": run_provenance(args.argv, study=str(args.file)),
            "results_csv": str(result.results_path),
            "rows": result.rows,
        }
    )
    if result.failed:
        args.console.error(
            f"{len(result.failed)} of {len(result.rows)} cases did not succeed "
            f"(see {result.results_path})"
        )
        return 3
    return 0


def output_folder(args: argparse.Namespace) -> Path:
    """``--out``, or ``results/study/<study file name>``."""
    return args.out if args.out is not None else Path("results") / "study" / args.file.stem


def outputs(args: argparse.Namespace) -> Outputs:
    """The results and the figure, moved into place together.

    The cache of finished cases is written at once (a killed study resumes from it).

    Raises:
        ConfigError: The output folder is the study file itself.
    """
    from scalf_opt.errors import ConfigError
    from scalf_opt.studies.runner import CACHE_DIR

    out = output_folder(args)
    if args.file.resolve() == out.resolve():
        raise ConfigError(f"--out {out}: is the study file {args.file} itself")
    return Outputs(folders={"--out": out}, direct=(out / CACHE_DIR,))

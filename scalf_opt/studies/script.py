"""The command line every sweep script in ``studies/`` shares: write the study file, run it.

``python studies/NAME.py [--quick] [--out DIR] [--workers N]``: the script's study text (a small
version with ``--quick``) is written to ``DIR/<file name>`` (so that ``scalf-opt study`` reruns
it) and run there, on N local worker processes (default one per CPU).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from pathlib import Path

from scalf_opt.files import write_atomic
from scalf_opt.studies.runner import StudyRun, choose_runner, run_study
from scalf_opt.studies.study_file import Study, read_study


def run_study_script(
    argv: Sequence[str] | None,
    doc: str,
    study_text: Callable[[bool], str],
    *,
    file_name: str,
    default_out: str,
    quick_help: str,
) -> tuple[Study, StudyRun, Path]:
    """Parse the script's options, write its study file and run it.

    Args:
        argv: The script's arguments (default: ``sys.argv``).
        doc: The script's docstring (its first line is the help's description).
        study_text: The study file's text; its argument says ``--quick``.
        file_name: The study file's name in the output folder.
        default_out: The output folder without ``--out``.
        quick_help: What ``--quick`` runs.

    Returns:
        The study, its result and the output folder.
    """
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=quick_help)
    parser.add_argument("--out", type=Path, default=Path(default_out))
    parser.add_argument("--workers", type=int, help="local worker processes (default: per CPU)")
    args = parser.parse_args(argv)
    study = read_study(write_atomic(args.out / file_name, study_text(args.quick)))
    return study, run_study(study, args.out, choose_runner(args.workers)), args.out

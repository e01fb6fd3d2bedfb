"""``scalf-opt figures``: the paper's figures (8-13, 17, 18, Table 6), and a landscape it lacked."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import (
    add_gait,
    add_loads,
    add_robot,
    bounded,
    check_output_dir,
    load_gait,
    load_robot,
    refuse_gait_with_saved,
    warn_without_effect,
)

MAX_GRID = 201
"""Most points per parameter of the landscape (201 x 201 energies)."""

NAME = "figures"
HELP = "draw the paper's figures (PNG and SVG): joints, forces, foot paths, search, energy"
EXAMPLES = (
    ("scalf-opt figures", "the paper's figures of the reference and the default optimum"),
    ("scalf-opt figures --from results/optimum --format png", "a saved optimum, PNG only"),
    ("scalf-opt figures --robot hyq --out results/hyq-figures", "another robot"),
    (
        "scalf-opt figures --from results/go1-3d",
        "a 3-D cycle (optimize --model 3d --out): the trunk's height, roll, pitch and the forces",
    ),
)


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    add_loads(parser, saved=True)
    parser.add_argument(
        "--from",
        dest="from_dirs",
        metavar="DIR",
        type=Path,
        action="append",
        default=[],
        help="a directory written by 'optimize --out' (repeat to compare; default: the "
        "reference and the default optimum, joint-6 by Ipopt; the first DIR's robot by default "
        "when the catalog has it); a 3-D cycle's (optimize --model 3d --out) draws its trunk "
        "height, roll, pitch and vertical foot forces (trunk.png)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/figures"),
        metavar="DIR",
        help="output directory (default results/figures)",
    )
    parser.add_argument(
        "--format",
        dest="formats",
        choices=("png", "svg"),
        action="append",
        help="file format (repeatable; default: both png and svg)",
    )
    parser.add_argument(
        "--grid",
        type=bounded(int, MAX_GRID),
        metavar="N",
        default=61,
        help=f"points per parameter of the pattern search's energy landscape, 3..{MAX_GRID} "
        "(default 61)",
    )


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every figure is written, 3 when the default optimum is not solved."""
    from scalf_opt.api.presentation import NotSolvedError, search_pipeline, shown_trajectories
    from scalf_opt.cli.progress import ProgressBar
    from scalf_opt.errors import ConfigError
    from scalf_opt.io.whole_body_export import is_cycle_dir
    from scalf_opt.studies.search import search_study
    from scalf_opt.viz.figure_set import write_figures
    from scalf_opt.viz.trajectories import energy_lines

    check_output_dir(args.out)
    formats = tuple(dict.fromkeys(args.formats or ("png", "svg")))
    if any(is_cycle_dir(d) for d in args.from_dirs):
        return _run_3d(args, formats)
    if args.grid < 3:
        raise ConfigError(f"--grid must be at least 3, got {args.grid}")
    refuse_gait_with_saved(args)
    robot = load_robot(args, next(iter(args.from_dirs), None))
    warn_without_effect(args, robot)
    gait = load_gait(args, robot)
    try:
        with ProgressBar(None, "figures", enabled=not args.quiet) as bar:
            pipeline, shown = shown_trajectories(
                robot, gait, args.from_dirs, args.accounting, bar.step, args.loads
            )
            bar.step("the pattern search's landscape")
            search = search_study(
                search_pipeline(pipeline, gait, args.from_dirs), grid_points=args.grid
            )
    except NotSolvedError as exc:
        args.console.error(f"{exc}; nothing written")
        return 3
    written = write_figures(args.out, robot, shown, search, formats)
    args.console.text("\n".join(energy_lines(shown)))
    names = sorted({p.stem for p in written}, key=[p.stem for p in written].index)
    args.console.text(f"wrote {args.out}/: {', '.join(names)} ({', '.join(formats)})")
    return 0


def _run_3d(args: argparse.Namespace, formats: tuple[str, ...]) -> int:
    """Draw the 3-D cycles of ``--from`` (every DIR must be one): the figure ``trunk``."""
    from scalf_opt.errors import ConfigError
    from scalf_opt.io.whole_body_export import is_cycle_dir, read_cycle
    from scalf_opt.viz.plotting import save_in_formats
    from scalf_opt.viz.whole_body_figure import trunk_figure

    sagittal = [d for d in args.from_dirs if not is_cycle_dir(d)]
    if sagittal:
        raise ConfigError(
            f"--from {sagittal[0]}: not a 3-D cycle; 3-D and sagittal results are drawn apart",
            field="from",
        )
    cycles = [read_cycle(d) for d in args.from_dirs]
    save_in_formats(trunk_figure(cycles), args.out, "trunk", formats)
    for cycle in cycles:
        args.console.text(cycle.headline)
    args.console.text(f"wrote {args.out}/: trunk ({', '.join(formats)})")
    return 0

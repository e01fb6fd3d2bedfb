"""``scalf-opt view``: one offline HTML page of the robot walking its foot paths (meshcat)."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import (
    Outputs,
    add_gait,
    add_loads,
    add_robot,
    load_gait,
    load_robot,
    refuse_gait_with_saved,
    warn_without_effect,
)

NAME = "view"
HELP = "write an offline 3-D view (one HTML file) of the robot walking its foot paths"
EXAMPLES = (
    ("scalf-opt view", "the reference and the default optimum (results/view/scene.html)"),
    ("scalf-opt view --from results/optimum --color-by power", "a saved optimum, by power"),
    ("scalf-opt view --robot solo12 --out solo12.html", "another robot, another file"),
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
        "when the catalog has it)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/view/scene.html"),
        metavar="FILE",
        help="the HTML file (default results/view/scene.html)",
    )
    parser.add_argument(
        "--cycles",
        type=int,
        metavar="N",
        default=3,
        help="gait cycles walked and animated, 1..50 (default 3)",
    )
    parser.add_argument(
        "--color-by",
        choices=("trajectory", "power"),
        default="trajectory",
        help="foot paths in one colour per trajectory, or by the leg's power [W]",
    )
    parser.add_argument(
        "--playback-speed",
        type=float,
        metavar="X",
        default=1.0,
        help="animation speed against real time, 0.01..100 (default 1; 0.25 is four times slower)",
    )
    parser.add_argument(
        "--beside-parent",
        action="store_true",
        help="a variant (scalf-opt variant) beside its parent: the parent's reference and "
        "default optimum walk the same gait in the same scene",
    )
    parser.add_argument(
        "--screenshot",
        type=Path,
        metavar="FILE",
        help="also write a PNG of the page rendered by a headless Chromium",
    )


def run(args: argparse.Namespace) -> int:
    """Exit 0 when the page is written, 3 when the default optimum is not solved."""
    from scalf_opt.api.presentation import (
        NotSolvedError,
        beside_parent,
        parent_of,
        shown_trajectories,
    )
    from scalf_opt.cli.progress import ProgressBar
    from scalf_opt.errors import ConfigError
    from scalf_opt.viz.scene import SceneOptions
    from scalf_opt.viz.trajectories import energy_lines
    from scalf_opt.viz.view import check_output_file, write_scene_html
    from scalf_opt.viz.visuals import load_visuals

    out = check_output_file(args.out, ".html")
    if args.screenshot is not None:
        from scalf_opt.viz.browser import find_chromium

        check_output_file(args.screenshot, ".png")
        if find_chromium() is None:  # before any work, not after it
            raise ConfigError(
                "--screenshot needs Chromium (install the 'chromium' package, or set "
                "SCALF_OPT_CHROMIUM)"
            )
    options = SceneOptions(
        n_cycles=args.cycles, color_by=args.color_by, playback_speed=args.playback_speed
    )
    refuse_gait_with_saved(args)
    robot = load_robot(args, next(iter(args.from_dirs), None))
    warn_without_effect(args, robot)
    if args.beside_parent:
        parent_of(robot)  # refused before any solve
    visuals = load_visuals(robot)  # a mesh too large or missing is refused before any solve
    try:
        with ProgressBar(None, "view", enabled=not args.quiet) as bar:
            _, shown = shown_trajectories(
                robot,
                load_gait(args, robot),
                args.from_dirs,
                args.accounting,
                bar.step,
                args.loads,
            )
            if args.beside_parent:
                shown = beside_parent(robot, shown, bar.step)
    except NotSolvedError as exc:
        args.console.error(f"{exc}; nothing written")
        return 3
    write_scene_html(out, robot, shown, options, visuals)
    args.console.text("\n".join(energy_lines(shown)))
    args.console.text(f"wrote {out} (open it in a browser; it needs no network)")
    if args.screenshot is not None:
        from scalf_opt.viz.browser import render_page

        # a still 40 % into the walk: the robots mid-way along their paths
        walk_s = options.n_cycles * shown[0].cycle.gait.period_s
        still_s = 0.4 * walk_s / options.playback_speed  # animation time
        rendering = render_page(out, args.screenshot, fragment=f"t={still_s:g}")
        if rendering.errors:
            raise RuntimeError(f"{out}: the page logged errors: {'; '.join(rendering.errors)}")
        args.console.text(f"wrote {args.screenshot}")
    return 0


def outputs(args: argparse.Namespace) -> Outputs:
    """The page and the screenshot, moved into place together."""
    return Outputs(files={"--out": args.out, "--screenshot": args.screenshot})

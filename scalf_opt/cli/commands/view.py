"""``scalf-opt view``: one offline HTML page of the robot walking its foot paths (meshcat)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from scalf_opt.cli.options import (
    Outputs,
    add_gait,
    add_loads,
    add_robot,
    add_source_model,
    load_gait,
    load_robot,
    option_given,
    refuse_gait_with_saved,
    warn_without_effect,
)
from scalf_opt.errors import ConfigError

if TYPE_CHECKING:
    from scalf_opt.viz.scene import SceneOptions

NAME = "view"
HELP = "write an offline 3-D view (one HTML file) of the robot walking its foot paths"
EXAMPLES = (
    ("scalf-opt view", "the reference and the default optimum (results/view/scene.html)"),
    ("scalf-opt view --from results/optimum --color-by power", "a saved optimum, by power"),
    ("scalf-opt view --robot solo12 --out solo12.html", "another robot, another file"),
    (
        "scalf-opt view --from results/go1-3d --out go1-3d.html",
        "a 3-D cycle (optimize --model 3d --out): the whole robot, trunk free, every joint",
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
        "when the catalog has it); a 3-D cycle's (optimize or gait --model 3d) shows the whole "
        "robot walking its plan",
    )
    add_source_model(
        parser,
        "shown as the whole robot walking its plan: the trunk's position and orientation and "
        "every joint (abduction included) from the plan's spline, the feet's paths coloured by "
        "trajectory or by the leg's power (all its joints)",
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
    from scalf_opt.viz.scene import SceneOptions
    from scalf_opt.viz.trajectories import energy_lines
    from scalf_opt.viz.view import check_output_file, write_scene_html
    from scalf_opt.viz.visuals import load_visuals

    out = check_output_file(args.out, ".html")
    _check_screenshot(args)
    options = SceneOptions(
        n_cycles=args.cycles, color_by=args.color_by, playback_speed=args.playback_speed
    )
    if _holds_3d_cycles(args):
        return _run_3d(args, options)
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
    # a still 40 % into the walk: the robots mid-way along their paths
    _screenshot(
        args, out, 0.4 * options.n_cycles * shown[0].cycle.gait.period_s / options.playback_speed
    )
    return 0


def _check_screenshot(args: argparse.Namespace) -> None:
    """Refuse a bad ``--screenshot`` file, or one without Chromium, before any work."""
    if args.screenshot is None:
        return
    from scalf_opt.viz.browser import find_chromium
    from scalf_opt.viz.view import check_output_file

    check_output_file(args.screenshot, ".png")
    if find_chromium() is None:
        raise ConfigError(
            "--screenshot needs Chromium (install the 'chromium' package, or set "
            "SCALF_OPT_CHROMIUM)"
        )


def _screenshot(args: argparse.Namespace, page: Path, still_s: float) -> None:
    """With ``--screenshot``: the page rendered by a headless Chromium, paused at ``still_s``.

    ``still_s``: animation time of the still [s].

    Raises:
        RuntimeError: The page logged errors.
    """
    if args.screenshot is None:
        return
    from scalf_opt.viz.browser import render_page

    rendering = render_page(page, args.screenshot, fragment=f"t={still_s:g}")
    if rendering.errors:
        raise RuntimeError(f"{page}: the page logged errors: {'; '.join(rendering.errors)}")
    args.console.text(f"wrote {args.screenshot}")


def _holds_3d_cycles(args: argparse.Namespace) -> bool:
    """Whether ``--from`` holds 3-D cycles (every DIR), checked against ``--model``.

    Raises:
        ConfigError: ``--model 3d`` without a 3-D cycle, ``--model sagittal`` with one, or 3-D
            and sagittal results together (one line naming ``--from`` and the folder).
    """
    from scalf_opt.io.whole_body_export import is_3d_cycle

    kinds = {d: is_3d_cycle(d) for d in args.from_dirs}
    three_d = [d for d, is_3d in kinds.items() if is_3d]
    sagittal = [d for d, is_3d in kinds.items() if not is_3d]
    if args.model == "3d" and not args.from_dirs:
        raise ConfigError(
            "--model 3d: give --from DIR, a 3-D cycle (optimize --model 3d --out DIR writes one)",
            field="model",
        )
    if args.model == "3d" and sagittal:
        raise ConfigError(
            f"--from {sagittal[0]}: not a 3-D cycle (--model 3d; no plan.csv beside a "
            "summary.json of model 3d: optimize --model 3d --out DIR writes one)",
            field="from",
        )
    if args.model == "sagittal" and three_d:
        raise ConfigError(
            f"--from {three_d[0]}: a 3-D cycle, not a sagittal result (--model sagittal; leave "
            "--model out)",
            field="from",
        )
    if three_d and sagittal:
        raise ConfigError(
            f"--from {sagittal[0]}: not a 3-D cycle, beside the 3-D cycle {three_d[0]}; 3-D and "
            "sagittal results are shown apart",
            field="from",
        )
    return bool(three_d)


def _refuse_for_3d(args: argparse.Namespace) -> None:
    """Refuse the options a 3-D cycle brings itself or that do not apply to it (one line).

    Raises:
        ConfigError: A gait option, ``--accounting``, ``--loads`` or ``--beside-parent``.
    """
    refuse_gait_with_saved(args)
    if option_given(args, "--accounting"):
        raise ConfigError(
            f"--accounting and --from {args.from_dirs[0]}: a 3-D cycle was charged with its own "
            "accounting (its summary.json's)",
            field="accounting",
        )
    if args.loads is not None:
        raise ConfigError(
            f"--loads and --from {args.from_dirs[0]}: a 3-D cycle's loads are its own contact "
            "forces",
            field="loads",
        )
    if args.beside_parent:
        raise ConfigError(
            f"--beside-parent and --from {args.from_dirs[0]}: a 3-D cycle is shown alone (its "
            "parent has no such cycle)",
            field="beside_parent",
        )


def _run_3d(args: argparse.Namespace, options: SceneOptions) -> int:
    """``view --from DIR`` of 3-D cycles: the whole robot walking each plan, side by side."""
    from scalf_opt.api.presentation import view_cycles

    _refuse_for_3d(args)
    robot = None if args.robot is None and args.urdf is None else load_robot(args)
    out, shown = view_cycles(args.out, args.from_dirs, robot, options)  # robot None: the cycle's
    for plan in shown:
        args.console.text(plan.headline)
    args.console.text(f"wrote {out} (open it in a browser; it needs no network)")
    period = shown[0].plan.schedule.period_s
    _screenshot(args, out, 0.4 * options.n_cycles * period / options.playback_speed)
    return 0


def outputs(args: argparse.Namespace) -> Outputs:
    """The page and the screenshot, moved into place together."""
    return Outputs(files={"--out": args.out, "--screenshot": args.screenshot})

"""Options several commands share (robot, gait, legs, outputs) and what they load."""

from __future__ import annotations

import argparse
import math
import os
import stat
from collections.abc import Callable
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from scalf_opt.energy.accounting import ACCOUNTINGS, PAPER_ACCOUNTING
from scalf_opt.energy.loads import DEFAULT_LOADS, LOAD_MODELS
from scalf_opt.errors import ConfigError, GaitError
from scalf_opt.locomotion.contact_schedule import DEFAULT_FRICTION
from scalf_opt.locomotion.gait import MAX_GAIT_LENGTH_M, MAX_PERIOD_S
from scalf_opt.optimize.solvers import DEFAULT_SOLVER, SOLVERS, solver_help
from scalf_opt.robots.catalog import robot_names
from scalf_opt.types import LEG_NAMES

if TYPE_CHECKING:
    from scalf_opt.io.saved import SavedSwings
    from scalf_opt.locomotion.gait import Gait
    from scalf_opt.model.robot import Robot


def bounded(kind: type, high: float, low: float | None = None) -> Callable[[str], Any]:
    """An argparse ``type`` that refuses a number above ``high`` (or below ``low``, if given).

    What lies below or is not finite is left to the field's own check, which names the field
    and is what the Python API raises too; the bound above keeps a command line from asking for
    a run that cannot end (``--grid 100000``, ``--starts 1000000000``).
    """

    def parse(text: str) -> Any:
        value = kind(text)  # a ValueError: argparse says "invalid float value: 'x'"
        if value > high or (low is not None and value < low):
            show = (lambda x: str(int(x))) if kind is int else (lambda x: f"{x:g}")
            span = f"{show(low)}..{show(high)}" if low is not None else f"at most {show(high)}"
            raise argparse.ArgumentTypeError(f"{text} is out of range ({span})")
        return value

    parse.__name__ = kind.__name__
    return parse


MAX_RATE_HZ = 100_000.0
"""Highest sample rate an option accepts [Hz] (a phase has at most 20,000 samples anyway)."""

GAIT_OPTIONS: dict[str, tuple[str, Callable[[str], Any], str]] = {
    "period_s": ("--period", bounded(float, MAX_PERIOD_S), "gait cycle T [s], at most 60"),
    "duty_cycle": ("--duty", float, "stance fraction of the cycle, in [0.5, 1)"),
    "step_length_m": (
        "--step-length",
        bounded(float, MAX_GAIT_LENGTH_M),
        "step length S [m], at most 10",
    ),
    "clearance_m": (
        "--clearance",
        bounded(float, MAX_GAIT_LENGTH_M),
        "mid-swing clearance H [m], at most 10",
    ),
    "stance_height_m": (
        "--stance-height",
        bounded(float, MAX_GAIT_LENGTH_M),
        "pitching hip above the ground z0 [m], at most 10",
    ),
    "sample_rate_hz": (
        "--rate",
        bounded(float, MAX_RATE_HZ),
        "sample rate of each phase [Hz], at most 100000 (and 20000 samples per phase)",
    ),
}
"""Gait fields that have a command-line option: field -> (option, type, help)."""


ACCOUNTING_HELP = (
    "how a joint's mechanical power is charged before its drive's losses are added: "
    + "; ".join(f"{name} = {rule.description}" for name, rule in ACCOUNTINGS.items())
    + f" (default {PAPER_ACCOUNTING}). Valve-controlled and electric drives meter their own "
    "input power and do not use it"
)
"""``--accounting``'s help, the same wherever a command takes it (the registry's words)."""


def add_robot(parser: argparse.ArgumentParser) -> None:
    """``--urdf PATH`` or ``--robot NAME``."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--urdf", type=Path, metavar="FILE", help="the robot's URDF file (default: SCalf's)"
    )
    group.add_argument(
        "--robot",
        choices=robot_names(),
        metavar="NAME",
        help=f"a known robot instead of --urdf: {', '.join(robot_names())}",
    )


SPEED_HELP = (
    "walk at this forward speed [m/s], in (0, 10]: the step length follows, S = v d T, from the "
    "gait's duty and period (instead of --step-length)"
)


def add_gait(parser: argparse.ArgumentParser, accounting: bool = True, speed: bool = False) -> None:
    """``--gait FILE``, one option per gait field, unless told otherwise ``--accounting``.

    With ``speed``: ``--speed``, which sets the step length (instead of ``--step-length``).
    """
    group = parser.add_argument_group(
        "gait",
        "the robot's default trot (the paper's, scaled to its legs), then the gait file's fields, "
        "then these options",
    )
    group.add_argument("--gait", type=Path, metavar="FILE", help="gait file (TOML, a [gait] table)")
    step = group.add_mutually_exclusive_group() if speed else group
    for field, (option, kind, text) in GAIT_OPTIONS.items():
        home = step if field == "step_length_m" else group
        home.add_argument(option, dest=field, type=kind, metavar="X", help=text)
    if speed:
        step.add_argument("--speed", type=float, metavar="X", help=SPEED_HELP)
    if accounting:
        parser.add_argument(
            "--accounting",
            choices=tuple(ACCOUNTINGS),
            default="paper",
            help=ACCOUNTING_HELP,
        )


def add_loads(parser: argparse.ArgumentParser, saved: bool = False) -> None:
    """``--loads``: what the stance feet carry (:data:`~scalf_opt.energy.loads.LOAD_MODELS`).

    With ``saved`` the default is ``None``: a saved result's own model, else the default.
    """
    parser.add_argument(
        "--loads",
        choices=tuple(LOAD_MODELS),
        default=None if saved else DEFAULT_LOADS,
        help="stance loads: the whole robot's dynamics (trunk and all four legs), shared in 3-D "
        "or in the sagittal plane (whole-body-sagittal, as the simulation referee's planar "
        "trunk), or the trunk's weight only (trunk, the paper's model); default: a saved "
        f"result's own, else {DEFAULT_LOADS}",
    )


def add_source_model(parser: argparse.ArgumentParser, effect: str) -> None:
    """``--model {sagittal,3d}``: what ``--from`` holds (default ``None``: read from it).

    ``effect``: what the command does with a 3-D cycle, the end of the help.
    """
    parser.add_argument(
        "--model",
        choices=("sagittal", "3d"),
        help=f"what --from holds (default: read from it); 3d: a cycle of optimize --model 3d, "
        f"{effect}",
    )


def add_method(parser: argparse.ArgumentParser) -> None:
    """``--method``: the swing solver (:data:`~scalf_opt.optimize.solvers.SOLVERS`)."""
    parser.add_argument(
        "--method",
        choices=tuple(SOLVERS),
        default=DEFAULT_SOLVER,
        help=f"the solver: {solver_help()}",
    )


def add_friction(parser: argparse.ArgumentParser) -> None:
    """``--friction``: the feet's friction coefficient of the 3-D model."""
    parser.add_argument(
        "--friction",
        type=float,
        default=DEFAULT_FRICTION,
        metavar="X",
        help=f"--model 3d: the feet's friction coefficient (default {DEFAULT_FRICTION:g})",
    )


def friction_of(args: argparse.Namespace) -> float:
    """``--friction``, checked for ``--model 3d``; with the sagittal model it must be left out.

    Raises:
        ConfigError: Not a number > 0, or given (not at its default) to the sagittal model.
    """
    friction = float(args.friction)
    if getattr(args, "model", "3d") != "3d":
        if friction != DEFAULT_FRICTION:
            raise ConfigError("--friction is an option of --model 3d", field="friction")
        return friction
    if not (math.isfinite(friction) and friction > 0):
        raise ConfigError(f"--friction {friction:g} must be > 0", field="friction")
    return friction


def add_accept_unconverged(parser: argparse.ArgumentParser) -> None:
    """``--accept-unconverged``: exit 0 even when something did not converge."""
    parser.add_argument(
        "--accept-unconverged",
        action="store_true",
        help="exit 0 even when an optimum, a bound level or the stance search did not converge "
        "(it is still marked so in every output); without it such a run exits 3",
    )


def option_given(args: argparse.Namespace, option: str) -> bool:
    """Whether ``option`` is on the command line (``--x V`` or ``--x=V``), not at its default."""
    return any(a == option or a.startswith(option + "=") for a in args.argv)


def warn_without_effect(args: argparse.Namespace, robot: Robot) -> None:
    """One line on stderr when ``--accounting`` was given but none of the robot's drives uses it.

    A drive that meters its own input power (valve-controlled cylinders, electric motors) does
    not charge the joint's mechanical power through the accounting, so the option changes
    nothing on a robot that has only such drives.
    """
    if not option_given(args, "--accounting"):
        return
    from scalf_opt.actuators.sidecar import drives_for

    drives = drives_for(robot).values()
    if drives and not any(d.charges_joint_power for d in drives):
        args.console.note(
            f"warning: --accounting {args.accounting} has no effect on {robot.name}: its drives "
            "meter their own input power"
        )


def leg_name(text: str) -> str:
    """A leg name in any case (``rf`` is ``RF``), for argparse ``type=``."""
    return text.upper()


def add_leg(parser: argparse.ArgumentParser, default: str = "RF") -> None:
    """``--leg NAME`` (any case)."""
    parser.add_argument(
        "--leg",
        type=leg_name,
        default=default,
        choices=LEG_NAMES,
        help=f"the leg (default {default})",
    )


def load_robot(args: argparse.Namespace, saved: Path | SavedSwings | None = None) -> Robot:
    """The robot named by ``--urdf`` or ``--robot``, else the saved result's, else SCalf.

    The saved result's robot is taken when its provenance names a catalog robot.

    Args:
        args: The command line.
        saved: A result directory (or its ``summary.json``) the command reads swings from,
            or those swings already read. Its provenance names the robot; only a catalog name
            is taken from it (a URDF path in a file is not followed), and the swings are still
            checked against that robot's URDF and mass where they are used.
    """
    from scalf_opt.robots.loading import load_robot as load

    name = args.robot
    if name is None and args.urdf is None and saved is not None:
        from scalf_opt.io.saved import SavedSwings, read_saved_swings

        recorded = (saved if isinstance(saved, SavedSwings) else read_saved_swings(saved)).robot
        if recorded in robot_names():
            name = recorded
    return load(name=name, urdf=args.urdf)


def gait_overrides(args: argparse.Namespace) -> dict[str, float]:
    """The gait fields given as options."""
    return {f: getattr(args, f) for f in GAIT_OPTIONS if getattr(args, f, None) is not None}


def load_gait(args: argparse.Namespace, robot: Robot, base: Gait | None = None) -> Gait:
    """The robot's default gait (or ``base``), under ``--gait``'s fields, under the gait options.

    Raises:
        GaitError: A value is out of range; the message names the option or the file's field.
    """
    from scalf_opt.api import read_gait

    overrides = gait_overrides(args)
    if args.gait is not None:
        _warn_other_robot(args, robot)
    try:
        gait = read_gait(args.gait, robot, base, **overrides)
    except GaitError as exc:
        if exc.field in overrides:
            option = GAIT_OPTIONS[exc.field][0]
            raise GaitError(f"{option} {overrides[exc.field]:g}: {exc}", field=exc.field) from exc
        raise
    speed = getattr(args, "speed", None)
    if speed is None:
        return gait
    from scalf_opt.optimize.gait_search import check_speed

    try:
        gait = gait.with_speed(check_speed(speed))
    except (ConfigError, GaitError) as exc:
        raise ConfigError(f"--speed {speed:g}: {exc}", field="speed") from exc
    _check_stance_reach(gait, robot, f"--speed {speed:g}")
    return gait


def _check_stance_reach(gait: Gait, robot: Robot, option: str) -> None:
    """Refuse a step length (from ``option``) that takes a stance foot out of the leg's reach.

    Raises:
        ConfigError: It does; the message names the option and the step length it asked.
    """
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.energy.workspace import check_workspace

    pipeline = EnergyPipeline(robot, gait)
    for leg in LEG_NAMES:
        try:
            check_workspace(
                pipeline.kinematics(leg),
                gait,
                "foot",
                pipeline.stance_paths[leg],
                "stance",
                ("step_length_m",),
            )
        except GaitError as exc:
            reason = exc.__cause__ or exc
            raise ConfigError(
                f"{option} asks a step length S = v d T = {gait.step_length_m:.4g} m, which the "
                f"stance cannot walk: {reason}",
                field="speed",
            ) from exc


def _warn_other_robot(args: argparse.Namespace, robot: Robot) -> None:
    """A line on stderr when ``--gait``'s file says it was made for another robot."""
    from scalf_opt.locomotion.gait_file import gait_file_robot

    made_for = gait_file_robot(args.gait)
    if made_for is not None and made_for != robot.name:
        args.console.note(
            f"warning: {args.gait} was made for {made_for}; walking it on {robot.name}, whose "
            "legs may need another gait"
        )


def gait_origin(args: argparse.Namespace, robot: Robot, base: str | None = None) -> str:
    """Which gait a command walks and where it came from, in one line for its report.

    Args:
        args: The command's options (``--gait`` and the gait options).
        robot: The robot, whose default trot is the base unless ``base`` says otherwise.
        base: Where the base gait came from instead (a saved optimum's).
    """
    from scalf_opt.locomotion.scaling import default_gait_origin

    parts = [base or default_gait_origin(robot)]
    if getattr(args, "gait", None) is not None:
        parts.append(f"under the gait file {args.gait}")
    given = [GAIT_OPTIONS[f][0] for f in gait_overrides(args)]
    if getattr(args, "speed", None) is not None:
        given.append(f"--speed {args.speed:g} (step length S = v d T)")
    if given:
        parts.append("under " + ", ".join(given))
    return "gait: " + ", ".join(parts)


def refuse_gait_with_saved(args: argparse.Namespace) -> None:
    """A result directory (``--from``) brings its own gait: refuse gait options beside it.

    Raises:
        ConfigError: ``--from`` with ``--gait`` or a gait option; the message names it.
    """
    if not getattr(args, "from_dirs", None):
        return
    given = [GAIT_OPTIONS[f][0] for f in gait_overrides(args)]
    if args.gait is not None:
        given.insert(0, "--gait")
    if given:
        raise ConfigError(f"{given[0]} and --from: a result directory brings its own gait")


MAX_NAME_BYTES = 255
"""Longest file or folder name (Linux, macOS and Windows file systems) [bytes]."""


def check_output_dir(path: Path | None, option: str = "--out") -> None:
    """Refuse, before any work, an output directory that cannot be written.

    Raises:
        ConfigError: ``path`` is a file, or its nearest existing ancestor is not writable.
    """
    if path is None:
        return
    too_long = [part for part in path.parts if len(part.encode()) > MAX_NAME_BYTES]
    if too_long:
        raise ConfigError(
            f"{option} {path}: a name in it is longer than the {MAX_NAME_BYTES} bytes a file "
            "name may have (File name too long)"
        )
    try:
        if path.exists() and not path.is_dir():
            raise ConfigError(f"{option} {path}: is a file, not a directory")
        existing = path
        while not existing.exists():
            existing = existing.parent
    except OSError as exc:  # a name too long, a loop of links
        raise ConfigError(f"{option} {path}: {exc.strerror}") from None
    if not existing.is_dir() or not os.access(existing, os.W_OK | os.X_OK):
        raise ConfigError(f"{option} {path}: {existing} is not a writable directory")


def check_output_file(path: Path | None, option: str = "--out") -> None:
    """Refuse, before any work, an output file that cannot be written.

    Raises:
        ConfigError: ``path`` is a directory, or its folder cannot be written.
    """
    if path is None:
        return
    try:
        kind = path.stat().st_mode if path.exists() else None
    except OSError as exc:  # a name too long, a loop of links
        raise ConfigError(f"{option} {path}: {exc.strerror}") from None
    if kind is not None and stat.S_ISDIR(kind):
        raise ConfigError(f"{option} {path}: is a directory, not a file")
    if kind is not None and not stat.S_ISREG(kind):
        raise ConfigError(
            f"{option} {path}: is not a regular file; only a regular file is replaced"
        )
    check_output_dir(path.parent if str(path.parent) else Path("."), option)


SAVED_RESULT_FILES = ("summary.json", "samples.csv", "timings.json")
"""The files of a saved result (``optimize --out DIR``): none may be written over by a command
that reads it."""


def check_not_the_source(path: Path | None, source: Path | None, option: str) -> None:
    """Refuse an output file that is one of the saved result's files the command reads.

    ``source`` is ``--from``: a folder, or its ``summary.json``.

    Raises:
        ConfigError: ``path`` is (or is a link to) ``summary.json``, ``samples.csv`` or
            ``timings.json`` of the saved result.
    """
    if path is None or source is None:
        return
    folder = source if source.is_dir() else source.parent
    target = path.resolve()
    for name in SAVED_RESULT_FILES:
        if (folder / name).resolve() == target:
            raise ConfigError(
                f"{option} {path}: is the {name} of the result it reads (--from {source}): "
                "write elsewhere"
            )


@dataclass(frozen=True)
class Outputs:
    """What a command writes: folders and files by the option that names them.

    The command line runs the command inside one :func:`~scalf_opt.files.output_set` of them:
    the files are moved into place together when the command ends, none when it fails.

    Attributes:
        folders: Output folders, by option (``None``: not given).
        files: Output files, by option.
        direct: Paths under a folder written in place at once (a study's cache).
    """

    folders: dict[str, Path | None] = dataclass_field(default_factory=dict)
    files: dict[str, Path | None] = dataclass_field(default_factory=dict)
    direct: tuple[Path, ...] = ()

    def check(self) -> None:
        """Refuse, before any work, an output that cannot be written (the message names it).

        Raises:
            ConfigError: See :func:`check_output_dir` and :func:`check_output_file`.
        """
        for option, path in self.folders.items():
            check_output_dir(path, option.split()[0])
        for option, path in self.files.items():
            check_output_file(path, option.split()[0])


def default_outputs(args: argparse.Namespace) -> Outputs | None:
    """The outputs of a command that does not declare its own: the folder ``--out``, if any."""
    out = getattr(args, "out", None)
    return Outputs(folders={"--out": out}) if isinstance(out, Path) else None

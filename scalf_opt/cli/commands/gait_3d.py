"""``scalf-opt gait --model 3d``: the cheapest whole-body trot per speed, the period optimized."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from scalf_opt.cli.options import add_friction, friction_of
from scalf_opt.errors import ConfigError

SAGITTAL_GAIT_ONLY = ("family", "method", "loads", "scheduler")
"""``gait`` options of the sagittal search: refused with ``--model 3d``."""


PERIOD_RANGE_HELP = (
    "--model 3d: MIN:MAX, the period a decision variable between MIN and MAX [s], starting from "
    "--period (the objective the mean drawn power: the energy per metre at the speed); gait's "
    "default: half to twice the robot's default trot's period"
)
"""``--period-range``'s help, the same in ``optimize`` and ``gait``."""


def add_3d_arguments(parser: argparse.ArgumentParser) -> None:
    """The options ``gait --model 3d`` reads."""
    parser.add_argument(
        "--duty",
        dest="duties",
        metavar="X",
        help="--model 3d: the duty factor of each start (0.2..0.8; default 0.5; below 0.5 a "
        "flying trot); each start is one NLP, the cheapest converged answer is the speed's",
    )
    parser.add_argument(
        "--period",
        dest="periods",
        metavar="X",
        help="--model 3d: the first period of each start [s] (default: the robot's default "
        "trot's); the period is a decision variable inside --period-range",
    )
    parser.add_argument("--period-range", metavar="X", help=PERIOD_RANGE_HELP)
    parser.add_argument(
        "--rate",
        dest="sample_rate_hz",
        type=float,
        metavar="X",
        help="--model 3d: the node rate [Hz] (default 25; the ten-times rule refines where the "
        "energy needs more)",
    )
    add_friction(parser)


def _numbers(text: str | None, option: str) -> list[float] | None:
    """``--duty`` or ``--period``'s comma-separated numbers (``None`` when not given)."""
    if text is None:
        return None
    try:
        values = [float(p) for p in text.split(",")]
    except ValueError:
        raise ConfigError(f"{option} {text}: give numbers separated by commas") from None
    if not all(math.isfinite(v) and v > 0 for v in values):
        raise ConfigError(f"{option} {text}: every value must be a number > 0")
    return list(dict.fromkeys(values))


def period_range(text: str | None, default_period_s: float) -> tuple[float, float]:
    """``--period-range MIN:MAX`` [s], or the default around the robot's period.

    Raises:
        ConfigError: Not two numbers, not ``0 < MIN < MAX``.
    """
    from scalf_opt.api.gait_3d import PERIOD_RANGE_SHARES

    if text is None:
        low, high = PERIOD_RANGE_SHARES
        return low * default_period_s, high * default_period_s
    try:
        low, high = (float(p) for p in text.split(":"))
    except ValueError:
        raise ConfigError(
            f"--period-range {text}: give MIN:MAX in seconds (e.g. 0.2:0.8)"
        ) from None
    if not (math.isfinite(low) and math.isfinite(high) and 0 < low < high):
        raise ConfigError(f"--period-range {text}: needs 0 < MIN < MAX [s]")
    return low, high


def refuse_sagittal_gait_options(args: argparse.Namespace, defaults: dict[str, Any]) -> None:
    """Refuse a sagittal search's option given with ``--model 3d`` (one line naming it).

    Raises:
        ConfigError: Such an option differs from its default.
    """
    for field in SAGITTAL_GAIT_ONLY:
        if getattr(args, field, None) != defaults.get(field):
            raise ConfigError(
                f"--{field} is an option of the sagittal gait search; --model 3d optimizes every "
                "joint of the whole cycle with Ipopt (leave it out)",
                field=field,
            )


def refuse_3d_options(args: argparse.Namespace) -> None:
    """Refuse a ``--model 3d`` option given to the sagittal search.

    Raises:
        ConfigError: ``--duty``, ``--period``, ``--period-range``, ``--rate`` or ``--friction``
            was given.
    """
    friction_of(args)  # refused here: an option of --model 3d
    for field, option in (
        ("duties", "--duty"),
        ("periods", "--period"),
        ("period_range", "--period-range"),
        ("sample_rate_hz", "--rate"),
    ):
        if getattr(args, field, None) is not None:
            raise ConfigError(
                f"{option} is an option of --model 3d; the sagittal search chooses period and "
                "duty itself",
                field=field,
            )


def cases(args: argparse.Namespace, speeds: list[float]) -> tuple[list[Any], str]:
    """One :class:`~scalf_opt.api.gait_3d.SpeedCase` per speed, and the robot's name.

    Raises:
        ConfigError: A bad ``--duty``, ``--period``, ``--period-range``, ``--rate`` or
            ``--friction``; a duty factor the 3-D trot schedule refuses.
    """
    from scalf_opt.api.gait_3d import DEFAULT_GAIT_RATE_HZ, SpeedCase, default_starts
    from scalf_opt.cli.options import load_robot
    from scalf_opt.errors import GaitError
    from scalf_opt.locomotion.contact_schedule import trot_schedule
    from scalf_opt.locomotion.scaling import default_gait_for

    robot = load_robot(args)
    gait = default_gait_for(robot)
    friction = friction_of(args)
    rate = DEFAULT_GAIT_RATE_HZ if args.sample_rate_hz is None else args.sample_rate_hz
    if not (math.isfinite(rate) and 0 < rate <= 1000):
        raise ConfigError(f"--rate {rate:g} must be in (0, 1000] [Hz]", field="sample_rate_hz")
    duties = _numbers(args.duties, "--duty")
    periods = _numbers(args.periods, "--period")
    low, high = period_range(args.period_range, gait.period_s)
    starts = default_starts(gait.period_s, duties, periods)
    for duty, period in starts:
        if not low <= period <= high:
            raise ConfigError(
                f"--period {period:g}: outside --period-range {low:g}:{high:g} [s]",
                field="periods",
            )
        try:
            trot_schedule(period, duty, rate)
        except GaitError as exc:
            raise ConfigError(f"--duty {duty:g}: {exc}", field="duties") from exc
    name = args.robot if args.urdf is None else None
    out = [
        SpeedCase(
            name,
            None if args.urdf is None else str(Path(args.urdf).resolve()),
            speed,
            starts,
            (low, high),
            rate,
            friction=friction,
            accounting=args.accounting,
        )
        for speed in speeds
    ]
    return out, robot.name


def read_compare(path: Path | None) -> list[dict[str, Any]] | None:
    """The rows of a sagittal ``gait`` run's ``gaits.csv`` (``--sagittal`` a folder or the file).

    Raises:
        ConfigError: It cannot be read, or lacks ``speed_m_s`` or ``cost_of_transport``.
    """
    import csv

    if path is None:
        return None
    file = path / "gaits.csv" if path.is_dir() else path
    try:
        rows = list(csv.DictReader(file.open()))
    except OSError as exc:
        raise ConfigError(f"--sagittal {file}: cannot be read ({exc.strerror})") from None
    for column in ("speed_m_s", "status", "cost_of_transport"):
        if not rows or column not in rows[0]:
            raise ConfigError(f"--sagittal {file}: no column {column!r} (a gaits.csv of gait)")
    return rows


def pinned_words(pinned_by: str) -> str:
    """``pinned_by`` (``"<joint> <quantity> <end>: <source>; ..."``) grouped by limit.

    ``"FL_calf q upper: joint range (URDF); FR_calf q upper: joint range (URDF)"`` reads
    ``"q upper of FL_calf, FR_calf (joint range (URDF))"``.
    """
    groups: dict[tuple[str, str], list[str]] = {}
    for part in pinned_by.split("; "):
        where, _, source = part.partition(": ")
        words = where.split(" ")
        if len(words) == 3:
            joint, quantity, end = words
            groups.setdefault((f"{quantity} {end}", source), []).append(joint)
        else:  # the period's range
            groups.setdefault((where, source), [])
    return "; ".join(
        f"{limit} of {', '.join(joints)} ({source})" if joints else f"{limit} ({source})"
        for (limit, source), joints in groups.items()
    )


def gait_3d_table(robot: str, rows: list[dict[str, Any]]) -> str:
    """The answers per speed as a text table, then what pins each and why a speed failed.

    "10x" is the answer's energy at ten times its rate against its nodes'; "grid" against the
    optimum of its last coarser grid (both at ten times the rate; "-": one grid only).
    """
    header = [
        "v [m/s]",
        "T [s]",
        "duty",
        "stride [m]",
        "P [W]",
        "CoT",
        "10x",
        "grid",
        "starts",
        "status",
    ]
    lines = [
        f"cheapest 3-D trot of {robot} per speed (the whole robot; the period optimized from "
        "each start, the cheapest converged start kept)",
        "  ".join(f"{h:>10s}" for h in header),
    ]
    for r in rows:
        ok = r["status"] == "ok"
        cells = [f"{r['speed_m_s']:g}"]
        cells += (
            [
                f"{r['period_s']:.4f}",
                f"{r['duty_cycle']:.3f}",
                f"{r['stride_m']:.4f}",
                f"{r['average_power_w']:.2f}",
                f"{r['cost_of_transport']:.4f}",
                f"{100 * r['rate_difference']:+.2f} %",
                "-" if r["grid_change"] == "" else f"{100 * r['grid_change']:+.2f} %",
            ]
            if ok
            else ["-"] * 7
        )
        cells += [str(r["starts_converged"]), r["status"]]
        lines.append("  ".join(f"{c:>10s}" for c in cells))
    for r in rows:
        if r["pinned_by"]:
            lines.append(f"  {r['speed_m_s']:g} m/s pinned at: {pinned_words(r['pinned_by'])}")
        if r["error"]:
            lines.append(f"  {r['speed_m_s']:g} m/s: {r['error']}")
    return "\n".join(lines)


def run_3d(args: argparse.Namespace, speeds: list[float]) -> int:
    """Exit 0 when every speed converged from some start, 3 otherwise (``gaits.csv`` says why)."""
    from scalf_opt.api.gait_3d import sweep_gaits_3d
    from scalf_opt.cli.progress import ProgressBar
    from scalf_opt.io.provenance import run_provenance

    compare = read_compare(args.sagittal)
    speed_cases, robot = cases(args, speeds)
    from scalf_opt.studies.runner import usable_cores

    workers = args.workers if args.workers is not None else usable_cores()
    with ProgressBar(None, "gait --model 3d", enabled=not args.quiet) as bar:
        sweep = sweep_gaits_3d(speed_cases, args.out, robot, workers, bar.step, compare)
    console = args.console
    console.text(gait_3d_table(robot, sweep.rows))
    console.text(
        f"wrote {args.out / 'gaits.csv'}, {args.out / 'gaits.png'} and per converged speed "
        f"{args.out}/speed_<v>/ (summary.json, plan.csv)"
    )
    console.json(
        {
            "provenance": run_provenance(args.argv, robot=robot),
            "gaits_csv": str(args.out / "gaits.csv"),
            "rows": sweep.rows,
        }
    )
    if sweep.failed:
        console.error(
            f"{len(sweep.failed)} of {len(sweep.rows)} speeds did not converge from any start "
            f"(see {args.out / 'gaits.csv'})"
        )
        return 3
    return 0

"""``scalf-opt gait``: the cheapest trot at every speed, on the study engine."""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

from scalf_opt.cli.commands.gait_3d import add_3d_arguments
from scalf_opt.cli.commands.optimize import SWING_FAMILY_HELP
from scalf_opt.cli.commands.study import MAX_WORKERS, WORKERS_HELP
from scalf_opt.cli.options import (
    ACCOUNTING_HELP,
    Outputs,
    add_loads,
    add_method,
    add_robot,
    bounded,
    load_robot,
)
from scalf_opt.energy.accounting import ACCOUNTINGS
from scalf_opt.energy.loads import DEFAULT_LOADS
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.optimize.solvers import DEFAULT_SOLVER

if TYPE_CHECKING:
    from scalf_opt.model.robot import Robot

MAX_SPEEDS = 200
"""Most speeds one run may ask for (each is a search of about a hundred swing optimizations)."""

DEFAULT_OUT = Path("results") / "gait"

SAGITTAL_DEFAULTS = {
    "family": DEFAULT_FAMILY,
    "method": DEFAULT_SOLVER,
    "loads": DEFAULT_LOADS,
    "scheduler": None,
}
"""The sagittal search's options at their defaults (``--model 3d`` refuses another value)."""

NAME = "gait"
HELP = "the cheapest trot at every speed: period, duty, step, stance and swings optimized"
JSON = True
EXAMPLES = (
    ("scalf-opt gait --speed 0.25:1.5:0.25", "six speeds on SCalf (results/gait)"),
    ("scalf-opt gait --speed 1.0 --workers 1", "the paper's speed, in this process"),
    ("scalf-opt gait --robot go1 --speed 0.2:0.7:0.1 --out results/go1", "an electric robot"),
    (
        "scalf-opt gait --model 3d --robot go1 --speed 0.4:1.4:0.2 --out results/go1-3d",
        "the whole robot in 3-D, the period optimized",
    ),
)


def all_speeds(texts: list[str]) -> list[float]:
    """Every ``--speed`` given (the option repeats), in order, each speed once [m/s].

    Raises:
        ConfigError: One of :func:`parse_speeds`' errors, or more than :data:`MAX_SPEEDS` speeds
            in all.
    """
    from scalf_opt.optimize.gait_search import check_speed

    speeds = list(dict.fromkeys(v for text in texts for v in parse_speeds(text)))
    if len(speeds) > MAX_SPEEDS:
        raise ConfigError(f"--speed: {len(speeds)} speeds in all, more than {MAX_SPEEDS}")
    return [check_speed(speed) for speed in speeds]


def parse_speeds(text: str) -> list[float]:
    """One ``--speed``: ``V``, ``V1,V2,...`` or ``START:STOP:STEP`` (STOP included) [m/s].

    Raises:
        ConfigError: Not numbers, a step not > 0, a stop below the start, more than
            :data:`MAX_SPEEDS` speeds (the message names ``--speed``).
    """
    try:
        if ":" in text:
            start, stop, step = (float(p) for p in text.split(":"))
            if not all(math.isfinite(v) for v in (start, stop, step)):
                raise ConfigError(f"--speed {text}: START, STOP and STEP must be finite numbers")
            if not (step > 0 and stop >= start):
                raise ConfigError(
                    f"--speed {text}: START:STOP:STEP needs a step > 0 and STOP >= START"
                )
            spans = (stop - start) / step  # finite numbers may still divide to infinity
            if not spans < MAX_SPEEDS:
                raise ConfigError(
                    f"--speed {text}: more than {MAX_SPEEDS} speeds from {start:g} to {stop:g} "
                    f"in steps of {step:g}"
                )
            count = math.floor(spans + 1e-9) + 1
            if count > MAX_SPEEDS:
                raise ConfigError(f"--speed {text}: {count} speeds, more than {MAX_SPEEDS}")
            return [round(start + i * step, 12) for i in range(count)]
        speeds = [float(p) for p in text.split(",")]
    except ValueError:
        raise ConfigError(
            f"--speed {text}: give V, V1,V2,... or START:STOP:STEP in m/s (e.g. 0.25:1.5:0.25)"
        ) from None
    if len(speeds) > MAX_SPEEDS:
        raise ConfigError(f"--speed {text}: {len(speeds)} speeds, more than {MAX_SPEEDS}")
    return speeds


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    parser.add_argument(
        "--speed",
        required=True,
        action="append",
        metavar="X",
        help="target speeds [m/s]: V, V1,V2,... or START:STOP:STEP with STOP included; the "
        f"option repeats (at most {MAX_SPEEDS} speeds in all, each at most 10 m/s)",
    )
    add_robot(parser)
    parser.add_argument(
        "--model",
        choices=("sagittal", "3d"),
        default="sagittal",
        help="sagittal (default): a pattern search over period, duty, step and stance around "
        "swing NLPs of two-joint legs; 3d: the whole robot in 3-D, each speed one NLP per "
        "start with the period a decision variable (minutes per speed)",
    )
    add_3d_arguments(parser)
    parser.add_argument(
        "--sagittal",
        type=Path,
        metavar="DIR",
        help="--model 3d: a sagittal gait run's folder (or its gaits.csv), drawn beside the 3-D "
        "costs of transport in gaits.png",
    )
    parser.add_argument("--family", default=DEFAULT_FAMILY, metavar="NAME", help=SWING_FAMILY_HELP)
    add_method(parser)
    parser.add_argument(
        "--accounting", choices=tuple(ACCOUNTINGS), default="paper", help=ACCOUNTING_HELP
    )
    add_loads(parser)
    parser.add_argument("--workers", type=bounded(int, MAX_WORKERS), metavar="N", help=WORKERS_HELP)
    parser.add_argument(
        "--scheduler",
        metavar="URL",
        help="a Dask scheduler, tcp://host:port (e.g. tcp://host:8786)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=DEFAULT_OUT,
        metavar="DIR",
        help="output folder (default results/gait): gaits.csv, gaits.png and per speed "
        "speed_<v>/ with gait.toml, summary.json and samples.csv",
    )


def _cell(value: Any, decimals: int | None = None) -> str:
    """A table cell: a float with ``decimals``, or to 4 significant digits without; ``-`` if none.

    A column's numbers line up with its decimals (``0.500`` beside ``0.575``); the speeds, which
    the user gave, keep their own digits.
    """
    if value is None or value == "":
        return "-"
    if isinstance(value, float):
        return f"{value:.4g}" if decimals is None else f"{value:.{decimals}f}"
    return str(value)


FIELD_DECIMALS = {"period_s": 4, "duty_cycle": 3, "step_length_m": 4, "stance_height_m": 4}
"""Decimals of the searched gait fields in the table: 0.1 ms, 0.001 of a period, 0.1 mm."""

COST_DECIMALS = 4
"""Decimals of the costs of transport in the table (dimensionless)."""


def gait_table(robot: str, rows: list[dict[str, Any]]) -> str:
    """The cheapest gaits as a text table, and what pins each."""
    header = ["v [m/s]", "T [s]", "duty", "S [m]", "z0 [m]", "front [m]", "hind [m]", "CoT"]
    header += ["default", "reference", "vs ref.", "status"]
    lines = [
        f"cheapest trot of {robot} per speed; cost of transport (CoT) of the cheapest, of the "
        "default trot",
        "at the speed with optimized swings (default) and with the reference swing (reference); "
        "vs ref.: CoT against reference",
    ]
    lines.append("  ".join(f"{h:>9s}" for h in header))
    for r in rows:
        cells = [_cell(r["speed_m_s"])]
        cells += [_cell(r[key], decimals) for key, decimals in FIELD_DECIMALS.items()]
        cells += [_cell(r["stance_x_offset_front_m"], 3), _cell(r["stance_x_offset_hind_m"], 3)]
        costs = ("cost_of_transport", "default_cost_of_transport", "reference_cost_of_transport")
        cells += [_cell(r[k], COST_DECIMALS) for k in costs]
        saved = r["saving_vs_reference_pct"]
        cells.append(f"{-saved:+.1f} %" if isinstance(saved, float) else "-")
        cells.append(r["status"])
        lines.append("  ".join(f"{c:>9s}" for c in cells))
    for r in rows:
        if r["pinned_by"]:
            lines.append(f"  {_cell(r['speed_m_s'])} m/s: a step further breaks a limit")
            lines += [f"    {line}" for line in pinned_lines(r["pinned_by"])]
        if r["error"]:
            lines.append(f"  {_cell(r['speed_m_s'])} m/s: {r['error']}")
        cot, reference = r["cost_of_transport"], r["reference_cost_of_transport"]
        if isinstance(cot, float) and isinstance(reference, float) and cot > reference:
            lines.append(
                f"  warning: {_cell(r['speed_m_s'])} m/s: the cheapest trot with {r['family']} "
                "swings costs more than the default trot with the reference swing: the family "
                "cannot come near the reference here (try another --family)"
            )
        if r["default_infeasible"]:
            lines.append(
                f"  {_cell(r['speed_m_s'])} m/s: the default trot cannot walk it: "
                f"{r['default_infeasible']}"
            )
    return "\n".join(lines)


_MOVES = {
    "period_s": ("a longer period", "a shorter period"),
    "duty_cycle": ("a higher duty", "a lower duty"),
    "stance_height_m": ("a higher stance", "a lower stance"),
    "stance_x_offset_front_m": ("the front feet further forward", "the front feet further back"),
    "stance_x_offset_hind_m": ("the hind feet further forward", "the hind feet further back"),
}
"""A searched field's step up and down, in words."""

_FIELD_WORDS = {
    "period_s": "period",
    "duty_cycle": "duty",
    "stance_height_m": "stance height",
    "stance_x_offset_front_m": "front feet's offset",
    "stance_x_offset_hind_m": "hind feet's offset",
}

_LIMIT_WORDS: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"^(\w+) q_(\w+): joint range \(URDF\)(, less margin)?$"), r"\1 \2's range (URDF)"),
    (
        re.compile(r"^(\w+) q_(\w+): joint range under the reference swing$"),
        r"\1 \2's range, walked by the reference swing",
    ),
    (
        re.compile(
            r"^(\w+) cyl_len_(\w+): cylinder cyl_len limit \(actuator file\)(, less margin)?$"
        ),
        r"\1 \2 cylinder's stroke (actuator file)",
    ),
    (re.compile(r"^swing not solved: (\w+) \((.*)\)$"), r"\1's swing not solved (\2)"),
    (
        re.compile(r"^duty_cycle below the search box's ([\d.]+), a trot's floor$"),
        r"the lowest duty this model walks, \1 (it has no flight phase)",
    ),
    (re.compile(r"^(\w+) below the search box's (.*)$"), r"the search box's lowest {\1}, \2"),
    (re.compile(r"^(\w+) above the search box's (.*)$"), r"the search box's highest {\1}, \2"),
)
"""A limit's name (:func:`~scalf_opt.optimize.gait_search.limit_name`) as the table says it."""


def pinned_lines(pinned_by: str) -> list[str]:
    """``pinned_by`` (``"<field> up|down: <limit>; ..."``, as ``gaits.csv`` keeps it) in words.

    A line per limit, then the steps that break it: ``"period_s up: RF q_knee: joint range
    (URDF); duty_cycle up: RF q_knee: joint range (URDF)"`` reads ``"RF knee's range (URDF): a
    longer period, a higher duty"``.
    """
    limits: dict[str, list[str]] = {}
    for part in pinned_by.split("; "):
        where, _, limit = part.partition(": ")
        field, _, direction = where.rpartition(" ")
        up, down = _MOVES.get(field, (f"{field} up", f"{field} down"))
        limits.setdefault(_limit_words(limit), []).append(up if direction == "up" else down)
    return [f"{limit}: {', '.join(moves)}" for limit, moves in limits.items()]


def _limit_words(limit: str) -> str:
    for pattern, words in _LIMIT_WORDS:
        if pattern.search(limit):
            named = pattern.sub(words, limit)
            return re.sub(r"\{(\w+)\}", lambda m: _FIELD_WORDS.get(m[1], m[1]), named)
    return limit


def _check_family(family: str) -> None:
    from scalf_opt.locomotion.swing.names import FREE_FAMILY
    from scalf_opt.locomotion.swing.registry import optimizable_family

    if family == FREE_FAMILY:
        raise ConfigError(
            "family free is the free-trajectory bound, not a family to search gaits with",
            field="family",
        )
    optimizable_family(family)


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every speed's search succeeded, 3 when some did not (``gaits.csv`` says why)."""
    from scalf_opt.api.gait_optimization import sweep_gaits
    from scalf_opt.io.provenance import run_provenance

    speeds = all_speeds(args.speed)
    if args.model == "3d":
        from scalf_opt.cli.commands.gait_3d import run_3d

        return run_3d(args, speeds)
    _check_family(args.family)
    robot: Robot = load_robot(args)
    sweep = sweep_gaits(
        robot,
        speeds,
        args.out,
        catalog_name=args.robot,
        urdf=args.urdf,
        family=args.family,
        method=args.method,
        accounting=args.accounting,
        loads=args.loads,
        workers=args.workers,
        scheduler=args.scheduler,
        quiet=args.quiet,
        command=args.argv,
    )
    out, rows = sweep.out, sweep.rows
    console = args.console
    console.text(gait_table(robot.name, rows))
    files = ", ".join(map(str, sweep.written))
    console.text(f"{len(rows)} speeds ({sweep.cached} from the cache); wrote {files}")
    console.text(f"and per solved speed {out}/speed_<v>/ (gait.toml, summary.json, samples.csv)")
    console.json(
        {
            "provenance": run_provenance(args.argv, robot=robot.name),
            "gaits_csv": str(out / "gaits.csv"),
            "rows": rows,
        }
    )
    if sweep.failed:
        console.error(
            f"{len(sweep.failed)} of {len(rows)} speeds did not succeed (see {out / 'gaits.csv'})"
        )
        return 3
    return 0


def outputs(args: argparse.Namespace) -> Outputs:
    """The table, the figure and the speeds' folders, moved into place together.

    The cache of finished speeds is written at once (a killed run resumes from it).
    """
    from scalf_opt.studies.runner import CACHE_DIR

    all_speeds(args.speed)  # a mistyped speed is told before another run's lock is
    if args.model == "3d":
        from scalf_opt.cli.commands.gait_3d import refuse_sagittal_gait_options

        refuse_sagittal_gait_options(args, SAGITTAL_DEFAULTS)
        return Outputs(folders={"--out": args.out})
    from scalf_opt.cli.commands.gait_3d import refuse_3d_options

    refuse_3d_options(args)
    if args.sagittal is not None:
        raise ConfigError("--sagittal is an option of --model 3d", field="sagittal")
    _check_family(args.family)
    return Outputs(folders={"--out": args.out}, direct=(args.out / CACHE_DIR,))

"""Study files: a declared sweep over gait fields, variant scales, robots, families and methods.

A study file is TOML::

    [study]
    name = "speed"            # figure title (default: the file's stem)
    robot = "scalf"           # a catalog robot, or
    urdf = "my_robot.urdf"    # a URDF (paths are relative to the study file), with optional
    legs = "my_legs.toml"     #   legs file and
    actuators = "act.toml"    #   actuator file
    family = "joint-4"        # swing family (default joint-6)
    method = "ipopt"          # a solver: ipopt (default) or pattern
    accounting = "paper"      # paper (default), positive or regenerative
    loads = "whole-body"      # stance loads: whole-body (default), whole-body-sagittal or trunk
    optimize = "pair"         # legs optimized: pair (default; LF, RH by symmetry), all, RF, ...

    [gait]                    # gait fields of every case, over the robot's default gait
    clearance_m = 0.08

    [variant]                 # variant scales of every case (a derived URDF; needs a robot)
    trunk_mass_scale = 1.0

    [sweep]                   # the axes: the cases are the cartesian product of their values
    "gait.period_s" = [0.4, 0.5, 0.6]
    "variant.thigh_length_scale" = [0.9, 1.1]
    "robot" = ["scalf", "hyq"]                # also family, method, accounting, loads
    "gait.period_s + gait.step_length_m" = [[0.6, 0.15], [0.5, 0.25]]  # fields set together
    speed_m_s = [0.5, 1.0, 1.5]  # or study.speed_m_s: the cheapest trot at each speed instead

    [plot]
    x = "speed_m_s"           # the figure's x axis: a swept key or a results.csv column

Every key is checked here, before any case runs; an error names the file and the key.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.energy.loads import DEFAULT_LOADS, stance_loads
from scalf_opt.errors import ConfigError, did_you_mean
from scalf_opt.io.study_columns import RESULT_COLUMNS
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import optimizable_family
from scalf_opt.optimize.gait_search import check_speed
from scalf_opt.optimize.solvers import DEFAULT_SOLVER, solver
from scalf_opt.robots.catalog import robot_names
from scalf_opt.robots.variants import VariantScales
from scalf_opt.tables import Table, number_value
from scalf_opt.types import LEG_NAMES

SETTINGS = ("robot", "family", "method", "accounting", "loads")
"""Study settings that a sweep may vary."""

OPTIMIZE_CHOICES = ("pair", "all", *LEG_NAMES)

SPEED = "speed_m_s"
"""The study key of a target speed: each case searches the cheapest trot at its speed."""

SEARCHED_GAIT_FIELDS = (
    "period_s",
    "duty_cycle",
    "step_length_m",
    "stance_height_m",
    "stance_x_offset_front_m",
    "stance_x_offset_hind_m",
)
"""Gait fields the cheapest-gait search chooses: a study with a speed may not set them."""

_STUDY_KEYS = ("name", "urdf", "legs", "actuators", "optimize", SPEED, *SETTINGS)
_TOP_KEYS = ("study", "gait", "variant", "sweep", "plot")
_GAIT_FIELDS = tuple(f.name for f in fields(Gait))

MAX_CASES = 10_000
"""Most cases a study may declare: about a week of 1-minute cases on one worker."""


@dataclass(frozen=True)
class Case:
    """One case of a study: everything needed to run it, as plain data.

    Attributes:
        index: Position in the study (0-based).
        swept: The swept keys and this case's values, in axis order.
        robot: Catalog robot, or ``None`` with ``urdf``.
        urdf: URDF path (absolute), or ``None``.
        legs: Legs file (absolute), or ``None``.
        actuators: Actuator file (absolute), or ``None``.
        family: Swing family.
        method: Optimizer.
        accounting: Power accounting.
        optimize: Legs optimized (``pair``, ``all`` or a leg).
        gait: Gait fields set over the robot's default gait.
        variant: Variant scales (empty: the robot itself).
        speed_m_s: A target speed [m/s]: the case searches the cheapest trot at it
            (:mod:`~scalf_opt.optimize.gait_search`) instead of optimizing a fixed gait's swings;
            ``None``: a fixed gait.
        loads: Stance load model (:mod:`scalf_opt.energy.loads`).
    """

    index: int
    swept: dict[str, Any]
    robot: str | None
    urdf: str | None
    legs: str | None
    actuators: str | None
    family: str
    method: str
    accounting: str
    optimize: str
    gait: dict[str, Any] = field(default_factory=dict)
    variant: dict[str, Any] = field(default_factory=dict)
    speed_m_s: float | None = None
    loads: str = DEFAULT_LOADS


@dataclass(frozen=True)
class Study:
    """A parsed study file.

    Attributes:
        path: The file.
        name: Its name (title of the figure).
        cases: The cases, in order (the last axis varies fastest).
        axes: The sweep's keys, in order (a combined axis is one key, ``"a + b"``).
        plot_x: The figure's x axis (a results.csv column).
    """

    path: Path
    name: str
    cases: tuple[Case, ...]
    axes: tuple[str, ...]
    plot_x: str


def _text(path: Path, table: dict[str, Any], key: str, where: str) -> str | None:
    return Table(path, where, table).text(key)


def _file(path: Path, table: dict[str, Any], key: str) -> str | None:
    value = _text(path, table, key, "study")
    if value is None:
        return None
    resolved = (path.parent / value).resolve()
    if not resolved.is_file():
        raise ConfigError(f"{path}: study.{key} = {value!r}: {resolved} not found")
    return str(resolved)


def _number(path: Path, key: str, value: Any) -> float | int:
    return number_value(path, key, value)


def _check_setting(path: Path, key: str, value: Any, label: str | None = None) -> str:
    label = label or key
    if not isinstance(value, str):
        raise ConfigError(f"{path}: {label} must be a text, got {value!r}")
    try:
        if key == "robot":
            if value not in robot_names():
                raise ConfigError(
                    f"unknown robot {value!r}: choose one of {', '.join(robot_names())}"
                )
        elif key == "family":
            optimizable_family(value)
        elif key == "method":
            solver(value)
        elif key == "accounting":
            power_accounting(value)
        else:
            stance_loads(value)
    except ConfigError as exc:
        raise ConfigError(f"{path}: {label}: {exc}") from exc
    return value


def _check_field(path: Path, key: str, value: Any) -> Any:
    """A swept or fixed value of ``key`` (``gait.x``, ``variant.x`` or a setting), checked."""
    if key in SETTINGS:
        return _check_setting(path, key, value)
    if key == SPEED:
        try:
            return check_speed(_number(path, key, value))
        except ConfigError as exc:
            raise ConfigError(f"{path}: {key}: {exc}") from exc
    kind, _, name = key.partition(".")
    if kind == "gait":
        if name not in Gait.field_names():
            raise ConfigError(f"{path}: {key!r}: {Gait.unknown_field(name)}")
        if name == "cycles" and (isinstance(value, bool) or not isinstance(value, int)):
            raise ConfigError(f"{path}: {key} must be an integer, got {value!r}")
        return _number(path, key, value)
    if kind == "variant":
        if name not in VariantScales.field_names():
            known = VariantScales.field_names()
            raise ConfigError(
                f"{path}: unknown variant field {name!r} in {key!r}"
                f"{did_you_mean(name, known)} (known: {', '.join(known)})"
            )
        value = _number(path, key, value)
        try:
            VariantScales.from_mapping({name: value}, str(path))
        except ConfigError as exc:
            raise ConfigError(f"{path}: {exc}") from exc
        return value
    keys = [
        *(f"gait.{f}" for f in Gait.field_names()),
        *(f"variant.{f}" for f in VariantScales.field_names()),
        SPEED,
        *SETTINGS,
    ]
    raise ConfigError(
        f"{path}: unknown sweep key {key!r}{did_you_mean(key, keys)} (use gait.<field>, "
        f"variant.<field>, {SPEED}, {', '.join(SETTINGS)})"
    )


Axis = tuple[str, list[str], list[tuple[Any, ...]]]
"""A sweep axis: its key, the fields it sets, and its points (a value per field each)."""


def _axes(path: Path, sweep: dict[str, Any]) -> list[Axis]:
    """Each axis: its key, the fields it sets and its values (one tuple per point)."""
    out = []
    for key, values in sweep.items():
        fields_ = [part.strip() for part in key.split("+")]
        if not isinstance(values, list) or not values:
            raise ConfigError(f"{path}: sweep.{key!r} must be a non-empty list")
        points = []
        for value in values:
            point = tuple(value) if len(fields_) > 1 and isinstance(value, list) else (value,)
            if len(point) != len(fields_):
                raise ConfigError(
                    f"{path}: sweep.{key!r}: each value must be a list of {len(fields_)} "
                    f"({', '.join(fields_)}), got {value!r}"
                )
            points.append(
                tuple(_check_field(path, f, v) for f, v in zip(fields_, point, strict=True))
            )
        out.append((key, fields_, points))
    seen: set[str] = set()
    for key, fields_, _ in out:
        for f in fields_:
            if f in seen:
                raise ConfigError(f"{path}: sweep sets {f} twice ({key!r})")
            seen.add(f)
    return out


def _check_gait_search(
    path: Path, optimize: str, fixed_gait: dict[str, Any], axes: list[Any]
) -> None:
    """Refuse what a study with a speed cannot have: a searched gait field, a leg choice."""
    if optimize != "pair":
        raise ConfigError(
            f"{path}: study.optimize = {optimize!r}: a study with a speed searches the gait with "
            'the diagonal pair\'s swings (optimize = "pair")'
        )
    given = [f"gait.{k}" for k in fixed_gait] + [
        f for _, fields_, _ in axes for f in fields_ if f.startswith("gait.")
    ]
    for name in given:
        if name.removeprefix("gait.") in SEARCHED_GAIT_FIELDS:
            raise ConfigError(
                f"{path}: {name}: a study with a speed searches the period, duty cycle, step "
                "length and stance itself (set the clearance, rate or cycles only)"
            )


def _misplaced(path: Path, name: str, value: Any) -> str:
    """The error for a top-level entry that is not one of the file's tables.

    A setting written above the first table (``family = "joint-4"``) is a top-level key in TOML;
    the message says which table it belongs in when its name says so.
    """
    if not isinstance(value, dict):
        home = next(
            (t for t, keys in (("study", _STUDY_KEYS), ("gait", _GAIT_FIELDS)) if name in keys),
            None,
        )
        if home is not None:
            return f"{path}: {name} belongs in the [{home}] table: write it below a [{home}] line"
        return (
            f"{path}: unknown top-level key {name}{did_you_mean(name, _STUDY_KEYS + _GAIT_FIELDS)}"
            f" (a study file holds only the tables {', '.join(_TOP_KEYS)})"
        )
    return (
        f"{path}: unknown table [{name}]{did_you_mean(name, _TOP_KEYS)} "
        f"(known: {', '.join(_TOP_KEYS)})"
    )


def read_study(path: str | Path) -> Study:
    """Read and check a study file and expand its cases.

    Raises:
        ConfigError: Unreadable file, unknown or invalid key or value (the message names the
            file and the key).
    """
    path = Path(path)
    tables = _tables(path, dict(Table.read(path, "study").data))
    study = tables["study"]
    urdf = _file(path, study, "urdf")
    if urdf is not None and "robot" in study:
        raise ConfigError(f"{path}: give study.robot or study.urdf, not both")
    legs = _file(path, study, "legs")
    if legs is not None and urdf is None:
        raise ConfigError(f"{path}: study.legs goes with study.urdf")
    settings = _settings(path, study, urdf)
    optimize = _text(path, study, "optimize", "study") or "pair"
    if optimize not in OPTIMIZE_CHOICES:
        raise ConfigError(
            f"{path}: study.optimize = {optimize!r} is not one of {', '.join(OPTIMIZE_CHOICES)}"
        )
    fixed_gait = {k: _check_field(path, f"gait.{k}", v) for k, v in tables["gait"].items()}
    speed = _check_field(path, SPEED, study[SPEED]) if SPEED in study else None
    fixed_variant = {k: _check_field(path, f"variant.{k}", v) for k, v in tables["variant"].items()}
    axes = _axes(path, tables["sweep"])
    _check_axes(path, axes, urdf, speed, optimize, fixed_gait)
    common = {
        "urdf": urdf,
        "legs": legs,
        "actuators": _file(path, study, "actuators"),
        "optimize": optimize,
    }
    cases = [
        _case(index, combo, axes, {**settings, SPEED: speed}, fixed_gait, fixed_variant, common)
        for index, combo in enumerate(itertools.product(*(points for _, _, points in axes)))
    ]
    swept_fields = [f for _, fields_, _ in axes for f in fields_]
    plot_x = _plot_x(path, tables["plot"], swept_fields)
    name = _text(path, study, "name", "study") or path.stem
    return Study(path, name, tuple(cases), tuple(key for key, _, _ in axes), plot_x)


def _tables(path: Path, data: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """The file's tables, each a table (absent: empty); refuses anything else at the top."""
    extra = sorted(set(data) - set(_TOP_KEYS))
    if extra:
        raise ConfigError(_misplaced(path, extra[0], data[extra[0]]))
    tables = {}
    for key in _TOP_KEYS:
        value = data.get(key, {})
        if not isinstance(value, dict):
            raise ConfigError(f"{path}: {key} must be a table, got {value!r}")
        tables[key] = value
    unknown = sorted(set(tables["study"]) - set(_STUDY_KEYS))
    if unknown:
        raise ConfigError(
            f"{path}: unknown key study.{unknown[0]}{did_you_mean(unknown[0], _STUDY_KEYS)} "
            f"(known: {', '.join(_STUDY_KEYS)})"
        )
    return tables


def _settings(path: Path, study: dict[str, Any], urdf: str | None) -> dict[str, Any]:
    """The study's settings (robot, family, method, accounting, loads), checked, defaulted."""
    settings: dict[str, Any] = {
        "robot": None if urdf else "scalf",
        "family": DEFAULT_FAMILY,
        "method": DEFAULT_SOLVER,
        "accounting": "paper",
        "loads": DEFAULT_LOADS,
    }
    for key in SETTINGS:
        if key in study:
            settings[key] = _check_setting(path, key, study[key], f"study.{key}")
    return settings


def _check_axes(
    path: Path,
    axes: list[Axis],
    urdf: str | None,
    speed: Any,
    optimize: str,
    fixed_gait: dict[str, Any],
) -> None:
    """The sweep's axes agree with the study's settings, and make at most MAX_CASES cases."""
    if urdf is not None and any("robot" in fields_ for _, fields_, _ in axes):
        raise ConfigError(f"{path}: sweep.robot needs study.robot, not study.urdf")
    swept_speed = any(SPEED in fields_ for _, fields_, _ in axes)
    if speed is not None and swept_speed:
        raise ConfigError(f"{path}: study.{SPEED} and sweep.{SPEED}: give one")
    if speed is not None or swept_speed:
        _check_gait_search(path, optimize, fixed_gait, axes)
    count = math.prod(len(points) for _, _, points in axes)
    if count > MAX_CASES:
        raise ConfigError(
            f"{path}: [sweep] makes {count} cases, more than the {MAX_CASES} a study may have "
            "(split it into several studies)"
        )


def _case(
    index: int,
    combo: tuple[tuple[Any, ...], ...],
    axes: list[Axis],
    values: dict[str, Any],
    fixed_gait: dict[str, Any],
    fixed_variant: dict[str, Any],
    common: dict[str, Any],
) -> Case:
    """The case at one point of the sweep: the fixed fields, then the swept ones over them."""
    values, gait, variant = dict(values), dict(fixed_gait), dict(fixed_variant)
    swept: dict[str, Any] = {}
    for (_, fields_, _), point in zip(axes, combo, strict=True):
        for f, v in zip(fields_, point, strict=True):
            swept[f] = v
            if f in SETTINGS or f == SPEED:
                values[f] = v
            elif f.startswith("gait."):
                gait[f.removeprefix("gait.")] = v
            else:
                variant[f.removeprefix("variant.")] = v
    return Case(
        index=index,
        swept=swept,
        robot=values["robot"],
        family=str(values["family"]),
        method=str(values["method"]),
        accounting=str(values["accounting"]),
        gait=gait,
        variant=variant,
        speed_m_s=values[SPEED],
        loads=str(values["loads"]),
        **common,
    )


def _plot_x(path: Path, plot: dict[str, Any], swept_fields: list[str]) -> str:
    """The figure's x axis: ``plot.x``, else the first swept field, else the case number."""
    plot_x = _text(path, plot, "x", "plot") or (swept_fields[0] if swept_fields else "case")
    extra = sorted(set(plot) - {"x"})
    if extra:
        raise ConfigError(f"{path}: unknown key plot.{extra[0]} (known: x)")
    columns = ["case", *swept_fields, *RESULT_COLUMNS]
    if plot_x not in columns:
        raise ConfigError(
            f"{path}: plot.x = {plot_x!r} is not a column of results.csv"
            f"{did_you_mean(plot_x, columns)} (case, a swept field"
            f"{': ' + ', '.join(swept_fields) if swept_fields else ''}, or one of "
            f"{', '.join(c for c in RESULT_COLUMNS if c != 'error')})",
            field="plot.x",
        )
    return plot_x


def speed_study(
    speeds: list[float],
    robot: str | None = None,
    urdf: str | None = None,
    family: str = DEFAULT_FAMILY,
    method: str = DEFAULT_SOLVER,
    accounting: str = "paper",
    name: str = "cheapest trot",
    loads: str = DEFAULT_LOADS,
) -> Study:
    """A study of the cheapest trot at each of ``speeds`` (``scalf-opt gait``'s cases).

    Args:
        speeds: Target speeds [m/s].
        robot: A catalog robot, or ``None`` with ``urdf``.
        urdf: A URDF path, or ``None``.
        family: Swing family.
        method: The swings' solver.
        accounting: Power accounting.
        name: The study's name (the figure's title).
        loads: Stance load model (:mod:`scalf_opt.energy.loads`).

    Raises:
        ConfigError: A speed out of range (the family, method and accounting are checked when
            the cases are set up).
    """
    values = [check_speed(v) for v in speeds]
    cases = tuple(
        Case(
            index=i,
            swept={SPEED: v},
            robot=robot if urdf is None else None,
            urdf=str(Path(urdf).resolve()) if urdf is not None else None,
            legs=None,
            actuators=None,
            family=family,
            method=method,
            accounting=accounting,
            optimize="pair",
            speed_m_s=v,
            loads=loads,
        )
        for i, v in enumerate(values)
    )
    return Study(Path("--speed"), name, cases, (SPEED,), SPEED)

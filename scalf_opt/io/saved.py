"""Read back the swing trajectories a ``summary.json`` (``evaluate``/``optimize --out``) holds.

A summary records, per leg, the swing family and its parameters, and the gait and accounting it
was evaluated with: enough to rebuild every sample of the cycle with the energy pipeline, so the
view, the figures, the simulation and ``evaluate --swing`` use exactly what ``optimize`` found.
The one reader of the file: it checks every field it uses, names the one that is wrong, and
refuses swings of another robot (:meth:`SavedSwings.check_robot`), a file that holds no optimum
(:meth:`SavedSwings.require_optimum`) and a gait of other timing
(:meth:`SavedSwings.check_timing`).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.energy.loads import PAPER_LOADS, stance_loads
from scalf_opt.errors import ConfigError, GaitError, ScalfError
from scalf_opt.files import read_untrusted_text
from scalf_opt.io.provenance import sha256_of
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.types import LEG_NAMES, Accounting

SUMMARY_FILE = "summary.json"

MAX_SUMMARY_BYTES = 16 * 1024 * 1024
"""Largest ``summary.json`` read [bytes] (a paper run's, with the bound and the stance: ~100 kB)."""

MAX_JSON_DEPTH = 32
"""Deepest nesting of lists and objects in a ``summary.json`` (written ones: 6)."""

MASS_TOLERANCE = 1e-9
"""Relative difference of total masses that still counts as the same robot."""

TIMING_FIELDS: tuple[str, ...] = (
    "period_s",
    "duty_cycle",
    "step_length_m",
    "clearance_m",
    "stance_height_m",
    "stance_x_offset_front_m",
    "stance_x_offset_hind_m",
)
"""Gait fields an optimum belongs to (its timing and stance): a gait that differs in one of them
is another problem; only the rate and the accounting may change."""

TIMING_RTOL = 1e-9
"""Relative difference allowed between a file's timing field and the gait's (round-off)."""

OPTIONAL_GAIT_FIELDS = {"stance_x_offset_front_m": 0.0, "stance_x_offset_hind_m": 0.0}
"""Gait fields older files lack, with the value they then had (the foot under the hip)."""


@dataclass(frozen=True)
class SavedSwings:
    """The swings of one result directory.

    Attributes:
        source: The ``summary.json`` read.
        gait: The gait they were evaluated with.
        accounting: The power accounting used.
        families: Swing family name per leg.
        parameters: The family's parameters per leg (family units; empty for the reference).
        methods: The optimizer per optimized leg (``ipopt``, ``pattern``), when recorded.
        robot: The robot's name from the file's provenance, when recorded.
        urdf_sha256: The SHA-256 of the URDF it was computed on, when recorded.
        total_mass_kg: The robot's mass the file records, when it does (files written before
            the provenance record still have it).
        optimization: The ``optimization`` records per optimized leg (``optimize``'s files).
        rate_hz: The rate the optimization converged at, when recorded [Hz].
        loads: The stance load model (:mod:`scalf_opt.energy.loads`); files written before
            the option have ``trunk``, the only model there was.
    """

    source: Path
    gait: Gait
    accounting: Accounting
    families: dict[str, str]
    parameters: dict[str, np.ndarray]
    methods: dict[str, str]
    robot: str | None = None
    urdf_sha256: str | None = None
    total_mass_kg: float | None = None
    optimization: dict[str, Any] | None = None
    rate_hz: float | None = None
    loads: str = PAPER_LOADS

    def require_optimum(self) -> None:
        """Refuse a file that holds no solved optimum (an ``evaluate`` result, a failed run).

        Raises:
            ConfigError: ``optimization`` is missing or empty, or a leg's record is not solved.
        """
        if not self.optimization:
            raise ConfigError(
                f"{self.source}: missing field optimization: not an optimum written by optimize"
            )
        for leg, record in self.optimization.items():
            if not isinstance(record, dict) or record.get("success") is not True:
                raise ConfigError(
                    f"{self.source}: field optimization.{leg}.success is not true: the file "
                    "holds no optimum"
                )

    def check_timing(self, gait: Gait) -> None:
        """Refuse a gait whose timing or stance differs from the file's.

        Raises:
            ConfigError: A timing field differs (the message names it and both values).
        """
        for name in TIMING_FIELDS:
            theirs, ours = getattr(self.gait, name), getattr(gait, name)
            if not math.isclose(theirs, ours, rel_tol=TIMING_RTOL, abs_tol=1e-12):
                raise ConfigError(
                    f"{self.source}: the swings were found for gait field {name} = {theirs!r}, "
                    f"the gait has {ours!r}: its timing and stance must match (only the rate and "
                    "the accounting may differ)",
                    field=name,
                )

    @property
    def swings(self) -> dict[str, tuple[str, np.ndarray]]:
        """Per leg in the file, the swing family's name and its parameters."""
        return {leg: (self.families[leg], self.parameters[leg]) for leg in self.families}

    def require_all_legs(self) -> dict[str, tuple[str, np.ndarray]]:
        """:attr:`swings`, which must name every leg (a simulation moves all four).

        Raises:
            ConfigError: A leg is missing (the message names the field).
        """
        for leg in LEG_NAMES:
            if leg not in self.families:
                raise ConfigError(f"{self.source}: missing field legs.{leg}")
        return self.swings

    def check_robot(self, robot: Robot) -> None:
        """Refuse to use these swings on another robot than the one they were computed on.

        The file's provenance names the robot and the SHA-256 of its URDF; a file without
        provenance (older versions) still records the robot's total mass.

        Raises:
            ConfigError: The name, the URDF's hash or the mass is another robot's (the message
                names the field), or the file records none of them.
        """
        again = "give the same --robot or --urdf"
        if self.robot is None and self.urdf_sha256 is None and self.total_mass_kg is None:
            raise ConfigError(
                f"{self.source}: names no robot (no provenance.robot, provenance.urdf_sha256 nor "
                f"total_mass_kg): its swings cannot be checked against {robot.name}'s; use the "
                "summary.json a command wrote, whole"
            )
        if self.robot is not None and self.robot != robot.name:
            raise ConfigError(
                f"{self.source}: field provenance.robot is {self.robot!r}, not {robot.name!r}: "
                f"{again}"
            )
        if self.urdf_sha256 is not None and self.urdf_sha256 != sha256_of(robot.urdf_path):
            raise ConfigError(
                f"{self.source}: field provenance.urdf_sha256 is not the SHA-256 of "
                f"{robot.urdf_path}: the swings belong to another URDF of {robot.name!r}; {again}"
            )
        if self.total_mass_kg is not None and not math.isclose(
            self.total_mass_kg, robot.total_mass_kg, rel_tol=MASS_TOLERANCE
        ):
            raise ConfigError(
                f"{self.source}: field total_mass_kg is {self.total_mass_kg:g} kg, but "
                f"{robot.name} weighs {robot.total_mass_kg:g} kg: the swings belong to another "
                f"robot; {again}"
            )

    @property
    def label(self) -> str:
        """A short name: the directory, its optimized families and methods."""
        optimized = sorted({f for f in self.families.values() if f != "reference"})
        what = ", ".join(optimized) if optimized else "reference"
        methods = sorted(set(self.methods.values()))
        if methods:
            what += f", {'/'.join(methods)}"
        return f"{self.source.parent.name or self.source.parent} ({what})"


def read_saved_swings(directory: str | Path) -> SavedSwings:
    """Read ``directory/summary.json``.

    Args:
        directory: A directory written by ``scalf-opt optimize --out`` or ``evaluate --out``, or
            the ``summary.json`` file itself.

    Raises:
        ConfigError: The file is missing, not JSON, or lacks a field; the message names the file
            and the field.
        GaitError: Its gait is out of range.
    """
    path = Path(directory)
    if path.is_dir() or path.suffix != ".json":
        path = path / SUMMARY_FILE
    if not path.exists():
        raise ConfigError(
            f"{path}: not found (give a directory written by 'scalf-opt optimize --out')"
        )
    data = read_json(path, "summary")
    if not isinstance(data, dict):
        raise ConfigError(f"{path}: not a summary (expected a JSON object)")
    gait = _gait(path, _field(path, data, "gait", dict))
    accounting, loads = _models(path, data)
    families, parameters = _swings(path, _field(path, data, "legs", dict))
    methods = {
        leg: str(record["method"])
        for leg, record in (data.get("optimization") or {}).items()
        if isinstance(record, dict) and "method" in record
    }
    optimization = data.get("optimization")
    run = data.get("optimization_run")
    record = data.get("provenance")
    source: dict[str, Any] = record if isinstance(record, dict) else {}
    robot, sha = source.get("robot"), source.get("urdf_sha256")
    return SavedSwings(
        path,
        gait,
        accounting,
        families,
        parameters,
        methods,
        robot if isinstance(robot, str) else None,
        sha if isinstance(sha, str) else None,
        _number_or_none(data.get("total_mass_kg")),
        optimization if isinstance(optimization, dict) else None,
        _number_or_none(run.get("sample_rate_hz") if isinstance(run, dict) else None),
        loads,
    )


def _number_or_none(value: Any) -> float | None:
    """``value`` as a float when it is a JSON number a float holds, else ``None``."""
    if not isinstance(value, int | float) or isinstance(value, bool):
        return None
    try:
        return float(value)
    except OverflowError:  # an integer of hundreds of digits
        return None


def _models(path: Path, data: dict[str, Any]) -> tuple[str, str]:
    """The summary's power accounting and stance load model, each checked to be known."""
    accounting = _field(path, data, "accounting", str)
    try:
        power_accounting(accounting)
    except ScalfError as exc:
        raise ConfigError(f"{path}: {exc}") from exc
    loads = data.get("loads", PAPER_LOADS)
    if not isinstance(loads, str):
        raise ConfigError(f"{path}: field loads must be a string, got {loads!r}")
    try:
        stance_loads(loads)
    except ScalfError as exc:
        raise ConfigError(f"{path}: {exc}") from exc
    return accounting, loads


def _swings(path: Path, legs: dict[str, Any]) -> tuple[dict[str, str], dict[str, np.ndarray]]:
    """Each saved leg's swing family and parameters, checked against the family's size."""
    families: dict[str, str] = {}
    parameters: dict[str, np.ndarray] = {}
    for leg in LEG_NAMES:
        if leg not in legs:
            continue
        record = _field(path, legs, leg, dict, f"legs.{leg}")
        family = _field(path, record, "swing_family", str, f"legs.{leg}.swing_family")
        params = _field(path, record, "swing_parameters", list, f"legs.{leg}.swing_parameters")
        try:
            swing_family = make_family(family)
        except ScalfError as exc:
            raise ConfigError(f"{path}: legs.{leg}.swing_family: {exc}") from exc
        n_params = swing_family.n_params
        if len(params) != n_params or not all(
            _number_or_none(v) is not None and math.isfinite(v) for v in params
        ):
            raise ConfigError(
                f"{path}: legs.{leg}.swing_parameters must be {n_params} finite numbers for family "
                f"{family!r}, got {params!r}"
            )
        names = record.get("swing_parameter_names")  # none in a file of an older version
        if names is not None and not (
            isinstance(names, list) and all(isinstance(n, str) for n in names)
        ):
            raise ConfigError(f"{path}: legs.{leg}.swing_parameter_names must be a list of names")
        try:
            parameters[leg] = swing_family.theta_from_record(params, names)
        except ScalfError as exc:
            raise ConfigError(f"{path}: legs.{leg}.swing_parameter_names: {exc}") from exc
        families[leg] = family
    if not families:
        raise ConfigError(f"{path}: legs holds none of {', '.join(LEG_NAMES)}")
    return families, parameters


def _depth_of(data: Any) -> int:
    """How deeply lists and objects nest in parsed JSON (iteratively: no recursion)."""
    deepest, stack = 0, [(data, 1)]
    while stack:
        value, depth = stack.pop()
        if isinstance(value, dict | list):
            deepest = max(deepest, depth)
            items = value.values() if isinstance(value, dict) else value
            stack.extend((item, depth + 1) for item in items)
    return deepest


def read_json(path: Path, kind: str) -> Any:
    """A JSON file read as untrusted input: a bounded regular file, nested at most so deep.

    Raises:
        ConfigError: Not a regular file, larger than :data:`MAX_SUMMARY_BYTES`, not UTF-8, not
            valid JSON, or nested deeper than :data:`MAX_JSON_DEPTH` (the message names it).
    """
    text = read_untrusted_text(path, kind, MAX_SUMMARY_BYTES)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ConfigError(f"{path}: not valid JSON ({exc.msg}, line {exc.lineno})") from exc
    except ValueError:  # an integer of more digits than Python converts (4300)
        raise ConfigError(f"{path}: a number in the JSON has too many digits") from None
    except RecursionError:
        data = None
    if (data is None and text.lstrip().startswith(("[", "{"))) or _depth_of(data) > MAX_JSON_DEPTH:
        raise ConfigError(f"{path}: JSON nested deeper than the {MAX_JSON_DEPTH} levels allowed")
    return data


def _field(path: Path, data: dict[str, Any], key: str, kind: type, name: str | None = None) -> Any:
    if key not in data:
        raise ConfigError(f"{path}: missing field {name or key!r}")
    value = data[key]
    if not isinstance(value, kind):
        raise ConfigError(f"{path}: field {name or key!r} must be a {kind.__name__}")
    return value


def _gait(path: Path, record: dict[str, Any]) -> Gait:
    values = {**OPTIONAL_GAIT_FIELDS, **{k: record[k] for k in Gait.field_names() if k in record}}
    missing = [k for k in Gait.field_names() if k not in values]
    if missing:
        raise ConfigError(f"{path}: gait lacks {', '.join(missing)}")
    try:
        return Gait(**values)
    except GaitError as exc:
        raise GaitError(f"{path}: {exc}") from exc
    except TypeError as exc:  # a mistyped value the dataclass cannot even compare
        raise ConfigError(f"{path}: bad gait ({exc})") from exc

"""The drive registry: every kind reads only its own tables, and a new drive is one module and
one registration that every command then takes, from the actuator file to an optimum."""

import shutil
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import casadi as ca
import pytest

import scalf_opt as so
import scalf_opt.actuators.registry as registry
from scalf_opt.actuators.drive import Drive, DriveKind, MaxFn
from scalf_opt.actuators.registry import DRIVE_KINDS, file_tables, register_drive_kind
from scalf_opt.actuators.sidecar import read_sidecar, robot_sidecar_path
from scalf_opt.cli import main
from scalf_opt.errors import ConfigError
from scalf_opt.robots.catalog import CATALOG
from scalf_opt.robots.files import robot_files_dir
from scalf_opt.robots.loading import load_robot
from scalf_opt.tables import Table
from scalf_opt.types import Expr


@pytest.mark.parametrize("kind", DRIVE_KINDS, ids=lambda k: k.tables[-1])
def test_every_kind_reads_its_own_tables_and_nothing_from_a_file_without_them(kind, tmp_path):
    assert kind.help and all(f"[{t}" in kind.help for t in kind.tables)
    others = [t for k in DRIVE_KINDS if k is not kind for t in k.tables]
    assert not set(kind.tables) & set(others)
    path = tmp_path / "x.toml"
    path.write_text('[sources]\n"x" = "y"\n')
    assert kind.read(Table.read(path, "actuator"), {}) == {}


@pytest.mark.parametrize("name", list(CATALOG))
def test_every_drive_of_the_catalog_comes_from_a_registered_table(name):
    path = robot_sidecar_path(load_robot(name))
    assert path is not None
    drives = read_sidecar(path).drives
    assert {d.file_table for d in drives.values()} <= set(file_tables())


@dataclass(frozen=True)
class EfficiencyDrive(Drive):
    """A toy drive: every joint watt costs ``1 / efficiency`` watts (the joint power charged
    through the accounting, the rest added as loss)."""

    efficiency: float = 1.0

    kind: ClassVar[str] = "efficiency"
    noun: ClassVar[str] = "efficiency drive"
    file_table: ClassVar[str] = "toy"

    def loss_rate(self, q: Expr, qd: Expr, tau: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        power = tau * qd / 100.0  # in hectowatts, where the NLP's smoothing width is negligible
        magnitude = 100.0 * (max_fn(power, 0) + max_fn(-power, 0))
        return (1.0 / self.efficiency - 1.0) * magnitude


def read_toy(file: Table, drives: Mapping[str, Drive]) -> dict[str, Drive]:
    out: dict[str, Drive] = {}
    for table in file.tables("toy").values():
        table.only(("joints", "efficiency"))
        efficiency = table.number("efficiency")
        if efficiency > 1.0:
            raise file.error(f"{table.key('efficiency')} must be at most 1")
        for joint in table.names("joints"):
            out[joint] = EfficiencyDrive(joint, efficiency)
    return out


TOY = DriveKind(("toy",), read_toy, "[toy.<name>]: efficiency and joints (a toy)")


@pytest.fixture
def toy_robot(monkeypatch, tmp_path):
    """SCalf's URDF with every leg joint on the toy drive at 50 % efficiency, and without."""
    monkeypatch.setattr(registry, "DRIVE_KINDS", list(registry.DRIVE_KINDS))
    register_drive_kind(TOY)
    joints = [f"{leg}_{j}" for leg in ("RF", "LF", "RH", "LH") for j in ("hip_pitch", "knee")]
    (tmp_path / "toy").mkdir()
    (tmp_path / "ideal").mkdir()
    for folder in ("toy", "ideal"):
        shutil.copy(robot_files_dir() / "scalf.urdf", tmp_path / folder / "robot.urdf")
    (tmp_path / "toy" / "robot_actuators.toml").write_text(
        f"[toy.all]\nefficiency = 0.5\njoints = {joints!r}\n".replace("'", '"')
    )
    return tmp_path / "toy" / "robot.urdf", tmp_path / "ideal" / "robot.urdf"


def test_a_new_drive_is_one_registration_end_to_end(toy_robot, capsys):
    toy, ideal = toy_robot
    with_toy = so.evaluate(load_robot(urdf=toy), loads="trunk")
    lossless = so.evaluate(load_robot(urdf=ideal), loads="trunk")
    assert {type(d) for d in with_toy.pipeline.robot_physics.drives.values()} == {EfficiencyDrive}
    # |tau qd| charged (the paper's accounting) plus as much again: twice the ideal drives'
    assert with_toy.cycle.energy_j == pytest.approx(2 * lossless.cycle.energy_j, 1e-9)
    result = so.optimize_swing(load_robot(urdf=toy), family="paper", loads="trunk")
    assert result.converged
    for leg in ("RF", "LH"):
        assert result.cycle.legs[leg].swing_energy_j < result.reference.legs[leg].swing_energy_j
    assert main(["evaluate", "--urdf", str(toy), "--loads", "trunk", "--json"]) == 0
    assert main(["model", "--urdf", str(toy)]) == 0
    assert "efficiency drive" in capsys.readouterr().out


def test_a_new_drive_gets_the_files_checks(toy_robot, capsys):
    toy, _ = toy_robot
    path = toy.with_name("robot_actuators.toml")
    path.write_text(path.read_text().replace("0.5", "1.5"))
    assert main(["evaluate", "--urdf", str(toy)]) == 2
    assert "toy.all.efficiency must be at most 1" in capsys.readouterr().err
    path.write_text(path.read_text().replace("efficiency = 1.5", "efficiency = 0.5\ncolor = 1"))
    assert main(["evaluate", "--urdf", str(toy)]) == 2
    assert "unknown key toy.all.color" in capsys.readouterr().err
    with pytest.raises(ConfigError, match=r"\[toy\] is already read"):
        register_drive_kind(TOY)


def test_a_table_of_no_kind_is_refused(tmp_path):
    path = tmp_path / "x_actuators.toml"
    path.write_text("[toy.all]\nefficiency = 0.5\njoints = ['A']\n")
    with pytest.raises(ConfigError, match=r"unknown key toy \(allowed: friction, cylinders"):
        read_sidecar(path)


def test_a_mistyped_table_is_told_the_nearest_name(tmp_path):
    path = tmp_path / "x_actuators.toml"
    path.write_text("[electrik.motor]\njoints = ['A']\n")
    with pytest.raises(ConfigError, match=r"unknown key electrik; did you mean 'electric'\?"):
        read_sidecar(path)

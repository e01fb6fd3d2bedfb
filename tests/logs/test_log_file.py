"""The cylinder-log file: read strictly, refused with the row and the column, written back."""

import numpy as np
import pytest

from scalf_opt.cli import main
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import LogError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.logs.log_file import log_csv_text, parse_log
from scalf_opt.logs.model_log import model_log
from scalf_opt.robots.loading import load_robot
from scalf_opt.sim.plan import REFERENCE_SWINGS


@pytest.fixture(scope="module")
def good_text():
    pipeline = EnergyPipeline(load_robot("scalf"), Gait())
    log, _ = model_log(pipeline, REFERENCE_SWINGS, 80.0, cycles=2)
    return log_csv_text(log)


def test_writing_and_reading_give_the_same_log(good_text):
    log = parse_log(good_text, "log.csv")
    again = parse_log(log_csv_text(log), "log.csv")
    assert list(log.legs) == ["RF", "LH", "LF", "RH"]
    for leg, data in log.legs.items():
        for field in ("t_s", "length_m", "force_n", "contact"):
            np.testing.assert_array_equal(getattr(data, field), getattr(again.legs[leg], field))
    lines = good_text.splitlines()
    assert lines[0] == "t_s,leg,hip_length_m,knee_length_m,hip_force_n,knee_force_n,contact"
    assert [line.split(",")[1] for line in lines[1:5]] == ["RF", "LH", "LF", "RH"]
    assert log.legs["RF"].rows[0] == 2  # row 1 is the header


def replace_cell(text, row, column, value):
    lines = text.splitlines()
    header = lines[0].split(",")
    cells = lines[row - 1].split(",")
    cells[header.index(column)] = value
    lines[row - 1] = ",".join(cells)
    return "\n".join(lines) + "\n"


def drop_column(text, column):
    lines = [line.split(",") for line in text.splitlines()]
    i = lines[0].index(column)
    return "\n".join(",".join(c[:i] + c[i + 1 :]) for c in lines) + "\n"


BAD_LOGS = [
    (
        "missing column",
        lambda t: drop_column(t, "knee_force_n"),
        "row 1, column knee_force_n: missing",
    ),
    (
        "unknown column",
        lambda t: t.replace("contact", "contacts", 1),
        "row 1, column contacts: not a log column",
    ),
    (
        "unknown leg",
        lambda t: replace_cell(t, 7, "leg", "XX"),
        "row 7, column leg: 'XX' is not a leg",
    ),
    (
        "NaN",
        lambda t: replace_cell(t, 9, "hip_force_n", "nan"),
        "row 9, column hip_force_n: 'nan' is not a finite number",
    ),
    (
        "not a number",
        lambda t: replace_cell(t, 9, "knee_length_m", "0.2x"),
        "row 9, column knee_length_m",
    ),
    (
        "time not increasing",
        lambda t: replace_cell(t, 10, "t_s", "0.0"),
        "row 10, column t_s: 0.0 s does not increase",
    ),
    (
        "contact not 0 or 1",
        lambda t: replace_cell(t, 4, "contact", "2"),
        "row 4, column contact: '2' is not 0 or 1",
    ),
    (
        "short row",
        lambda t: t.replace("\n", ",\n", 3).replace(",\n", "\n", 2),
        "row 3: 8 cells, the header has 7",
    ),
    ("empty", lambda t: "", "row 1: empty file"),
    ("header only", lambda t: t.splitlines()[0] + "\n", "row 2: the log has no samples"),
]


@pytest.mark.parametrize(("case", "corrupt", "message"), BAD_LOGS, ids=[c[0] for c in BAD_LOGS])
def test_a_bad_log_is_refused_naming_the_row_and_the_column(good_text, case, corrupt, message):
    with pytest.raises(LogError, match=None) as error:
        parse_log(corrupt(good_text), "log.csv")
    assert str(error.value).startswith("log.csv: ")
    assert message in str(error.value)


@pytest.mark.parametrize(
    ("corrupt", "message"),
    [
        (
            lambda t: replace_cell(t, 20, "knee_length_m", "0.5"),
            "row 20, column knee_length_m: 0.5 m is outside the",
        ),
        (
            lambda t: "\n".join(t.splitlines()[:150]) + "\n",
            "column t_s: leg RF never touches down in the log",
        ),
    ],
    ids=["length outside the stroke", "shorter than one cycle"],
)
def test_the_command_refuses_a_bad_log_in_one_line(tmp_path, capsys, good_text, corrupt, message):
    path = tmp_path / "log.csv"
    path.write_text(corrupt(good_text))
    assert main(["analyze-log", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and err.startswith(f"scalf-opt: error: {path}: ")
    assert message in err


def test_a_missing_file_and_a_robot_without_cylinders(tmp_path, capsys, good_text):
    assert main(["analyze-log", str(tmp_path / "none.csv")]) == 2
    assert "log file not found" in capsys.readouterr().err
    path = tmp_path / "log.csv"
    path.write_text(good_text)
    assert main(["analyze-log", str(path), "--robot", "solo12"]) == 2
    assert "has no hydraulic cylinder" in capsys.readouterr().err
    assert main(["analyze-log", str(path), "--period", "-1"]) == 2
    assert "--period -1" in capsys.readouterr().err

"""``scalf-opt gait``: the cheapest trot per speed as a table, files every command loads, a
resumed run from the cache, and one-line errors for a bad ``--speed``."""

import csv
import json

import pytest

from scalf_opt.cli import main
from scalf_opt.cli.commands.gait import MAX_SPEEDS, all_speeds, parse_speeds
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait_file import read_gait
from scalf_opt.studies.gait_case import GAIT_COLUMNS
from tests.cli.conftest import GAIT_ARGV as ARGV

SHARED_RUN = pytest.mark.xdist_group("cli_runs")
"""The tests that read the `gait_run` (tests/cli/conftest.py), test_cli_help.py's too."""


@pytest.fixture
def run(gait_run):
    return gait_run


def test_speeds_are_a_value_a_list_or_a_range_with_its_end():
    assert parse_speeds("1") == [1.0]
    assert parse_speeds("0.5,1.25") == [0.5, 1.25]
    assert parse_speeds("0.25:1.5:0.25") == [0.25, 0.5, 0.75, 1.0, 1.25, 1.5]
    for bad in ("1.0x", "1:0:0.5", "0:1:0", "0:1", f"0.001:10:{1 / (MAX_SPEEDS + 5)}"):
        with pytest.raises(ConfigError, match="--speed"):
            parse_speeds(bad)


def test_the_speed_option_repeats_and_each_speed_counts_once():
    assert all_speeds(["0.5", "0.8,0.5", "1:1.2:0.1"]) == [0.5, 0.8, 1.0, 1.1, 1.2]
    with pytest.raises(ConfigError, match="--speed: 201 speeds in all"):
        all_speeds(["0.01:1:0.01", "1.01:2.01:0.01"])


@SHARED_RUN
def test_the_table_the_figure_and_a_folder_per_speed(run, capsys):
    out, code = run
    assert code == 0
    with (out / "gaits.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0]) == list(GAIT_COLUMNS) and len(rows) == 1
    row = rows[0]
    assert row["status"] == "ok" and float(row["speed_m_s"]) == 1.0
    cot = float(row["cost_of_transport"])
    assert (
        cot <= float(row["default_cost_of_transport"]) <= float(row["reference_cost_of_transport"])
    )
    assert (out / "gaits.png").stat().st_size > 10_000
    gait = read_gait(out / "speed_1" / "gait.toml")
    assert gait.speed_m_s == pytest.approx(1.0, rel=1e-12)
    assert gait.period_s == pytest.approx(float(row["period_s"]), rel=1e-12)
    # the gait file says its robot: walked on another one, a command says so
    assert 'robot = "scalf"' in (out / "speed_1" / "gait.toml").read_text()
    other = ["evaluate", "--robot", "go1", "--gait", str(out / "speed_1" / "gait.toml")]
    main(other)
    assert "was made for scalf; walking it on go1" in capsys.readouterr().err
    # the swings are loadable: evaluate them on their gait, same cost of transport
    assert main(["evaluate", "--swing", str(out / "speed_1"), "--json"]) == 0
    evaluated = json.loads(capsys.readouterr().out)
    assert evaluated["cost_of_transport"] == pytest.approx(cot, rel=1e-9)


@SHARED_RUN
def test_a_second_run_comes_from_the_cache_with_the_same_table(run, capsys):
    out, _ = run
    before = (out / "gaits.csv").read_bytes()
    assert main([*ARGV, "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert next(iter(data)) == "provenance" and data["rows"][0]["status"] == "ok"
    assert (out / "gaits.csv").read_bytes() == before


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["gait", "--speed", "0"], "--speed: the speed must be a number in (0, 10] m/s"),
        (["gait", "--speed", "fast"], "--speed fast: give V, V1,V2,... or START:STOP:STEP"),
        (["gait", "--speed", "1", "--family", "free"], "--family: family free is the"),
        (["gait", "--speed", "1", "--workers", "2", "--scheduler", "tcp://x:1"], "not both"),
    ],
)
def test_a_bad_option_is_one_line(argv, message, tmp_path, capsys):
    assert main([*argv, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "out").exists()


def test_the_table_lines_up_each_columns_decimals():
    """A searched field or a cost of transport has the same decimals in every row (``0.500``
    beside ``0.575``, not ``0.5``); the speeds keep the digits they were given with."""
    from scalf_opt.cli.commands.gait import gait_table

    def row(speed, period, duty, cot):
        return {
            "speed_m_s": speed,
            "period_s": period,
            "duty_cycle": duty,
            "step_length_m": speed * period * duty,
            "stance_height_m": 0.8,
            "stance_x_offset_front_m": 0.04,
            "stance_x_offset_hind_m": -0.04,
            "cost_of_transport": cot,
            "default_cost_of_transport": 0.12,
            "reference_cost_of_transport": 0.2,
            "saving_vs_reference_pct": 100 * (1 - cot / 0.2),
            "status": "ok",
            "pinned_by": "",
            "error": "",
            "family": "joint-6",
            "default_infeasible": "",
        }

    table = gait_table("scalf", [row(0.25, 0.8625, 0.5, 0.089), row(1.0, 0.5, 0.575, 0.1419)])
    first, second = (line.split() for line in table.splitlines()[3:5])
    fields = ["0.25", "0.8625", "0.500", "0.1078", "0.8000", "0.040", "-0.040"]
    assert first[:9] == [*fields, "0.0890", "0.1200"]
    assert second[:4] == ["1", "0.5000", "0.575", "0.2875"]


def test_what_pins_a_gait_reads_as_limits_and_steps():
    """gaits.csv keeps ``field up|down: limit``; the table says each limit once, in words."""
    from scalf_opt.cli.commands.gait import pinned_lines

    pinned = (
        "period_s up: RF cyl_len_knee: cylinder cyl_len limit (actuator file), less margin; "
        "duty_cycle up: RF cyl_len_knee: cylinder cyl_len limit (actuator file), less margin; "
        "duty_cycle down: duty_cycle below the search box's 0.5, a trot's floor; "
        "stance_height_m up: LH q_knee: joint range (URDF), less margin; "
        "stance_x_offset_hind_m down: swing not solved: LH (Maximum_Iterations_Exceeded)"
    )
    assert pinned_lines(pinned) == [
        "RF knee cylinder's stroke (actuator file): a longer period, a higher duty",
        "the lowest duty this model walks, 0.5 (it has no flight phase): a lower duty",
        "LH knee's range (URDF): a higher stance",
        "LH's swing not solved (Maximum_Iterations_Exceeded): the hind feet further back",
    ]


def test_a_bad_speed_is_told_before_another_runs_lock(tmp_path, capsys, monkeypatch):
    """While another run writes the folder, a mistyped speed is still the error the user sees,
    and a busy folder is named as the user gave it."""
    from scalf_opt.files import output_set

    out = tmp_path / "gait"
    with output_set([out], []):  # another run, writing the folder
        assert main(["gait", "--speed", "0", "--out", str(out)]) == 2
        assert "--speed: the speed must be a number" in capsys.readouterr().err
        monkeypatch.chdir(tmp_path)
        assert main(["gait", "--speed", "0.5", "--out", "gait"]) == 2
        assert capsys.readouterr().err.startswith("scalf-opt: error: gait: another scalf-opt run")

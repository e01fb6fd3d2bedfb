"""The cheapest trot as a study axis: ``speed_m_s`` in a study file, checked before any case
runs, and a speed case's row with the cheapest gait's columns beside the study's."""

import csv

import pytest

import scalf_opt.studies.case as case_module
from scalf_opt.errors import ConfigError
from scalf_opt.studies.case import case_key
from scalf_opt.studies.gait_case import GAIT_COLUMNS
from scalf_opt.studies.runner import choose_runner, run_study
from scalf_opt.studies.study_file import read_study, speed_study


def study(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path


def test_a_speed_axis_makes_cheapest_gait_cases(tmp_path):
    s = read_study(study(tmp_path, '[study]\nfamily = "paper"\n[sweep]\nspeed_m_s = [0.5, 1.0]\n'))
    assert [c.speed_m_s for c in s.cases] == [0.5, 1.0]
    assert [c.swept for c in s.cases] == [{"speed_m_s": 0.5}, {"speed_m_s": 1.0}]
    fixed = read_study(study(tmp_path, "[study]\nspeed_m_s = 0.75\n[gait]\nclearance_m = 0.1\n"))
    assert fixed.cases[0].speed_m_s == 0.75 and fixed.cases[0].gait == {"clearance_m": 0.1}
    plain = read_study(study(tmp_path, "[study]\n"))
    assert plain.cases[0].speed_m_s is None
    # a speed is another case (another cache entry); the CLI's cases are a study file's
    assert case_key(plain.cases[0]) != case_key(fixed.cases[0])
    cli = speed_study([0.5, 1.0], robot="scalf", family="paper")
    assert [case_key(c) for c in cli.cases] == [case_key(c) for c in s.cases]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[study]\nspeed_m_s = 1.0\n[gait]\nperiod_s = 0.5\n", "gait.period_s: a study with a"),
        ('[sweep]\nspeed_m_s = [1.0]\n"gait.duty_cycle" = [0.6]\n', "gait.duty_cycle: a study"),
        ('[study]\nspeed_m_s = 1.0\noptimize = "RF"\n', 'optimize = "pair"'),
        ("[study]\nspeed_m_s = 0\n", "speed_m_s: the speed must be a number in (0, 10]"),
        ("[sweep]\nspeed_m_s = [1.0, true]\n", "speed_m_s must be a number"),
        ("[study]\nspeed_m_s = 1.0\n[sweep]\nspeed_m_s = [1.0]\n", "give one"),
    ],
)
def test_a_bad_speed_study_is_refused_naming_the_key(tmp_path, text, message):
    with pytest.raises(ConfigError, match=r"s\.toml") as info:
        read_study(study(tmp_path, text))
    assert message in str(info.value)


def test_a_speed_case_s_row_has_the_cheapest_gait(tmp_path, monkeypatch, cheapest_trot):
    """The study engine's row of a speed case (the search itself: the session's, reused)."""
    calls = []

    def search(pipeline, goal, progress=None):
        calls.append((goal.speed_m_s, goal.family.name))
        return cheapest_trot

    monkeypatch.setattr(case_module, "optimize_gait", search)
    s = read_study(study(tmp_path, '[study]\nfamily = "paper"\n[sweep]\nspeed_m_s = [1.0]\n'))
    run = run_study(s, tmp_path / "out", choose_runner(1))
    assert calls == [(1.0, "paper")]
    assert set(GAIT_COLUMNS) <= set(run.columns)
    (row,) = run.rows
    assert row["status"] == "ok" and row["speed_m_s"] == 1.0
    cycle = cheapest_trot.cycle()
    assert row["optimized_energy_j"] == pytest.approx(cycle.energy_j, rel=1e-12)
    assert row["cost_of_transport_optimized"] <= row["cost_of_transport_reference"]
    assert row["saving_pct"] == pytest.approx(row["saving_vs_reference_pct"], rel=1e-12)
    with (tmp_path / "out" / "results.csv").open() as handle:
        assert next(csv.DictReader(handle))["period_s"] == repr(cycle.gait.period_s)

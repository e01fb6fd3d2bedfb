"""Study files and their runs: the schema and its errors, the cache (a rerun or a killed run
completes only the rest), failed cases, a local pool and a Dask cluster of two workers that
write the same results.csv as the serial run."""

import io

import pytest

from scalf_opt.cli import main
from scalf_opt.errors import ConfigError
from scalf_opt.studies import runner as runner_module
from scalf_opt.studies.progress import Progress
from scalf_opt.studies.runner import choose_runner, run_study
from scalf_opt.studies.study_file import read_study

STUDY = """
[study]
name = "tiny"
robot = "scalf"
family = "joint-3"
[gait]
clearance_m = 0.07
[sweep]
"gait.period_s" = [0.45, 0.55]
"gait.stance_height_m" = [0.75, 2.0]
"""


def write(tmp_path, text, name="s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_cases_are_the_product_of_the_axes(tmp_path):
    study = read_study(write(tmp_path, STUDY))
    assert [c.swept for c in study.cases] == [
        {"gait.period_s": 0.45, "gait.stance_height_m": 0.75},
        {"gait.period_s": 0.45, "gait.stance_height_m": 2.0},
        {"gait.period_s": 0.55, "gait.stance_height_m": 0.75},
        {"gait.period_s": 0.55, "gait.stance_height_m": 2.0},
    ]
    assert study.cases[0].gait == {"clearance_m": 0.07, "period_s": 0.45, "stance_height_m": 0.75}
    assert study.plot_x == "gait.period_s" and study.name == "tiny"


def test_combined_axes_and_settings(tmp_path):
    text = """
[study]
family = "joint-2"
[sweep]
"gait.period_s + gait.step_length_m" = [[0.6, 0.15], [0.5, 0.25]]
robot = ["scalf", "go1"]
[plot]
x = "speed_m_s"
"""
    study = read_study(write(tmp_path, text))
    assert len(study.cases) == 4 and study.cases[1].robot == "go1"
    assert study.cases[2].gait == {"period_s": 0.5, "step_length_m": 0.25}
    assert study.plot_x == "speed_m_s" and study.cases[0].method == "ipopt"


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("[study]\nrobots = 'x'\n", "unknown key study.robots; did you mean 'robot'"),
        ("[studies]\n", r"unknown table \[studies\]; did you mean 'study'"),
        ("family = 'joint-4'\n[study]\n", r"family belongs in the \[study\] table"),
        ("period_s = 0.4\n", r"period_s belongs in the \[gait\] table"),
        ("robt = 'go1'\n", "unknown top-level key robt; did you mean 'robot'"),
        ("[sweep]\n'gait.speed' = [1]\n", r"unknown gait field 'speed' \(known"),
        ("[sweep]\n'hip' = [1]\n", "unknown sweep key 'hip'"),
        ("[sweep]\nclearance_m = [1]\n", "'clearance_m'; did you mean 'gait.clearance_m'"),
        ("[sweep]\n'gait.period_s' = []\n", "must be a non-empty list"),
        ("[sweep]\n'gait.period_s' = ['a']\n", "gait.period_s must be a number"),
        ("[sweep]\n'variant.thigh_length_scale' = [0]\n", "thigh_length_scale = 0 must be"),
        ("[sweep]\n'gait.period_s + gait.clearance_m' = [[1]]\n", "a list of 2"),
        ("[sweep]\n'gait.period_s' = [1]\n'gait.period_s + gait.cycles' = [[1, 2]]\n", "twice"),
        ("[sweep]\nrobot = ['scalf', 'spot']\n", "unknown robot 'spot'"),
        ("[study]\nfamily = 'reference'\n", "has no free parameter"),
        ("[study]\nurdf = 'none.urdf'\n", "none.urdf not found"),
        ("[study]\noptimize = 'XY'\n", "study.optimize = 'XY'"),
        ("[plot]\ny = 1\n", "unknown key plot.y"),
        (
            "[sweep]\n'gait.clearance_m' = [0.1]\n[plot]\nx = 'clearance_m'\n",
            "plot.x = 'clearance_m' is not a column of results.csv; did you mean "
            "'gait.clearance_m'.*a swept field: gait.clearance_m,",
        ),
    ],
)
def test_schema_errors_name_file_and_key(tmp_path, text, match):
    with pytest.raises(ConfigError, match=match) as info:
        read_study(write(tmp_path, text))
    assert "s.toml" in str(info.value)


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    folder = tmp_path_factory.mktemp("serial")
    study = read_study(write(folder, STUDY))
    return study, run_study(study, folder / "out", choose_runner(workers=1))


def test_a_failed_case_is_recorded_and_the_others_go_on(serial):
    _, result = serial
    statuses = [row["status"] for row in result.rows]
    assert statuses == ["ok", "error", "ok", "error"]
    bad = result.rows[1]
    assert "stance_height_m = 2" in bad["error"] and bad["optimized_energy_j"] is None
    good = result.rows[0]
    assert 0 < good["saving_pct"] < 100
    assert good["optimized_energy_j"] < good["reference_energy_j"]
    assert good["cost_of_transport_optimized"] < good["cost_of_transport_reference"]
    lines = result.results_path.read_text().splitlines()
    assert lines[0].startswith("case,gait.period_s,gait.stance_height_m,status,robot,speed_m_s")
    assert len(lines) == 5 and result.figure_path.stat().st_size > 10_000


def test_a_rerun_takes_every_case_from_the_cache(serial, tmp_path, monkeypatch):
    study, result = serial

    def never(case):
        raise AssertionError("a cached case ran again")

    monkeypatch.setattr(runner_module, "run_case", never)
    out = result.results_path.parent
    before = result.results_path.read_text()
    again = run_study(study, out, choose_runner(workers=1))
    # the two failed cases are input errors: cached too
    assert again.cached == 4 and result.results_path.read_text() == before


def test_a_run_killed_half_way_completes_only_the_rest(serial, tmp_path, monkeypatch):
    study, result = serial
    calls = []
    real = runner_module.run_case

    def counting(case):
        calls.append(case.index)
        if len(calls) == 2:
            raise KeyboardInterrupt  # the run is killed during its second case
        return real(case)

    monkeypatch.setattr(runner_module, "run_case", counting)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_study(study, out, choose_runner(workers=1))
    assert not (out / "results.csv").exists() and len(list((out / "cache").iterdir())) == 1
    calls.clear()
    monkeypatch.setattr(runner_module, "run_case", real)
    finished = run_study(study, out, choose_runner(workers=1))
    assert finished.cached == 1
    assert finished.results_path.read_text() == result.results_path.read_text()


def test_a_pool_of_two_workers_runs_from_a_script_without_a_main_guard(serial, tmp_path):
    """The local pool's workers are fresh interpreters that do not run the caller's script
    again (multiprocessing's spawn did: every case was 'worker process died')."""
    import subprocess
    import sys

    study, result = serial
    script = tmp_path / "unguarded.py"
    script.write_text(
        "import sys\n"
        "from scalf_opt.studies.runner import choose_runner, run_study\n"
        "from scalf_opt.studies.study_file import read_study\n"
        "print('the script runs')\n"
        "run_study(read_study(sys.argv[1]), sys.argv[2], choose_runner(workers=2), quiet=True)\n"
    )
    out = tmp_path / "out"
    done = subprocess.run(
        [sys.executable, str(script), str(study.path), str(out)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "the script runs\n" and done.stderr == ""
    assert (out / "results.csv").read_text() == result.results_path.read_text()


def test_a_dask_cluster_of_two_workers_writes_the_same_results(serial, tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    study, result = serial
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        dask_run = run_study(study, tmp_path, choose_runner(scheduler=cluster.scheduler_address))
    assert dask_run.cached == 0
    assert dask_run.results_path.read_text() == result.results_path.read_text()


def test_progress_bar_only_on_a_terminal():
    pipe = io.StringIO()
    bar = Progress(3, pipe)
    bar.update(True)
    bar.close()
    assert pipe.getvalue() == ""

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    tty = Terminal()
    bar = Progress(2, tty)
    bar.update(True)
    bar.update(False)
    bar.close()
    assert "2/2 cases, 1 not ok" in tty.getvalue() and tty.getvalue().endswith("\n")


def test_progress_shows_what_a_running_case_last_said(monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    tty = Terminal()
    bar = Progress(2, tty)
    bar.note("0.5 m/s: gait 7, T = 0.550 s, duty 0.600")
    assert tty.getvalue().endswith("0/2 cases, 0 s; 0.5 m/s: gait 7, T = 0.550 s, duty 0.600")
    bar.update(True)
    bar.update(True)
    bar.close()
    last = tty.getvalue().rstrip("\n").split("\r")[-1]
    assert last.rstrip() == "[" + "#" * Progress.WIDTH + "] 2/2 cases, 0 s"  # no note once done
    monkeypatch.setenv("COLUMNS", "60")  # a narrow terminal: one line, cut
    bar = Progress(2, tty := Terminal())
    bar.note("0.5 m/s: gait 7, T = 0.550 s, duty 0.600")
    assert len(tty.getvalue().split("\r")[-1]) == 59


def test_command_line(serial, capsys):
    study, result = serial
    out = result.results_path.parent
    code = main(["study", str(study.path), "--workers", "1", "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 3  # two cases failed: results.csv says which
    assert "4 cases (4 from the cache)" in captured.out
    assert "2 of 4 cases did not succeed" in captured.err and captured.err.count("\n") == 1
    assert main(["study", str(study.path), "--workers", "0", "--out", str(out)]) == 2
    assert "--workers must be at least 1" in capsys.readouterr().err


def test_a_study_process_killed_mid_run_keeps_its_cache_and_the_rerun_completes(serial, tmp_path):
    """SIGKILL the command while it works: no cleanup runs, yet what it wrote stays consistent."""
    import json
    import signal
    import subprocess
    import sys
    import time

    study_file = write(tmp_path, STUDY)
    out = tmp_path / "out"
    command = [sys.executable, "-m", "scalf_opt", "study", str(study_file), "--workers", "1"]
    proc = subprocess.Popen([*command, "--out", str(out)], stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while not list((out / "cache").glob("*.json")) and time.monotonic() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    finished = sorted((out / "cache").glob("*.json"))
    assert 1 <= len(finished) < 4 and not (out / "results.csv").exists()
    for path in finished:  # every finished case is whole: an atomic rename, never a torn write
        json.loads(path.read_text())
    rerun = subprocess.run([*command, "--out", str(out)], capture_output=True, text=True)
    assert rerun.returncode in (0, 3), rerun.stderr  # 3: the study's impossible cases
    _, serial_result = serial
    assert (out / "results.csv").read_text() == serial_result.results_path.read_text()


def test_quiet_shows_no_progress_at_all(serial, monkeypatch, capsys):
    """``-q`` turns off the bar and the heartbeat of a study (the README: "-q turns both off")."""
    made = []

    class Recorder(Progress):
        def __init__(self, total, stream=None, enabled=None, label="study"):
            made.append(enabled)
            super().__init__(total, stream, enabled, label)

    monkeypatch.setattr(runner_module, "Progress", Recorder)
    study, result = serial
    out = result.results_path.parent
    argv = ["study", str(study.path), "--workers", "1", "--out", str(out)]
    main([*argv, "-q"])
    main(argv)
    capsys.readouterr()
    assert made == [False, None]  # quiet: nothing; else a bar on a terminal, a heartbeat elsewhere
